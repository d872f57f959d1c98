"""Level III figures beyond the paper's: several models against a measurement, the design
landscape, and the one-mode-enough study."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Protocol

import numpy as np

from pdamper.plots.figures import _axes

if TYPE_CHECKING:
    from collections.abc import Sequence

    from matplotlib.axes import Axes

    from pdamper.coupling import FreeVibrationResult
    from pdamper.coupling.comparison import ModelComparison
    from pdamper.coupling.measurement import AlignedMeasurement
    from pdamper.coupling.modal import ModeCountStudy
    from pdamper.design.study import DesignCandidate, DesignStudyResult, DesignVariable


class _Band(Protocol):
    """What the band figures read of N realisations of one run (a
    :class:`~pdamper.runs.realisations.Level3Band`)."""

    model: str
    at: float

    @property
    def count(self) -> int: ...

    def trajectory(self) -> dict: ...

    def amplitude_at(self) -> dict: ...

    def damping_ratio(self) -> list[dict]: ...


def _label(name: str, comparison: ModelComparison | None) -> str:
    if comparison is None:
        return name
    return (f"{name} (peaks RMS {comparison.peak_rms_error * 1e3:.2f} mm, "
            f"zeta RMS {comparison.zeta_rms_error:.4f}, "
            f"drift {comparison.final_phase_drift:+.2f} rad)")


def plot_model_trajectories(results: dict[str, FreeVibrationResult],
                            measured: AlignedMeasurement | None = None,
                            comparisons: dict[str, ModelComparison] | None = None,
                            ax: Axes | None = None,
                            envelope: FreeVibrationResult | None = None) -> Axes:
    """End-effector trajectories of several models (Fig. 7 with models 1-3), optionally
    with the aligned measurement and each model's error metrics in its label.

    Parameters
    ----------
    results
        ``{label: FreeVibrationResult}``.
    measured
        An :class:`~pdamper.coupling.measurement.AlignedMeasurement`, or None.
    comparisons
        ``{label: ModelComparison}`` (metrics shown in the legend).
    envelope
        A run without particles whose negative peaks are drawn as a dashed envelope.
    """
    ax = _axes(ax)
    comparisons = comparisons or {}
    if measured is not None:
        keep = measured.time >= 0
        ax.plot(measured.time[keep], measured.displacement[keep] * 1e3, color="k", lw=1.6,
                alpha=0.45, label=f"measured ({measured.quantity})")
    for label, res in results.items():
        ax.plot(res.time, res.displacement * 1e3, lw=1, label=_label(label,
                                                                       comparisons.get(label)))
    if envelope is not None:
        ax.plot(envelope.peak_times, -envelope.peak_amplitudes * 1e3, "k--", lw=1,
                label="envelope without particles")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("end-effector displacement x [mm]")
    ax.legend(fontsize="x-small", loc="lower right")
    return ax


def plot_model_damping_ratios(results: dict[str, FreeVibrationResult],
                              measured: AlignedMeasurement | None = None,
                              comparisons: dict[str, ModelComparison] | None = None,
                              ax: Axes | None = None) -> Axes:
    """Damping ratio over the mean cycle amplitude (Fig. 8, Eqs. 24-25) for several models
    and the measurement, with the amplitude bands of the comparison shaded."""
    ax = _axes(ax)
    if measured is not None:
        amp, zeta = measured.damping_ratio
        ax.plot(amp * 1e3, zeta, "ks", ms=5, label="measured")
    for label, res in results.items():
        amp, zeta = res.damping_ratio
        ax.plot(amp * 1e3, zeta, "o-", ms=4, label=_label(label, (comparisons or {}).get(label)))
    bands = next((c.bands for c in (comparisons or {}).values() if c.bands), ())
    for k, b in enumerate(bands):
        ax.axvspan(b.low * 1e3, b.high * 1e3, color="0.85" if k % 2 else "0.93", zorder=0)
    return _zeta_axes(ax)


def plot_phase_drift(comparisons: dict[str, ModelComparison], ax: Axes | None = None) -> Axes:
    """Phase drift of each model's negative peaks against the measurement [rad]."""
    ax = _axes(ax)
    for label, c in comparisons.items():
        ax.plot(np.arange(1, c.phase_drift.size + 1), c.phase_drift, "o-", ms=4, label=label)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel("negative peak n")
    ax.set_ylabel("phase drift 2 pi (t_model - t_measured) / T [rad]")
    ax.legend(fontsize="small")
    return ax


