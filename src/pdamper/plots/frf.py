"""Figure of a forced response (:class:`~pdamper.coupling.frf.FRFResult`): amplitude and
phase against frequency, every harmonic-balance branch and the stepped sines, the bare
structure's response beside them, and (on a third axes) the damper's loss factor with its
motion mode along the response. Titles, labels and units are the user's (mm, Hz, the load
as given): no figure numbers of the paper."""

from __future__ import annotations

import numpy as np


def plot_frf(res, axes=None, label: str | None = None, linear: bool = True,
             color: str = "C0"):
    """Amplitude [mm] (top) and phase [deg] (below) of the output point against f [Hz],
    and, where ``axes`` holds a third Axes, the damper's loss factor eta [-] along the
    response, its points coloured by the bed's motion mode.

    Harmonic balance: stable solutions as a solid line of dots, unstable ones hollow, edges
    (describing-function discontinuities) as crosses; stepped sines as lines with
    triangles pointing in their direction (points that did not become steady hollow).
    ``axes``: two or three matplotlib Axes (a new figure of three when None); ``linear``:
    draw the bare structure's response (no particles, closed form, dashed grey);
    ``color``: of the stable harmonic-balance solutions (another per model where several
    share the axes). Returns them.
    """
    if axes is None:
        from matplotlib.figure import Figure

        axes = Figure(figsize=(8, 8.5), layout="constrained").subplots(3, 1, sharex=True)
    amp_ax, ph_ax = axes[0], axes[1]
    eta_ax = axes[2] if len(axes) > 2 else None
    f = res.frequency
    tag = f"{label}: " if label else ""
    if linear:
        amp_ax.plot(f, np.abs(res.linear) * 1e3, color="0.6", lw=1, ls="--",
                    label=f"{tag}bare structure (no particles)")
        ph_ax.plot(f, _lag(np.angle(res.linear)), color="0.6", lw=1, ls="--")
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
                ph_ax.plot(ff, _lag(hb.phase[sel]), **st)
    marks = {"up": (">", "C1"), "down": ("<", "C2")}
    for name, c in res.sweeps.items():
        mk, col = marks.get(name, ("s", "C4"))
        amp_ax.plot(f, c.amplitude * 1e3, color=col, lw=1, label=f"{tag}stepped sine {name}")
        amp_ax.plot(f[c.steady], c.amplitude[c.steady] * 1e3, mk, ms=4, color=col)
        if np.any(~c.steady):
            amp_ax.plot(f[~c.steady], c.amplitude[~c.steady] * 1e3, mk, ms=5, mfc="none",
                        color=col, label=f"{tag}{name}: not steady")
        ph_ax.plot(f, _lag(c.phase), color=col, lw=1)
    _mark_outside_assumptions(res, amp_ax, tag)
    amp_ax.set_ylabel("amplitude [mm]")
    amp_ax.legend(fontsize=8)
    amp_ax.grid(alpha=0.3)
    ph_ax.set_ylabel("phase [deg]")
    low = min((float(np.nanmin(line.get_ydata())) for line in ph_ax.get_lines()
               if np.size(line.get_ydata()) and np.any(np.isfinite(line.get_ydata()))),
              default=-180.0)
    ph_ax.set_ylim(-370 if low < -185 else -190, 10)
    ph_ax.grid(alpha=0.3)
    if eta_ax is not None:
        _loss_factor(res, eta_ax, tag, color)
    axes[-1].set_xlabel("frequency [Hz]")
    amp_ax.set_title(f"forced response, {res.model} model, {res.load.describe()}")
    return axes


def _mark_outside_assumptions(res, ax, tag: str) -> None:
    """Ring the answers (stepped sines, harmonic-balance solutions) found where the damper
    model's assumptions fail (``assumptions_hold`` false, :mod:`pdamper.coupling.frf`);
    the legend names the checks that failed and the fidelity to use there."""
    from pdamper.analysis.analytical import assumption_kinds

    ff, aa, kinds = [], [], {}
    curves = list(res.sweeps.values())
    if res.harmonic_balance is not None:
        curves.append(res.harmonic_balance)
    for c in curves:
        if "assumptions_hold" not in c.diagnostics:
            continue
        bad = ~np.asarray(c.diagnostics["assumptions_hold"], bool) & np.isfinite(c.amplitude)
        ff.append(np.broadcast_to(res.frequency.reshape((-1,) + (1,) * (bad.ndim - 1)),
                                  bad.shape)[bad])
        aa.append(np.asarray(c.amplitude)[bad] * 1e3)
        for r in np.asarray(c.diagnostics["assumptions"], object)[bad]:
            kinds.update(dict.fromkeys(assumption_kinds(r)))
    if not ff or not np.concatenate(ff).size:
        return
    names = ", ".join(k.replace("_", " ") for k in kinds) or "assumptions"
    ax.plot(np.concatenate(ff), np.concatenate(aa), "o", ms=8, mfc="none", mec="k", mew=0.8,
            ls="none", label=f"{tag}outside the analytic model's assumptions ({names}): "
                             "use fields from a DEM map, or dem")


def _lag(phase) -> np.ndarray:
    """A phase [rad] as a lag in degrees, in (-360, 0] (a 1-DOF's stays in (-180, 0]; past
    a second mode the lag runs on instead of wrapping to +180)."""
    return -np.mod(-np.degrees(np.asarray(phase, float)), 360.0)


def _loss_factor(res, ax, tag: str, color: str) -> None:
    """The damper's loss factor along the response (the sweeps, else the stable
    harmonic-balance solutions), each point coloured by its motion mode."""
    from pdamper.coupling.pseudo_force import motion_mode

    f = res.frequency
    curves = [(c.loss_factor, c.mode) for c in res.sweeps.values()]
    if not curves and res.harmonic_balance is not None:
        hb = res.harmonic_balance
        eta = np.where(hb.steady, hb.loss_factor, np.nan)
        j = np.argmax(np.where(hb.steady, hb.amplitude, -np.inf), axis=1)
        rows = np.arange(f.size)
        curves = [(eta[rows, j], hb.mode[rows, j])]
    seen: set[int] = set()
    for eta, mode in curves:
        ax.plot(f, eta, color=color, lw=0.8, alpha=0.6)
        for code in np.unique(mode):
            sel = mode == code
            m = motion_mode(code)
            text = m.title if m is not None else "no motion mode"
            ax.plot(f[sel], eta[sel], "o", ms=3, color=f"C{(int(code) + 2) % 10}",
                    label=None if int(code) in seen else f"{tag}{text}")
            seen.add(int(code))
    ax.set_ylabel("damper loss factor eta [-]")
    ax.grid(alpha=0.3)
    if seen:
        ax.legend(fontsize=7, title="motion mode", title_fontsize=7)
