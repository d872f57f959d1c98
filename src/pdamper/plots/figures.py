"""Plot functions for the paper's figures (Figs. 4, 5, 7, 8, 9)."""

from __future__ import annotations

import math

import numpy as np

from pdamper.analysis.analytical import ETA_MAX
from pdamper.analysis.modes import MotionMode
from pdamper.constants import STANDARD_GRAVITY

_MODE_COLORS = {
    MotionMode.SOLID: "#3b4cc0",
    MotionMode.SINGLE_CAC_HARMONIC: "#4daf4a",
    MotionMode.SINGLE_CAC_SUBHARMONIC: "#a6d96a",
    MotionMode.DOUBLE_CAC_HARMONIC: "#d7301f",
    MotionMode.DOUBLE_CAC_SUBHARMONIC: "#fdae61",
    MotionMode.SCATTERING: "#999999",
    MotionMode.RATTLING: "#7b3294",
}
#: Colour of a point without a mode (not classified, or its run failed).
_NO_MODE_COLOR = "#ffffff"


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6.0, 4.0), layout="constrained")
    return ax


def plot_bed_trajectory(trajectory, ax=None):
    """Bed trajectory against the container walls (Fig. 4).

    Parameters
    ----------
    trajectory : pdamper.analysis.analytical.BedTrajectory
    """
    ax = _axes(ax)
    t = trajectory.time * 1e3
    ax.plot(t, trajectory.container_bottom * 1e3, "k--", lw=1, label="container bottom")
    ax.plot(t, trajectory.container_top * 1e3, "k:", lw=1, label="container top - bed")
    ax.plot(t, trajectory.bed * 1e3, color=_MODE_COLORS[trajectory.mode], lw=2,
            label=f"bed ({trajectory.mode.title})")
    ax.set_xlabel("time t [ms]")
    ax.set_ylabel("position [mm]")
    ax.legend(loc="best", fontsize="small")
    return ax


def _grid_lines(ax, ds, gravity=STANDARD_GRAVITY):
    f = ds["frequency"].values
    ff = np.linspace(f.min(), f.max(), 200)
    x_g = gravity / (2 * np.pi * ff) ** 2 * 1e3
    ax.plot(ff, x_g, "k--", lw=1, label="A = g")
    if "clearance" in ds.attrs:
        ax.axhline(ds.attrs["clearance"] / math.pi * 1e3, color="k", ls=":", lw=1,
                   label="X_opt = h / pi")
    lo, hi = ds["amplitude"].values.min() * 1e3, ds["amplitude"].values.max() * 1e3
    if hi > lo:  # (a one-stroke grid keeps the limits of its cell)
        ax.set_ylim(lo, hi)


def _mark_cells(ax, ds, hatch: str = "0.7") -> None:
    """Mark the cells that are no steady value: transients (x) and failed runs (grey x);
    hatch (in colour ``hatch``) those outside the analytical model's assumptions."""
    f = ds["frequency"].values
    x = ds["amplitude"].values * 1e3
    ff, xx = np.meshgrid(f, x, indexing="ij")
    failed = ds["status"].values != 0 if "status" in ds else np.zeros(ff.shape, bool)
    if "stationary" in ds:
        transient = (ds["stationary"].values == 0) & ~failed
        if transient.any():
            ax.plot(ff[transient], xx[transient], "kx", ms=4, mew=0.8, ls="none",
                    label="transient (not steady)")
    if failed.any():
        ax.plot(ff[failed], xx[failed], "x", color="0.45", ms=6, mew=1.5, ls="none",
                label="run failed")
    if "assumptions_hold" in ds:
        _hatch_outside_assumptions(ax, ds, ~failed, hatch)


