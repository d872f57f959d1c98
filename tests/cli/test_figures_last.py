"""No result lost to a figure: every design objective draws its landscape (``optimize --plot``
and ``pdamper report``), and a figure that fails leaves the results written before it (JSON,
NetCDF, results.json) and ends with one line, status 1."""

from __future__ import annotations

import json
import math

import pytest

from pdamper.design.study import OBJECTIVES

#: A force history of 2 N at 5 Hz over 2 s (the load of ``peak`` and ``rms``).
_FORCE = "time [s], force [N]\n" + "".join(
    f"{k * 5e-3:.3f}, {2 * math.sin(2 * math.pi * 5 * k * 5e-3):.5f}\n" for k in range(401))
#: Tiny studies: two designs, three frequencies of the band.
_VARY = "particles=0:32:32"
_BAND = "4Hz:7Hz:3"


def _objective_args(objective: str, tmp_path) -> list[str]:
    if objective in ("peak", "rms"):
        (tmp_path / "force.csv").write_text(_FORCE)
        return ["--load", str(tmp_path / "force.csv")]
    if objective in ("peak-frf", "rms-frf"):
        return ["--band", _BAND]
    return []


def _scenario(objective: str, tmp_path) -> str:
    text = f'[optimization]\nobjective = "{objective}"\nvary = ["{_VARY}"]\n'
    if objective in ("peak", "rms"):
        (tmp_path / "force.csv").write_text(_FORCE)
        text += '[load]\nforce = "force.csv"\n'
    if objective in ("peak-frf", "rms-frf"):
        text += f'band = "{_BAND}"\n'
    path = tmp_path / "study.toml"
    path.write_text(text)
    return str(path)


def test_every_objective_has_a_label():
    from pdamper.design.study import OBJECTIVE_LABELS

    assert set(OBJECTIVE_LABELS) == set(OBJECTIVES)


@pytest.mark.parametrize("objective", sorted(OBJECTIVES))
def test_optimize_plot_every_objective(cli, tmp_path, objective):
    plot = tmp_path / "landscape.png"
    code, out, err = cli("optimize", "--objective", objective, "--vary", _VARY,
                         *_objective_args(objective, tmp_path), "--plot", plot, "--json")
    assert code == 0, err
    assert json.loads(out)["objective_name"] == objective
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("objective", sorted(OBJECTIVES))
def test_report_every_objective(cli, tmp_path, objective):
    out_dir = tmp_path / "report"
    code, out, err = cli("report", "--scenario", _scenario(objective, tmp_path), "--out",
                         out_dir, "--json")
    assert code == 0, err
    assert "design_landscape" in json.loads(out)["figures"]
    results = json.loads((out_dir / "results.json").read_text())
    assert results["design_study"]["objective_name"] == objective
    assert [c["status"] for c in results["design_study"]["candidates"]] == ["ok", "ok"]
    assert "could not be drawn" not in (out_dir / "report.html").read_text()


def _broken(*_args, **_kwargs):
    raise RuntimeError("a broken figure writer")


def _one_error_line(err: str, field: str) -> None:
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"error: {field}: ") and "could not be drawn" in lines[0]
    assert "Traceback" not in err


def test_optimize_figure_fails_after_the_study(cli, tmp_path, monkeypatch):
    import pdamper.plots

    monkeypatch.setattr(pdamper.plots, "plot_design_landscape", _broken)
    code, out, err = cli("optimize", "--objective", "peak-frf", "--band", _BAND, "--vary",
                         _VARY, "--plot", tmp_path / "x.png", "--json")
    assert code == 1
    _one_error_line(err, "plot")
    study = json.loads(out)  # complete: the whole study was printed before the figure
    assert [c["particles"] for c in study["candidates"]] == [0, 32]
    assert study["best"]["particles"] == 32
    assert not (tmp_path / "x.png").exists()


def test_frf_figure_fails_after_json_and_netcdf(cli, tmp_path, monkeypatch):
    import xarray as xr

    import pdamper.plots.frf

    monkeypatch.setattr(pdamper.plots.frf, "plot_frf", _broken)
    nc = tmp_path / "frf.nc"
    code, out, err = cli("frf", "--frequency", "5Hz:6Hz:3", "--sweep", "up", "--out", nc,
                         "--plot", tmp_path / "frf.png", "--json")
    assert code == 1
    _one_error_line(err, "plot")
    payload = json.loads(out)
    with xr.open_dataset(nc) as ds:
        assert ds.sizes["frequency"] == 3
        assert len(payload["points"]) == 3
    assert not (tmp_path / "frf.png").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]


def test_simulate_figure_fails_after_json_and_netcdf(cli, tmp_path, monkeypatch):
    import xarray as xr

    import pdamper.plots

    monkeypatch.setattr(pdamper.plots, "plot_model_trajectories", _broken)
    nc = tmp_path / "run.nc"
    code, out, err = cli("simulate", "--duration", "0.5s", "--out", nc, "--plot",
                         tmp_path / "run.png", "--json")
    assert code == 1
    _one_error_line(err, "plot")
    assert json.loads(out)["final_amplitude"] > 0
    with xr.open_dataset(nc) as ds:
        assert float(ds["time"][-1]) == pytest.approx(0.5, abs=0.01)


def test_report_figure_fails_leaves_the_results(cli, tmp_path, monkeypatch):
    import pdamper.plots

    monkeypatch.setattr(pdamper.plots, "plot_design_landscape", _broken)
    out_dir = tmp_path / "report"
    code, out, err = cli("report", "--scenario", _scenario("peak-frf", tmp_path), "--out",
                         out_dir)
    assert code == 1
    _one_error_line(err, "out")
    assert "design_landscape" in err
    results = json.loads((out_dir / "results.json").read_text())
    assert [c["particles"] for c in results["design_study"]["candidates"]] == [0, 32]
    assert results["figure_errors"] == {"design_landscape": "RuntimeError: a broken figure "
                                                            "writer"}
    assert "free_decay" in results["figures"]  # the other figures stand
    page = (out_dir / "report.html").read_text()
    assert "The figure design_landscape could not be drawn" in page
