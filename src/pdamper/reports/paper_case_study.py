"""The reference paper's case study written out: figures, maps, the comparison table and
one page with all of it.

The study itself, each reported number of the paper next to ours, is computed by
:func:`pdamper.runs.paper_case_study.run_case_study`; :func:`write_case_study` writes the
figures (PNG), the maps (NetCDF), the comparison table (Markdown and JSON) and
``report.html``, one self-contained page with all of it (:mod:`pdamper.reports.html`).
"""

from __future__ import annotations

import io
import json
import math
from collections.abc import Callable, Iterator
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from pdamper.analysis.modes import MotionMode
from pdamper.contact.restitution import RestitutionCurve
from pdamper.coupling import FreeVibrationResult
from pdamper.files import atomic_write_bytes, atomic_write_netcdf, atomic_write_text
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.reports.html import ReportFigure, render_report
from pdamper.runs.paper_case_study import (
    DEM_MAP_FILE,
    CaseStudy,
    Row,
    _cor_curves,
    _cor_text,
    _need,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from xarray import Dataset



def _markdown(rows: list[Row]) -> str:
    mark = {True: "yes", False: "**no**", None: ""}
    lines = ["| quantity | paper | pdamper | agrees | source | note |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {r.quantity} | {r.paper} | {r.ours} | {mark[r.agrees]} | {r.source} | {r.note} |"
              for r in rows]
    return "\n".join(lines) + "\n"


def _dem_runs(cs: CaseStudy) -> list[tuple[str, FreeVibrationResult]]:
    """The DEM (model 1) runs with their labels: the paper's curves and the scenario's COR."""
    runs = []
    if cs.run_dem_curves is not None:
        runs.append(("DEM (model 1), paper's COR curves", cs.run_dem_curves))
    if cs.run_dem is not None and cs.run_dem is not cs.run_dem_curves:
        runs.append((f"DEM (model 1), {_cor_text(_need(cs.damper, 'damper'))}", cs.run_dem))
    return runs


def _fig2(cs: CaseStudy) -> Figure:
    """Fig. 2: material table (left) and COR curves (right), with the single DEM impacts."""
    from matplotlib.figure import Figure

    from pdamper import plots

    d = _need(cs.damper, "damper")
    pp, pw = _cor_curves(d)
    fig = Figure(figsize=(12, 4.5), layout="constrained")
    a1, a2 = fig.subplots(1, 2, width_ratios=(1, 1.5))
    plots.plot_material_table({"sphere": d.particle_material, "wall": d.wall_material}, ax=a1,
                              friction=d.friction)
    a1.set_title("Fig. 2-left: material data (scenario)", fontsize="medium")
    curves: list[tuple[str, RestitutionCurve]] = [
        ("sphere-sphere, paper (reconstructed)", paper.PAPER_COR_PP),
        ("sphere-wall, paper (reconstructed)", paper.PAPER_COR_PW)]
    styles = ["-", "-"]
    if (pp, pw) != (paper.PAPER_COR_PP, paper.PAPER_COR_PW):
        curves += [(f"sphere-sphere, scenario: {pp.describe()}", pp),
                   (f"sphere-wall, scenario: {pw.describe()}", pw)]
        styles += ["--", "--"]
    points = {f"DEM single impacts, {c.pair}": (c.velocity, c.cor_simulated)
              for c in cs.cor_checks}
    plots.plot_restitution_curves(curves, ax=a2, styles=styles, points=points)
    a2.axvline(paper.PAPER_COR_MAX_VELOCITY, color="k", ls=":", lw=1)
    a2.set_title("Fig. 2-right: COR over impact velocity", fontsize="medium")
    return fig


def _figures(cs: CaseStudy) -> Iterator[tuple[str, Figure]]:
    """The case study's figures as ``(file name, matplotlib Figure)``; no pyplot state."""
    from matplotlib.figure import Figure

    from pdamper import plots

    yield "fig2_materials_cor.png", _fig2(cs)
    fig = Figure(figsize=(13, 7), layout="constrained")
    axes = fig.subplots(2, 3)
    for ax, (case, tr) in zip(axes.ravel(), cs.trajectories, strict=True):
        plots.plot_bed_trajectory(tr, ax=ax)
        f = float(tr.response.frequency)
        x = float(tr.response.amplitude)
        ax.set_title(f"{case}: X = {x * 1e3:g} mm, f = {f:g} Hz", fontsize="medium")
    yield "fig4_trajectories.png", fig
    field_map = _need(cs.field_map, "analytical map")
    run_32, run_empty = _need(cs.run_32, "model 3 run"), _need(cs.run_empty, "empty run")
    n = field_map.attrs.get("particle_count", "")
    fig = Figure(figsize=(7, 5), layout="constrained")
    ax = plots.plot_mode_map(field_map, ax=fig.subplots())
    ax.set_title(f"Fig. 5a: motion modes (analytical), {n} spheres")
    yield "fig5a_motion_modes.png", fig
    fig = Figure(figsize=(7, 5), layout="constrained")
    ax = plots.plot_loss_factor_map(field_map, ax=fig.subplots())
    ax.set_title(f"Fig. 5c: effective loss factor (analytical), {n} spheres")
    yield "fig5c_loss_factor.png", fig
    if cs.dem_map is not None:
        yield from _dem_figures(cs, n)
    fig = Figure(figsize=(9, 4), layout="constrained")
    ax = fig.subplots()
    plots.plot_free_vibration(run_32, ax=ax, label=f"analytical (model 3), {n} spheres",
                              envelope=run_empty)
    if cs.run_fields is not None:
        plots.plot_free_vibration(cs.run_fields, ax=ax,
                                  label=f"effective fields (model 2, {cs.fields_source})")
    for label, run in _dem_runs(cs):
        plots.plot_free_vibration(run, ax=ax, label=f"{label}, {n} spheres")
    if cs.dem_band is not None:
        plots.plot_trajectory_band(cs.dem_band, ax=ax,
                                   label=f"DEM (model 1), random packings, {n} spheres")
    ax.set_title("Fig. 7: end-effector trajectory, damper models 1-3")
    yield "fig7_trajectory.png", fig
    fig = Figure(figsize=(6, 4), layout="constrained")
    ax = fig.subplots()
    plots.plot_damping_ratio(run_32, ax=ax, label=f"analytical (model 3), {n} spheres")
    if cs.run_fields is not None:
        plots.plot_damping_ratio(cs.run_fields, ax=ax, label="effective fields (model 2)")
    for label, run in _dem_runs(cs):
        plots.plot_damping_ratio(run, ax=ax, label=f"{label}, {n} spheres")
    if cs.dem_band is not None:
        plots.plot_damping_ratio_band(cs.dem_band, ax=ax,
                                      label=f"DEM (model 1), random packings, {n} spheres")
    ax.set_title("Fig. 8: damping ratio, damper models 1-3")
    yield "fig8_damping_ratio.png", fig
    fig = Figure(figsize=(12, 4), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    plots.plot_optimization(_need(cs.optimization, "optimisation"), ax=a1)
    a1.set_title("Sect. 4.2.2: objective landscape")
    plots.plot_free_vibration(_need(cs.run_best, "paper optimum's run"), ax=a2,
                              label=f"analytical, {cs.best_count} spheres", envelope=run_empty)
    a2.set_title("Fig. 9: optimised damper")
    yield "fig9_optimization.png", fig


def _dem_figures(cs: CaseStudy, n: object) -> Iterator[tuple[str, Figure]]:
    """Fig. 5 a-d, DEM next to analytical on the DEM's grid; their difference; Fig. 3."""
    from matplotlib.figure import Figure

    from pdamper import plots

    dem = _need(cs.dem_map, "DEM map")
    ana = _need(cs.analytic_on_dem_grid, "analytical map on the DEM grid")
    top = max(4 / math.pi, float(np.nanmax(dem["loss_factor"].values))
              if np.isfinite(dem["loss_factor"].values).any() else 0.0)
    mtop = max(1.0, float(np.nanmax(dem["effective_mass_ratio"].values))
               if np.isfinite(dem["effective_mass_ratio"].values).any() else 0.0)
    fig = Figure(figsize=(13, 14), layout="constrained")
    axes = fig.subplots(3, 2)
    for col, (ds, who) in enumerate(((ana, "analytical"), (dem, "DEM"))):
        plots.plot_mode_map(ds, ax=axes[0, col]).set_title(f"motion modes ({who})")
        plots.plot_loss_factor_map(ds, ax=axes[1, col], vmax=top).set_title(
            f"effective loss factor ({who})")
        plots.plot_effective_mass_map(ds, ax=axes[2, col], vmax=mtop).set_title(
            "effective mass ratio (" + ("Eq. 22" if who == "analytical" else "DEM, Eq. 4")
            + ")")
    fig.suptitle(f"Fig. 5 a-d: analytical (left) and DEM (right), {n} spheres; x: transient,"
                 " grey x: run failed")
    yield "fig5_dem_vs_analytic.png", fig
    fig = Figure(figsize=(7, 5), layout="constrained")
    ax = plots.plot_field_difference(dem, ana, ax=fig.subplots())
    ax.set_title("effective loss factor: DEM minus analytical")
    yield "fig5_dem_minus_analytic.png", fig
    if cs.snapshots:
        fig = Figure(figsize=(13, 3.6 * len(cs.snapshots)), layout="constrained")
        axes = np.atleast_1d(fig.subplots(len(cs.snapshots), 1))
        for ax, (label, res) in zip(axes, cs.snapshots, strict=True):
            plots.plot_particle_snapshots(res, ax=ax, vmax=2.0)
            ax.set_title(f"Fig. 3 {label}: X = {res.attrs['amplitude_m'] * 1e3:g} mm, "
                         f"f = {res.frequency:g} Hz", fontsize="medium")
        yield "fig3_snapshots.png", fig


def _agreement_markdown(cs: CaseStudy) -> str:
    a = cs.agreement
    run = _need(cs.dem_map_run, "DEM map run")
    ds = _need(cs.dem_map, "DEM map")
    lines = [f"\n## DEM map against the analytical one ({ds['loss_factor'].shape[0]} x "
             f"{ds['loss_factor'].shape[1]} points)\n",
             f"{a['cells']} cells with a result ({a['steady']} steady), {a['failed']} failed; "
             f"motion modes agree in {100 * a['mode_agreement']:.0f} % of the cells, median "
             f"|delta eta| {a['median_abs_delta_eta']:.3f}. "
             + ("Taken from the cached map." if run.cached else
                f"Computed in {run.seconds:.0f} s on {run.workers} worker(s) "
                f"({run.computed} points computed, {run.reused} reused)."),
             "", "| analytical mode | cells | same mode in the DEM | median abs(delta eta) |",
             "|---|---|---|---|"]
    for label, by in a["by_mode"].items():
        lines.append(f"| {MotionMode.from_label(label).title} | {by['cells']} | "
                     f"{100 * by['mode_agreement']:.0f} % | {by['median_abs_delta_eta']:.3f} |")
    return "\n".join(lines) + "\n"


def write_case_study(cs: CaseStudy, out: Path,
                     progress: Callable[[str], None] | None = None) -> list[Path]:
    """Write figures, the map and the table of ``cs`` into the existing directory ``out``.

    Every file goes through the atomic writer: an interrupted run leaves complete files
    or none, never a half-written one.
    """
    from pdamper import __version__

    say: Callable[[str], None] = progress or (lambda _msg: None)
    out = Path(out)
    say("writing figures")
    written, report_figures = _write_figures(cs, out, say)
    say("writing map and table")
    field_map = _need(cs.field_map, "analytical map")
    field_map.attrs["pdamper_version"] = __version__
    written.append(atomic_write_netcdf(out / "fig5_analytic_map.nc", field_map))
    if cs.dem_map is not None:
        written.append(_write_dem_map(cs, cs.dem_map, out))
    written.append(atomic_write_text(out / "results.md", _results_markdown(cs, __version__)))
    written.append(atomic_write_text(out / "results.json",
                                     json.dumps(_results_json(cs, __version__), indent=2)))
    say("writing report.html")
    opt = _need(cs.optimization, "optimisation")
    written.append(atomic_write_text(out / "report.html", render_report(
        title="pdamper: the reference paper's case study", version=__version__, rows=cs.rows,
        figures=report_figures, models=cs.models(), timings=cs.timings,
        landscape=[c.as_dict() for c in opt.candidates], at=opt.at,
        inputs=cs.inputs)))
    return written


def _write_figures(cs: CaseStudy, out: Path, say: Callable[[str], None]
                   ) -> tuple[list[Path], list[ReportFigure]]:
    """Each figure as a PNG in ``out``: the files written and the report's figures."""
    written: list[Path] = []
    report_figures = []
    for name, fig in _figures(cs):
        say(f"writing {name}")
        buf = io.BytesIO()
        fig.savefig(buf, dpi=120, format="png")
        png = buf.getvalue()
        written.append(atomic_write_bytes(out / name, png))
        caption = next((ax.get_title() for ax in fig.axes if ax.get_title()), name)
        report_figures.append(ReportFigure(name, caption, png))
    return written, report_figures


def _write_dem_map(cs: CaseStudy, dem_map: Dataset, out: Path) -> Path:
    """The DEM map's file in ``out``, written unless it is the map's own cache there."""
    dem_path = out / DEM_MAP_FILE
    run = cs.dem_map_run
    # the map stored (or found) in its cache under the output directory is not written
    # again: a rerun leaves it untouched
    stored = (run is not None and run.path is not None and Path(run.path).is_file()
              and Path(run.path).name == DEM_MAP_FILE)
    if not stored:
        atomic_write_netcdf(dem_path, dem_map)
    return dem_path


def _results_markdown(cs: CaseStudy, version: str) -> str:
    """``results.md``: the comparison table, the DEM map's agreement, the landscape."""
    opt = _need(cs.optimization, "optimisation")
    agree = sum(r.agrees is True for r in cs.rows)
    return ("# pdamper: the reference paper's case study\n\n"
            f"pdamper {version}, analytical damper model"
            + (" and DEM" if cs.dem_map is not None else "")
            + f". {agree} of {len(cs.rows)} reported numbers agree within the tolerance each "
            "row's test states (rows without a verdict report a number the paper does not "
            "give).\n\n"
            + _markdown(cs.rows)
            + (_agreement_markdown(cs) if cs.dem_map is not None else "")
            + f"\n## Objective landscape (amplitude at {opt.at:g} s)\n\n"
            + "| particles | mass [g] | amplitude [mm] |\n|---|---|---|\n"
            + "".join(f"| {c.particles} | {c.mass * 1e3:.1f} | {c.objective * 1e3:.2f} |\n"
                      for c in opt.candidates))


def _results_json(cs: CaseStudy, version: str) -> dict[str, Any]:
    """``results.json``: the rows, the runs' inputs, the COR models, the maps' records."""
    damper = _need(cs.damper, "damper")
    field_map = _need(cs.field_map, "analytical map")
    dem_map = None
    if cs.dem_map is not None:
        map_run = _need(cs.dem_map_run, "DEM map run")
        dem_map = {"file": DEM_MAP_FILE,
                   "shape": [int(n) for n in cs.dem_map["loss_factor"].shape],
                   "agreement": cs.agreement, "cached": bool(map_run.cached),
                   "seconds": map_run.seconds, "workers": map_run.workers}
    return {
        "version": version,
        "model": "analytic" if cs.run_dem is None else "analytic + dem",
        "inputs": cs.inputs,
        "rows": [asdict(r) for r in cs.rows],
        "optimization": _need(cs.optimization, "optimisation").as_dict(),
        "paper_reported": [{k: v for k, v in asdict(r).items() if k != "accept"}
                           for r in paper.PAPER_REPORTED],
        "damping_ratio_32": [{"amplitude": float(a), "zeta": float(z)}
                             for a, z in zip(*_need(cs.run_32, "model 3 run").damping_ratio,
                                             strict=True)],
        "level3_runs": {name: {"model": run.model, **run.inputs}
                        for name, run in (("scenario_damper", cs.run_32),
                                          ("no_particles", cs.run_empty),
                                          ("paper_optimum", cs.run_best), ("dem", cs.run_dem),
                                          ("dem_paper_cor_curves", cs.run_dem_curves),
                                          ("fields", cs.run_fields))
                        if run is not None},
        **({"dem_realisations": cs.dem_band.as_dict()} if cs.dem_band is not None else {}),
        "restitution": {
            "scenario": {"particle_particle": _cor_curves(damper)[0].describe(),
                         "particle_wall": _cor_curves(damper)[1].describe()},
            "paper": {"particle_particle": paper.PAPER_COR_PP.describe(),
                      "particle_wall": paper.PAPER_COR_PW.describe()},
            "dem_single_impacts": [c.as_dict() for c in cs.cor_checks]},
        "models": cs.models(),
        "fields_source": cs.fields_source,
        "fields_failure": cs.fields_failure,
        "timings": cs.timings,
        "map_shape": [int(n) for n in field_map["loss_factor"].shape],
        "dem_map": dem_map,
    }
