"""Results of a free vibration of a structure carrying a damper (paper Sect. 4.2)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pdamper.analysis.modes import MotionMode
from pdamper.coupling.decrement import damping_ratio_from_peaks


@dataclass(frozen=True)
class CycleUpdate:
    """Damper state set at one minimum of the end-effector (pseudo-force coupling).

    Attributes
    ----------
    time
        Time of the minimum [s].
    amplitude
        X = |x_min| [m].
    frequency
        Effective eigenfrequency used for the update, sqrt(K / (M + m_eff)) / 2 pi [Hz].
    mode
        Motion mode of the damper at (frequency, amplitude); None if the model does not
        classify it (e.g. effective fields from an unclassified DEM map).
    effective_mass
        m_eff [kg].
    damping
        d = E~ / (pi W X^2) [kg/s].
    loss_factor
        eta [-].
    """

    time: float
    amplitude: float
    frequency: float
    mode: MotionMode | None
    effective_mass: float
    damping: float
    loss_factor: float


@dataclass(frozen=True)
class FreeVibrationResult:
    """Trajectory and damping of a free vibration.

    Attributes
    ----------
    time, displacement
        Sampled end-effector trajectory [s], [m].
    peak_times, peak_amplitudes
        Negative peaks (minima) [s] and their amplitudes |x| [m], the release included.
    cycles
        The damper updates, one per minimum (pseudo-force coupling).
    model
        Fidelity of the damper model.
    inputs
        The inputs of the run, for the record.
    details
        What the coupling computed on the way (the co-simulation's
        :class:`~pdamper.dem.DEMResult`); None for the pseudo-force coupling.
    """

    time: np.ndarray
    displacement: np.ndarray
    peak_times: np.ndarray
    peak_amplitudes: np.ndarray
    cycles: tuple[CycleUpdate, ...] = ()
    model: str = ""
    inputs: dict = field(default_factory=dict)
    details: Any = field(default=None, repr=False, compare=False)

    @property
    def damping_ratio(self) -> tuple[np.ndarray, np.ndarray]:
        """(mean amplitude [m], zeta [-]) per cycle, Eqs. (24)-(25)."""
        return damping_ratio_from_peaks(self.peak_amplitudes)

    @property
    def damping_per_mode(self):
        """Each mode's damping ratio from its own modal coordinate
        (:func:`~pdamper.coupling.decrement.modal_damping_ratios`), for a run on more than
        one mode (its ``details`` hold the modal coordinates); None otherwise."""
        from pdamper.coupling.decrement import modal_damping_ratios

        q = getattr(self.details, "modal", None)
        if q is None or np.ndim(q) != 2 or np.shape(q)[0] < 2:
            return None
        return modal_damping_ratios(self.time, q)

    @property
    def final_amplitude(self) -> float:
        """Amplitude of the last negative peak [m]."""
        return float(self.peak_amplitudes[-1])

    @property
    def effective_frequency(self) -> np.ndarray:
        """Effective eigenfrequency of each cycle, 1 / (t_n+1 - t_n) [Hz]."""
        return 1.0 / np.diff(self.peak_times)

    def amplitude_at(self, t: float) -> float:
        """Amplitude envelope at time ``t`` [s], in [m].

        Interpolated exponentially between the negative peaks around ``t`` (a linear
        oscillator decays exponentially within a cycle), so that it is continuous in the
        design parameters; beyond the last peak it is the last peak's amplitude.
        """
        tp, ap = self.peak_times, self.peak_amplitudes
        i = int(np.searchsorted(tp, t, side="right")) - 1
        if i < 0:
            return float(ap[0])
        if i >= len(tp) - 1 or ap[i + 1] <= 0 or ap[i] <= 0:
            return float(ap[min(i, len(ap) - 1)])
        q = (t - tp[i]) / (tp[i + 1] - tp[i])
        return float(ap[i] * (ap[i + 1] / ap[i]) ** q)

    def to_dataset(self):
        """The trajectory as an :class:`xarray.Dataset` with units."""
        import xarray as xr

        amp, zeta = self.damping_ratio
        return xr.Dataset(
            {
                "displacement": ("time", self.displacement,
                                 {"long_name": "end-effector displacement", "units": "m"}),
                "peak_amplitude": ("peak", self.peak_amplitudes,
                                   {"long_name": "negative peak amplitude", "units": "m"}),
                "peak_time": ("peak", self.peak_times, {"units": "s"}),
                "damping_ratio": ("cycle", zeta, {"long_name": "damping ratio (Eq. 25)",
                                                  "units": "1"}),
                "mean_amplitude": ("cycle", amp, {"units": "m"}),
            },
            coords={"time": ("time", self.time, {"units": "s"})},
            attrs={"model": self.model},
        )


def with_reasons(values: dict[str, Any], reasons: dict[str, str]) -> dict[str, Any]:
    """``values`` as JSON: every non-finite number becomes null and is listed, with the
    reason from ``reasons``, in a sibling ``not_applicable`` (``{key: reason}``), so that a
    reader never meets a bare null where a number was promised.

    >>> with_reasons({"a": 1.0, "b": float("nan")}, {"b": "no load"})
    {'a': 1.0, 'b': None, 'not_applicable': {'b': 'no load'}}
    """
    import math

    out: dict[str, Any] = {}
    why: dict[str, str] = {}
    for key, v in values.items():
        if v is None or isinstance(v, float | np.floating) and not math.isfinite(v):
            out[key] = None
            why[key] = reasons.get(key, "not a finite number in this run")
        else:
            out[key] = v
    if why:
        out["not_applicable"] = why
    return out

