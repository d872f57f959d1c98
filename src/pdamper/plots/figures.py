"""Plot functions for the paper's figures (Figs. 4, 5, 7, 8, 9)."""

from __future__ import annotations

import math

import numpy as np

from pdamper.analysis.modes import MotionMode
from pdamper.constants import STANDARD_GRAVITY

_MODE_COLORS = {
    MotionMode.SOLID: "#3b4cc0",
    MotionMode.SINGLE_CAC_HARMONIC: "#4daf4a",
    MotionMode.SINGLE_CAC_SUBHARMONIC: "#a6d96a",
    MotionMode.DOUBLE_CAC_HARMONIC: "#d7301f",
    MotionMode.DOUBLE_CAC_SUBHARMONIC: "#fdae61",
    MotionMode.SCATTERING: "#999999",
}


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
    ax.set_ylim(ds["amplitude"].values.min() * 1e3, ds["amplitude"].values.max() * 1e3)


def plot_mode_map(ds, ax=None):
    """Motion modes over frequency and stroke (Fig. 5a).

    Parameters
    ----------
    ds : xarray.Dataset
        An effective field with ``motion_mode`` (see :func:`pdamper.analysis.fields.effective_field`).
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    ax = _axes(ax)
    modes = list(MotionMode)
    cmap = ListedColormap([_MODE_COLORS[m] for m in modes])
    norm = BoundaryNorm(np.arange(len(modes) + 1) - 0.5, cmap.N)
    f = ds["frequency"].values
    x = ds["amplitude"].values * 1e3
    ax.pcolormesh(f, x, ds["motion_mode"].values.T, cmap=cmap, norm=norm, shading="nearest")
    _grid_lines(ax, ds)
    handles = [Patch(color=_MODE_COLORS[m], label=m.title) for m in modes]
    ax.legend(handles=handles + ax.get_lines(), fontsize="x-small", loc="upper right")
    ax.set_xlabel("excitation frequency f [Hz]")
    ax.set_ylabel("container stroke X [mm]")
    return ax


def plot_loss_factor_map(ds, ax=None, variable: str = "loss_factor"):
    """Effective loss factor over frequency and stroke (Fig. 5b/5c), colour on a log scale
    from 0.1 (dark) to 1 (yellow) as in the paper."""
    from matplotlib.colors import LogNorm

    ax = _axes(ax)
    f = ds["frequency"].values
    x = ds["amplitude"].values * 1e3
    data = np.clip(ds[variable].values.T, 0.1, 1.0)
    m = ax.pcolormesh(f, x, data, cmap="viridis", norm=LogNorm(0.1, 1.0), shading="nearest")
    ax.figure.colorbar(m, ax=ax, label=ds[variable].attrs.get("long_name", variable))
    _grid_lines(ax, ds)
    ax.legend(fontsize="x-small", loc="upper right")
    ax.set_xlabel("excitation frequency f [Hz]")
    ax.set_ylabel("container stroke X [mm]")
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