def plot_design_landscape(study: DesignStudyResult, ax: Axes | None = None) -> Axes:
    """Objective over the design variables of a design study
    (:class:`~pdamper.design.DesignStudyResult`); infeasible designs as grey crosses,
    failed ones as red crosses, the best as a star, the designs on the Pareto front of
    added mass against the objective ringed, the lightest design within the study's
    tolerance of the best as a green diamond.

    One variable: objective against it (designs evaluated from several realisations:
    their mean, the min-max shaded). Two or more: the first two variables as axes, the
    objective as colour (categorical variables by index).
    """
    ax = _axes(ax)
    names = [v.name for v in study.variables]
    unit, ylabel = study.objective.display_scale, study.objective.label
    if len(names) == 1:
        _landscape_of_one(ax, study, names, unit, ylabel)
    else:
        _landscape_of_two(ax, study, names, unit, ylabel)
    ax.legend(fontsize="x-small")
    return ax


def _coord(v: DesignVariable, c: DesignCandidate) -> float:
    """The axis coordinate of design ``c`` along ``v`` (mm, g, %, a count, a material's
    index)."""
    from pdamper.design.study import DESIGN_VARIABLES

    value = c.design[v.name]
    if v.kind == "categorical":
        return float(list(v.values).index(value)) if v.values else 0.0
    return (value * DESIGN_VARIABLES[v.name].display[1] if v.kind == "continuous"
            else float(value))


def _axis_label(v: DesignVariable) -> str:
    return {"particles": "particle count n_p", "radius": "sphere radius [mm]",
            "container_length": "container length [mm]",
            "container_width": "container width [mm]",
            "container_depth": "container depth [mm]",
            "particle_material": "particle material", "bed_mass": "bed mass [g]",
            "fill": "fill [% of the lattice's count]"}[v.name]


def _outside(ax: Axes, xs: list[float], ys: list[float]) -> None:
    """Designs evaluated but outside the study's limits: open grey squares."""
    if xs:
        ax.plot(xs, ys, "s", ms=9, mfc="none", mec="0.45", mew=1.2,
                label="outside the limits (infeasible)")


def plot_design_front(study: DesignStudyResult, ax: Axes | None = None) -> Axes:
    """The designs of a study by mass (bed plus container [g]) and objective: the Pareto
    front of the designs within the limits as a line, the designs outside them marked
    (open grey squares), the mass limit and a limit on the objective itself as dashed
    lines, the best as a star and the lightest within the tolerance as a green diamond."""
    from pdamper.design.study import LIMIT_QUANTITIES

    ax = _axes(ax)
    unit = study.objective.display_scale
    ok = [c for c in study.candidates if c.status == "ok" and c.objective is not None]
    inside = [c for c in ok if not c.violations]

    def xy(cs):
        return [c.total_mass * 1e3 for c in cs], [_objective(c) * unit for c in cs]

    if inside:
        ax.plot(*xy(inside), "o", color="C0", ms=5, label="designs within the limits")
    _outside(ax, *xy([c for c in ok if c.violations]))
    front = study.front
    if front:
        ax.plot(*xy(front), "-", color="k", lw=1, label="Pareto front")
    _front_spread(ax, ok, front, unit)
    for lim in study.limits:
        if lim.quantity == "mass":
            ax.axvline(lim.value * 1e3, ls="--", color="r", lw=1,
                       label=f"limit: {lim.describe()}")
        elif LIMIT_QUANTITIES[lim.quantity][2].get(study.objective.name) == "objective":
            ax.axhline(lim.value * unit, ls="--", color="r", lw=1,
                       label=f"limit: {lim.describe()}")
    if study.best is not None:
        ax.plot(*xy([study.best]), "r*", ms=14, label="best")
    light = study.lightest_within
    if light is not None:
        ax.plot(*xy([light]), "gD", ms=8,
                label=f"lightest within {study.tolerance * 100:g} %")
    ax.set_xlabel("mass of bed and container [g]")
    ax.set_ylabel(study.objective.label)
    ax.legend(fontsize="x-small")
    return ax


def has_spread(study: DesignStudyResult) -> bool:
    """Whether the study's designs carry a spread of their objective (``objective_std``:
    under the uncertain inputs, or over realisations)."""
    return any("objective_std" in c.extra for c in study.candidates)


