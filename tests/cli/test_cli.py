"""The ``pdamper`` command line: JSON interfaces, NetCDF output, one-line errors."""

import json

import pytest


@pytest.fixture
def run(cli):
    """``run(capsys, *args)`` of the older tests, on the shared ``cli`` fixture."""
    return lambda _capsys, *args: cli(*args)


def test_analytic_json_keys_and_values(capsys, run):
    code, out, _ = run(capsys, "analytic", "--frequency", "10Hz", "--amplitude", "32mm",
                       "--particles", "32", "--json")
    assert code == 0
    d = json.loads(out)
    for key in ("mode", "loss_factor", "dissipated_energy_per_cycle", "effective_mass_ratio",
                "clearance", "optimal_stroke"):
        assert key in d
    assert d["mode"] == "double_cac_harmonic"
    assert d["clearance"] == pytest.approx(0.1)
    assert d["optimal_stroke"] == pytest.approx(0.1 / 3.141592653589793)
    assert 1.0 < d["loss_factor"] < 4 / 3.141592653589793
    assert d["version"] and d["inputs"]["excitation"]["frequency"] == 10.0


def test_analytic_human_output_echoes_units(capsys, run):
    code, out, _ = run(capsys, "analytic", "--frequency", "6 Hz", "--amplitude", "1.5 cm")
    assert code == 0
    assert "f = 6 Hz, X = 15 mm" in out and "single CaC, harmonic" in out


def test_map_writes_netcdf_with_units(tmp_path, capsys, run):
    import xarray as xr

    path = tmp_path / "map.nc"
    code, out, _ = run(capsys, "map", "--model", "analytic", "--frequency", "2Hz:20Hz:14",
                       "--amplitude", "1mm:200mm:24", "--particles", "32", "--out", str(path),
                       "--json")
    assert code == 0
    ds = xr.open_dataset(path, engine="h5netcdf")
    assert dict(ds.sizes) == {"frequency": 14, "amplitude": 24}
    for v in ("loss_factor", "effective_mass_ratio", "dissipated_energy_per_cycle",
              "motion_mode"):
        assert v in ds
    assert ds["frequency"].attrs["units"] == "Hz" and ds["amplitude"].attrs["units"] == "m"
    assert ds["dissipated_energy_per_cycle"].attrs["units"] == "J"
    assert "flag_meanings" in ds["motion_mode"].attrs
    assert float(ds["loss_factor"].max()) == pytest.approx(json.loads(out)["max_loss_factor"])
    ds.close()


def test_simulate_json(capsys, run):
    code, out, _ = run(capsys, "simulate", "--damper", "analytic", "--particles", "32",
                       "--duration", "2s", "--json")
    assert code == 0
    d = json.loads(out)
    assert {"time", "amplitude"} <= set(d["peaks"][0])
    assert {"amplitude", "zeta"} <= set(d["damping_ratio"][0])
    assert d["peaks"][0]["amplitude"] == pytest.approx(0.058)
    assert d["final_amplitude"] == pytest.approx(d["peaks"][-1]["amplitude"])
    assert len(d["damping_ratio"]) == len(d["peaks"]) - 1


def test_optimize_json_lists_every_candidate(capsys, run):
    code, out, _ = run(capsys, "optimize", "--damper", "analytic", "--at", "0.8s", "--json")
    assert code == 0
    d = json.loads(out)
    assert {"particles", "mass", "objective"} <= set(d["best"])
    assert len(d["candidates"]) == 12
    assert d["best"]["objective"] == min(c["objective"] for c in d["candidates"])


def test_example_scenario_round_trips_through_every_command(tmp_path, capsys, run):
    code, out, _ = run(capsys, "example-scenario")
    assert code == 0 and "[particles]" in out
    p = tmp_path / "s.toml"
    p.write_text(out)
    code, out, _ = run(capsys, "analytic", "--scenario", str(p), "--json")
    assert code == 0 and json.loads(out)["mode"] == "double_cac_harmonic"


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["analytic", "--particles", "300"], "particles.count"),
        (["analytic", "--particles", "-3"], "particles.count"),
        (["analytic", "--frequency", "0Hz"], "excitation.frequency"),
        (["analytic", "--amplitude", "-3mm"], "excitation.amplitude"),
        (["analytic", "--frequency", "10 furlongs"], "excitation.frequency"),
        (["map", "--frequency", "2Hz:20Hz"], "map.frequency"),
        (["simulate", "--duration", "-1s"], "simulation.duration"),
        (["simulate", "--damper", "quantum"], "simulation.model"),
        (["simulate", "--model", "quantum"], "simulation.model"),
        (["optimize", "--at", "0s"], "optimization.at"),
    ],
)
def test_bad_input_exits_nonzero_with_one_line(capsys, args, field, run):
    code, out, err = run(capsys, *args)
    assert code == 2
    assert err.count("\n") == 1 and err.startswith(f"error: {field}")
    assert out == ""


