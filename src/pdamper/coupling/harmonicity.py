"""How near-harmonic the motion is that a describing-function damper was evaluated on.

The pseudo-force coupling (Sect. 4.1, models 2 and 3) takes the damper's loss factor and
effective mass from its *harmonic* response (Eqs. 2-4) at one amplitude and frequency per
cycle, and holds them until the next update. That is the damper's force where the damper
point moves near-harmonically over each stretch between two updates; on a beating sum of
modes or a shock it is not, and the loss factor it carries can be far off (jumping 0 <-> 0.7
from cycle to cycle on a two-mode shock).

The measure, per update ``k`` at ``t_k`` (amplitude ``X_k``, frequency ``f_k``): the RMS
deviation of the damper point's motion over the next period ``T_k = 1 / f_k`` from the
harmonic motion the describing function assumed there,

    x_h(t) = x(t_k) + X_k (1 - cos(2 pi f_k (t - t_k))),
    e_k = RMS_{[t_k, t_k + T_k]}(x - x_h) / (X_k / sqrt 2),

0 for a sine at the update's amplitude and frequency (a lightly damped decay: a few %; the
paper's 1-DOF decay with its heavy bed, whose amplitude drops by a quarter a cycle: 0.15),
about 1 where the motion is as far from that sine as the sine is from rest. The run's
measure is the mean of ``e_k`` weighted by the energy the damper dissipates over that
period by its describing function, ``E~_k = pi d_k W_k X_k^2`` (Eq. 2 with
``d = E~ / (pi W X^2)``): the periods that decide the answer count. The run is
**near-harmonic** where it is at most :data:`NEAR_HARMONIC_DEVIATION` (0.25: at most about
6 % of the motion's energy off the assumed harmonic). Measured: the paper's 1-DOF decay 0.15,
its harmonic 2 N load 0.06; the machine frame's two-mode release from -3 mm 0.29 (its modes
beat), its 1 kN shock at the tip 1.1 (the loss factor jumping 0 <-> 1.2 between updates).

The damper models whose force follows the motion itself (the plastic block of
``--model plastic``, the DEM) have no such periods: not applicable there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Largest dissipation-weighted RMS deviation of a near-harmonic run [-] (module docstring).
NEAR_HARMONIC_DEVIATION = 0.25
#: The fidelity whose damper force follows any motion (named where a run is not
#: near-harmonic).
FOLLOWING_FIDELITY = "plastic"


@dataclass(frozen=True)
class Harmonicity:
    """The measure of one run (module docstring).

    Attributes
    ----------
    deviation
        The dissipation-weighted mean RMS deviation ``e_k`` of the periods after the
        updates from their assumed harmonic [-].
    largest_deviation
        The largest ``e_k`` of a period that carried at least 1 % of the largest period's
        dissipation [-].
    windows
        Periods measured (those that end within the run).
    threshold
        :data:`NEAR_HARMONIC_DEVIATION`.
    """

    deviation: float
    largest_deviation: float
    windows: int
    threshold: float = NEAR_HARMONIC_DEVIATION

    @property
    def near_harmonic(self) -> bool:
        """Whether the deviation is at most the threshold."""
        return bool(self.deviation <= self.threshold)

    def as_dict(self) -> dict:
        return {"deviation": self.deviation, "largest_deviation": self.largest_deviation,
                "windows": self.windows, "threshold": self.threshold,
                "near_harmonic": self.near_harmonic}

    def warning(self, name: str = "") -> str | None:
        """One line for the text output where the run is not near-harmonic; None where
        it is."""
        if self.near_harmonic:
            return None
        who = f"{name}: " if name else ""
        return (f"{who}not near-harmonic: the damper point's motion deviates by "
                f"{self.deviation:.2f} (RMS, above {self.threshold:g}) from the harmonic "
                "its loss factor was taken at; use --model "
                f"{FOLLOWING_FIDELITY}, whose damper force follows the motion itself")


def window_deviation(t: np.ndarray, x: np.ndarray, t0: float, amplitude: float,
                     frequency: float) -> float:
    """``e_k`` of the motion ``x(t)`` over ``[t0, t0 + 1 / frequency]`` (module
    docstring); NaN where that period is not inside the samples or has fewer than 8.

    >>> t = np.linspace(0.0, 0.2, 401)
    >>> x = -np.cos(2 * np.pi * 10 * t)
    >>> round(window_deviation(t, x, 0.0, 1.0, 10.0), 6)
    0.0
    >>> round(window_deviation(t, x - 0.5 * np.sin(2 * np.pi * 20 * t), 0.0, 1.0, 10.0), 3)
    0.5
    """
    if not (frequency > 0 and amplitude > 0):
        return math.nan
    t1 = t0 + 1.0 / frequency
    if t1 > t[-1] * (1.0 + 1e-12) or t0 < t[0]:
        return math.nan
    i0, i1 = np.searchsorted(t, [t0, t1], side="left")
    tt, xx = t[i0:i1 + 1], x[i0:i1 + 1]
    if tt.size < 8 or not tt[-1] > tt[0]:
        return math.nan
    x0 = float(np.interp(t0, t, x))
    xh = x0 + amplitude * (1.0 - np.cos(2.0 * math.pi * frequency * (tt - t0)))
    ms = np.trapezoid((xx - xh) ** 2, tt) / (tt[-1] - tt[0])
    return float(math.sqrt(ms) / (amplitude / math.sqrt(2.0)))


def harmonicity(time, damper_displacement, cycles) -> Harmonicity | None:
    """The measure of a run whose damper was updated at ``cycles``
    (:class:`~pdamper.coupling.results.CycleUpdate`); None where no update's period ends
    within the run or no update exerted a force (no bed: d = 0 and m_eff = 0)."""
    if all(c.damping == 0.0 and c.effective_mass == 0.0 for c in cycles):
        return None  # no bed: the describing function exerted no force to be wrong about
    t = np.asarray(time, float)
    x = np.asarray(damper_displacement, float)
    devs, weights = [], []
    for c in cycles:
        e = window_deviation(t, x, c.time, c.amplitude, c.frequency)
        w = math.pi * c.damping * 2.0 * math.pi * c.frequency * c.amplitude ** 2
        if math.isfinite(e) and math.isfinite(w):
            devs.append(e)
            weights.append(max(w, 0.0))
    if not devs:
        return None
    e_arr, w_arr = np.array(devs), np.array(weights)
    if not w_arr.sum() > 0:  # the damper dissipated nothing: the motion's own deviations
        w_arr = np.ones_like(e_arr)
    mean = float(np.sum(e_arr * w_arr) / np.sum(w_arr))
    big = w_arr >= 0.01 * w_arr.max()
    return Harmonicity(mean, float(e_arr[big].max()), int(e_arr.size))


def of_result(result) -> Harmonicity | None:
    """The measure of a :class:`~pdamper.coupling.results.FreeVibrationResult` or a
    :class:`~pdamper.coupling.loads.LoadResponse` of a describing-function damper (its
    ``cycles``); None for a run without updates (a damper force that follows the motion)
    or whose updates' periods all end after the run."""
    if not result.cycles:
        return None
    x_d = getattr(result.details, "damper_displacement", None)
    if x_d is None:
        x_d = getattr(result, "damper_displacement", None)
    if x_d is None:  # a 1-DOF release: the end-effector is the damper point
        x_d = result.displacement
    return harmonicity(result.time, x_d, result.cycles)


