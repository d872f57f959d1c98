"""The ``pdamper dem`` command."""

from __future__ import annotations

import json
import math

import xarray as xr

from pdamper.cli import main
from pdamper.dem.result import WALL_TIME_KEYS


def test_dem_command_writes_netcdf_and_json(tmp_path, capsys):
    """JSON keys, NetCDF with units and inputs, complex power over the chosen cycles."""
    out = tmp_path / "run.nc"
    rc = main(["dem", "--frequency", "10Hz", "--amplitude", "20mm", "--particles", "16",
               "--cycles", "3", "--skip-cycles", "1", "--out", str(out), "--integrator",
               "verlet", "--restitution-pp", "0.7", "--restitution-pw", "0.8", "--json"])
    assert rc == 0
    data = json.loads(capsys.readouterr().out)
    for key in ("steps", "wall_seconds", "loss_factor", "effective_mass_ratio",
                "energy_balance_error", "seed", "version", "inputs", "max_overlap_ratio",
                "max_impact_velocity"):
        assert key in data
    assert data["steps"] > 1000
    # one meaning per key: the excitation's, the settling's and the whole run's
    # (the model settles through its per-process memo, yet that settling was done for this
    # command: its steps and seconds count in the run's, not reported as reused)
    assert not data["settle_reused"] and data["settle_steps"] > 0 and data["settle_seconds"] > 0
    assert data["steps"] == data["total_steps"] \
        == data["excitation_steps"] + data["settle_steps"]
    assert math.isclose(data["wall_seconds"],
                        data["excitation_wall_seconds"] + data["settle_seconds"])
    assert data["total_wall_seconds"] == data["wall_seconds"]
    assert all(data["units"][k] == "s" for k in WALL_TIME_KEYS)
    assert data["energy_balance_error"] < 0.02
    assert "pdamper_version" not in data  # one version key
    assert data["inputs"]["dem"]["restitution_pp"] == 0.7
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds["force_z"].attrs["units"] == "N"
        assert ds["time"].attrs["units"] == "s"
        assert ds.attrs["seed"] == 0
        assert json.loads(ds.attrs["inputs"])["excitation"]["amplitude"] == 0.02
        assert ds.sizes["time"] == 3 * 400 + 1  # 4 kHz default sample rate at 10 Hz
    assert not list(tmp_path.glob("*.tmp"))


def test_dem_command_vtk_and_random_packing(tmp_path, capsys):
    """Random packing with a seed and ParaView snapshots."""
    rc = main(["dem", "--particles", "8", "--cycles", "2", "--skip-cycles", "1", "--packing",
               "random", "--seed", "4", "--vtk", str(tmp_path / "vtk"), "--snapshot-rate",
               "50Hz", "--json"])
    assert rc == 0
    data = json.loads(capsys.readouterr().out)
    assert data["seed"] == 4
    assert (tmp_path / "vtk" / "particles.pvd").exists()
    assert len(list((tmp_path / "vtk").glob("*.vtp"))) >= 10


