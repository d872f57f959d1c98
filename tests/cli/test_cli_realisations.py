"""``--realisations N`` of ``dem``, ``map --model dem`` and ``simulate``: N random packings
(seeds dem.seed + k) and the spread of their answers, each realisation the run of its
seed on its own."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

RANDOM = "[dem]\npacking = \"random\"\nseed = {seed}\n"
FAST_MAP = "[dem]\ncycles = 3\nskip_cycles = 1\npacking = \"random\"\nseed = {seed}\n"


def _toml(tmp_path, name: str, text: str):
    p = tmp_path / name
    p.write_text(text)
    return p


def _json(cli, *args):
    code, out, err = cli(*args, "--json")
    assert code == 0, err
    return json.loads(out)


# --------------------------------------------------------------------------- Level II
def test_dem_five_realisations_at_10hz_32mm_contain_the_separate_seeds(cli):
    """``dem --realisations 5`` at 10 Hz / 32 mm from a random packing: its mean is the mean
    of five separately run seeds and lies within its min-max; each spread is non-zero."""
    base = ["dem", "--frequency", "10Hz", "--amplitude", "32mm", "--particles", "16",
            "--cycles", "3", "--skip-cycles", "1", "--packing", "random"]
    data = _json(cli, *base, "--seed", "11", "--realisations", "5", "--serial")
    rec = data["realisations"]
    assert rec["count"] == 5 and rec["seeds"] == [11, 12, 13, 14, 15]
    single = [_json(cli, *base, "--seed", str(s)) for s in rec["seeds"]]
    for key in ("loss_factor", "effective_mass_ratio"):
        v = np.array([s[key] for s in single])
        st = rec[key]
        assert math.isclose(st["mean"], v.mean(), rel_tol=1e-12)
        assert st["min"] <= v.mean() <= st["max"]
        assert st["std"] > 0 and math.isclose(st["std"], v.std(ddof=1), rel_tol=1e-9)
        assert st["min"] < st["max"]


def _map_args(f: str, x: str, *more):
    return ["map", "--model", "dem", "--frequency", f, "--amplitude", x, "--particles", "16",
            *more]


def _check_spread(ds, count: int) -> None:
    """Every cell carries the mean, std, min and max of its ``count`` realisations."""
    assert ds.sizes["realisation"] == count and ds.attrs["statistic"] == "mean"
    for name in ("loss_factor", "effective_mass_ratio"):
        each = ds[f"{name}_realisations"].values
        assert each.shape == (count, *ds[name].shape)
        assert np.isfinite(each).all()
        np.testing.assert_allclose(ds[name].values, each.mean(axis=0), rtol=1e-12)
        np.testing.assert_allclose(ds[f"{name}_std"].values, each.std(axis=0, ddof=1),
                                   rtol=1e-9)
        assert (ds[f"{name}_min"].values == each.min(axis=0)).all()
        assert (ds[f"{name}_max"].values == each.max(axis=0)).all()
    # different packings give different loss factors (the spread is not zero somewhere)
    assert (ds["loss_factor_std"].values > 0).any()


def test_map_realisations_equal_the_maps_of_their_seeds(tmp_path, cli):
    """A 2 x 2 DEM map of 2 realisations from seed 4: realisation k is the map of seed
    4 + k run on its own; the file and the JSON carry the spread of every cell."""
    out = tmp_path / "r.nc"
    data = _json(cli, *_map_args("8Hz:12Hz:2", "10mm:30mm:2", "--serial", "--out", out,
                                 "--realisations", "2", "--scenario",
                                 _toml(tmp_path, "s4.toml", FAST_MAP.format(seed=4))))
    assert data["statistic"] == "mean" and data["realisations"]["seeds"] == [4, 5]
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        ds = ds.load()
    _check_spread(ds, 2)
    assert ds["seed"].values.tolist() == [4, 5] and json.loads(ds.attrs["seeds"]) == [4, 5]
    assert data["realisations"]["loss_factor"]["std"] == ds["loss_factor_std"].values.tolist()
    for k, seed in enumerate((4, 5)):
        one = tmp_path / f"s{seed}.nc"
        _json(cli, *_map_args("8Hz:12Hz:2", "10mm:30mm:2", "--serial", "--out", one,
                              "--scenario", _toml(tmp_path, f"s{seed}.toml",
                                                  FAST_MAP.format(seed=seed))))
        with xr.open_dataset(one, engine="h5netcdf") as single:
            np.testing.assert_array_equal(ds["loss_factor_realisations"][k].values,
                                          single["loss_factor"].values)
    assert not (tmp_path / "r.nc.partial").exists()


@pytest.mark.long
def test_map_three_realisations_5x7_carry_the_spread_of_every_cell(tmp_path, cli):
    """A 5 x 7 DEM map of 3 realisations on 2 dask workers: every one of the 35 cells has
    its mean, standard deviation, min and max (file and JSON)."""
    out = tmp_path / "m.nc"
    data = _json(cli, *_map_args("6Hz:14Hz:5", "5mm:35mm:7", "--workers", "2", "--out", out,
                                 "--realisations", "3", "--scenario",
                                 _toml(tmp_path, "s.toml", FAST_MAP.format(seed=0))))
    assert data["shape"] == [5, 7] and data["failed"] == 0 and data["computed"] == 3 * 35
    rec = data["realisations"]
    assert rec["count"] == 3 and rec["seeds"] == [0, 1, 2]
    for stat in ("mean", "std", "min", "max"):
        cells = np.array(rec["loss_factor"][stat], dtype=float)
        assert cells.shape == (5, 7) and np.isfinite(cells).all()
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        _check_spread(ds.load(), 3)


def test_map_realisations_input_errors(tmp_path, cli):
    """One line naming realisations: a deterministic model, the lattice, a bad count."""
    lattice = _toml(tmp_path, "l.toml", "[map]\ndem_packing = \"lattice\"\n")
    for args, words in (
            (["map", "--model", "analytic", "--realisations", "2"], "analytic"),
            (_map_args("8Hz:12Hz:2", "10mm:30mm:2", "--realisations", "2", "--scenario",
                       lattice), "lattice"),
            (_map_args("8Hz:12Hz:2", "10mm:30mm:2", "--realisations", "0"), ">= 1"),
            (_map_args("8Hz:12Hz:2", "10mm:30mm:2", "--realisations", "two"), "whole")):
        code, _, err = cli(*args)
        assert code == 2 and err.startswith("error: realisations:"), err
        assert err.count("\n") == 1 and words in err, err


# --------------------------------------------------------------------------- Level III
def _simulate(*args):
    return ["simulate", "--duration", "0.8s", "--at", "0.75s", *args]


@pytest.mark.long
def test_simulate_dem_five_realisations_band_at_0p75s(tmp_path, cli):
    """Level III model 1 (the DEM on the structure), 5 random packings on 2 workers: the
    JSON band of the amplitude at 0.75 s, envelope and damping ratio per amplitude; each
    realisation is the run of its seed alone; the plot draws the band."""
    sc = _toml(tmp_path, "r.toml", RANDOM.format(seed=0))
    plot = tmp_path / "band.png"
    data = _json(cli, *_simulate("--model", "dem", "--realisations", "5", "--workers", "2",
                                 "--plot", plot, "--scenario", sc))
    rec = data["realisations"]
    assert rec["count"] == 5 and rec["seeds"] == [0, 1, 2, 3, 4] and rec["at"] == 0.75
    a = rec["amplitude_at"]
    assert len(a["values"]) == 5 and len(set(a["values"])) == 5  # five packings, five answers
    assert a["min"] < a["mean"] < a["max"] and a["std"] > 0
    assert 0.01 < a["mean"] < 0.058  # decayed from the 58 mm release
    assert math.isclose(a["mean"], np.mean(a["values"]), rel_tol=1e-12)
    # the top-level run is the first realisation (seed 0) and realisation 3 is seed 3 alone
    assert data["final_amplitude"] == rec["final_amplitude"]["values"][0]
    alone = _json(cli, *_simulate("--model", "dem", "--scenario",
                                  _toml(tmp_path, "s3.toml", RANDOM.format(seed=3))))
    assert alone["final_amplitude"] == rec["final_amplitude"]["values"][3]
    env = rec["envelope"]
    i = env["time"].index(min(env["time"], key=lambda t: abs(t - 0.75)))
    assert env["min"][i] <= env["mean"][i] <= env["max"][i]
    assert rec["damping_ratio"] and all(r["min"] <= r["mean"] <= r["max"]
                                        for r in rec["damping_ratio"])
    assert plot.stat().st_size > 10_000


def test_simulate_fields_band_from_a_map_with_realisations(tmp_path, cli):
    """Model 2 from a DEM map of 2 realisations: realisation k of the band is the free
    vibration with the field of the map's realisation k alone."""
    from pdamper.runs.realisations import realisation_map

    out = tmp_path / "m.nc"
    _json(cli, "map", "--model", "dem", "--frequency", "4Hz:7Hz:2", "--amplitude",
          "10mm:60mm:2", "--serial", "--out", out, "--realisations", "2", "--scenario",
          _toml(tmp_path, "s.toml", FAST_MAP.format(seed=2)))
    clamp = _toml(tmp_path, "f.toml", "[fields]\nextrapolation = \"clamp\"\n"
                  "nonstationary = \"use\"\n")
    band = tmp_path / "band.nc"
    data = _json(cli, *_simulate("--model", "fields", "--fields", out, "--realisations", "2",
                                 "--scenario", clamp, "--out", band))
    rec = data["realisations"]
    assert rec["count"] == 2 and rec["map_realisations"] == [0, 1] and "seeds" not in rec
    with xr.open_dataset(band, engine="h5netcdf") as nc:  # the band in the trajectory file
        assert nc.attrs["realisations"] == 2
        assert nc["envelope_max"].values.tolist() == rec["envelope"]["max"]
        assert (nc["displacement_min"] <= nc["displacement_max"]).all()
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        ds = ds.load()
    for k in (0, 1):
        one = tmp_path / f"r{k}.nc"
        realisation_map(ds, k).to_netcdf(one, engine="h5netcdf")
        alone = _json(cli, *_simulate("--model", "fields", "--fields", one, "--scenario",
                                      clamp))
        assert alone["final_amplitude"] == rec["final_amplitude"]["values"][k]
    code, _, err = cli(*_simulate("--model", "fields", "--fields", out, "--realisations", "3",
                                  "--scenario", clamp))
    assert code == 2 and err.startswith("error: realisations:") and "at most the 2" in err