def cycle_deviation(a: np.ndarray, steady: np.ndarray, z0: np.ndarray, phi: np.ndarray,
                    omega: float, stroke: float, samples: int = 64) -> float:
    """The deviation of one load cycle of a describing-function stepped sine
    (:func:`pdamper.coupling.frf.stepped_sine_pseudo_force`) from the harmonic it assumed:
    the modal state ``z(t) = Re(Z e^{i W t}) + e^{A t} (z0 - Re Z)`` over ``[0, 2 pi / W]``
    (``a``: A, ``steady``: Z), the damper point's motion ``x = phi . q`` and

        e = RMS(x - <x> - Re(X e^{i (W t + arg x*)})) / (X / sqrt 2),

    with ``X`` = ``stroke`` [m], the amplitude the describing function was taken at, and
    ``x*`` the cycle's first harmonic: 0 for a steady step, about 1 where the motion is as
    far from that harmonic as the harmonic is from rest (a step whose transient or whose
    cycle-to-cycle jumps of the describing function have not died out). NaN without a
    stroke.

    >>> a = np.array([[0.0, 1.0], [-100.0, -2.0]])
    >>> om = 10.0
    >>> z = np.linalg.solve(1j * om * np.eye(2) - a, np.array([0.0, 1.0]))
    >>> round(cycle_deviation(a, z, z.real, np.array([1.0]), om, abs(z[0])), 9)
    0.0
    """
    if not (stroke > 0 and math.isfinite(stroke)):
        return math.nan
    n = phi.size
    period = 2.0 * math.pi / omega
    t = np.linspace(0.0, period, samples + 1)
    lam, vec = np.linalg.eig(a)
    coef = np.linalg.solve(vec, (z0 - steady.real).astype(complex))
    free = ((vec[None, :, :] * np.exp(np.outer(t, lam))[:, None, :]) @ coef).real
    z = (steady[None, :] * np.exp(1j * omega * t)[:, None]).real + free
    x = z[:, :n] @ phi
    hat = 2.0 / period * np.trapezoid(x * np.exp(-1j * omega * t), t)
    mean = np.trapezoid(x, t) / period
    xh = (stroke * np.exp(1j * (omega * t + np.angle(hat)))).real
    rms = math.sqrt(float(np.trapezoid((x - mean - xh) ** 2, t)) / period)
    return float(rms / (stroke / math.sqrt(2.0)))


