"""The damper's quantities declared once: every field of ParticleDamper has one declaration
(unit, range, doc, its scenario key); the scenario's [container] and [particles] keys, the
uncertain inputs and the design variables resolve to those declarations and check a value
with the same message; [container] length reaches ParticleDamper.length without a rename."""

from __future__ import annotations

import dataclasses
import math

import pytest

import pdamper.dem.settings as dem_settings
import pdamper.settings as settings
from pdamper.damper import QUANTITIES, ParticleDamper, quantity, uncertain_fields
from pdamper.design.study import VARIABLES, DesignVariable, parse_variable
from pdamper.errors import InputError
from pdamper.io.scenario import ContainerSpec, MaterialSpec, ParticlesSpec, load_scenario
from pdamper.io.uncertain import UNCERTAIN_FIELDS, parse_uncertain
from pdamper.materials import PVC, S235
from pdamper.parameters import PAPER_DAMPER

SECTIONS = {"container": ContainerSpec, "particles": ParticlesSpec}
#: what makes two surfaces' declarations of one quantity the same
RANGE = ("unit", "kind", "low", "high", "low_inclusive", "high_inclusive", "choices")


def test_every_field_of_the_damper_is_declared_once_under_its_one_name():
    decls = ParticleDamper.declarations()
    assert list(decls) == [f.name for f in dataclasses.fields(ParticleDamper)]
    keys = [d["key"] for d in decls.values()]
    assert len(set(keys)) == len(keys) == len(decls)
    for name, d in decls.items():
        assert d["kind"] in settings.KINDS, name
        assert len(d["doc"]) > 10, name
        assert d["key"].count(".") == 1, name
        assert QUANTITIES[d["key"]] == name
        if d["kind"] in ("number", "whole", "curve"):
            assert d["low"] is not None, f"{name}: its range is declared"
    assert decls["length"]["unit"] == decls["particle_radius"]["unit"] == "m"
    assert decls["container_mass"]["unit"] == "kg"


def test_the_declaration_machinery_is_one_for_the_dem_and_the_damper():
    """pdamper.dem.settings re-exports the level-0 machinery: one setting(), one check."""
    for name in ("setting", "declaration", "allowed", "check_setting", "Settings", "KINDS"):
        assert getattr(dem_settings, name) is getattr(settings, name), name


def test_the_damper_checks_its_values_against_the_declarations():
    with pytest.raises(InputError, match=r"^container.mass: must be in \[0, inf\] kg, got -1 kg"):
        dataclasses.replace(PAPER_DAMPER, container_mass=-1.0)
    with pytest.raises(InputError, match=r"^particles.radius: must be in \(0, inf\] m"):
        ParticleDamper(0.12, 0.04, 0.04, 0.0, 32, S235, PVC)


@pytest.mark.parametrize("section", SECTIONS)
def test_every_scenario_key_of_the_damper_resolves_to_its_one_declaration(section):
    cls = SECTIONS[section]
    decls = cls.declarations()
    assert list(decls) == list(cls.model_fields)
    for key, d in decls.items():
        name = f"{section}.{key}"
        assert d["key"] == name
        q = quantity(name)
        assert {k: d[k] for k in RANGE} == {k: q[k] for k in RANGE}, name
        assert d["doc"] == q["doc"], name
        assert {"unit", "kind", "low", "high", "choices", "doc", "default"} <= set(d)
    # and every quantity of those sections is a key of its section
    assert {k for k in QUANTITIES if k.startswith(f"{section}.")} == \
        {f"{section}.{k}" for k in decls}


def test_the_inline_material_is_declared():
    d = MaterialSpec.declarations()
    assert d["youngs_modulus"]["unit"] == "Pa" and d["density"]["unit"] == "kg/m^3"
    assert (d["poisson_ratio"]["low"], d["poisson_ratio"]["high"]) == (-1.0, 0.5)


def test_every_uncertain_field_of_the_damper_has_its_declarations_unit_and_range():
    damper = {k: v for k, v in UNCERTAIN_FIELDS.items() if k in QUANTITIES}
    assert damper == uncertain_fields()
    assert set(damper) == {k for k in QUANTITIES if quantity(k)["kind"] in ("number", "curve")}
    for key, (unit, low, high) in damper.items():
        q = quantity(key)
        assert unit == q["unit"] and low == q["low"], key
        assert high == (math.inf if q["high"] is None else q["high"]), key
    assert UNCERTAIN_FIELDS["dem.restitution_pw"] == ("", 0.0, 1.0)


def test_every_design_variable_resolves_to_one_declaration():
    fields = [v.field for v in VARIABLES.values()]
    assert len(set(fields)) == len(fields)
    for name, v in VARIABLES.items():
        q = quantity(v.field)
        assert v.attribute == q["attribute"] and v.unit == q["unit"], name
        assert v.description == q["doc"], name
        assert v.kind == {"whole": "integer", "number": "continuous",
                          "material": "categorical"}[q["kind"]], name


def _message(call) -> str:
    with pytest.raises(InputError) as info:
        call()
    return info.value.message


def test_a_bad_container_length_has_one_message_on_every_surface():
    scenario = _message(lambda: load_scenario(None, {"container.length": "-1 mm"}))
    uncertain = _message(lambda: parse_uncertain("-1 mm +- 0.1 mm", "container.length"))
    vary = _message(lambda: parse_variable("container.length=-1mm:1mm:3"))
    assert scenario == uncertain == vary == "must be in (0, inf] m, got -0.001 m"


