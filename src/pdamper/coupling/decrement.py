"""Damping ratio from the logarithmic decrement of successive negative peaks (Eqs. 24-25),
of one trajectory or of each modal coordinate of an N-mode free decay."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def damping_ratio_from_peaks(amplitudes) -> tuple[np.ndarray, np.ndarray]:
    """Damping ratio of each cycle from successive peak amplitudes.

    ``theta = ln(X_n / X_n+1)`` (Eq. 24), ``zeta = theta / sqrt(4 pi^2 + theta^2)``
    (Eq. 25), sampled at the mean amplitude ``X_n+1/2 = (X_n + X_n+1) / 2``.

    Parameters
    ----------
    amplitudes : array_like
        Positive peak amplitudes X_n [m] in time order.

    Returns
    -------
    mean_amplitude, zeta : ndarray
        Both of length ``len(amplitudes) - 1``.

    Examples
    --------
    A linear oscillator with zeta = 0.05 decays by exp(-2 pi zeta / sqrt(1 - zeta^2)):

    >>> import math
    >>> q = math.exp(-2 * math.pi * 0.05 / math.sqrt(1 - 0.05**2))
    >>> _, z = damping_ratio_from_peaks([1.0, q, q * q])
    >>> [round(float(v), 6) for v in z]
    [0.05, 0.05]
    """
    a = np.asarray(amplitudes, float)
    theta = np.log(a[:-1] / a[1:])
    zeta = theta / np.sqrt(4.0 * np.pi**2 + theta**2)
    return 0.5 * (a[:-1] + a[1:]), zeta


def negative_peaks(t, x) -> tuple[np.ndarray, np.ndarray]:
    """Times and amplitudes ``|x|`` of the negative peaks (local minima below zero) of a
    sampled trajectory, refined by a parabola through the three samples around each."""
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    i = np.flatnonzero((x[1:-1] < x[:-2]) & (x[1:-1] <= x[2:]) & (x[1:-1] < 0)) + 1
    x0, x1, x2 = x[i - 1], x[i], x[i + 1]
    den = x0 - 2 * x1 + x2
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(den > 0, 0.5 * (x0 - x2) / den, 0.0)
    dt = t[i + 1] - t[i]
    tp = t[i] + s * dt
    xp = x1 - 0.25 * (x0 - x2) * s
    return tp, -xp


@dataclass(frozen=True)
class ModeDamping:
    """Damping ratio of one mode of a free decay, from its own modal coordinate.

    Attributes
    ----------
    mode
        Mode number (1 = lowest) [-].
    damping_ratio
        Median of the per-cycle ratios (Eq. 25) of this mode's coordinate [-]; None where the
        estimate is not applicable (``reason`` says why).
    amplitudes, ratios
        Mean amplitude of each cycle of the modal coordinate [sqrt(kg) m] and its ratio [-].
    reason
        Why the estimate is not applicable, else None.
    """

    mode: int
    damping_ratio: float | None
    amplitudes: np.ndarray
    ratios: np.ndarray
    reason: str | None = None

    def as_dict(self) -> dict:
        """JSON-ready summary (the per-cycle arrays left out)."""
        return {"mode": self.mode, "damping_ratio": self.damping_ratio, "cycles":
                int(self.ratios.size), "not_applicable": self.reason}


def _lobe_peaks(t, x) -> tuple[np.ndarray, np.ndarray]:
    """:func:`negative_peaks`, one per negative lobe (a run of samples below zero): its
    lowest interior sample, refined by the same parabola. A smooth oscillation has one
    local minimum per lobe (the same peaks); a coordinate kicked by impacts (the DEM's) has
    ripples whose local minima are not cycles of the mode."""
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    neg = np.concatenate([[False], x < 0, [False]])
    edges = np.flatnonzero(np.diff(neg.astype(np.int8)))
    keep = []
    for a, b in zip(edges[::2], edges[1::2], strict=True):  # the lobe x[a:b]
        i = a + int(np.argmin(x[a:b]))
        if 0 < i < x.size - 1 and x[i] < x[i - 1] and x[i] <= x[i + 1]:
            keep.append(i)
    i = np.array(keep, dtype=int)
    if i.size == 0:
        return np.empty(0), np.empty(0)
    x0, x1, x2 = x[i - 1], x[i], x[i + 1]
    den = x0 - 2 * x1 + x2
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(den > 0, 0.5 * (x0 - x2) / den, 0.0)
    return t[i] + s * (t[i + 1] - t[i]), -(x1 - 0.25 * (x0 - x2) * s)


def modal_damping_ratios(t, modal, min_cycles: int = 2) -> tuple[ModeDamping, ...]:
    """Each mode's damping ratio in a free decay of N modes, against its own amplitude.

    A beating sum of modes has no meaningful logarithmic decrement; each modal coordinate
    q_i(t) of a linear, modally damped structure is a single decaying oscillation, so the
    decrement of its own negative peaks (Eqs. 24-25; one per negative lobe, so that the
    ripples of impacts on a DEM run's coordinate are not taken for cycles) gives zeta_i.
    With a damper the coordinates couple and the ratio is the equivalent one of that mode
    at its amplitude.

    Parameters
    ----------
    t : array_like
        Sample times [s].
    modal : array_like
        Modal coordinates, shape (N, samples) (e.g. ``ModalRun.modal``).
    min_cycles
        Fewest negative peaks after the first one for an estimate [-].

    Returns
    -------
    tuple of ModeDamping
        One per mode. A mode with fewer than ``min_cycles + 1`` negative peaks, or whose
        amplitude grows (energy fed in from another mode: negative per-cycle ratio, which is
        not the mode's damping), is reported as not applicable with the reason, never as a
        negative damping ratio.

    Examples
    --------
    >>> t = np.linspace(0.0, 2.0, 40001)
    >>> q = np.vstack([np.exp(-0.02 * 2 * np.pi * 5 * t) * np.cos(2 * np.pi * 5 * t),
    ...                0.1 * np.exp(-0.01 * 2 * np.pi * 30 * t) * np.cos(2 * np.pi * 30 * t)])
    >>> [round(m.damping_ratio, 4) for m in modal_damping_ratios(t, q)]
    [0.02, 0.01]
    """
    q = np.atleast_2d(np.asarray(modal, float))
    out = []
    for i, qi in enumerate(q):
        _, amp = _lobe_peaks(t, qi)
        amp = amp[amp > 0]
        if amp.size < min_cycles + 1:
            out.append(ModeDamping(i + 1, None, np.empty(0), np.empty(0),
                                   f"{amp.size} negative peaks of the modal coordinate, "
                                   f"fewer than {min_cycles + 1}"))
            continue
        a_mean, zeta = damping_ratio_from_peaks(amp)
        z = float(np.median(zeta))
        reason = None
        if not z > 0:
            reason = ("the modal coordinate does not decay (energy exchanged with other "
                      "modes): no damping ratio of its own")
        out.append(ModeDamping(i + 1, None if reason else z, a_mean, zeta, reason))
    return tuple(out)


#: How the equivalent damping ratio of a resonance is obtained (recorded with each).
HALF_POWER_METHOD = ("half-power bandwidth: f1, f2 where the amplitude is the peak's / sqrt(2) "
                     "(linear between frequencies); zeta^2 = (1 - 1 / sqrt(1 + R^2)) / 2, "
                     "R = (f2^2 - f1^2) / (f2^2 + f1^2), exact for a 1-DOF displacement "
                     "response")


def resonance_damping(frequency, amplitude) -> list[dict]:
    """Equivalent damping ratio of each resonance of a frequency response, from its
    half-power bandwidth (:data:`HALF_POWER_METHOD`).

    Parameters
    ----------
    frequency : array_like
        Frequencies f [Hz], ascending.
    amplitude : array_like
        Response amplitude at each frequency (any unit; NaN where there is none).

    Returns
    -------
    list of dict
        One per resonance (a local maximum above both neighbours, inside the sweep):
        ``frequency`` [Hz] and ``amplitude`` of the peak, ``f_low``/``f_high`` [Hz],
        ``damping_ratio`` [-] and ``not_applicable`` (None, or why there is no ratio: a
        half-power point outside the sweep or beyond the next resonance).

    Examples
    --------
    >>> f = np.linspace(4.0, 6.0, 20001)
    >>> r = f / 5.0
    >>> x = 1.0 / np.abs(1.0 - r**2 + 2j * 0.02 * r)
    >>> round(resonance_damping(f, x)[0]["damping_ratio"], 5)
    0.02
    """
    f = np.asarray(frequency, float)
    a = np.asarray(amplitude, float)
    ok = np.isfinite(a)
    f, a = f[ok], a[ok]
    out: list[dict] = []
    if f.size < 3:
        return out
    peaks = np.flatnonzero((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:])) + 1
    for k, i in enumerate(peaks):
        half = a[i] / np.sqrt(2.0)
        lo_lim = peaks[k - 1] if k > 0 else 0
        hi_lim = peaks[k + 1] if k + 1 < peaks.size else a.size - 1
        row: dict = {"frequency": float(f[i]), "amplitude": float(a[i]), "f_low": None,
                     "f_high": None, "damping_ratio": None, "not_applicable": None}
        below = np.flatnonzero(a[lo_lim:i] < half)
        above = np.flatnonzero(a[i:hi_lim + 1] < half)
        if below.size == 0 or above.size == 0:
            row["not_applicable"] = ("the response does not fall to the peak's 1/sqrt(2) on "
                                     "both sides within the sweep (and before the next "
                                     "resonance)")
            out.append(row)
            continue
        j = lo_lim + below[-1]  # a[j] < half <= a[j + 1]
        f1 = f[j] + (half - a[j]) * (f[j + 1] - f[j]) / (a[j + 1] - a[j])
        m = i + above[0]  # a[m - 1] >= half > a[m]
        f2 = f[m - 1] + (a[m - 1] - half) * (f[m] - f[m - 1]) / (a[m - 1] - a[m])
        r = (f2**2 - f1**2) / (f2**2 + f1**2)
        row.update(f_low=float(f1), f_high=float(f2),
                   damping_ratio=float(np.sqrt(0.5 * (1.0 - 1.0 / np.sqrt(1.0 + r * r)))))
        out.append(row)
    return out


def frf_resonances(res) -> dict:
    """The equivalent damping ratio of each resonance of an
    :class:`~pdamper.coupling.frf.FRFResult`, without the damper (the closed-form linear
    response) and with it (each sweep; the harmonic balance's largest stable solution):
    ``{"method": ..., "without_damper": [...], "up": [...], ...}``
    (:func:`resonance_damping`)."""
    out: dict = {"method": HALF_POWER_METHOD,
                 "without_damper": resonance_damping(res.frequency, np.abs(res.linear))}
    hb = res.harmonic_balance
    if hb is not None:
        stable = np.where(np.asarray(hb.branch) == "stable", hb.amplitude, np.nan)
        with np.errstate(all="ignore"):
            amp = np.nanmax(np.where(np.isnan(stable), -np.inf, stable), axis=1)
        out["harmonic_balance"] = resonance_damping(res.frequency,
                                                    np.where(np.isfinite(amp), amp, np.nan))
    for name, c in res.sweeps.items():
        out[name] = resonance_damping(res.frequency, c.amplitude)
    return out
