"""``--uncertainty N``: the spread of the Level II and III answers under "value +- sd"."""

import json

import pytest


def _scenario(tmp_path, text):
    p = tmp_path / "s.toml"
    p.write_text(text)
    return p


def test_friction_alone_moves_no_analytic_answer(tmp_path, cli):
    # the analytical model (Eqs. 5-22) has no friction: zero spread, no driver
    p = _scenario(tmp_path, '[particles]\nfriction = "0.1 +- 0.03"\n')
    code, out, err = cli("analytic", "--scenario", p, "--uncertainty", "16", "--json")
    assert code == 0, err
    u = json.loads(out)["uncertainty"]
    assert u["seed"] == 0 and u["points"] == 16 and u["runs"] == 16 * 3 + 1
    assert u["inputs"][0]["field"] == "particles.friction"
    assert u["inputs"][0]["sd"] == 0.03 and u["inputs"][0]["low"] == 0.0
    eta = u["answers"]["loss_factor"]
    assert eta["std"] == 0.0 and eta["driver"] is None
    assert eta["mean"] == pytest.approx(eta["nominal"])


def test_simulate_friction_and_length_tolerance(tmp_path, cli):
    p = _scenario(tmp_path, '[particles]\nfriction = "0.1 +- 0.03"\n'
                  '[container]\nlength = "120 mm +- 0.5 mm"\n'
                  '[simulation]\nduration = "1 s"\n')
    code, out, err = cli("simulate", "--scenario", p, "--uncertainty", "16",
                         "--uncertainty-seed", "3", "--json")
    assert code == 0, err
    d = json.loads(out)
    u = d["uncertainty"]
    assert u["seed"] == 3 and d["inputs"]["particles"]["friction"] == 0.1
    amp = u["answers"]["amplitude_at"]
    assert set(amp["percentiles"]) == {"p5", "p25", "p50", "p75", "p95"}
    assert amp["std"] > 0 and amp["min"] <= amp["percentiles"]["p5"] <= amp["mean"] \
        <= amp["percentiles"]["p95"] <= amp["max"]
    # the clearance (container length) drives; friction does not enter model 3
    for name in ("amplitude_at", "final_amplitude", "mean_damping_ratio"):
        a = u["answers"][name]
        assert a["driver"] == "container.length" and a["ranking"][0] == "container.length"
        assert a["total_order"]["particles.friction"] == 0.0
    assert u["driver"] == "container.length"
    env = u["bands"]["envelope"]
    assert env["time"][0] == 0.0 and env["time"][-1] == pytest.approx(1.0)
    assert env["nominal"][0] == pytest.approx(0.058)  # the release, |x0|
    assert "envelope" not in u["answers"]


def test_cli_uncertain_option_is_the_scenario_syntax(cli):
    code, out, err = cli("analytic", "--uncertain", "particles.friction=0.1 +- 0.03",
                         "--uncertain", "excitation.amplitude=32mm+-1mm",
                         "--uncertainty", "8", "--json")
    assert code == 0, err
    u = json.loads(out)["uncertainty"]
    assert sorted(i["field"] for i in u["inputs"]) == ["excitation.amplitude",
                                                       "particles.friction"]
    assert u["answers"]["loss_factor"]["driver"] == "excitation.amplitude"


def test_human_output_names_the_driver(tmp_path, cli):
    code, out, _ = cli("analytic", "--uncertain", "container.length=120mm+-1mm",
                       "--uncertainty", "8")
    assert code == 0 and "driver container.length" in out


def test_a_map_of_the_nominal_geometry_refuses_a_sampled_length(tmp_path, cli):
    # model 2's map is a property of one geometry: a sampled container length is another
    m = tmp_path / "map.nc"
    code, _, err = cli("map", "--model", "analytic", "--particles", "32", "--frequency",
                       "2Hz:20Hz:6", "--amplitude", "1mm:200mm:8", "--out", m)
    assert code == 0, err
    code, _, err = cli("simulate", "--model", "fields", "--fields", m, "--particles", "32",
                       "--uncertain", "container.length=120mm+-0.2mm", "--uncertainty", "4")
    assert code == 2 and err.startswith("error: fields.file: at the uncertainty sample "
                                        "container.length") and err.count("\n") == 1


def test_without_uncertainty_the_nominal_value_runs_and_the_sd_is_recorded(tmp_path, cli):
    p = _scenario(tmp_path, '[container]\nlength = "120 mm +- 0.2 mm"\n')
    code, out, err = cli("analytic", "--scenario", p, "--json")
    assert code == 0, err
    d = json.loads(out)
    assert "uncertainty" not in d and d["inputs"]["container"]["length"] == pytest.approx(0.12)
    (u,) = d["uncertain_inputs"]
    assert u["field"] == "container.length" and u["sd"] == pytest.approx(2e-4)
    assert u["distribution"] == "normal truncated to the valid range"


def test_map_carries_the_spread_of_every_cell(tmp_path, cli):
    import numpy as np
    import xarray as xr

    m = tmp_path / "map.nc"
    code, out, err = cli("map", "--particles", "32", "--frequency", "4Hz:20Hz:5",
                         "--amplitude", "log:2mm:128mm:7", "--out", m, "--uncertain",
                         "container.length=120mm+-1mm", "--uncertain",
                         "particles.friction=0.1+-0.03", "--uncertainty", "8", "--json")
    assert code == 0, err
    u = json.loads(out)["uncertainty"]
    assert u["answers"]["mean_loss_factor"]["driver"] == "container.length"
    assert u["answers"]["mean_loss_factor"]["total_order"]["particles.friction"] == 0.0
    with xr.open_dataset(m) as ds:
        assert set(u["variables"]) <= set(ds.data_vars)
        p5, p50, p95 = (ds[f"loss_factor_{q}"].values for q in ("p5", "p50", "p95"))
        assert p5.shape == ds["loss_factor"].shape == (5, 7)
        ok = np.isfinite(p5)
        assert np.all(p5[ok] <= p50[ok]) and np.all(p50[ok] <= p95[ok])
        assert np.nanmax(ds["loss_factor_std"].values) > 0  # the clearance moves some cells
        assert ds["loss_factor_std"].attrs["uncertainty_points"] == 8