def _front_spread(ax: Axes, ok: Sequence[DesignCandidate], front: Sequence[DesignCandidate],
                  unit: float) -> None:
    """Each design's spread on the mass-objective plane: its mean +- one standard
    deviation as an error bar (``objective_mean``, ``objective_std``; over realisations
    the objective is the mean), and along the Pareto front the band of the 5-95 %
    percentiles under the uncertain inputs (``objective_p5``, ``objective_p95``) or the
    realisations' min-max."""
    spread = [c for c in ok if "objective_std" in c.extra]
    if not spread:
        return
    ax.errorbar([(c.total_mass or 0.0) * 1e3 for c in spread],
                [float(c.extra.get("objective_mean", _objective(c))) * unit for c in spread],
                yerr=[c.extra["objective_std"] * unit for c in spread], fmt="none",
                ecolor="C0", elinewidth=1, capsize=3, label="mean +- std of each design")
    band = [c for c in front if "objective_std" in c.extra]
    lo, hi = (("objective_p5", "objective_p95") if band and "objective_p5" in band[0].extra
              else ("objective_min", "objective_max"))
    if band and all(lo in c.extra for c in band):
        ax.fill_between([(c.total_mass or 0.0) * 1e3 for c in band],
                        [float(c.extra[lo]) * unit for c in band],
                        [float(c.extra[hi]) * unit for c in band],
                        color="0.6", alpha=0.3, lw=0,
                        label="front's 5-95 %" if lo == "objective_p5"
                        else "front's min-max of the realisations")


def _objective(c: DesignCandidate) -> float:
    """The objective of an evaluated (``"ok"``) design, which has one."""
    assert c.objective is not None
    return c.objective


def _landscape_of_one(ax: Axes, study: DesignStudyResult, names: list[str], unit: float,
                      ylabel: str) -> None:
    """One variable: the objective against it, with its realisations' band."""
    ok = [c for c in study.candidates if c.status == "ok"]
    bad = [c for c in study.candidates if c.status != "ok"]
    v0 = study.variables[0]
    pts = sorted(ok, key=lambda c: _coord(v0, c))
    line, = ax.plot([_coord(v0, c) for c in pts], [_objective(c) * unit for c in pts], "o-",
                    label="designs")
    if pts and all("objective_min" in c.extra for c in pts):  # realisations: their band
        ax.fill_between([_coord(v0, c) for c in pts],
                        [c.extra["objective_min"] * unit for c in pts],
                        [c.extra["objective_max"] * unit for c in pts],
                        color=line.get_color(), alpha=0.25, lw=0,
                        label="min-max of the realisations (line: their mean)")
    out = [c for c in pts if c.violations]
    _outside(ax, [_coord(v0, c) for c in out], [_objective(c) * unit for c in out])
    if bad:
        y0 = min((_objective(c) * unit for c in ok), default=0.0)
        for status, color in (("infeasible", "0.5"), ("failed", "r")):
            sel = [c for c in bad if c.status == status]
            if sel:
                ax.plot([_coord(v0, c) for c in sel], [y0] * len(sel), "x", color=color,
                        label=status)
    if study.best is not None:
        ax.plot([_coord(v0, study.best)], [_objective(study.best) * unit], "r*", ms=14,
                label=f"best: {_describe(study.best, names)}")
    front, light = study.front, study.lightest_within
    if front:
        ax.plot([_coord(v0, c) for c in front], [_objective(c) * unit for c in front], "o",
                ms=11, mfc="none", mec="k", label="Pareto front (mass vs objective)")
    if light is not None:
        ax.plot([_coord(v0, light)], [_objective(light) * unit], "gD", ms=9,
                label=f"lightest within {study.tolerance * 100:g} %: "
                      f"{_describe(light, names)}")
    ax.set_xlabel(_axis_label(v0))
    ax.set_ylabel(ylabel)


def _landscape_of_two(ax: Axes, study: DesignStudyResult, names: list[str], unit: float,
                      ylabel: str) -> None:
    """Two or more variables: the first two as axes, the objective as colour."""
    ok = [c for c in study.candidates if c.status == "ok"]
    bad = [c for c in study.candidates if c.status != "ok"]
    v0, v1 = study.variables[0], study.variables[1]
    if ok:
        m = ax.scatter([_coord(v0, c) for c in ok], [_coord(v1, c) for c in ok],
                       c=[_objective(c) * unit for c in ok], cmap="viridis_r"
                       if study.objective.sense == "min" else "viridis", s=60,
                       edgecolors="k", linewidths=0.3)
        ax.figure.colorbar(m, ax=ax, label=ylabel)
    out = [c for c in ok if c.violations]
    _outside(ax, [_coord(v0, c) for c in out], [_coord(v1, c) for c in out])
    for status, color in (("infeasible", "0.5"), ("failed", "r")):
        sel = [c for c in bad if c.status == status]
        if sel:
            ax.plot([_coord(v0, c) for c in sel], [_coord(v1, c) for c in sel], "x",
                    color=color, label=status)
    if study.best is not None:
        ax.plot([_coord(v0, study.best)], [_coord(v1, study.best)], "r*", ms=16,
                label=f"best: {_describe(study.best, names)}")
    front, light = study.front, study.lightest_within
    if front:
        ax.plot([_coord(v0, c) for c in front], [_coord(v1, c) for c in front], "o", ms=13,
                mfc="none", mec="k", label="Pareto front (mass vs objective)")
    if light is not None:
        ax.plot([_coord(v0, light)], [_coord(v1, light)], "gD", ms=9,
                label=f"lightest within {study.tolerance * 100:g} %: "
                      f"{_describe(light, names)}")
    for v, setter in ((v0, ax.set_xticks), (v1, ax.set_yticks)):
        if v.kind == "categorical" and v.values is not None:  # (a categorical has values)
            setter(range(len(v.values)), list(v.values))
    ax.set_xlabel(_axis_label(v0))
    ax.set_ylabel(_axis_label(v1))
    if len(names) > 2:
        ax.set_title(f"{len(names) - 2} more variable(s) not shown on the axes",
                     fontsize="small")