def test_malformed_scenario_file(tmp_path, capsys, run):
    p = tmp_path / "bad.toml"
    p.write_text("[particles\ncount = 3")
    code, _, err = run(capsys, "analytic", "--scenario", str(p))
    assert code == 2 and err.startswith("error: scenario: malformed TOML")


def test_failed_map_leaves_no_file(tmp_path, capsys, run):
    path = tmp_path / "map.nc"
    code, _, _ = run(capsys, "map", "--amplitude", "-1mm:2mm:3", "--out", str(path))
    assert code == 2 and not path.exists()


@pytest.mark.long
@pytest.mark.filterwarnings("error:constrained_layout not applied:UserWarning")
def test_paper_main_job_writes_figures_and_table(tmp_path, capsys, run):
    """`pdamper paper --out DIR`: Figs. 3, 4, 5, 7, 8, 9, the maps and the table; the DEM
    map (a reduced 2 x 2 grid here) is cached in DIR: a rerun does not recompute it."""
    out_dir = tmp_path / "paper"
    sc = tmp_path / "s.toml"
    sc.write_text('[map]\nfrequency = "2Hz:20Hz:7"\namplitude = "2mm:200mm:9"\n'
                  'dem_frequency = "6Hz:10Hz:2"\ndem_amplitude = "15mm:32mm:2"\n'
                  '[dem]\ncycles = 4\nskip_cycles = 1\n')
    code, out, _ = run(capsys, "paper", "--out", str(out_dir), "--scenario", str(sc),
                       "--workers", "2", "--json")
    assert code == 0
    names = {p.name for p in out_dir.iterdir()}
    for n in ("fig4_trajectories.png", "fig5a_motion_modes.png", "fig5c_loss_factor.png",
              "fig7_trajectory.png", "fig8_damping_ratio.png", "fig9_optimization.png",
              "results.md", "results.json", "fig5_analytic_map.nc", "fig5_dem_map.nc",
              "fig5_dem_vs_analytic.png", "fig5_dem_minus_analytic.png", "fig3_snapshots.png"):
        assert n in names
    table = json.loads((out_dir / "results.json").read_text())
    rows = {r["quantity"]: r for r in table["rows"]}
    assert all(rows[q]["agrees"] for q in rows if q.startswith("Fig. 4"))
    assert "| quantity | paper | pdamper |" in (out_dir / "results.md").read_text()
    assert not any(n.startswith(".") or n.endswith(".partial") for n in names)
    assert table["dem_map"]["shape"] == [2, 2] and not table["dem_map"]["cached"]
    assert len(table["rows"]) == len(table["paper_reported"])  # every row, DEM ones too
    assert "steady DEM cells of the 2 x 2 DEM map" in rows
    stamp = (out_dir / "fig5_dem_map.nc").stat().st_mtime_ns
    code, _, _ = run(capsys, "paper", "--out", str(out_dir), "--scenario", str(sc), "--json")
    assert code == 0 and json.loads((out_dir / "results.json").read_text())["dem_map"]["cached"]
    assert (out_dir / "fig5_dem_map.nc").stat().st_mtime_ns == stamp


@pytest.mark.parametrize("args", [["analytic", "--frequency"], ["analytic", "--bogus"],
                                  ["nonsense"]])
def test_usage_errors_are_one_line(capsys, args, run):
    code, out, err = run(capsys, *args)
    assert code == 2
    assert err.startswith("error: ") and err.count("\n") == 1 and "Traceback" not in err


def test_runaway_duration_is_refused(capsys, run):
    code, _, err = run(capsys, "simulate", "--duration", "1e6 s")
    assert code == 2 and err.startswith("error: simulation.duration")
