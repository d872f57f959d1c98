"""``--uncertainty N`` under a load history (``simulate --load``) and in a design study
(``optimize``: each design's objective as mean and spread, a robust choice on a quantile)."""

import json

import numpy as np
import pytest


def _shock(tmp_path):
    # a 1 kN half-sine of 10 ms (the machine frame's shock, coarser)
    t = np.linspace(0.0, 0.02, 41)
    f = np.where(t <= 0.01, 1000.0 * np.sin(np.pi * t / 0.01), 0.0)
    p = tmp_path / "shock.csv"
    rows = (f"{a:.6g}, {b:.9g}" for a, b in zip(t, f, strict=True))
    p.write_text("time [s], force [N]\n" + "\n".join(rows))
    return p


def test_load_history_spread_and_envelope_band(tmp_path, cli):
    shock = _shock(tmp_path)
    args = ("simulate", "--load", shock, "--tail", "0.3s", "--particles", "0",
            "--uncertain", "mode1.damping_ratio=1%+-0.3%", "--uncertain",
            "particles.friction=0.1+-0.03", "--uncertainty", "4")
    code, out, err = cli(*args, "--json", "--plot", tmp_path / "band.png")
    assert code == 0, err
    d = json.loads(out)
    u = d["uncertainty"]
    assert u["runs"] == 4 * 4 + 1
    peak, rms = u["answers"]["peak"], u["answers"]["rms"]
    assert peak["nominal"] == pytest.approx(d["peak"], rel=1e-12)  # the nominal run's
    assert rms["nominal"] == pytest.approx(d["rms"], rel=1e-12)
    # the free vibration after the shock decays with mode 1's damping: the RMS spreads
    assert rms["std"] > 0 and rms["driver"] == "mode1.damping_ratio"
    env = u["bands"]["envelope"]
    assert len(env["time"]) == len(env["p95"]) >= 20
    assert max(env["nominal"]) == pytest.approx(d["peak"], rel=1e-12)
    assert all(lo <= hi for lo, hi in zip(env["p5"], env["p95"], strict=True))
    assert list(u["not_used"]) == ["particles.friction"]
    assert (tmp_path / "band.png").stat().st_size > 0
    code, out, _ = cli(*args)
    assert code == 0 and "particles.friction: not used by the analytic fidelity" in out


def test_optimize_mean_and_robust_quantile(cli):
    args = ("optimize", "--vary", "particles=0:64:32", "--at", "0.8s", "--uncertain",
            "mode1.damping_ratio=0.33%+-0.1%", "--uncertain", "container.length=120mm+-1mm",
            "--uncertainty", "4", "--json")
    code, out, err = cli(*args)
    assert code == 0, err
    mean = json.loads(out)
    assert mean["statistic"] == "mean" and mean["uncertainty"]["samples"] == 8
    for c in mean["candidates"]:
        e = c  # the extras are keys of the candidate
        vals = [e[f"objective_p{p}"] for p in (5, 25, 50, 75, 95)]
        assert vals == sorted(vals) and e["objective_std"] > 0
        assert c["objective"] == pytest.approx(e["objective_mean"])
    code, out, err = cli(*args, "--robust-quantile", "90%")
    assert code == 0, err
    rob = json.loads(out)
    assert rob["statistic"] == "quantile 0.9" and rob["uncertainty"]["robust_quantile"] == 0.9
    for c in rob["candidates"]:
        e = c  # the extras are keys of the candidate
        # a minimised amplitude: the quantile 90 % of the samples meet, above the median
        assert c["objective"] == pytest.approx(e["objective_quantile"])
        assert e["objective_p50"] <= e["objective_quantile"] <= e["objective_p95"] + 1e-12
    code, _, err = cli("optimize", "--robust-quantile", "0.9")
    assert code == 2 and err.startswith("error: robust_quantile: is a quantile over the "
                                        "samples")
    code, _, err = cli(*args, "--robust-quantile", "1.5")
    assert code == 2 and err.startswith("error: robust_quantile: must be in (0, 1)")


def test_optimize_realisations_of_a_fields_map(tmp_path, cli):
    # each design over the realisations of the fields' map: its values are the single
    # studies' on each realisation's map alone
    import xarray as xr

    from pdamper.files import atomic_write_netcdf
    from pdamper.runs.realisations import combine_realisations, realisation_map

    m = tmp_path / "m.nc"
    code, _, err = cli("map", "--model", "analytic", "--particles", "32", "--frequency",
                       "2Hz:12Hz:11", "--amplitude", "log:0.5mm:200mm:30", "--out", m)
    assert code == 0, err
    first = xr.load_dataset(m)
    second = first.copy(deep=True)
    second["loss_factor"] = second["loss_factor"] * 0.7
    both = combine_realisations([first, second], [0, 1])

    def study(ds, name, *extra):
        f = tmp_path / f"{name}.nc"
        atomic_write_netcdf(f, ds)
        s = tmp_path / f"{name}.toml"
        s.write_text(f'[fields]\nfile = "{f}"\n[particles]\ncount = 32\n')
        code, out, err = cli("optimize", "--scenario", s, "--model", "fields", "--vary",
                             "particles=32:32:1", "--at", "0.8s", "--json", *extra)
        assert code == 0, err
        return json.loads(out)

    d = study(both, "both", "--realisations", "2")
    assert d["realisations"]["map_realisations"] == [0, 1]
    alone = [study(realisation_map(both, k), f"r{k}")["candidates"][0]["objective"]
             for k in range(2)]
    (c,) = d["candidates"]
    assert c["objective_values"] == pytest.approx(alone, rel=1e-9)
    assert c["objective"] == pytest.approx(np.mean(alone), rel=1e-9)
    assert alone[1] > alone[0]