def frf_marks(curve) -> dict | None:
    """Per frequency of a stepped sine (:class:`~pdamper.coupling.frf.FRFCurve`) of a
    describing-function damper: ``harmonic_deviation`` (:func:`cycle_deviation` of the
    step's last cycle) and ``near_harmonic`` (at most :data:`NEAR_HARMONIC_DEVIATION`);
    None for a sweep without the measure (a damper force that follows the motion)."""
    dev = curve.diagnostics.get("harmonic_deviation")
    if dev is None:
        return None
    dev = np.asarray(dev, float)
    return {"harmonic_deviation": dev,
            "near_harmonic": ~(dev > NEAR_HARMONIC_DEVIATION)}


#: Why a forced response's answer carries no near-harmonic measure.
FRF_NOT_APPLICABLE = {
    "harmonic_balance": "harmonic balance solves for a harmonic motion: no run to judge "
                        "(the stepped sines' rows carry the measure)",
    "following": "the damper force follows the motion itself (no loss factor taken from a "
                 "harmonic response); the plastic block's rows carry its distortion",
}


def frf_summary(res) -> dict:
    """The forced response's JSON key ``near_harmonic``: per sweep of a
    describing-function damper the steps judged, those not near-harmonic and their
    frequencies [Hz], the largest deviation and the threshold; ``null`` with the reason
    where no sweep carries the measure (``not_applicable``)."""
    by: dict[str, dict] = {}
    for name, c in res.sweeps.items():
        marks = frf_marks(c)
        if marks is None:
            continue
        sel = ~marks["near_harmonic"]
        dev = marks["harmonic_deviation"]
        by[name] = {"points": int(dev.size), "not_near_harmonic": int(sel.sum()),
                    "frequencies": [float(v) for v in res.frequency[sel]],
                    "largest_deviation": float(np.nanmax(dev)) if np.any(np.isfinite(dev))
                    else None}
    if not by:
        why = (FRF_NOT_APPLICABLE["following"] if res.sweeps
               else FRF_NOT_APPLICABLE["harmonic_balance"])
        return {"near_harmonic": None, "not_applicable": {"near_harmonic": why}}
    return {"near_harmonic": {"by_sweep": by, "threshold": NEAR_HARMONIC_DEVIATION,
                              "all": not any(v["not_near_harmonic"] for v in by.values())}}


def frf_warning(res) -> str | None:
    """One line for the text of a forced response where a describing-function step is
    not near-harmonic (its frequencies and sweeps); None where every step is."""
    bad: list[str] = []
    worst = 0.0
    for name, c in res.sweeps.items():
        marks = frf_marks(c)
        if marks is None:
            continue
        sel = ~marks["near_harmonic"]
        if np.any(sel):
            worst = max(worst, float(np.nanmax(marks["harmonic_deviation"][sel])))
            fs = res.frequency[sel]
            bad.append(f"{name} at {fs.size} frequencies ({fs[0]:g}-{fs[-1]:g} Hz)")
    if not bad:
        return None
    return (f"! not near-harmonic: {'; '.join(bad)}: the damper point's last cycle deviates "
            f"by up to {worst:.2f} (RMS, above {NEAR_HARMONIC_DEVIATION:g}) from the harmonic "
            f"its loss factor was taken at (JSON near_harmonic per row); use --model "
            f"{FOLLOWING_FIDELITY}, whose damper force follows the motion itself")


#: Why the measure is missing from a run (JSON ``not_applicable``).
NOT_APPLICABLE = ("the damper force follows the motion itself (no loss factor taken from a "
                  "harmonic response), no update's period ends within the run, or there is "
                  "no bed (no damper force to take)")


def payload(result) -> dict:
    """The JSON keys of a run: ``harmonicity`` (:meth:`Harmonicity.as_dict`) and
    ``near_harmonic``, both null with the reason under ``not_applicable`` where the
    measure does not apply."""
    h = of_result(result)
    if h is None:
        return {"harmonicity": None, "near_harmonic": None,
                "not_applicable": {"harmonicity": NOT_APPLICABLE,
                                   "near_harmonic": NOT_APPLICABLE}}
    return {"harmonicity": h.as_dict(), "near_harmonic": h.near_harmonic}


def design_marks(result) -> dict:
    """A design's extras from its run (a free vibration or a load history, or an
    :class:`~pdamper.coupling.frf.FRFResult` of its forced response): ``near_harmonic``
    (bool) and ``harmonic_deviation`` (the run's :attr:`Harmonicity.deviation`; of a
    forced response the largest of its stepped sines' steps) [-]; {} where the measure
    does not apply (a damper force that follows the motion)."""
    if hasattr(result, "sweeps"):  # a forced response
        marks = [frf_marks(c) for c in result.sweeps.values()]
        devs: list[np.ndarray] = [m["harmonic_deviation"] for m in marks if m is not None]
        if not devs:
            return {}
        dev: np.ndarray = np.concatenate(devs)
        dev = dev[np.isfinite(dev)]
        if dev.size == 0:
            return {}
        worst = float(dev.max())
        return {"near_harmonic": bool(worst <= NEAR_HARMONIC_DEVIATION),
                "harmonic_deviation": worst}
    h = of_result(result)
    if h is None:
        return {}
    return {"near_harmonic": h.near_harmonic, "harmonic_deviation": h.deviation}
