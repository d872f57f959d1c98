"""Error metrics between simulated free vibrations and a measurement (paper Sect. 4.2.1,
Figs. 7 and 8: "a very good agreement ... when comparing the trajectories").

For each model, against an :class:`~pdamper.coupling.measurement.AlignedMeasurement`:

- **peak amplitudes**: the n-th negative peak of the model against the n-th measured one
  (n >= 1: the release is an input, not a result), as RMS error [m] and relative to the mean
  measured amplitude [-];
- **damping ratio per amplitude band**: the measured zeta (Eqs. 24-25) against the model's
  zeta interpolated at the measured mean amplitudes, averaged per band of amplitude (the
  measured range in ``bands`` equal parts, or given edges) [-];
- **phase drift**: the time of the n-th negative peak of the model minus the measured one
  [s], and as phase ``2 pi dt / T_n`` with the measured cycle period [rad]; a constant
  frequency error shows as a drift growing linearly with n.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

#: Default number of amplitude bands of the damping-ratio comparison.
DEFAULT_BANDS = 4
#: Share of the model's amplitude range by which a measured amplitude may lie outside it and
#: still be compared (the model's end value is held).
_RANGE_SLACK = 0.02


@dataclass(frozen=True)
class Band:
    """Damping ratios in one amplitude band [low, high) [m]."""

    low: float
    high: float
    cycles: int
    measured_zeta: float
    model_zeta: float
    error: float
    rms_error: float

    def as_dict(self) -> dict:
        """JSON of the band; a band without a compared cycle has its damping ratios null,
        with the reason under ``not_applicable``."""
        from pdamper.coupling.results import with_reasons

        why = ("no measured cycle in this band is within the model's range of amplitudes"
               if self.cycles == 0 else "not a finite number")
        return with_reasons(vars(self), dict.fromkeys(
            ("measured_zeta", "model_zeta", "error", "rms_error"), why))


@dataclass(frozen=True)
class ModelComparison:
    """Error metrics of one model against the measurement (module docstring).

    Attributes
    ----------
    model
        Fidelity of the model.
    peaks
        Number of compared negative peaks (after the release).
    peak_rms_error
        RMS of (model - measured) peak amplitudes [m].
    peak_rms_relative
        ``peak_rms_error`` over the mean measured amplitude of those peaks [-].
    peak_errors
        Per peak, model - measured [m].
    bands
        Damping-ratio comparison per amplitude band.
    zeta_rms_error
        RMS over all compared cycles of (model - measured) zeta [-].
    time_drift
        Per peak, t_model - t_measured [s].
    phase_drift
        Per peak, ``2 pi time_drift / T_n`` [rad].
    final_phase_drift
        The last compared peak's phase drift [rad].
    """

    model: str
    peaks: int
    peak_rms_error: float
    peak_rms_relative: float
    peak_errors: np.ndarray
    bands: tuple[Band, ...]
    zeta_rms_error: float
    time_drift: np.ndarray
    phase_drift: np.ndarray
    final_phase_drift: float

    def as_dict(self) -> dict:
        from pdamper.coupling.results import with_reasons

        no_peaks = "no negative peak after the release to compare"
        return with_reasons({
            "model": self.model, "peaks": self.peaks, "peak_rms_error": self.peak_rms_error,
            "peak_rms_relative": self.peak_rms_relative,
            "peak_errors": [float(v) for v in self.peak_errors],
            "damping_ratio_bands": [b.as_dict() for b in self.bands],
            "zeta_rms_error": self.zeta_rms_error,
            "time_drift": [float(v) for v in self.time_drift],
            "phase_drift": [float(v) for v in self.phase_drift],
            "final_phase_drift": self.final_phase_drift,
        }, {"peak_rms_error": no_peaks, "peak_rms_relative": no_peaks,
            "final_phase_drift": no_peaks,
            "zeta_rms_error": "no measured cycle is within the model's range of amplitudes"})


def _band_edges(amplitudes: np.ndarray, bands: int | Sequence[float]) -> np.ndarray:
    if isinstance(bands, int):
        lo, hi = float(np.min(amplitudes)), float(np.max(amplitudes))
        edges = np.linspace(lo, hi, bands + 1)
        edges[-1] = np.nextafter(hi, math.inf)  # the largest amplitude belongs to the top band
        return edges
    edges = np.asarray(sorted(bands), float)
    if edges.size < 2:
        raise ValueError("band edges need at least two values")
    return edges


def compare_with_measurement(result, measured, bands: int | Sequence[float] = DEFAULT_BANDS
                             ) -> ModelComparison:
    """Metrics of ``result`` (a :class:`~pdamper.coupling.FreeVibrationResult`) against
    ``measured`` (an :class:`~pdamper.coupling.measurement.AlignedMeasurement`).

    Parameters
    ----------
    bands
        Number of equal amplitude bands over the measured range, or explicit edges [m].

    A measurement released from more than
    :data:`~pdamper.coupling.measurement.MAX_RELEASE_RATIO` times (or less than its
    inverse) the simulated release is refused
    (:func:`~pdamper.coupling.measurement.check_release_scale`).
    """
    from pdamper.coupling.measurement import check_release_scale

    ta, aa = np.asarray(result.peak_times), np.asarray(result.peak_amplitudes)
    if aa.size:  # the release is the first peak
        check_release_scale(measured, float(aa[0]))
    tm, am = np.asarray(measured.peak_times), np.asarray(measured.peak_amplitudes)
    n = min(ta.size, tm.size)
    err = aa[1:n] - am[1:n]
    rms = float(np.sqrt(np.mean(err**2))) if err.size else float("nan")
    rel = rms / float(np.mean(am[1:n])) if err.size else float("nan")
    # damping ratio at the measured mean amplitudes
    amp_m, zeta_m = measured.damping_ratio
    amp_s, zeta_s = result.damping_ratio
    order = np.argsort(amp_s)
    if amp_s.size:  # a little beyond the model's range (noise on the measured peaks) is held
        slack = _RANGE_SLACK * (amp_s.max() - amp_s.min())
        inside = (amp_m >= amp_s.min() - slack) & (amp_m <= amp_s.max() + slack)
    else:
        inside = np.zeros(amp_m.shape, bool)
    zeta_at = np.interp(amp_m, amp_s[order], zeta_s[order]) if amp_s.size else \
        np.full(amp_m.shape, np.nan)
    zerr = np.where(inside, zeta_at - zeta_m, np.nan)
    out_bands = []
    if amp_m.size:
        edges = _band_edges(amp_m, bands)
        for lo, hi in zip(edges[:-1], edges[1:], strict=True):
            sel = (amp_m >= lo) & (amp_m < hi) & inside
            k = int(np.count_nonzero(sel))
            if k == 0:
                out_bands.append(Band(float(lo), float(hi), 0, float("nan"), float("nan"),
                                      float("nan"), float("nan")))
                continue
            out_bands.append(Band(float(lo), float(hi), k, float(np.mean(zeta_m[sel])),
                                  float(np.mean(zeta_at[sel])), float(np.mean(zerr[sel])),
                                  float(np.sqrt(np.mean(zerr[sel] ** 2)))))
    finite = zerr[np.isfinite(zerr)]
    zrms = float(np.sqrt(np.mean(finite**2))) if finite.size else float("nan")
    dt = ta[1:n] - tm[1:n]
    periods = np.diff(tm[:n])
    phase = 2.0 * math.pi * dt / periods if dt.size else np.array([])
    return ModelComparison(
        model=getattr(result, "model", ""), peaks=int(err.size), peak_rms_error=rms,
        peak_rms_relative=rel, peak_errors=err, bands=tuple(out_bands), zeta_rms_error=zrms,
        time_drift=dt, phase_drift=phase,
        final_phase_drift=float(phase[-1]) if phase.size else float("nan"))