def test_a_bad_radius_and_count_have_one_message_on_every_surface():
    radius = {_message(lambda: load_scenario(None, {"particles.radius": "0 mm"})),
              _message(lambda: parse_uncertain("0 mm +- 0.1 mm", "particles.radius")),
              _message(lambda: parse_variable("radius=0mm:1mm:3"))}
    assert radius == {"must be in (0, inf] m, got 0 m"}
    count = {_message(lambda: load_scenario(None, {"particles.count": -16})),
             _message(lambda: parse_variable("particles=-16:16:16")),
             _message(lambda: parse_variable("particles.count=-16,16"))}
    assert count == {"must be a whole number >= 0, got -16"}


def test_the_walk_of_container_length_from_toml_to_the_damper(tmp_path):
    """[container] length -> ContainerSpec.length (declared by the damper's quantity
    container.length) -> ParticleDamper.length: one declaration, no rename."""
    path = tmp_path / "s.toml"
    path.write_text('[container]\nlength = "130 mm"\n', encoding="utf-8")
    sc = load_scenario(path)
    assert sc.container.length == pytest.approx(0.130)
    assert sc.damper().length == pytest.approx(0.130)
    section = ContainerSpec.declarations()["length"]
    field = ParticleDamper.declarations()["length"]
    assert section["key"] == field["key"] == "container.length"
    assert QUANTITIES["container.length"] == "length"
    assert {k: section[k] for k in RANGE} == {k: field[k] for k in RANGE}


def test_every_section_key_reaches_the_field_its_declaration_names():
    """Each [container] / [particles] key set to its own value arrives in the damper's
    field that QUANTITIES names for it."""
    values = {"container.length": 0.13, "container.width": 0.05, "container.depth": 0.06,
              "container.mass": 0.2, "particles.radius": 0.004, "particles.count": 48,
              "particles.friction": 0.3, "particles.material": "POM",
              "container.material": "S235"}
    assert set(values) == {k for k in QUANTITIES if k.split(".")[0] in SECTIONS}
    d = load_scenario(None, values).damper()
    for key, value in values.items():
        got = getattr(d, QUANTITIES[key])
        assert (got.name if key.endswith("material") else got) == value, key


@pytest.mark.parametrize(("spec", "name"), [
    ("particles=16:32:16", "particles"), ("count=16,32", "particles"),
    ("particle_count=16", "particles"), ("particles.count=16:32:16", "particles"),
    ("radius=3mm", "radius"), ("particle_radius=3mm", "radius"),
    ("particles.radius=3mm", "radius"),
    ("container-length=100mm", "container_length"), ("length=100mm", "container_length"),
    ("container.length=100mm", "container_length"),
    ("container_width=40mm", "container_width"), ("container.depth=40mm", "container_depth"),
    ("particle-material=S235", "particle_material"), ("material=S235", "particle_material"),
    ("particles.material=S235", "particle_material"),
])
def test_every_name_of_a_design_variable_is_taken(spec, name):
    """The old --vary names stay aliases; the scenario key names the same variable."""
    v = parse_variable(spec)
    assert isinstance(v, DesignVariable) and v.name == name


def test_the_uncertain_names_of_the_damper_are_the_scenario_keys():
    """--uncertain container.length=... (and every damper field) keeps its name."""
    u = parse_uncertain("120 mm +- 0.1 mm", "container.length")
    assert (u.field, u.unit, u.low, u.high) == ("container.length", "m", 0.0, math.inf)
    u = parse_uncertain("0.1 +- 0.03", "particles.friction")
    assert u.field == "particles.friction"
    assert parse_uncertain("0.8 +- 0.05", "dem.restitution_pp").high == 1.0
    with pytest.raises(InputError, match=r"must be in \(0, 1\], got 1.2"):
        parse_uncertain("1.2 +- 0.05", "dem.restitution_pp")


def test_scenario_sections_hand_their_declarations_to_a_resolver():
    """The scenario's damper sections list their keys' declarations as the settings of the
    DEM do (Settings.declarations)."""
    for cls in (ContainerSpec, ParticlesSpec, MaterialSpec):
        assert issubclass(cls, settings.Settings)
        for key, d in cls.declarations().items():
            assert d == {**settings.declaration(cls, key), "doc": d["doc"],
                         "default": d["default"]}


@pytest.mark.long
def test_the_type_checker_rejects_a_misspelt_damper_quantity(tmp_path, monkeypatch):
    """The damper's quantities are plain dataclass fields to mypy: a misspelt one, as an
    attribute or a keyword, and a missing required one are type errors."""
    from pathlib import Path

    api = pytest.importorskip("mypy.api")
    import pdamper

    monkeypatch.setenv("MYPYPATH", str(Path(pdamper.__file__).parents[1]))
    snippet = tmp_path / "snippet.py"
    snippet.write_text("from pdamper.damper import ParticleDamper\n\n\n"
                       "def f(d: ParticleDamper) -> float:\n"
                       "    ParticleDamper(lenght=0.12)\n"
                       "    ParticleDamper()\n"
                       "    return d.lenght\n", encoding="utf-8")
    out, _, status = api.run([str(snippet), "--ignore-missing-imports",
                              "--cache-dir", str(tmp_path / "cache")])
    assert status == 1, out
    assert 'no attribute "lenght"' in out
    assert 'Unexpected keyword argument "lenght"' in out
    assert 'Missing positional arguments "length"' in out
