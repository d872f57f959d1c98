"""``pdamper dem --uncertainty N``: a fitted COR curve's parameter uncertainty through the DEM."""

import json

import numpy as np
import pytest

#: Measured sphere-wall CORs with scatter: an exponential fit of 3 parameters.
_V = np.linspace(0.05, 1.5, 10)
_E = 0.45 + 0.45 * np.exp(-_V / 0.3) + np.array(
    [0.02, -0.01, 0.015, -0.02, 0.0, 0.01, -0.015, 0.02, -0.005, 0.01])
#: A cheap point: 4 spheres, 3 cycles.
_SCENARIO = ('[particles]\ncount = 4\n[excitation]\nfrequency = "10 Hz"\n'
             'amplitude = "32 mm"\n[dem]\ncycles = 3\nskip_cycles = 1\n'
             '[restitution]\n'
             'particle_wall = { model = "table", file = "cor.csv", fit = "exponential" }\n')


def _files(tmp_path):
    rows = "".join(f"{v:.4f}, {e:.4f}, 0.02\n" for v, e in zip(_V, _E, strict=True))
    (tmp_path / "cor.csv").write_text("velocity [m/s], cor [-], std [-]\n" + rows)
    p = tmp_path / "s.toml"
    p.write_text(_SCENARIO)
    return p


def test_cor_fit_uncertainty_moves_the_dem_loss_factor(tmp_path, cli):
    p = _files(tmp_path)
    code, out, err = cli("dem", "--scenario", p, "--json")
    assert code == 0, err
    plain = json.loads(out)
    code, out, err = cli("dem", "--scenario", p, "--uncertain",
                         "restitution.particle_wall=fit", "--uncertainty", "4", "--serial",
                         "--json")
    assert code == 0, err
    d = json.loads(out)
    u = d["uncertainty"]
    fields = [i["field"] for i in u["inputs"]]
    assert fields == [f"restitution.particle_wall[pc{k}]" for k in (1, 2, 3)]
    assert all(i["group"] == "restitution.particle_wall" and i["sd"] == 1.0
               and i["low"] < 0 < i["high"] for i in u["inputs"])
    assert u["runs"] == 4 * (3 + 2) + 1
    # the nominal sample is the fitted curve itself: the plain run, to the last digit
    assert d["loss_factor"] == plain["loss_factor"]
    eta = u["answers"]["loss_factor"]
    assert eta["nominal"] == plain["loss_factor"]
    assert eta["std"] > 0 and eta["min"] < eta["max"]
    assert eta["driver"] in fields
    assert set(eta["groups"]["restitution.particle_wall"]["inputs"]) == set(fields)
    # the record: each axis' direction in the parameters
    assert set(d["uncertain_inputs"][0]["direction"]) == {"e0", "e_inf", "v_c"}


def test_dem_uncertainty_on_the_sweep_engine_as_in_this_process(tmp_path, cli):
    # two worker processes run the same samples from the same seed: the same answers
    p = _files(tmp_path)
    answers = []
    for how in (["--serial"], ["--workers", "2"]):
        code, out, err = cli("dem", "--scenario", p, "--uncertain",
                             "restitution.particle_wall=fit", "--uncertainty", "4", *how,
                             "--json")
        assert code == 0, err
        answers.append(json.loads(out)["uncertainty"]["answers"]["loss_factor"])
    assert answers[0]["mean"] == answers[1]["mean"] and answers[0]["std"] == answers[1]["std"]


def test_cor_fit_uncertainty_refused_where_no_dem_runs(tmp_path, cli):
    p = _files(tmp_path)
    code, _, err = cli("analytic", "--scenario", p, "--uncertain",
                       "restitution.particle_wall=fit", "--uncertainty", "4")
    assert code == 2 and err.startswith("error: restitution.particle_wall:")
    assert "pdamper dem --uncertainty" in err


@pytest.mark.parametrize("extra", [["--uncertainty", "65536"]])
def test_dem_uncertainty_judged_by_its_cost(tmp_path, cli, extra):
    p = _files(tmp_path)
    (tmp_path / "s.toml").write_text(_SCENARIO.replace("count = 4", "count = 32")
                                     .replace("cycles = 3", 'cycles = "auto"'))
    code, _, err = cli("dem", "--scenario", p, "--uncertain",
                       "restitution.particle_wall=fit", *extra)
    assert code == 2 and err.startswith("error: uncertainty:") and "runs" in err
