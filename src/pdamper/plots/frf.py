"""Figure of a forced response (:class:`~pdamper.coupling.frf.FRFResult`): amplitude and
phase against frequency, every harmonic-balance branch and the stepped sines."""

from __future__ import annotations

import numpy as np


def plot_frf(res, axes=None, label: str | None = None, linear: bool = True,
             color: str = "C0"):
    """Amplitude [mm] (top) and phase [deg] (bottom) of the output point against f [Hz].

    Harmonic balance: stable solutions as a solid line of dots, unstable ones hollow, edges
    (describing-function discontinuities) as crosses; stepped sines as lines with
    triangles pointing in their direction (points that did not become steady hollow).
    ``axes``: two matplotlib Axes (a new figure when None); ``color``: of the stable
    harmonic-balance solutions (another per model where several share the axes). Returns
    them.
    """
    if axes is None:
        from matplotlib.figure import Figure

        axes = Figure(figsize=(8, 6.5), layout="constrained").subplots(2, 1, sharex=True)
    amp_ax, ph_ax = axes
    f = res.frequency
    tag = f"{label}: " if label else ""
    if linear:
        amp_ax.plot(f, np.abs(res.linear) * 1e3, color="0.6", lw=1, ls="--",
                    label=f"{tag}no particles")
        ph_ax.plot(f, np.degrees(np.angle(res.linear)), color="0.6", lw=1, ls="--")
    hb = res.harmonic_balance
    if hb is not None:
        style = {"stable": dict(marker="o", ms=3, ls="none", color=color),
                 "unstable": dict(marker="o", ms=4, ls="none", mfc="none", color="C3"),
                 "edge": dict(marker="x", ms=4, ls="none", color="C7")}
        for kind, st in style.items():
            sel = hb.branch == kind
            if np.any(sel):
                ff = np.broadcast_to(f[:, None], sel.shape)[sel]
                amp_ax.plot(ff, hb.amplitude[sel] * 1e3, label=f"{tag}harmonic balance, {kind}",
                            **st)
                ph_ax.plot(ff, np.degrees(hb.phase[sel]), **st)
    marks = {"up": (">", "C1"), "down": ("<", "C2")}
    for name, c in res.sweeps.items():
        mk, col = marks.get(name, ("s", "C4"))
        amp_ax.plot(f, c.amplitude * 1e3, color=col, lw=1, label=f"{tag}stepped sine {name}")
        amp_ax.plot(f[c.steady], c.amplitude[c.steady] * 1e3, mk, ms=4, color=col)
        if np.any(~c.steady):
            amp_ax.plot(f[~c.steady], c.amplitude[~c.steady] * 1e3, mk, ms=5, mfc="none",
                        color=col, label=f"{tag}{name}: not steady")
        ph_ax.plot(f, np.degrees(c.phase), color=col, lw=1)
    amp_ax.set_ylabel("amplitude [mm]")
    amp_ax.legend(fontsize=8)
    amp_ax.grid(alpha=0.3)
    ph_ax.set_ylabel("phase [deg]")
    ph_ax.set_xlabel("frequency [Hz]")
    ph_ax.set_ylim(-190, 10)
    ph_ax.grid(alpha=0.3)
    ld = res.load
    amp_ax.set_title(f"forced response, {res.model} model, {ld.kind} {ld.amplitude:g} {ld.unit}")
    return axes
