"""``pdamper map``: grids with units and log spacing, a particle-count axis, the DEM on
dask.distributed, resume from <out>.partial/, failed points in ``status``."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

FAST_DEM = "[dem]\ncycles = 3\nskip_cycles = 1\npacking = \"random\"\nseed = 1\n"


@pytest.fixture
def fast_dem(tmp_path):
    p = tmp_path / "fast.toml"
    p.write_text(FAST_DEM)
    return p


def test_analytic_particle_axis_and_log_spacing(tmp_path, cli):
    out = tmp_path / "a.nc"
    code, stdout, _ = cli("map", "--particles", "16:96:6", "--amplitude", "log:1mm:100mm:3",
                          "--frequency", "5Hz:20Hz:4", "--out", out, "--json")
    assert code == 0
    d = json.loads(stdout)
    assert d["dims"] == ["particles", "frequency", "amplitude"] and d["shape"] == [6, 4, 3]
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds["particles"].values.tolist() == [16, 32, 48, 64, 80, 96]
        assert ds["amplitude"].values == pytest.approx([0.001, 0.01, 0.1])
        assert (ds["status"] == 0).all() and (ds["stationary"] == 1).all()
        assert json.loads(ds.attrs["inputs"])["map"]["particles"] == "16:96:6"
    assert not (tmp_path / "a.nc.partial").exists()


@pytest.mark.parametrize(("args", "field"), [
    (["--particles", "16:90:6"], "map.particles"),  # 16, 30.8, ...: not whole
    (["--particles", "100:300:3"], "map.particles"),  # more than fit
    (["--particles", "many"], "particles"),
    (["--amplitude", "log:0mm:10mm:3"], "map.amplitude"),
    (["--workers", "0", "--model", "dem"], "workers"),
])
def test_bad_grids_name_the_field(tmp_path, cli, args, field):
    code, _, err = cli("map", *args, "--out", tmp_path / "m.nc")
    assert code == 2 and err.startswith(f"error: {field}")
    assert not list(tmp_path.iterdir())


def test_dem_map_on_a_local_cluster(tmp_path, cli, fast_dem):
    """The DEM point by point on dask.distributed (2 worker processes), with the
    variables, diagnostics and attributes the issue names."""
    out = tmp_path / "d.nc"
    code, stdout, err = cli("map", "--model", "dem", "--scenario", fast_dem, "--frequency",
                            "8Hz:12Hz:2", "--amplitude", "20mm:40mm:2", "--workers", "2",
                            "--out", out, "--json")
    assert code == 0, err
    d = json.loads(stdout)
    assert d["workers"] == 2 and d["computed"] == 4 and d["failed"] == 0
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        for v in ("loss_factor", "effective_mass_ratio", "dissipated_energy_per_cycle",
                  "motion_mode", "stationary", "status", "error", "wall_seconds", "steps",
                  "energy_balance_error", "max_overlap_ratio", "max_impact_velocity",
                  "cycles"):
            assert v in ds, v
        assert ds["wall_seconds"].attrs["units"] == "s" and (ds["cycles"] == 3).all()
        assert ds["max_impact_velocity"].attrs["units"] == "m s-1"
        assert (ds["max_impact_velocity"] > 0).all()
        assert (ds["motion_mode"] >= 0).all() and (ds["status"] == 0).all()
        assert ds.attrs["seed"] == 1 and ds.attrs["pdamper_version"]
        assert json.loads(ds.attrs["inputs"])["dem"]["cycles"] == 3
        assert ds.attrs["map_key"]


@pytest.mark.long
def test_dem_map_spans_16_to_192_spheres(tmp_path, cli):
    """A DEM map over the particle count of the benchmark damper runs at
    every count with the map's default packing ("auto": random up to where random addition
    jams, about 103 spheres here; the full container of 192 from the lattice)."""
    out = tmp_path / "n.nc"
    scenario = tmp_path / "s.toml"
    # two cycles (one averaged): the map runs at every count, not a steady-state study
    scenario.write_text("[dem]\ncycles = 2\nskip_cycles = 1\nseed = 1\n")
    code, _, err = cli("map", "--model", "dem", "--scenario", scenario, "--particles",
                       "16:192:2", "--frequency", "20Hz", "--amplitude", "32mm", "--serial",
                       "--out", out)
    assert code == 0, err
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds["particles"].values.tolist() == [16, 192]
        assert (ds["status"] == 0).all(), ds["error"].values
        assert ds["random_packing"].values.ravel().tolist() == [1, 0]
        assert ds.attrs["packing"] == "auto"
        assert (ds["energy_balance_error"] < 0.01).all()
        # free flights: the jammed full container leaves no sphere out of its steps (16
        # random spheres may settle into the 4 x 4 layer the floor holds exactly, which flies
        # as one block touching the side walls, or not: free flights of random beds are
        # tested on 32 spheres, tests/dem)
        frac = ds["stepped_fraction"].values.ravel()
        assert ds["stepped_fraction"].attrs["units"] == "1"
        assert 0.0 < frac[0] <= 1.0 and frac[1] > 0.9


def test_dem_map_resumes_from_its_partial_points(tmp_path, cli, fast_dem):
    """Lose two of four finished points: the rerun computes those two only and ends with
    the same map (wall times aside, which are measurements)."""
    out = tmp_path / "d.nc"
    args = ("map", "--model", "dem", "--scenario", fast_dem, "--frequency", "8Hz:12Hz:2",
            "--amplitude", "20mm:40mm:2", "--serial", "--out", out, "--json")
    assert cli(*args, "--keep-partial")[0] == 0
    first = xr.open_dataset(out, engine="h5netcdf").load()
    part = tmp_path / "d.nc.partial"
    files = sorted(part.iterdir())
    assert len(files) == 4
    for p in files[:2]:
        p.unlink()
    code, stdout, _ = cli(*args)
    d = json.loads(stdout)
    assert code == 0 and d["computed"] == 2 and d["reused"] == 2
    assert not part.exists()  # removed once the map is complete
    second = xr.open_dataset(out, engine="h5netcdf").load()
    skip = {"wall_seconds", "point_seconds"}
    for v in first.data_vars:
        if v not in skip:
            np.testing.assert_array_equal(first[v].values, second[v].values, err_msg=v)


def test_failed_dem_points_end_in_status_not_in_an_error(tmp_path, cli):
    """An unstable DEM setting (Verlet at 0.9 contact times per step) fails at every
    point: the map still ends, every point is recorded as failed with its error."""
    sc = tmp_path / "bad.toml"
    sc.write_text('[dem]\nintegrator = "verlet"\nsafety = 0.9\ncycles = 2\nskip_cycles = 1\n')
    out = tmp_path / "f.nc"
    code, stdout, _ = cli("map", "--model", "dem", "--scenario", sc, "--frequency",
                          "20Hz", "--amplitude", "100mm:150mm:2", "--serial",
                          "--out", out, "--json")
    assert code == 0 and json.loads(stdout)["failed"] == 2
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert (ds["status"] == 1).all() and np.isnan(ds["loss_factor"]).all()
        assert all(e.startswith("SimulationError: unstable DEM run")
                   for e in ds["error"].values.ravel())
        assert (ds["attempts"] == 1).all()  # deterministic: not retried


def test_dem_map_with_a_cor_table_in_the_scenario(tmp_path, cli):
    """A 2 x 2 DEM map whose curves come from a COR table (the curve crosses to the worker
    processes and keys the settled beds): every point computed, and a table that holds 0.5
    at every speed gives the map of the constant 0.5 (run in this process)."""
    (tmp_path / "flat.csv").write_text("velocity [m/s], cor [-]\n0.1, 0.5\n1.0, 0.5\n3.0, 0.5\n")
    dem = "[dem]\ncycles = 2\nskip_cycles = 1\nintegrator = \"verlet\"\n[particles]\ncount = 4\n"
    (tmp_path / "table.toml").write_text(
        dem + '[restitution]\nparticle_wall = { model = "table", file = "flat.csv" }\n'
        'particle_particle = { model = "table", file = "flat.csv" }\n')
    (tmp_path / "constant.toml").write_text(
        dem + "[restitution]\nparticle_wall = 0.5\nparticle_particle = 0.5\n")
    grid = ("--frequency", "10Hz:15Hz:2", "--amplitude", "5mm:10mm:2")
    maps = {}
    for name, how in (("table", ("--workers", "2")), ("constant", ("--serial",))):
        out = tmp_path / f"{name}.nc"
        code, stdout, err = cli("map", "--model", "dem", *grid, *how, "--scenario",
                                tmp_path / f"{name}.toml", "--out", out, "--json")
        assert code == 0, err
        d = json.loads(stdout)
        assert d["computed"] == 4 and d["failed"] == 0, d
        with xr.open_dataset(out, engine="h5netcdf") as ds:
            assert (ds["status"] == 0).all()
            maps[name] = ds["loss_factor"].values
    assert np.isfinite(maps["table"]).all()
    np.testing.assert_array_equal(maps["table"], maps["constant"])
