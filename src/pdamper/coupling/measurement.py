"""A measured end-effector trajectory, conditioned and aligned with the simulations
(paper Sect. 4: the laser vibrometer's velocity, integrated, released from x0).

Pipeline (:func:`align_measurement`):

1. **Integration** (done when the signal is read, :class:`MeasuredTrajectory`): a velocity
   is integrated once, an acceleration twice (trapezoidal rule). Unknown integration
   constants and a constant bias of the sensor become a polynomial drift of degree 1
   (velocity) or 2 (acceleration) in the displacement.
2. **Drift and static offset**: the displacement oscillates about a constant equilibrium.
   Its centre is estimated once per half cycle from three successive extrema, assuming an
   exponential envelope: for a maximum M between minima m1, m2,
   ``(M - c)^2 = (c - m1)(c - m2)``, i.e. ``c = (M^2 - m1 m2) / (2M - m1 - m2)`` (and
   likewise for a minimum between two maxima); exact for a damped sinusoid, unlike the
   plain mean of a cycle, which is biased by about zeta times the amplitude. A polynomial
   of the drift degree (degree 0 = the static offset for a displacement) is fitted through
   the centres and subtracted.
3. **Release (time offset) and initial deflection**: the samples up to the first upward
   zero crossing are fitted (least squares) by a body at rest at x0 until t_r, then the
   free decay ``x0 e^{-s tau} (cos wd tau + s/wd sin wd tau)``, with wd and s from the
   next two minima; t_r and x0 are fitted. The aligned record starts at t_r = 0.

Peaks are the lowest points of the negative lobes (between zero crossings, with a
hysteresis band above the noise), each refined by a least-squares parabola over 1/8 of the
lobe around it; the release counts as the first peak, as in the simulations. The damping
ratio follows from Eqs. (24)-(25) (:func:`pdamper.coupling.damping_ratio_from_peaks`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pdamper.coupling.decrement import damping_ratio_from_peaks
from pdamper.errors import InputError

#: Drift degree of the displacement after integrating each measured quantity.
DRIFT_DEGREE = {"displacement": 0, "velocity": 1, "acceleration": 2}
#: Fewest negative peaks after the release needed to align and compare a record.
MIN_PEAKS = 3
#: Largest ratio between the measured and the simulated release deflection (either way)
#: that is compared [-]. Beyond it the two describe different experiments, most likely a
#: unit of the file's header (``[m]`` for millimetres: 1000) or a release that is not the
#: simulated one; the peak errors are then meaningless and the damping bands hold no
#: common amplitude.
MAX_RELEASE_RATIO = 10.0


@dataclass(frozen=True)
class MeasuredTrajectory:
    """A measured end-effector record as displacement (integrated if need be).

    Attributes
    ----------
    time
        Sample times [s], strictly increasing (any origin).
    displacement
        Displacement [m] (any offset; drift from integration possible).
    quantity
        What was measured: ``"displacement"``, ``"velocity"`` or ``"acceleration"``.
    source
        Where it came from (file name).
    columns
        The columns read, as written in the file.
    """

    time: np.ndarray
    displacement: np.ndarray
    quantity: str = "displacement"
    source: str = ""
    columns: tuple[str, ...] = ()

    @classmethod
    def from_signal(cls, time, values, quantity: str, source: str = "",
                    columns: tuple[str, ...] = ()) -> MeasuredTrajectory:
        """Integrate a velocity [m/s] or acceleration [m/s^2] to a displacement [m]."""
        from scipy.integrate import cumulative_trapezoid

        if quantity not in DRIFT_DEGREE:
            raise InputError("measured", f"quantity must be one of {', '.join(DRIFT_DEGREE)}, "
                             f"got {quantity!r}")
        t = np.asarray(time, float)
        y = np.asarray(values, float)
        for _ in range(DRIFT_DEGREE[quantity]):
            y = cumulative_trapezoid(y, t, initial=0.0)
        return cls(t, y, quantity, source, columns)

    @property
    def drift_degree(self) -> int:
        return DRIFT_DEGREE[self.quantity]


@dataclass(frozen=True)
class AlignedMeasurement:
    """A measurement aligned with the simulations: release at t = 0, equilibrium at x = 0.

    Attributes
    ----------
    time, displacement
        Aligned record [s], [m] (samples before the release have negative times).
    peak_times, peak_amplitudes
        Negative peaks, the release first (t = 0, |x0|) [s], [m].
    time_offset
        Release time in the file's time base [s].
    static_offset
        Equilibrium in the file's displacement (the drift polynomial at the release) [m].
    initial_deflection
        Fitted x0 [m] (negative).
    drift
        Coefficients of the removed drift polynomial (highest power first) in the file's
        time base [m, m/s, m/s^2].
    source, quantity
        From the :class:`MeasuredTrajectory`.
    """

    time: np.ndarray
    displacement: np.ndarray
    peak_times: np.ndarray
    peak_amplitudes: np.ndarray
    time_offset: float
    static_offset: float
    initial_deflection: float
    drift: tuple[float, ...] = ()
    source: str = ""
    quantity: str = "displacement"
    model: str = field(default="measured", init=False)

    @property
    def damping_ratio(self) -> tuple[np.ndarray, np.ndarray]:
        """(mean amplitude [m], zeta [-]) per cycle, Eqs. (24)-(25)."""
        return damping_ratio_from_peaks(self.peak_amplitudes)

    @property
    def effective_frequency(self) -> np.ndarray:
        """1 / (t_n+1 - t_n) per cycle [Hz]."""
        return 1.0 / np.diff(self.peak_times)

    def amplitude_at(self, t: float) -> float:
        """Exponential envelope of the negative peaks at ``t`` [s] (as the simulations)."""
        tp, ap = self.peak_times, self.peak_amplitudes
        i = int(np.searchsorted(tp, t, side="right")) - 1
        if i < 0:
            return float(ap[0])
        if i >= len(tp) - 1:
            return float(ap[-1])
        q = (t - tp[i]) / (tp[i + 1] - tp[i])
        return float(ap[i] * (ap[i + 1] / ap[i]) ** q)


# ----------------------------------------------------------------------------- extrema
def _noise(x: np.ndarray) -> float:
    """Robust noise level: median absolute second difference / sqrt(6) (white noise)."""
    if x.size < 5:
        return 0.0
    d2 = x[2:] - 2.0 * x[1:-1] + x[:-2]
    return float(np.median(np.abs(d2 - np.median(d2))) * 1.4826 / math.sqrt(6.0))


def _lobes(x: np.ndarray, band: float) -> list[tuple[int, int, int]]:
    """Lobes of ``x`` about 0 as (sign, first, last) index ranges; a crossing counts only
    when the signal leaves the band ``[-band, band]`` on the other side (hysteresis)."""
    idx = np.flatnonzero(np.abs(x) > band)
    if idx.size == 0:
        return []
    sign = np.where(x[idx] > 0, 1, -1)
    lobes = []
    start = 0
    for c in np.flatnonzero(sign[1:] != sign[:-1]):
        a, b, new = idx[c], idx[c + 1], sign[c + 1]
        # the lobe ends at the last sample in (a, b] not yet on the new side of zero
        other = np.flatnonzero(np.sign(x[a:b + 1]) != new)
        end = a + int(other[-1])
        lobes.append((int(sign[c]), start, end))
        start = end + 1
    lobes.append((int(sign[-1]), start, x.size - 1))
    return lobes


def _refine(t: np.ndarray, x: np.ndarray, i: int, first: int, last: int, half: int,
            sign: int) -> tuple[float, float]:
    """Extremum near sample ``i`` refined by a least-squares parabola over ``i +/- half``
    samples inside the lobe; falls back to the sample if the fit is not a proper vertex."""
    lo, hi = max(first, i - half), min(last, i + half)
    if hi - lo < 2:
        return float(t[i]), float(x[i])
    tt = t[lo:hi + 1] - t[i]
    c2, c1, c0 = np.polyfit(tt, x[lo:hi + 1], 2)
    if sign * c2 >= 0 or c2 == 0:  # not curved the right way: keep the sample
        return float(t[i]), float(x[i])
    tv = -c1 / (2.0 * c2)
    if not tt[0] <= tv <= tt[-1]:
        return float(t[i]), float(x[i])
    return float(t[i] + tv), float(c0 - c1 * c1 / (4.0 * c2))


def extrema(t, x, band: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Extrema of the lobes of ``x`` about zero: (times [s], values, sign per lobe).

    Each lobe (between zero crossings with hysteresis ``band``, default four noise levels)
    gives its lowest (negative lobe) or highest (positive lobe) point, refined by a
    least-squares parabola over 1/8 of the lobe's samples either side. Lobes that touch the
    record's ends are left out (their extremum may lie outside the record).
    """
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    if band is None:
        band = 4.0 * _noise(x)
    lobes = _lobes(x, band)
    tt, xx, ss = [], [], []
    for sign, first, last in lobes:
        if first == 0 or last == x.size - 1:
            continue
        seg = x[first:last + 1]
        i = first + int(np.argmin(seg) if sign < 0 else np.argmax(seg))
        half = max(1, (last - first) // 8)
        tp, xp = _refine(t, x, i, first, last, half, sign)
        tt.append(tp)
        xx.append(xp)
        ss.append(sign)
    return np.array(tt), np.array(xx), np.array(ss, int)


def lobe_minima(t, x, band: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Times and amplitudes ``|x|`` of the negative-lobe minima of a (noisy) record;
    see :func:`extrema`."""
    tp, xp, s = extrema(t, x, band)
    return tp[s < 0], -xp[s < 0]


def _centres(te: np.ndarray, xe: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Equilibrium estimates from each three successive alternating extrema (module
    docstring, step 2)."""
    tc, xc = [], []
    for k in range(1, len(xe) - 1):
        a, m, b = xe[k - 1], xe[k], xe[k + 1]
        den = 2.0 * m - a - b
        if den == 0:
            continue
        tc.append(te[k])
        xc.append((m * m - a * b) / den)
    return np.array(tc), np.array(xc)


# ----------------------------------------------------------------------------- alignment
def _fail(m: MeasuredTrajectory, msg: str) -> InputError:
    return InputError("measured", f"{m.source or 'the measurement'}: {msg}")


def check_release_scale(measured: AlignedMeasurement, initial_displacement: float) -> float:
    """The ratio ``|x0 measured| / |x0 simulated|`` [-]; an :class:`InputError` naming the
    factor where it is beyond :data:`MAX_RELEASE_RATIO` either way (orders of magnitude:
    the record's unit, or another release than the simulated one).

    Parameters
    ----------
    measured
        The aligned measurement; its release is its first peak (the fitted
        ``initial_deflection``) [m].
    initial_displacement
        The simulated release deflection x0 [m].
    """
    peaks = np.asarray(measured.peak_amplitudes, float)
    if peaks.size == 0:
        return math.nan
    x_m, x_s = abs(float(peaks[0])), abs(float(initial_displacement))
    ratio = x_m / x_s if x_s > 0 else math.inf
    if not 1.0 / MAX_RELEASE_RATIO <= ratio <= MAX_RELEASE_RATIO:
        factor = f"{ratio:.3g} times" if ratio >= 1 else f"1/{1.0 / ratio:.3g} of"
        source = getattr(measured, "source", "") or "the measurement"
        raise InputError("measured", f"{source}: released from "
                         f"{x_m:.4g} m, {factor} the simulated release of {x_s:.4g} m "
                         f"(structure.initial_displacement); compared only within a factor "
                         f"of {MAX_RELEASE_RATIO:g}: check the unit in the file's header")
    return ratio


def align_measurement(m: MeasuredTrajectory, time_offset: float | None = None,
                      static_offset: float | None = None) -> AlignedMeasurement:
    """Remove drift and static offset, find the release and the initial deflection, and
    the negative peaks (module docstring).

    Parameters
    ----------
    m
        The measurement.
    time_offset
        Release time in the record's time base [s], if known (skips the fit of t_r).
    static_offset
        Equilibrium in the record's displacement [m], if known (skips the drift fit; only
        for displacement records).
    """
    t, x = np.asarray(m.time, float), np.asarray(m.displacement, float)
    deg = m.drift_degree
    if static_offset is not None and deg:
        raise _fail(m, "a static offset can be given for displacement records only")
    # a median offset is enough to find the lobes; then the drift polynomial is refined
    # from the centres of the residual (centres move a little as the offset improves)
    coeffs = np.array([float(np.median(x) if static_offset is None else static_offset)])
    for _ in range(3 if static_offset is None else 0):
        y = x - np.polyval(coeffs, t)
        te, xe, se = extrema(t, y)
        if se.size < 2 * MIN_PEAKS + 1:
            raise _fail(m, f"needs at least {MIN_PEAKS} full oscillation cycles after the "
                        f"release, found {se.size} half cycles")
        tc, xc = _centres(te, xe)
        if tc.size <= deg:
            raise _fail(m, "too few cycles to estimate the drift")
        coeffs = _add(coeffs, np.polyfit(tc, xc, deg))
    y = x - np.polyval(coeffs, t)
    te, xe, se = extrema(t, y)
    neg = se < 0
    tz_candidates = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    if tz_candidates.size == 0:
        raise _fail(m, "the record never crosses its equilibrium upwards")
    iz = int(tz_candidates[0])
    t_z = float(t[iz] - y[iz] * (t[iz + 1] - t[iz]) / (y[iz + 1] - y[iz]))
    tm, am = te[neg & (te > t_z)], -xe[neg & (te > t_z)]
    if tm.size < MIN_PEAKS:
        raise _fail(m, f"needs at least {MIN_PEAKS} negative peaks after the release, "
                    f"found {tm.size}")
    period = tm[1] - tm[0]
    wd = 2.0 * math.pi / period
    sigma = max(math.log(am[0] / am[1]) / period, 0.0) if am[1] > 0 else 0.0
    x0_guess = float(np.min(y[: iz + 1]))
    if time_offset is None:
        t_r, x0 = _fit_release(t[: iz + 1], y[: iz + 1], t_z, wd, sigma, x0_guess)
    else:
        t_r = float(time_offset)
        x0 = x0_guess
    if not x0 < 0:
        raise _fail(m, "the record does not start below its equilibrium (released from a "
                    "negative deflection)")
    peak_t = np.concatenate([[0.0], tm - t_r])
    peak_a = np.concatenate([[abs(x0)], am])
    return AlignedMeasurement(time=t - t_r, displacement=y, peak_times=peak_t,
                              peak_amplitudes=peak_a, time_offset=t_r,
                              static_offset=float(np.polyval(coeffs, t_r)),
                              initial_deflection=x0, drift=tuple(float(c) for c in coeffs),
                              source=m.source, quantity=m.quantity)


def _add(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Sum of two polynomial coefficient arrays (highest power first)."""
    n = max(len(a), len(b))
    return np.pad(a, (n - len(a), 0)) + np.pad(b, (n - len(b), 0))


def _release_model(t, t_r, x0, wd, sigma):
    tau = np.maximum(t - t_r, 0.0)
    return x0 * np.exp(-sigma * tau) * (np.cos(wd * tau) + sigma / wd * np.sin(wd * tau))


def _fit_release(t, y, t_z, wd, sigma, x0_guess) -> tuple[float, float]:
    """Least-squares (t_r, x0) of rest-then-free-decay on the samples up to the first
    upward zero crossing (module docstring, step 3)."""
    from scipy.optimize import least_squares

    tau_z = (math.pi - math.atan2(wd, sigma)) / wd  # zero of the decay after release
    t_r0 = t_z - tau_z
    res = least_squares(lambda p: _release_model(t, p[0], p[1], wd, sigma) - y,
                        x0=[t_r0, x0_guess], x_scale=[1.0 / wd, abs(x0_guess) or 1.0],
                        method="lm")
    return float(res.x[0]), float(res.x[1])