def _describe(c: DesignCandidate, names: list[str]) -> str:
    from pdamper.design.study import show_value

    return ", ".join(show_value(n, c.design[n]) for n in names)


def plot_mode_study(study: ModeCountStudy, ax: Axes | None = None) -> Axes:
    """Amplitude at T against the number of retained modes, one line per damper position
    (a :class:`~pdamper.coupling.modal.ModeCountStudy`)."""
    ax = _axes(ax)
    for k, pos in enumerate(study.positions):
        ax.plot(study.modes, np.asarray(study.amplitude[k]) * 1e3, "o-",
                label=f"damper at x = {pos * 1e3:.0f} mm")
    ax.set_xlabel("retained bending modes N")
    ax.set_ylabel(f"amplitude at t = {study.at:g} s [mm]")
    ax.set_xticks(list(study.modes))
    ax.legend(fontsize="small")
    if not math.isnan(study.at):
        ax.set_title("when is one mode enough?", fontsize="medium")
    return ax


def _zeta_axes(ax):
    """Label the damping-ratio axes of Fig. 8 (the amplitude falling to the right)."""
    ax.set_xlabel("mean amplitude X_n+1/2 [mm]")
    ax.set_ylabel("damping ratio zeta [-]")
    if not ax.xaxis_inverted():
        ax.invert_xaxis()
    ax.legend(fontsize="x-small")
    return ax


def plot_trajectory_band(band: _Band, ax: Axes | None = None, label: str | None = None) -> Axes:
    """End-effector trajectory of N realisations as a band (Fig. 7): the mean of the
    sampled trajectories as a line, their pointwise min-max shaded, and the amplitude at
    ``band.at`` as a point with its min-max bar (drawn at -X, on the negative peaks' side).

    ``band``: a :class:`~pdamper.runs.realisations.Level3Band` (``trajectory()``,
    ``amplitude_at()``, ``at``, ``count``).
    """
    ax = _axes(ax)
    tr = band.trajectory()
    name = label or band.model
    line, = ax.plot(tr["time"], tr["mean"] * 1e3, lw=1,
                    label=f"{name}: mean of {band.count} realisations, min-max shaded")
    ax.fill_between(tr["time"], tr["min"] * 1e3, tr["max"] * 1e3, color=line.get_color(),
                    alpha=0.3, lw=0)
    a = band.amplitude_at()
    ax.errorbar([band.at], [-a["mean"] * 1e3],
                yerr=[[(a["max"] - a["mean"]) * 1e3], [(a["mean"] - a["min"]) * 1e3]],
                fmt="o", color=line.get_color(), ms=4, capsize=4,
                label=f"{name}: X({band.at:g} s) = {a['mean'] * 1e3:.2f} mm "
                      f"[{a['min'] * 1e3:.2f}, {a['max'] * 1e3:.2f}]")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("end-effector displacement x [mm]")
    ax.legend(fontsize="x-small", loc="lower right")
    return ax


def plot_damping_ratio_band(band: _Band, ax: Axes | None = None,
                            label: str | None = None) -> Axes:
    """Damping ratio per amplitude of N realisations (Fig. 8): the mean line over the
    amplitudes every realisation covers, the min-max of the realisations shaded."""
    ax = _axes(ax)
    rows = band.damping_ratio()
    name = label or band.model
    if rows:
        a = np.array([r["amplitude"] for r in rows]) * 1e3
        line, = ax.plot(a, [r["mean"] for r in rows], "o-", ms=3,
                        label=f"{name}: mean of {band.count} realisations, min-max shaded")
        ax.fill_between(a, [r["min"] for r in rows], [r["max"] for r in rows],
                        color=line.get_color(), alpha=0.3, lw=0)
    return _zeta_axes(ax)
