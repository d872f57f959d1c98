"""Damping ratio from the logarithmic decrement of successive negative peaks (Eqs. 24-25)."""

from __future__ import annotations

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
