"""docs/scenario.md is generated from the scenario schema and is up to date; the generator
reads each key's type, unit, default and constraint from the declarations."""

from pathlib import Path

from pdamper.io import scenario_reference as ref
from pdamper.io.scenario import Scenario

DOC = Path(__file__).resolve().parents[2] / "docs" / "scenario.md"


def test_the_committed_page_is_the_generated_one():
    assert DOC.read_text(encoding="utf-8") == ref.reference(), (
        "docs/scenario.md is out of date: python -m pdamper.io.scenario_reference "
        "--write docs/scenario.md")


def test_every_section_and_key_of_the_schema_is_on_the_page():
    text = ref.reference()
    for section, info in Scenario.model_fields.items():
        models = [m for m in ref._members(info.annotation) if ref._is_model(m)]
        if not models:
            assert f"| `{section}` |" in text
            continue
        assert f"`[{section}]`" in text, section
        for model in models:
            for key in model.model_fields:
                assert f"| `{key}`" in text, f"{section}.{key}"


def _row(text, heading, key):
    part = text.split(heading, 1)[1].split("\n## ", 1)[0]
    return next(line for line in part.splitlines() if line.startswith(f"| `{key}`"))


def test_type_unit_default_and_constraint_come_from_the_declarations():
    text = ref.reference()
    freq = _row(text, "## `[excitation]`", "frequency").split(" | ")
    assert freq[1:5] == ["number", "Hz", '`"10 Hz"`', "> 0"]
    count = _row(text, "## `[particles]`", "count").split(" | ")
    assert count[1] == "integer" and count[4] == ">= 0"
    gravity = _row(text, "## `[excitation]`", "gravity")
    assert "m/s^2" in gravity and ">= 0, finite" in gravity
    model = _row(text, "## `[simulation]`", "model")
    assert model.startswith("| `model`, `damper` |")  # the alias is listed
    beam = _row(text, "### `structure.beam`", "elements")
    assert ">= 1, <= 1000" in beam


def test_the_check_mode_sees_a_stale_page(tmp_path, capsys):
    stale = tmp_path / "scenario.md"
    stale.write_text("# old\n", encoding="utf-8")
    assert ref.main(["--check", str(stale)]) == 1
    assert "out of date" in capsys.readouterr().err
    assert ref.main(["--check", str(DOC)]) == 0
