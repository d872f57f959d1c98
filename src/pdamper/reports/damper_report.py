"""A report of the user's own damper: one self-contained ``report.html`` for any scenario.

What the report shows is computed by :func:`pdamper.runs.damper_report.run_damper_report`
(the maps, the free decays, the forced response, the design landscape, the uncertainty
and the realisations of one scenario); :func:`figures` draws it, and
:func:`write_damper_report` writes ``report.html`` (the look of ``pdamper paper``'s page,
:mod:`pdamper.reports.html`) and ``results.json``. :func:`merge_sections` is where further
sections (the forced response, realisation bands) join the page.
"""

from __future__ import annotations

import io
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from pdamper.reports.html import _STYLE, ReportFigure, _e, _img, _table
from pdamper.runs.damper_report import DamperReport, _timed
from pdamper.units import display

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure


def _png(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    return buf.getvalue()


def _one_count(ds, count: int):
    """A map with a particle-count axis at the count nearest ``count`` (2-D for plots)."""
    if "particles" in ds.dims:
        return ds.sel(particles=count, method="nearest")
    return ds


def figures(rep: DamperReport) -> list[ReportFigure]:
    """The report's figures (PNG). A figure that cannot be drawn is left out and its error
    kept in ``rep.figure_errors`` (``name -> message``): the computed answers and the other
    figures stand, and the command ends non-zero naming it."""
    assert rep.damper is not None  # (set by run_damper_report, as the maps)
    wanted: list[tuple[str, str, Callable[[DamperReport], Figure]]] = [
        ("level2_map", f"Level II map of the analytical model, {rep.damper.count} particles "
         "(Eqs. 5-22)", _level2_figure)]
    if rep.dem_map is not None:
        wanted.append(("level2_dem_map", "Level II map of the DEM (complex power method, "
                       "Eqs. 1-4)", _dem_map_figure))
    wanted += [("free_decay", "free decay and damping ratio, the models compared",
                _free_decay_figure),
               ("design_landscape", "design landscape (analytical model) with the Pareto "
                "front of added mass against the objective", _landscape_figure)]
    if "level3" in rep.uncertainty:
        wanted.append(("uncertainty", "spread of the answers under the uncertain inputs "
                       "(histograms, the envelope's 5-95 % band) and the inputs' total "
                       "Sobol' indices", lambda r: uncertainty_figure(r.uncertainty)))
    if rep.forced:
        wanted.append(("forced_response", "amplitude and phase of the structure under a "
                       "harmonic force, the models compared (harmonic balance)",
                       _forced_figure))
    if rep.band is not None:
        wanted.append(("realisations", "DEM model 1 over random packings: the band of the "
                       "free decay and of the damping ratio", _band_figure))
    out: list[ReportFigure] = []
    for name, caption, draw in wanted:
        try:
            out.append(ReportFigure(name, caption, _png(draw(rep))))
        except Exception as exc:  # noqa: BLE001 - a figure never loses the results
            rep.figure_errors[name] = f"{type(exc).__name__}: {exc}"
    return out


def _level2_figure(rep: DamperReport) -> Figure:
    from matplotlib.figure import Figure

    from pdamper import plots

    assert rep.damper is not None
    ds = _one_count(rep.level2_map, rep.damper.count)
    fig = Figure(figsize=(15, 4.4), layout="constrained")
    a = fig.subplots(1, 3)
    plots.plot_mode_map(ds, ax=a[0])
    plots.plot_loss_factor_map(ds, ax=a[1])
    plots.plot_effective_mass_map(ds, ax=a[2])
    a[0].set_title("motion mode")
    a[1].set_title("loss factor")
    a[2].set_title("effective mass ratio")
    return fig


def _dem_map_figure(rep: DamperReport) -> Figure:
    from matplotlib.figure import Figure

    from pdamper import plots

    assert rep.damper is not None
    dm = _one_count(rep.dem_map, rep.damper.count)
    fig = Figure(figsize=(10, 4.4), layout="constrained")
    a = fig.subplots(1, 2)
    plots.plot_loss_factor_map(dm, ax=a[0])
    plots.plot_effective_mass_map(dm, ax=a[1])
    a[0].set_title("loss factor (DEM)")
    a[1].set_title("effective mass ratio (DEM)")
    return fig


def _free_decay_figure(rep: DamperReport) -> Figure:
    from matplotlib.figure import Figure

    from pdamper import plots

    fig = Figure(figsize=(11, 7.5), layout="constrained")
    a = fig.subplots(2, 1)
    plots.plot_model_trajectories(rep.runs, ax=a[0], envelope=rep.empty)
    a[0].set_title("free decay of the structure with the damper")
    plots.plot_model_damping_ratios(rep.runs, ax=a[1])
    a[1].set_title("damping ratio per cycle (Eqs. 24-25)")
    return fig


def _landscape_figure(rep: DamperReport) -> Figure:
    from matplotlib.figure import Figure

    from pdamper import plots

    assert rep.study is not None  # the report always runs its design study
    if not rep.study.limits:
        fig = Figure(figsize=(8, 5.2), layout="constrained")
        plots.plot_design_landscape(rep.study, ax=fig.subplots())
        return fig
    fig = Figure(figsize=(13, 5.2), layout="constrained")  # with limits: the front too
    left, right = fig.subplots(1, 2)
    plots.plot_design_landscape(rep.study, ax=left)
    plots.plot_design_front(rep.study, ax=right)
    return fig


def _forced_figure(rep: DamperReport) -> Figure:
    from matplotlib.figure import Figure

    from pdamper.plots.frf import plot_frf

    fig = Figure(figsize=(9, 6.5), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    for i, (label, r) in enumerate(rep.forced.items()):
        plot_frf(r, axes=axes, label=label, linear=i == 0, color=("C0", "C4", "C5")[i % 3])
    band = rep.uncertainty["frf"].bands.get("amplitude") if "frf" in rep.uncertainty else None
    if band is not None:  # the analytical model's amplitude under the uncertain inputs
        axes[0].fill_between(band["frequency"], np.asarray(band["p5"]) * 1e3,
                             np.asarray(band["p95"]) * 1e3, color="C1", alpha=0.3, lw=0,
                             label="5-95 % under the uncertain inputs (analytical)")
        for edge in ("p5", "p95"):  # its edges drawn: a narrow band stays visible
            axes[0].plot(band["frequency"], np.asarray(band[edge]) * 1e3, color="C1",
                         lw=0.8, marker=".", ms=3)
        axes[0].legend(fontsize="x-small")
    axes[0].set_title(f"forced response, {rep.forced_load.describe()}")
    return fig


def _band_figure(rep: DamperReport) -> Figure:
    from matplotlib.figure import Figure

    from pdamper import plots

    fig = Figure(figsize=(11, 7.5), layout="constrained")
    a = fig.subplots(2, 1)
    plots.plot_trajectory_band(rep.band, ax=a[0], label="DEM (model 1)")
    plots.plot_damping_ratio_band(rep.band, ax=a[1], label="DEM (model 1)")
    return fig


def uncertainty_figure(results: dict) -> Figure:
    """Histograms of the Level III amplitude at t and the Level II loss factor with their
    5-95 % band, the band of the Level III envelope over time, and the total Sobol' index
    of each input per answer."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(15, 8.8), layout="constrained")
    grid = fig.subplots(2, 2)
    ax = [grid[0, 0], grid[0, 1], grid[1, 1]]
    band = results["level3"].bands.get("envelope") if "level3" in results else None
    if band is not None:
        a, t = grid[1, 0], band["time"]
        a.fill_between(t, band["p5"] * 1e3, band["p95"] * 1e3, color="C1", alpha=0.3,
                       label="5-95 %")
        a.plot(t, band["mean"] * 1e3, "k", lw=1, label="mean")
        a.plot(t, band["nominal"] * 1e3, "C3--", lw=1, label="nominal inputs")
        a.set_xlabel("time t [s]")
        a.set_ylabel("amplitude envelope [mm]")
        a.set_title("free decay under the uncertain inputs (analytical model)")
        a.legend(fontsize="x-small")
    else:
        grid[1, 0].set_axis_off()
    for a, (level, name, k, unit) in zip(ax[:2], (("level3", "amplitude_at", 1e3, "mm"),
                                                  ("level2", "loss_factor", 1.0, "-")),
                                         strict=True):
        r = results.get(level)
        if r is None:
            a.set_axis_off()
            continue
        s = r.answers[name]
        a.hist(r.values[name] * k, bins=20, color="C0", alpha=0.7)
        a.axvspan(s.percentiles[5.0] * k, s.percentiles[95.0] * k, color="C1", alpha=0.2,
                  label="5-95 %")
        a.axvline(s.mean * k, color="k", label="mean")
        a.axvline(s.nominal * k, color="C3", ls="--", label="nominal inputs")
        a.set_xlabel(f"{name} [{unit}]")
        a.set_ylabel("samples")
        a.legend(fontsize="x-small")
    names = [u.field for u in next(iter(results.values())).inputs]
    answers = [(lv, n) for lv, r in results.items() for n in r.answers]
    width = 0.8 / max(len(names), 1)
    for i, inp in enumerate(names):
        ax[2].bar(np.arange(len(answers)) + i * width,
                  [results[lv].answers[n].total_order[inp] for lv, n in answers], width,
                  label=inp)
    ax[2].set_xticks(np.arange(len(answers)) + 0.4 - width / 2,
                     [n for _, n in answers], rotation=30, ha="right", fontsize="small")
    ax[2].set_ylabel("total Sobol' index")
    ax[2].legend(fontsize="x-small")
    return fig


# ---------------------------------------------------------------------------- the page
def merge_sections(forced_response: str | None = None,
                   realisations: str | None = None) -> list[str]:
    """Further HTML sections (``<h2>...</h2>`` and content) to add after the computed ones,
    in order; None: left out."""
    return [s for s in (forced_response, realisations) if s]


def _forced_html(rep: DamperReport) -> list[str]:
    summary = rep.forced_summary()
    if summary is None:
        why = rep.not_applicable.get("forced_response")
        return [] if why is None else ["<h2>Forced response</h2>",
                                       f"<p>Not applicable: {_e(why)}.</p>"]
    load = rep.forced_load
    rows = [[label + (" (! fields from the analytical model)"
                      if m.get("fields_from") == "analytic" else ""),
             _mm(m["peak_amplitude"]), "" if m["peak_frequency"] is None
             else f"{m['peak_frequency']:.3f}",
             "yes" if m["several_solutions"] else "no", _assumptions_cell(m)]
            for label, m in summary["models"].items()]
    rows.append(["no particles (linear FRF)",
                 f"{summary['no_particles']['peak_amplitude'] * 1e3:.2f}",
                 f"{summary['no_particles']['peak_frequency']:.3f}", "no", ""])
    first = next(iter(rep.forced.values()))
    return ["<h2>Forced response</h2>",
            (f"<p>{_e(rep.forced_text[0].upper() + rep.forced_text[1:])}, "
             if rep.forced_text else
             f"<p>Harmonic force of {load.amplitude:.4g} N at the damper's point (the amplitude "
             "that drives the structure without particles to the release amplitude at its "
             "natural frequency), ")
            + f"{first.frequency.size} frequencies over "
            f"{first.frequency[0]:.3g}-{first.frequency[-1]:.3g} Hz; harmonic balance with "
            "the damper's describing function (Eqs. 1-4), every stable solution "
            "(docs/forced.md). Where a model has several solutions at a frequency, up and "
            "down sweeps jump between them.</p>",
            _table(["model", "largest steady amplitude [mm]", "at f [Hz]",
                    "several solutions somewhere", "analytic model's assumptions"], rows,
                   "forced_response", [["", "num", "num", "", ""]] * len(rows)),
            *_fig(rep, "forced_response")]


def _source_cell(m: dict) -> str:
    """What a run's damper data rest on, marked (``!``) where its effective fields are the
    analytical model's rather than a DEM map's."""
    if m.get("fields_from") == "analytic":
        return f"{m['source']} (! {m['fields_note']})"
    return m["source"]


def _near_harmonic_cell(m: dict) -> str:
    """Whether a run's describing-function answers rest on a near-harmonic motion
    (:mod:`pdamper.coupling.harmonicity`); why not applicable otherwise."""
    h = m.get("harmonicity")
    if h is None:
        why = m.get("not_applicable", {}).get("near_harmonic")
        return "" if why is None else f"not applicable: {why}"
    if h["near_harmonic"]:
        return f"yes (deviation {h['deviation']:.2f} <= {h['threshold']:g})"
    return (f"! no: deviation {h['deviation']:.2f} > {h['threshold']:g}; use the plastic or "
            "dem fidelity, whose damper force follows the motion itself")


def _decay_cell(a: dict | None) -> str:
    """Whether a free decay's damper answers hold the analytical model's assumptions."""
    if a is None:
        return ""
    if not a["flagged"]:
        return f"hold at every update ({a['points']})"
    kinds = ", ".join(k.replace("_", " ") for k in a["reasons"])
    return (f"fail at {a['flagged']} of {a['points']} updates ({kinds}): use fields from a "
            "DEM map, or dem")


def _assumptions_cell(m: dict) -> str:
    """Whether a model's forced response rests on the analytical model's assumptions:
    at its peak (the reason and the fidelity to use where not) and over every answer."""
    a = m.get("assumptions")
    if a is None:
        return ""
    where = f"fail at {a['flagged']} of {a['points']} answers" if a["flagged"] else \
        "hold at every answer"
    if not m.get("peak_assumptions_hold", True):
        return (f"fail at the peak: {m['peak_assumptions']}; {where}; use fields from a "
                "DEM map, or dem")
    return f"hold at the peak; {where}" + ("; use fields from a DEM map, or dem there"
                                          if a["flagged"] else "")


def _band_html(rep: DamperReport) -> list[str]:
    band = rep.band
    if band is None:
        return []
    a = band.amplitude_at()
    fa = band.final_amplitude()
    rows = [[f"amplitude at {band.at:g} s", f"{a['mean'] * 1e3:.2f}", f"{a['std'] * 1e3:.2f}",
             f"{a['min'] * 1e3:.2f}", f"{a['max'] * 1e3:.2f}"],
            ["final amplitude", f"{fa['mean'] * 1e3:.2f}", f"{fa['std'] * 1e3:.2f}",
             f"{fa['min'] * 1e3:.2f}", f"{fa['max'] * 1e3:.2f}"]]
    return ["<h2>Realisations of the DEM (model 1)</h2>",
            f"<p>{band.count} random packings (seeds {', '.join(map(str, band.seeds or []))}) "
            "of the chaotic bed: mean, standard deviation (divisor N - 1), min and max; the "
            "figure shades min-max around the mean.</p>",
            _table(["answer [mm]", "mean", "std", "min", "max"], rows, "realisations",
                   [["", "num", "num", "num", "num"]] * len(rows)), *_fig(rep, "realisations")]


def _fig(rep: DamperReport, name: str) -> list[str]:
    """The figure ``name`` as HTML, or the sentence saying why it could not be drawn."""
    if name in rep.figure_errors:
        return [f"<p><strong>The figure {_e(name)} could not be drawn</strong> "
                f"({_e(rep.figure_errors[name])}); the numbers of this section and "
                "results.json are complete.</p>"]
    return [_img(f) for f in rep.figures if f.name == name]


def _mm(v) -> str:
    return "" if v is None else f"{v * 1e3:.2f}"


def _uncertainty_html(rep: DamperReport) -> list[str]:
    if not rep.uncertainty:
        return ["<h2>Uncertainty</h2>", "<p>No input of this scenario carries an uncertainty. "
                "Give one as <code>\"value +- sd\"</code> (a standard deviation; normal, "
                "truncated to the field's range), e.g. <code>friction = \"0.1 +- 0.03\"</code> "
                "or <code>length = \"120 mm +- 0.1 mm\"</code>, to see the spread of the "
                "answers here.</p>"]
    first = next(iter(rep.uncertainty.values()))
    parts = ["<h2>Uncertainty</h2>",
             f"<p>Quasi-Monte Carlo (scrambled Sobol', seed {first.seed}), "
             f"{first.points} base points, analytical model; Sobol' indices by Saltelli "
             "(first order) and Jansen (total) on the same runs, 95 % bootstrap intervals. "
             "The driver of an answer is the input with the largest total index.</p>",
             _table(["input", "nominal", "standard deviation", "unit", "range"],
                    [_input_row(u) for u in first.inputs], "uncertain_inputs")]
    rows, idx = [], []
    for level, r in rep.uncertainty.items():
        for name, a in r.answers.items():
            k, unit = display(1.0, a.unit or "1")  # mm, g, mJ in the table; SI in JSON
            rows.append([level, name, unit, f"{k * a.nominal:.5g}", f"{k * a.mean:.5g}",
                         f"{k * a.std:.3g}", f"{k * a.percentiles[5.0]:.5g}",
                         f"{k * a.percentiles[50.0]:.5g}", f"{k * a.percentiles[95.0]:.5g}",
                         a.driver or "none (no spread)"])
            for inp in a.total_order:
                lo, hi = a.total_order_interval[inp]
                idx.append([level, name, inp, f"{a.first_order[inp]:.3f}",
                            f"{a.total_order[inp]:.3f}", f"[{lo:.3f}, {hi:.3f}]"])
    parts.append(_table(["level", "answer", "unit", "nominal", "mean", "std", "5 %", "50 %",
                         "95 %", "driver"], rows, "uncertainty",
                        [["", "", "", "num", "num", "num", "num", "num", "num", ""]]
                        * len(rows)))
    drivers, rows = _drivers_html(rep)
    parts.append(_table(["level", "answer", "input", "first-order index", "total index",
                         "total: 95 % interval"], idx + rows, "sobol_indices",
                        [["", "", "", "num", "num", ""]] * len(idx + rows)))
    return parts[:-1] + drivers + parts[-1:]


def _input_row(u) -> list[str]:
    """An uncertain input's row: nominal, standard deviation and range in the unit people
    read (:func:`pdamper.units.display`)."""
    k, unit = display(1.0, u.unit or "1")
    return [u.field, f"{k * u.value:.6g}", f"{k * u.sd:.3g}", unit,
            f"[{k * u.low:g}, {k * u.high:g}]"]


#: What each level of the propagation answers, in words.
_LEVELS = {"level2": "the Level II answers at the excitation",
           "level3": "the free decay", "frf": "the forced response ([frf])",
           "load": "the response to the load record ([load])"}


def _drivers_html(rep: DamperReport) -> tuple[list[str], list[list[str]]]:
    """The chosen design's sensitivity drivers: a paragraph naming the design, its
    objective's answer under the uncertain inputs and its driver, and the rows of its
    Sobol' indices (level ``chosen design``, largest total index first) for the table of
    indices."""
    dd = rep.design_drivers
    if not dd:
        return [], []
    r, answer = dd["result"], dd["answer"]
    a = r.answers[answer]
    st = rep.study
    names = [] if st is None else [v.name for v in st.variables]
    rows = [["chosen design", answer, inp, f"{a.first_order[inp]:.3f}",
             f"{a.total_order[inp]:.3f}",
             "[{:.3f}, {:.3f}]".format(*a.total_order_interval[inp])]
            for inp in sorted(a.total_order, key=lambda k: -a.total_order[k])]
    k, unit = (1e3, "mm") if a.unit == "m" else (1.0, a.unit or "")
    unused = [f for f in r.not_used if f in a.total_order]
    return (["<h3>What the chosen design is sensitive to</h3>",
             f"<p>The best design ({_e(_brief(st.best, names) if st is not None else '')}) "
             f"under the uncertain inputs: {_e(answer)} of {_e(_LEVELS[dd['level']])}, "
             f"mean {a.mean * k:.4g} {_e(unit)}, standard deviation {a.std * k:.3g} "
             f"{_e(unit)}, 5-95 % [{a.percentiles[5.0] * k:.4g}, "
             f"{a.percentiles[95.0] * k:.4g}] {_e(unit)}; its driver: <strong>"
             f"{_e(a.driver or 'none (no spread)')}</strong> (the rows <em>chosen design"
             "</em> of the table of indices)"
             + (f"; not used by the analytical model: {_e(', '.join(unused))}"
                if unused else "") + ".</p>"], rows)


def render_damper_report(rep: DamperReport, extra: Sequence[str] = ()) -> str:
    """The page as a string; ``extra``: the sections of :func:`merge_sections`."""
    d = rep.damper
    assert d is not None  # (set by run_damper_report)
    inputs = _table(["quantity", "value"], [
        ["container (L x W x D)", f"{d.length * 1e3:g} x {d.width * 1e3:g} x "
                                  f"{d.depth * 1e3:g} mm, {d.wall_material.name}"],
        ["particles", f"{d.count} spheres of radius {d.particle_radius * 1e3:g} mm, "
                      f"{d.particle_material.name}, bed mass {d.bed_mass * 1e3:.1f} g"],
        ["clearance h, optimal stroke h/pi", f"{d.clearance * 1e3:.2f} mm, "
                                             f"{d.optimal_stroke * 1e3:.2f} mm"],
        ["friction mu", f"{d.friction:g}"],
        ["excitation (Level II answers)", f"f = {rep.inputs['excitation']['frequency']:g} Hz, "
                                          f"X = {rep.inputs['excitation']['amplitude'] * 1e3:g}"
                                          f" mm, g = {rep.inputs['excitation']['gravity']:g} "
                                          "m/s^2"],
        ["structure", _structure_text(rep.structure)],
        ["release x0, duration", f"{rep.inputs['structure']['initial_displacement'] * 1e3:g} "
                                 f"mm, {rep.inputs['simulation']['duration']:g} s"],
        *([["uncertain inputs (standard deviations)", "; ".join(
            f"{u.field} = {u.value:.6g} +- {u.sd:.3g} {u.unit}".rstrip()
            for u in rep.uncertain)]] if rep.uncertain else []),
        *_mode_rows(rep)],
        "inputs")
    models = rep.models()
    model_table = _table(["run", "model", "damper data", f"amplitude at {rep.at:g} s [mm]",
                          "final amplitude [mm]", "wall time [s]",
                          f"analytic model's assumptions up to {rep.at:g} s",
                          "near-harmonic"],
                         [[m["label"], m["model"], _source_cell(m), _mm(m["amplitude_at"]),
                           _mm(m["final_amplitude"]),
                           "" if m["seconds"] is None else f"{m['seconds']:.3f}",
                           _decay_cell(m.get("assumptions")), _near_harmonic_cell(m)]
                          for m in models], "models",
                         [["", "", "", "num", "num", "num", "", ""]] * len(models))
    summary, limits, land = _landscape_html(rep)
    timings = _table(["step", "wall time [s]"],
                     [[k, f"{v:.3f}"] for k, v in rep.timings.items()], "timings",
                     [["", "num"]] * len(rep.timings))
    seeds = ", ".join(f"{k} = {v}" for k, v in rep.seeds.items())
    def fig(name):
        return _fig(rep, name)

    parts = [
        "<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{_e(rep.title)}</title>", f"<style>{_STYLE}</style>", "</head>", "<body>",
        f"<h1>{_e(rep.title)}</h1>",
        f'<p class="summary">pdamper {_e(rep.version)}; seeds: {_e(seeds)}.</p>',
        "<h2>Inputs</h2>", inputs,
        "<h2>Level II: the damper under harmonic excitation</h2>", *fig("level2_map"),
        *fig("level2_dem_map"),
        "<h2>Level III: free decay, the models compared</h2>", model_table,
        *fig("free_decay"),
        "<h2>Design landscape</h2>", f"<p>{_e(summary)}</p>", *limits,
        *fig("design_landscape"), land,
        *_uncertainty_html(rep), *fig("uncertainty"),
        *_forced_html(rep), *_band_html(rep),
        *extra,
        "<h2>Run times</h2>", timings,
        "<h2>All inputs</h2>", *_inputs_html(rep),
        f"<p>Generated by pdamper {_e(rep.version)}.</p>", "</body>", "</html>"]
    return "\n".join(parts) + "\n"


def _landscape_html(rep: DamperReport) -> tuple[str, list[str], str]:
    """The design landscape: its summary in words, the limits with their margins and the
    table of every design (variables in display units)."""
    st = rep.study
    assert st is not None  # (set by run_damper_report)
    on_front = {id(c) for c in st.front}
    light, best = st.lightest_within, st.best
    names = [v.name for v in st.variables]
    scale, shown_unit = st.objective.display_scale, st.objective.label.rsplit("[", 1)[-1]
    land_rows = []
    for c in st.candidates:
        mark = ", ".join(w for w, ok in (("best", c is best), ("lightest within "
                                          f"{st.tolerance * 100:g} %", c is light),
                                         ("front", id(c) in on_front)) if ok)
        status = ("outside the limits" if c.violations else c.status)
        reason = c.reason or "; ".join(c.violations)
        land_rows.append([*(_shown(n, c.design.get(n)) for n in names),
                          "" if c.mass is None else f"{c.mass * 1e3:.1f}",
                          "" if c.objective is None else f"{c.objective * scale:.5g}",
                          status + (f": {reason}" if reason else "")
                          + (f"; ! {c.extra['assumptions']}"
                             if c.extra.get("assumptions_hold") is False else ""), mark])
    land = _table([*(_head(n) for n in names), "added mass [g]",
                   f"{st.objective.name} [{shown_unit}", "status", "on the front"],
                  land_rows, "landscape",
                  [["num"] * len(names) + ["num", "num", "", ""]] * len(land_rows))
    summary = (f"best: {_brief(best, names)}; lightest within {st.tolerance * 100:g} % of "
               f"the best: {_brief(light, names)}; {len(st.front)} designs on the Pareto "
               "front." + ("" if st.no_best is None else f" No best design: {st.no_best}.")
               + ("" if best is None or best.extra.get("assumptions_hold") is not False else
                  f" The best design rests on answers outside the analytic model's "
                  f"assumptions ({best.extra['assumptions']})."))
    limits = _limits_html(st, names)
    return summary, limits, land


def _value(v) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    return "" if v is None else str(v)


def _shown(name: str, v) -> str:
    """A design variable's value in its display unit, without the unit (the column head
    has it)."""
    from pdamper.design.study import DESIGN_VARIABLES

    kind = DESIGN_VARIABLES[name]
    if v is None or kind.kind != "continuous" or not isinstance(v, float):
        return _value(v)
    return f"{v * kind.display[1]:.4g}"


def _head(name: str) -> str:
    """The column head of a design variable: its name and display unit (``radius [mm]``)."""
    from pdamper.design.study import DESIGN_VARIABLES

    kind = DESIGN_VARIABLES[name]
    unit = kind.display[0] if kind.kind == "continuous" else ""
    return f"{name} [{unit}]" if unit else name


def _brief(c, names) -> str:
    from pdamper.design.study import show_value

    if c is None:
        return "none"
    mass = "" if c.mass is None else f" ({c.mass * 1e3:.0f} g" + (
        f", {c.total_mass * 1e3:.0f} g with the container)" if c.container_mass else ")")
    return ", ".join(f"{n} = {show_value(n, c.design.get(n))}" for n in names) + mass


def _limits_html(st, names) -> list[str]:
    """The study's limits and, for each design chosen (best, lightest within the
    tolerance, lightest within the limits, or the one closest to them), every limit's value
    and margin, in display units; nothing without limits."""
    from pdamper.design.study import describe_design, show_quantity

    if not st.limits:
        return []
    chosen = [("best", st.best), (f"lightest within {st.tolerance * 100:g} %",
                                  st.lightest_within),
              ("lightest within the limits", st.lightest_feasible),
              ("closest to the limits (none meets them)", st.closest)]
    rows: list[list[str]] = []
    seen: list[Any] = []
    for label, c in chosen:
        if c is None or any(c is d for d in seen):
            continue
        seen.append(c)
        for r in c.limits:
            rows.append([label, describe_design(c, names), f"{r['quantity']} {r['op']} "
                         f"{show_quantity(r['limit'], r['unit'])}",
                         show_quantity(r["value"], r["unit"]),
                         ("" if r["met"] else "-") + show_quantity(abs(r["margin"]), r["unit"]),
                         f"{r['relative_margin'] * 100:.3g}", "yes" if r["met"] else "no"])
    text = (f"Limits: {'; '.join(lim.describe() for lim in st.limits)}; "
            f"{len(st.feasible)} of {sum(c.status == 'ok' for c in st.candidates)} evaluated "
            "designs meet them (the mass is the bed's and the container's). A design "
            "outside them is infeasible: never best, lightest or on the front.")
    return [f"<p>{_e(text)}</p>",
            _table(["design", "variables", "limit", "value", "margin", "margin [%]", "met"],
                   rows, "limits", [["", "", "", "num", "num", "num", ""]] * len(rows))]


def _mode_rows(rep: DamperReport) -> list[list[str]]:
    """Rows of the inputs table: each mode's data (frequency, damping ratio, shapes, the
    mass referred to the damper) and the damping the damper adds to it."""
    rows = []
    gains = {g["mode"]: g for g in rep.mode_damping}
    for m in rep.modal.get("modes", []):
        rows.append([f"mode {m['mode']}", f"f = {m['frequency']:.4g} Hz, damping ratio "
                     f"{m['damping_ratio'] * 100:.3g} %, shape at the damper "
                     f"{m['damper_shape']:.4g} kg^-0.5 ({m['mass_at_damper']:.4g} kg "
                     f"referred there), at the observation point "
                     f"{m['observation_shape']:.4g} kg^-0.5"])
    for g in gains.values():
        rows.append([f"damping the damper adds to mode {g['mode']}",
                     f"+{g['added'] * 100:.3g} % (loss factor {g['loss_factor']:.3g} at "
                     f"{g['frequency']:.4g} Hz and the optimal stroke h/pi = "
                     f"{g['stroke'] * 1e3:.3g} mm; Eqs. 2-3): "
                     f"{g['damping_ratio'] * 100:.3g} % -> {g['total'] * 100:.3g} %"])
    return rows


def _inputs_html(rep: DamperReport) -> list[str]:
    """The inputs the report used (JSON, SI), the data files it read embedded, and the
    keys it did not use with the reason."""
    used = rep.used or rep.inputs
    out = ["<p>The inputs this report used (SI units); the data files it read are "
           "embedded below.</p>", f"<pre>{_e(json.dumps(used, indent=2))}</pre>"]
    for key, f in rep.embedded.items():
        what = {"modes": "modes file", "load": "load record"}.get(key, key)
        out.append(f"<details open><summary>{_e(what)} {_e(f['name'])}</summary>"
                   f"<pre>{_e(f['text'])}</pre></details>")
    if rep.not_used:
        out.append("<p>Not used by this report: " + _e("; ".join(
            f"{k} ({why})" for k, why in rep.not_used.items())) + ".</p>")
    return out


def _structure_text(s) -> str:
    if hasattr(s, "mass") and hasattr(s, "stiffness"):
        return f"1 DOF (Eq. 23): M = {s.mass:.4g} kg, K = {s.stiffness:g} N/m, " \
               f"f = {s.natural_frequency:.3f} Hz"
    return f"{s.modes} mode(s) at " + ", ".join(f"{f:.4g}" for f in s.frequencies) + " Hz"


def write_damper_report(rep: DamperReport, out: Path, extra: Sequence[str] = ()) -> list[Path]:
    """Write ``report.html`` and ``results.json`` under ``out``; returns the paths. The
    figures are made first, unless ``rep`` has them (their time under ``"figures"``)."""
    from pdamper.files import atomic_write_text

    if not rep.figures:
        rep.figures = _timed(rep, "figures", lambda: figures(rep))
    out = Path(out)
    # the answers first, the page with its figures after them
    data = json.dumps(_finite(json.loads(json.dumps(rep.as_dict(), default=_json_default))),
                      indent=2, allow_nan=False)
    json_path = atomic_write_text(out / "results.json", data + "\n", "out")
    page = render_damper_report(rep, extra or merge_sections())
    html_path = atomic_write_text(out / "report.html", page, "out")
    return [html_path, json_path]


def _finite(o):
    """Non-finite floats as null: strict JSON."""
    if isinstance(o, float):
        return o if np.isfinite(o) else None
    if isinstance(o, dict):
        return {k: _finite(v) for k, v in o.items()}
    if isinstance(o, list):
        return [_finite(v) for v in o]
    return o


def _json_default(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o)}")


__all__ = ["figures", "merge_sections", "render_damper_report", "uncertainty_figure",
           "write_damper_report"]
