"""The scenario drives every command (architecture issue): ``pdamper paper`` honours the
scenario's duration, Fig. 5 grid, optimisation step and ``[dem]`` section, and
``pdamper dem --scenario`` equals the same options on the command line."""

from __future__ import annotations

import json

import pytest

from pdamper.dem.result import WALL_TIME_KEYS

SCENARIO = """
[simulation]
duration = "1.2 s"
[optimization]
step = 32
[map]
frequency = "4Hz:20Hz:5"
amplitude = "5mm:150mm:6"
dem_frequency = "10Hz"
dem_amplitude = "32mm"
[dem]
integrator = "gear"
safety = 0.03
seed = 3
"""


@pytest.mark.long
def test_paper_honours_the_scenario(tmp_path, cli):
    scenario = tmp_path / "s.toml"
    scenario.write_text(SCENARIO)
    out = tmp_path / "paper"
    code, stdout, err = cli("paper", "--out", out, "--scenario", scenario, "--json")
    assert code == 0, err
    res = json.loads((out / "results.json").read_text())
    assert res["map_shape"] == [5, 6]
    assert [c["particles"] for c in res["optimization"]["candidates"]] == list(range(0, 192, 32))
    runs = res["level3_runs"]
    assert runs["scenario_damper"]["duration"] == 1.2 and runs["dem"]["duration"] == 1.2
    assert runs["dem"]["seed"] == 3 and runs["dem"]["integrator"] == "gear"
    assert res["inputs"]["dem"]["safety"] == 0.03
    rows = {r["quantity"]: r for r in res["rows"]}
    assert "maximum eta on the 5 x 6 grid" in rows
    opt = next(r for q, r in rows.items() if q.startswith("optimal particle count"))
    assert "64 within" in opt["ours"]
    from pdamper.parameters import PAPER_REPORTED

    assert len(res["rows"]) == len(PAPER_REPORTED) == 40  # every reported number, DEM ones too
    assert res["dem_map"]["shape"] == [1, 1]  # the scenario's DEM grid
    assert runs["dem_paper_cor_curves"]["duration"] == 1.2  # the paper's COR curves, same options
    assert runs["dem_paper_cor_curves"]["seed"] == 3


def test_paper_count_off_the_step_is_still_compared():
    """With step 48 the paper's 64 spheres are no candidate; the row still compares them."""
    from pdamper.io.scenario import load_scenario
    from pdamper.runs.paper_case_study import run_case_study

    sc = load_scenario(None, {"optimization.step": 48, "map.frequency": "4Hz:20Hz:3",
                              "map.amplitude": "5mm:150mm:4"})
    cs = run_case_study(sc, dem=False)
    counts = [c.particles for c in cs.optimization.candidates]
    assert counts == [0, 48, 96, 144] and 64 not in counts
    opt = next(r for r in cs.rows if r.quantity.startswith("optimal particle count"))
    assert "64 within" in opt.ours
    assert "; lightest within 5 %: " in opt.ours  # the mass-aware rule, the scenario's tolerance


def test_dem_scenario_equals_command_line(tmp_path, cli):
    scenario = tmp_path / "dem.toml"
    scenario.write_text("""
[particles]
count = 16
friction = 0.2
[excitation]
frequency = "12 Hz"
amplitude = "15 mm"
[dem]
integrator = "verlet"
cycles = 3
skip_cycles = 1
restitution_pp = 0.7
restitution_pw = 0.9
damping_model = "gonthier"
packing = "random"
seed = 5
safety = 0.03
sample_rate = "3 kHz"
""")
    code, from_file, err = cli("dem", "--scenario", scenario, "--json")
    assert code == 0, err
    code, from_options, err = cli(
        "dem", "--particles", 16, "--friction", 0.2, "--frequency", "12 Hz", "--amplitude",
        "15 mm", "--integrator", "verlet", "--cycles", 3, "--skip-cycles", 1,
        "--restitution-pp", 0.7, "--restitution-pw", 0.9, "--damping-model", "gonthier",
        "--packing", "random", "--seed", 5, "--safety", 0.03, "--sample-rate", "3 kHz",
        "--json")
    assert code == 0, err
    a, b = json.loads(from_file), json.loads(from_options)
    for d in (a, b):
        for key in WALL_TIME_KEYS:  # the only keys two runs differ in
            d.pop(key)
    assert a == b
    assert a["inputs"]["dem"]["integrator"] == "verlet" and a["seed"] == 5
    # and the command line overrides the file
    code, out, err = cli("dem", "--scenario", scenario, "--cycles", 2, "--json")
    assert code == 0, err
    assert json.loads(out)["inputs"]["dem"]["cycles"] == 2


def test_dem_quiet_rule_from_the_scenario(tmp_path, cli):
    """A resting bed (A = 0.8 g; its second cycle still settles) is quiet: steady after
    2 + 2 x 2 cycles; without the rule
    (``[dem] quiet_window_cycles = 0``) after 2 + 3 x 4 (docs/fields.md); the quiet rule's
    windows and skip from the scenario."""
    args = ("dem", "--particles", 4, "--frequency", "20 Hz", "--amplitude", "0.5 mm",
            "--json")
    code, out, err = cli(*args)
    assert code == 0, err
    quiet = json.loads(out)
    assert quiet["stationary"] and quiet["quiet_window"]
    assert quiet["cycles"] == 6 and quiet["averaged_cycles"] == [3, 6]
    assert quiet["motion_mode"] == "solid"
    scenario = tmp_path / "three.toml"
    scenario.write_text("[dem]\nquiet_windows = 3\nquiet_skip_cycles = 2\n")
    code, out, err = cli(*args, "--scenario", scenario)
    assert code == 0, err
    three = json.loads(out)
    assert three["quiet_window"] and three["averaged_cycles"] == [3, 8]
    scenario = tmp_path / "full.toml"
    scenario.write_text("[dem]\nquiet_window_cycles = 0\n")
    code, out, err = cli(*args, "--scenario", scenario)
    assert code == 0, err
    full = json.loads(out)
    assert full["stationary"] and not full["quiet_window"]
    assert full["cycles"] == 14 and full["averaged_cycles"] == [3, 14]


def test_dem_human_summary_unless_json(cli):
    code, out, err = cli("dem", "--particles", 16, "--cycles", 2, "--skip-cycles", 1,
                         "--integrator", "verlet")
    assert code == 0, err
    assert out.startswith("DEM (verlet, from the lattice), 16 spheres") and "effective loss factor" in out
    with pytest.raises(json.JSONDecodeError):
        json.loads(out)


def test_example_scenario_shows_the_dem_section(cli):
    code, out, _ = cli("example-scenario")
    assert code == 0 and "[dem]" in out
    for key in ("integrator", "cycles", "skip_cycles", "restitution_pp", "restitution_pw",
                "error_estimate", "accuracy", "max_refinements", "quiet_window_cycles",
                "quiet_scatter", "quiet_windows", "quiet_skip_cycles",
                "damping_model", "packing", "seed", "safety", "sample_rate", "snapshot_rate"):
        assert f"{key} = " in out, key


@pytest.mark.parametrize("option", ["--model", "--damper"])
def test_model_option_in_simulate_and_optimize(cli, option):
    code, out, err = cli("simulate", option, "analytic", "--duration", "0.5s", "--json")
    assert code == 0, err
    assert json.loads(out)["inputs"]["simulation"]["model"] == "analytic"
    code, out, err = cli("optimize", option, "analytic", "--step", 64, "--json")
    assert code == 0, err