def _edges(v: np.ndarray) -> np.ndarray:
    """Cell edges of a grid drawn with ``shading="nearest"`` (midpoints; a one-value grid
    gets a cell of +-5 %)."""
    if v.size == 1:
        return np.array([v[0] * 0.95, v[0] * 1.05]) if v[0] else np.array([-0.5, 0.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def _hatch_outside_assumptions(ax, ds, answered: np.ndarray, color: str) -> None:
    """Hatch the cells where the analytical model's assumptions fail (``assumptions_hold``
    0), the legend line naming the checks that failed and the fidelity to use there."""
    from matplotlib.collections import PolyCollection

    from pdamper.analysis.analytical import assumption_summary

    flagged = (ds["assumptions_hold"].values == 0) & answered
    if not flagged.any():
        return
    fe = _edges(np.asarray(ds["frequency"].values, float))
    xe = _edges(np.asarray(ds["amplitude"].values, float) * 1e3)
    verts = [[(fe[i], xe[j]), (fe[i + 1], xe[j]), (fe[i + 1], xe[j + 1]), (fe[i], xe[j + 1])]
             for i, j in zip(*np.nonzero(flagged), strict=True)]
    why = assumption_summary(ds["assumptions_hold"].values[answered] == 1,
                             ds["assumptions"].values[answered])
    kinds = ", ".join(k.replace("_", " ") for k in why["reasons"]) or "assumptions"
    ax.add_collection(PolyCollection(
        verts, facecolors="none", edgecolors=color, linewidths=0.0, hatch="////",
        label=f"outside the analytic model's assumptions ({kinds}):\n"
              "use fields from a DEM map, or dem"))


def _field_axes(ax, ds, hatch: str = "0.7") -> None:
    _grid_lines(ax, ds)
    _mark_cells(ax, ds, hatch)
    x = ds["amplitude"].values
    if x.size > 2 and np.all(x > 0) and np.allclose(np.diff(np.log(x)), np.log(x[1] / x[0])) \
            and not np.allclose(np.diff(x), x[1] - x[0]):
        ax.set_yscale("log")  # a geometric grid ("log:..."): equal cells
    ax.set_xlabel("excitation frequency f [Hz]")
    ax.set_ylabel("container stroke X [mm]")


def plot_mode_map(ds, ax=None):
    """Motion modes over frequency and stroke (Fig. 5a; from the DEM as well).

    Parameters
    ----------
    ds : xarray.Dataset
        An effective field with ``motion_mode`` (see :mod:`pdamper.analysis.fields`); for a
        particle-count axis select one count first (``ds.sel(particles=32)``). Transient
        cells (``stationary == 0``) and failed runs (``status == 1``) are marked.
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    ax = _axes(ax)
    codes = [-1] + [int(m) for m in MotionMode]
    colors = [_NO_MODE_COLOR] + [_MODE_COLORS[m] for m in MotionMode]
    cmap = ListedColormap(colors)
    norm = BoundaryNorm(np.arange(codes[0], codes[-1] + 2) - 0.5, cmap.N)
    f = ds["frequency"].values
    x = ds["amplitude"].values * 1e3
    data = ds["motion_mode"].values
    ax.pcolormesh(f, x, data.T, cmap=cmap, norm=norm, shading="nearest")
    _field_axes(ax, ds, hatch="k")
    present = set(np.unique(data).tolist())
    shown = [m for m in MotionMode if m is not MotionMode.RATTLING or int(m) in present]
    handles = [Patch(color=_MODE_COLORS[m], label=m.title) for m in shown]
    if -1 in present:
        handles.append(Patch(facecolor=_NO_MODE_COLOR, edgecolor="0.5", label="no mode"))
    marked = [c for c in ax.collections if not str(c.get_label()).startswith("_")]
    ax.legend(handles=handles + ax.get_lines() + marked, fontsize="x-small",
              loc="upper right")
    return ax


def plot_loss_factor_map(ds, ax=None, variable: str = "loss_factor", vmin: float = 0.1,
                         vmax: float | None = None):
    """Effective loss factor over frequency and stroke (Fig. 5b/5c) on a log colour scale
    from ``vmin`` (dark; the paper: 0.1 or less) to ``vmax`` (default: 4/pi = 1.27, the
    collect-and-collide optimum of Eq. 21, or the field's maximum if larger), so that the
    band between 1 and 1.27 stays visible; transient and failed cells are marked."""
    from matplotlib.colors import LogNorm

    ax = _axes(ax)
    f = ds["frequency"].values
    x = ds["amplitude"].values * 1e3
    values = np.asarray(ds[variable].values, float)
    top = ETA_MAX if vmax is None else vmax
    if vmax is None and np.isfinite(values).any():
        top = max(top, float(np.nanmax(values)))
    data = np.clip(values.T, vmin, top)
    m = ax.pcolormesh(f, x, data, cmap="viridis", norm=LogNorm(vmin, top), shading="nearest")
    cb = ax.figure.colorbar(m, ax=ax, label=ds[variable].attrs.get("long_name", variable))
    ticks = [t for t in (0.1, 0.2, 0.5, 1.0, ETA_MAX, 2.0, 5.0) if vmin <= t <= top]
    cb.set_ticks(ticks, labels=[("4/pi" if t == ETA_MAX else f"{t:g}") for t in ticks])
    _field_axes(ax, ds)
    ax.legend(fontsize="x-small", loc="upper right")
    return ax


def plot_effective_mass_map(ds, ax=None, vmax: float | None = None):
    """Effective particle mass over bed mass (Fig. 5d), linear colour scale from 0 to
    ``vmax`` (default: 1, or the field's maximum if larger)."""
    ax = _axes(ax)
    f = ds["frequency"].values
    x = ds["amplitude"].values * 1e3
    values = np.asarray(ds["effective_mass_ratio"].values, float)
    top = 1.0 if vmax is None else vmax
    if vmax is None and np.isfinite(values).any():
        top = max(top, float(np.nanmax(values)))
    m = ax.pcolormesh(f, x, values.T, cmap="cividis", vmin=0.0, vmax=top, shading="nearest")
    ax.figure.colorbar(m, ax=ax, label="effective particle mass / bed mass")
    _field_axes(ax, ds)
    ax.legend(fontsize="x-small", loc="upper right")
    return ax


def plot_field_difference(ds, reference, ax=None, variable: str = "loss_factor",
                          limit: float | None = None):
    """``ds - reference`` of ``variable`` (e.g. DEM minus analytical loss factor) on the
    grid of ``ds`` (``reference`` interpolated onto it where the grids differ), diverging
    colours symmetric about 0 (``limit``: the colour range, default the largest
    difference)."""
    ax = _axes(ax)
    ref = reference[variable]
    same = (np.array_equal(reference["frequency"].values, ds["frequency"].values)
            and np.array_equal(reference["amplitude"].values, ds["amplitude"].values))
    if not same:
        ref = ref.interp(frequency=ds["frequency"], amplitude=ds["amplitude"])
    diff = np.asarray(ds[variable].values, float) - np.asarray(ref.values, float)
    lim = limit if limit is not None else (float(np.nanmax(np.abs(diff)))
                                           if np.isfinite(diff).any() else 1.0)
    lim = lim or 1.0
    f = ds["frequency"].values
    x = ds["amplitude"].values * 1e3
    m = ax.pcolormesh(f, x, diff.T, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="nearest")
    name = ds[variable].attrs.get("long_name", variable)
    ax.figure.colorbar(m, ax=ax, label=f"difference of {name}")
    _field_axes(ax, ds)
    ax.legend(fontsize="x-small", loc="upper right")
    return ax


def plot_particle_snapshots(result, ax=None, count: int = 8, cycle: int | None = None,
                            vmax: float | None = None):
    """Fig. 3: the particles at ``count`` instants of one excitation cycle, side view
    (x-z), coloured by the particle speed over the container velocity amplitude V.

    Parameters
    ----------
    result : pdamper.dem.DEMResult
        A harmonic run recorded with snapshots (``snapshot_rate`` of at least ``count``
        per cycle).
    count
        Instants shown, evenly spread over the cycle [-].
    cycle
        Which cycle (1-based; default the last whole one).
    vmax
        Top of the colour scale [-] (default: 1, or the largest speed if larger).
    """
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle, Rectangle

    from pdamper.errors import InputError

    ax = _axes(ax)
    f = result.frequency
    if f is None:
        raise InputError("result", "Fig. 3 snapshots need a harmonic excitation")
    ts = np.asarray(result.snapshot_time)
    n_cycles = int(np.floor(result.simulated_time * f + 1e-9))
    c = n_cycles if cycle is None else int(cycle)
    if not 1 <= c <= n_cycles:
        raise InputError("cycle", f"must be in [1, {n_cycles}], got {cycle}")
    t_lo, t_hi = (c - 1) / f, c / f
    wanted = t_lo + (np.arange(count) + 0.5) / count / f
    idx = np.unique([int(np.argmin(np.abs(ts - t))) for t in wanted])
    idx = idx[(ts[idx] >= t_lo - 0.5 / f / count) & (ts[idx] <= t_hi + 0.5 / f / count)]
    if idx.size < 2:
        raise InputError("snapshot_rate", f"the run holds {ts.size} snapshots; record at least "
                         f"{count} per cycle (snapshot_rate >= {count * f:g} Hz)")
    box = result.attrs.get("box_m", [0.04, 0.04, 0.12])
    lx, lz = float(box[0]), float(box[2])
    amp = float(result.attrs.get("amplitude_m", np.ptp(result.container_position) / 2))
    v_amp = 2 * np.pi * f * amp
    gap = 0.35 * lx
    patches, speeds = [], []
    for k, i in enumerate(idx):
        x0 = k * (lx + gap)
        zc = float(np.interp(ts[i], result.time, result.container_position))
        ax.add_patch(Rectangle((x0 * 1e3, zc * 1e3), lx * 1e3, lz * 1e3, fill=False, lw=1.2))
        pos = result.snapshot_positions[i]
        vel = result.snapshot_velocities[i]
        for p, r, v in zip(pos, result.radius, vel, strict=True):
            patches.append(Circle(((x0 + p[0]) * 1e3, p[2] * 1e3), r * 1e3))
            speeds.append(float(np.linalg.norm(v)) / v_amp)
        phase = (ts[i] - t_lo) * f
        ax.text((x0 + lx / 2) * 1e3, (zc + lz) * 1e3 + 4, f"{phase:.2f} T", ha="center",
                fontsize="x-small")
    coll = PatchCollection(patches, cmap="jet", edgecolor="k", linewidth=0.2)
    coll.set_array(np.asarray(speeds))
    coll.set_clim(0.0, max(1.0, float(np.max(speeds))) if vmax is None else vmax)
    ax.add_collection(coll)
    ax.figure.colorbar(coll, ax=ax, label="particle speed / V")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xticks([])
    ax.set_ylabel("height z [mm]")
    ax.set_xlabel(f"one cycle (cycle {c}), time in periods T = {1e3 / f:.4g} ms")
    return ax


def plot_free_vibration(result, ax=None, label: str | None = None, envelope=None):
    """End-effector trajectory (Figs. 7, 9), optionally with the envelope of another run
    (e.g. without particles)."""
    ax = _axes(ax)
    ax.plot(result.time, result.displacement * 1e3, lw=1, label=label or result.model)
    if envelope is not None:
        ax.plot(envelope.peak_times, -envelope.peak_amplitudes * 1e3, "k--", lw=1,
                label="envelope without particles")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("end-effector displacement x [mm]")
    ax.legend(fontsize="small")
    return ax


def plot_damping_ratio(result, ax=None, label: str | None = None):
    """Damping ratio over the mean cycle amplitude (Fig. 8, Eqs. 24-25)."""
    ax = _axes(ax)
    amp, zeta = result.damping_ratio
    ax.plot(amp * 1e3, zeta, "o-", ms=4, label=label or result.model)
    ax.set_xlabel("mean amplitude X_n+1/2 [mm]")
    ax.set_ylabel("damping ratio zeta [-]")
    if not ax.xaxis_inverted():  # once, also when several runs share the axes
        ax.invert_xaxis()
    ax.legend(fontsize="small")
    return ax


def plot_optimization(opt, ax=None):
    """Objective over the particle count (Sect. 4.2.2)."""
    ax = _axes(ax)
    n = [c.particles for c in opt.candidates]
    obj = [c.objective * 1e3 for c in opt.candidates]
    ax.plot(n, obj, "o-")
    ax.plot([opt.best.particles], [opt.best.objective * 1e3], "r*", ms=14,
            label=f"best: {opt.best.particles} particles")
    ax.set_xlabel("particle count n_p")
    ax.set_ylabel(f"amplitude at t = {opt.at:g} s [mm]")
    ax.legend(fontsize="small")
    return ax


def plot_step_profile(profile, ax=None):
    """Where a DEM run's steps go within the excitation cycle: the share of the steps and
    of the integrator's wall time in each phase bin (bars), and the mean step (line, right
    axis).

    Parameters
    ----------
    profile : xarray.Dataset
        :meth:`pdamper.dem.DEMResult.step_profile`.
    """
    ax = _axes(ax)
    phase = profile["phase"].values
    width = phase[1] - phase[0] if phase.size > 1 else 1.0
    ax.bar(phase, 100 * profile["step_share"].values, width=0.9 * width, color="#9ecae1",
           label="steps")
    ax.step(phase, 100 * profile["wall_share"].values, where="mid", color="#08519c",
            label="wall time")
    ax.set_xlabel("phase of z_c = X sin(2 pi f t) [-]")
    ax.set_ylabel("share of the run [%]")
    top = 100 * max(float(profile["step_share"].max()), float(profile["wall_share"].max()))
    ax.set_ylim(0.0, 1.3 * top if top > 0 else 1.0)  # room for the legend
    right = ax.twinx()
    right.plot(phase, 1e6 * profile["mean_step"].values, "o-", color="#d7301f", ms=3,
               label="mean step")
    right.set_ylabel("mean step [us]", color="#d7301f")
    right.set_yscale("log")
    steps_us = 1e6 * profile["mean_step"].values
    if np.isfinite(steps_us).any():
        right.set_ylim(np.nanmin(steps_us) / 1.5, 4.0 * np.nanmax(steps_us))
    ax.set_title(f"{profile.attrs['integrator']}, {profile.attrs['particles']} spheres, "
                 f"{profile.attrs['cycles']} cycles, {profile.attrs['steps']} steps",
                 fontsize="small")
    # one legend, on the right axes (drawn over the left one)
    handles = ax.get_legend_handles_labels()
    more = right.get_legend_handles_labels()
    right.legend(handles[0] + more[0], handles[1] + more[1], loc="upper center",
                 fontsize="small", framealpha=0.9, ncols=3)
    return ax
