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


def modal_damping_ratios(t, modal, min_cycles: int = 2) -> tuple[ModeDamping, ...]:
    """Each mode's damping ratio in a free decay of N modes, against its own amplitude.

    A beating sum of modes has no meaningful logarithmic decrement; each modal coordinate
    q_i(t) of a linear, modally damped structure is a single decaying oscillation, so the
    decrement of its own negative peaks (Eqs. 24-25) gives zeta_i. With a damper the
    coordinates couple and the ratio is the equivalent one of that mode at its amplitude.

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
        _, amp = negative_peaks(t, qi)
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