def test_simulate_realisations_input_errors(tmp_path, cli):
    """One line naming the field: no model with realisations, the lattice, a band time
    outside the simulated time."""
    rnd = _toml(tmp_path, "r.toml", RANDOM.format(seed=0))
    for args, field, words in (
            (_simulate("--model", "analytic", "--realisations", "2"), "realisations",
             "must be 1"),
            (_simulate("--model", "dem", "--realisations", "2"), "realisations", "lattice"),
            (_simulate("--model", "dem", "--realisations", "-1", "--scenario", rnd),
             "realisations", ">= 1"),
            (["simulate", "--model", "dem", "--duration", "0.5s", "--at", "0.75s",
              "--realisations", "2", "--scenario", rnd], "optimization.at", "0.5 s")):
        code, _, err = cli(*args)
        assert code == 2 and err.startswith(f"error: {field}:"), err
        assert err.count("\n") == 1 and words in err, err


# --------------------------------------------------------------------------- design studies
def test_optimize_dem_realisations_spread_per_design(tmp_path, cli):
    """``optimize --realisations 2`` (DEM, random packings from seed 7): each design's
    objective is the mean over seeds 7 and 8, each value the study of that seed alone."""
    args = ["optimize", "--model", "dem", "--vary", "particles=16:32:16", "--at", "0.3s",
            "--workers", "0"]
    plot = tmp_path / "landscape.png"
    data = _json(cli, *args, "--realisations", "2", "--plot", plot, "--scenario",
                 _toml(tmp_path, "s7.toml", RANDOM.format(seed=7)))
    assert plot.stat().st_size > 10_000
    assert data["statistic"] == "mean" and data["realisations"]["seeds"] == [7, 8]
    alone = {s: _json(cli, *args, "--scenario", _toml(tmp_path, f"s{s}.toml",
                                                        RANDOM.format(seed=s)))
             for s in (7, 8)}
    for i, c in enumerate(data["candidates"]):
        v = [alone[s]["candidates"][i]["objective"] for s in (7, 8)]
        assert c["objective_values"] == v and v[0] != v[1]
        assert math.isclose(c["objective"], np.mean(v), rel_tol=1e-12)
        assert (c["objective_min"], c["objective_max"]) == (min(v), max(v))
        assert math.isclose(c["objective_std"], abs(v[0] - v[1]) / math.sqrt(2), rel_tol=1e-9)
    code, _, err = cli("optimize", "--realisations", "2")  # the analytical model
    assert code == 2 and err.startswith("error: realisations:") and "analytic" in err