def test_dem_command_input_errors(capsys):
    """User errors: one line naming the field, exit status 2."""
    assert main(["dem", "--particles", "500"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: particles.count:") and err.count("\n") == 1
    assert main(["dem", "--amplitude", "3 kg"]) == 2
    assert "amplitude" in capsys.readouterr().err
    assert main(["dem", "--integrator", "rk4"]) == 2
    assert "integrator" in capsys.readouterr().err
    assert main(["dem", "--cycles", "3", "--skip-cycles", "3"]) == 2
    assert "dem.skip_cycles" in capsys.readouterr().err


def test_dem_command_damping_models(capsys):
    """--damping-model tsuji (LIGGGHTS/EDEM 'Hertz with COR') runs and is recorded; the
    fastest impact is reported (m/s)."""
    rc = main(["dem", "--particles", "16", "--cycles", "2", "--skip-cycles", "1",
               "--damping-model", "tsuji", "--json"])
    assert rc == 0
    data = json.loads(capsys.readouterr().out)
    assert data["inputs"]["dem"]["damping_model"] == "tsuji"
    assert data["units"]["max_impact_velocity"] == "m/s"
    assert 0.1 < data["max_impact_velocity"] < 5.0
    assert main(["dem", "--damping-model", "hooke"]) == 2
    assert "damping_model" in capsys.readouterr().err


def test_dem_command_free_flights_on_and_off(tmp_path, capsys):
    """``--no-free-flight`` steps every sphere (stepped_fraction 1, recorded in the inputs);
    the default takes free spheres out of Gear's steps; the scenario key does the same."""
    # 32 spheres: 16 settle into the one locked layer the box floor holds (4 x 4), which
    # flies as a block, every sphere always touching its neighbours
    common = ["dem", "--particles", "32", "--cycles", "2", "--skip-cycles", "1", "--packing",
              "random", "--json"]
    assert main(common + ["--no-free-flight"]) == 0
    off = json.loads(capsys.readouterr().out)
    assert off["stepped_fraction"] == 1.0
    assert off["inputs"]["dem"]["gear_free_flight"] is False
    assert main(common) == 0
    on = json.loads(capsys.readouterr().out)
    assert on["stepped_fraction"] < 0.9
    assert on["inputs"]["dem"]["gear_free_flight"] is True
    sc = tmp_path / "s.toml"
    sc.write_text("[dem]\ngear_free_flight = false\n")
    assert main(common + ["--scenario", str(sc)]) == 0
    assert json.loads(capsys.readouterr().out)["stepped_fraction"] == 1.0


# -- a COR table in the scenario reaches the DEM kernels
COR_TABLE = "velocity [m/s], cor [-], std [-]\n0.20, 0.89, 0.01\n0.60, 0.86, 0.01\n1.80, 0.80, 0.02\n"
#: A table whose COR is 0.5 at every speed: the kernels must see the constant 0.5.
FLAT_TABLE = "velocity [m/s], cor [-]\n0.1, 0.5\n1.0, 0.5\n3.0, 0.5\n"


def _dem_json(cli, *args):
    code, out, err = cli("dem", "--particles", "4", "--cycles", "3", "--skip-cycles", "1",
                         "--integrator", "verlet", *args, "--json")
    assert code == 0, err
    return json.loads(out)


def test_dem_runs_with_a_cor_table_in_the_scenario(tmp_path, cli):
    """``particle_wall = { model = "table", file = ... }`` (docs/restitution.md): the run
    ends, and a flat table gives to the bit the run of the constant it holds."""
    (tmp_path / "cor.csv").write_text(COR_TABLE)
    (tmp_path / "flat.csv").write_text(FLAT_TABLE)
    for name, entry in (("table", '{ model = "table", file = "cor.csv" }'),
                        ("flat", '{ model = "table", file = "flat.csv" }'),
                        ("constant", "0.5")):
        (tmp_path / f"{name}.toml").write_text(
            f"[restitution]\nparticle_wall = {entry}\nparticle_particle = {entry}\n")
    table = _dem_json(cli, "--scenario", tmp_path / "table.toml")
    assert math.isfinite(table["loss_factor"]) and table["energy_balance_error"] < 0.02
    assert table["inputs"]["restitution"]["particle_wall"]["model"] == "table"
    flat = _dem_json(cli, "--scenario", tmp_path / "flat.toml")
    constant = _dem_json(cli, "--scenario", tmp_path / "constant.toml")
    default = _dem_json(cli)
    assert flat["loss_factor"] == constant["loss_factor"] and flat["steps"] == constant["steps"]
    assert flat["loss_factor"] != default["loss_factor"]  # 0.6 / 0.85 without the table


_SHORT = ["dem", "--particles", "16", "--cycles", "3", "--skip-cycles", "1", "--packing",
          "random", "--json"]


def _run(capsys, *args):
    assert main([*_SHORT, *args]) == 0
    return json.loads(capsys.readouterr().out)


def test_dem_realisations_equal_separately_run_seeds(capsys):
    """``--realisations 3`` from seed 5: the mean and spread of three separate runs of seeds
    5, 6, 7 (to round-off); the top-level loss factor and mass ratio are the mean."""
    import numpy as np

    data = _run(capsys, "--seed", "5", "--realisations", "3", "--serial")
    rec = data["realisations"]
    assert rec["count"] == 3 and rec["seeds"] == [5, 6, 7]
    assert data["seed"] == 5 and data["statistic"] == "mean"
    single = [_run(capsys, "--seed", str(k)) for k in (5, 6, 7)]
    for key in ("loss_factor", "effective_mass_ratio"):
        v = np.array([s[key] for s in single])
        assert len(set(v.tolist())) == 3  # three different packings, three answers
        st = rec[key]
        assert np.allclose(st["values"], v, rtol=1e-12, atol=0)
        assert math.isclose(st["mean"], v.mean(), rel_tol=1e-12)
        assert math.isclose(st["std"], v.std(ddof=1), rel_tol=1e-9)
        assert (st["min"], st["max"]) == (v.min(), v.max())
        assert st["min"] <= st["mean"] <= st["max"]
        assert math.isclose(data[key], v.mean(), rel_tol=1e-12)
    # the other run keys are those of the first realisation
    assert data["steps"] == single[0]["steps"]


def test_dem_realisations_on_workers_equal_serial(capsys):
    """The dask workers give the same numbers as the serial path."""
    serial = _run(capsys, "--realisations", "2", "--serial")["realisations"]
    parallel = _run(capsys, "--realisations", "2", "--workers", "2")["realisations"]
    assert parallel["workers"] == 2
    for key in ("loss_factor", "effective_mass_ratio"):
        assert parallel[key]["values"] == serial[key]["values"]
        assert parallel[key]["std"] == serial[key]["std"]


def test_dem_one_realisation_is_the_single_run(capsys):
    """``--realisations 1`` is the run without the option, key for key."""
    plain = _run(capsys)
    one = _run(capsys, "--realisations", "1")
    for d in (plain, one):
        for key in WALL_TIME_KEYS:  # the only keys two runs differ in
            d.pop(key)
    assert one == plain and "realisations" not in one


def test_dem_realisations_input_errors(capsys):
    """Bad counts, the lattice and one-run outputs: one line naming realisations."""
    base = ["dem", "--particles", "16", "--cycles", "3", "--skip-cycles", "1"]
    for bad, words in ((["--realisations", "0"], ">= 1"), (["--realisations=-2"], ">= 1"),
                       (["--realisations", "2.5"], "whole number"),
                       (["--realisations", "many"], "whole number"),
                       (["--realisations", "100000000", "--packing", "random"], "fewer"),
                       (["--realisations", "3", "--packing", "lattice"], "lattice"),
                       (["--realisations", "2", "--packing", "random", "--out", "x.nc"],
                        "--out")):
        assert main([*base, *bad]) == 2, bad
        err = capsys.readouterr().err
        assert err.startswith("error: realisations:") and err.count("\n") == 1, err
        assert words in err, err


def test_a_fresh_process_counts_its_settling_in_the_dem_json(tmp_path):
    """``pdamper dem --json`` in a process of its own (as a user runs it): the settling
    done for the run counts in ``steps`` and ``wall_seconds`` and is not reported as
    reused, although the model settles first through its per-process memo."""
    import os
    import subprocess
    import sys

    out = subprocess.run(
        [sys.executable, "-m", "pdamper", "dem", "--frequency", "20Hz", "--amplitude",
         "10mm", "--particles", "8", "--cycles", "2", "--skip-cycles", "1", "--integrator",
         "verlet", "--json"],
        capture_output=True, text=True, check=True, env={**os.environ}, timeout=600)
    data = json.loads(out.stdout)
    settling = data["settling"]
    assert not settling["reused"] and not data["settle_reused"]
    assert settling["steps"] == data["settle_steps"] > 0
    assert settling["wall_seconds"] == data["settle_seconds"] > 0
    assert settling["simulated_time"] > 0 and settling["stop"] in ("time", "at rest")
    assert data["steps"] == data["excitation_steps"] + settling["steps"]
    assert math.isclose(data["wall_seconds"],
                        data["excitation_wall_seconds"] + settling["wall_seconds"])
