"""The ``dem`` command's flags come from one table (pdamper.cli.dem.FLAGS) whose keys are
declared settings; the public flags keep their names."""

from __future__ import annotations

import json

import pytest

from pdamper.cli._common import flag_name
from pdamper.cli.dem import FLAGS
from pdamper.io.scenario import DEMSpec, Scenario

#: The kind of a declaration -> the type of its flag (quantities with units are text).
TYPES = {"number": float, "whole": int, "flag": bool, "choice": str, "cycles": str}

#: Every flag of ``pdamper dem`` that sets a scenario key, as released.
PUBLIC = ("--frequency", "--amplitude", "--particles", "--cycles", "--max-cycles",
          "--integrator", "--skip-cycles", "--friction", "--restitution-pp",
          "--restitution-pw", "--damping-model", "--seed", "--packing", "--sample-rate",
          "--safety", "--error-estimate/--no-error-estimate", "--accuracy",
          "--free-flight/--no-free-flight", "--snapshot-rate", "--gravity",
          "--friction-model")


def test_the_table_names_only_declared_settings_and_scenario_keys():
    for flag, key, kind, text in FLAGS:
        section, _, name = key.partition(".")
        assert section in Scenario.model_fields, key
        table = Scenario.model_fields[section].annotation
        keys = table.flat_fields() if hasattr(table, "flat_fields") else table.model_fields
        assert name in keys, key
        assert text.endswith("."), flag
        if section == "dem":
            decl = DEMSpec.flat_fields()[name].json_schema_extra
            if decl:  # a declared setting: the flag's type follows its declaration
                assert kind is (str if decl["unit"] else TYPES[decl["kind"]]), flag
    assert len({flag_name(f) for f, *_ in FLAGS}) == len(FLAGS)
    assert len({k for _, k, *_ in FLAGS}) == len(FLAGS)


def test_public_flags_keep_their_names():
    assert tuple(f for f, *_ in FLAGS) == PUBLIC
    from typer.main import get_command

    from pdamper.cli._app import _register, app

    _register()
    cmd = get_command(app).commands["dem"]
    opts = {o for p in cmd.params for o in (*p.opts, *p.secondary_opts)}
    for flag in PUBLIC:
        assert set(flag.split("/")) <= opts, flag
    assert {"--out", "--vtk", "--realisations", "--workers", "--serial", "--json",
            "--scenario", "--force"} <= opts


@pytest.mark.parametrize(("args", "field"), [
    (["--safety", "2"], "dem.safety"),
    (["--packing", "hex"], "dem.packing"),
    (["--cycles", "many"], "dem.cycles"),
    (["--sample-rate", "3 m"], "dem.sample_rate"),
])
def test_a_bad_flag_names_its_setting(cli, args, field):
    code, out, err = cli("dem", *args)
    assert code != 0 and out == ""
    assert err.strip().splitlines() == [err.strip()]  # one line
    assert err.startswith(f"error: {field}: ")


def test_flags_reach_the_settings_as_the_scenario_keys_do(cli, tmp_path):
    scenario = tmp_path / "s.toml"
    scenario.write_text('[dem]\ngear_free_flight = false\nsafety = 0.03\n')
    args = ["dem", "--particles", "4", "--cycles", "2", "--skip-cycles", "1", "--integrator",
            "verlet", "--json"]
    code, out, _ = cli(*args, "--no-free-flight", "--safety", "0.03")
    assert code == 0
    by_flags = json.loads(out)
    code, out, _ = cli(*args, "--scenario", scenario)
    assert code == 0
    by_file = json.loads(out)
    assert by_flags["inputs"]["dem"] == by_file["inputs"]["dem"]
    assert by_flags["inputs"]["dem"]["gear_free_flight"] is False
    assert by_flags["inputs"]["dem"]["safety"] == 0.03
    assert by_flags["loss_factor"] == by_file["loss_factor"]
