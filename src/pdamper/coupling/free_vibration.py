"""Free vibration of a 1-DOF structure carrying a particle damper (paper Sects. 4.1-4.2).

For the pseudo-force models the equation of motion between two updates is linear,

    (M + m_eff) x'' + (D + d) x' + K x = 0,

and is solved in closed form from one minimum of the end-effector (where x' = 0) to the
next, one damped period later; there the damper is updated from the new minimum's amplitude
(Sect. 4.1, item 2). The solution is exact: no time step.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from pdamper.analysis.modes import MotionMode
from pdamper.coupling.decrement import damping_ratio_from_peaks
from pdamper.errors import InputError, check_range

logger = logging.getLogger(__name__)

#: Largest stored trajectory [samples] (a longer run is a typo, not a design question).
MAX_SAMPLES = 2e7

#: Fixed-point iterations between the effective eigenfrequency and the effective mass.
_FREQUENCY_ITERATIONS = 3


@dataclass(frozen=True)
class CycleUpdate:
    """Damper state set at one minimum of the end-effector.

    Attributes
    ----------
    time
        Time of the minimum [s].
    amplitude
        X = |x_min| [m].
    frequency
        Effective eigenfrequency used for the update, sqrt(K / (M + m_eff)) / 2 pi [Hz].
    mode
        Motion mode of the damper at (frequency, amplitude).
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
    mode: MotionMode
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
        The damper updates, one per minimum (pseudo-force models).
    model
        Fidelity of the damper model.
    inputs
        The inputs of the run, for the record.
    """

    time: np.ndarray
    displacement: np.ndarray
    peak_times: np.ndarray
    peak_amplitudes: np.ndarray
    cycles: tuple[CycleUpdate, ...] = ()
    model: str = ""
    inputs: dict = field(default_factory=dict)

    @property
    def damping_ratio(self) -> tuple[np.ndarray, np.ndarray]:
        """(mean amplitude [m], zeta [-]) per cycle, Eqs. (24)-(25)."""
        return damping_ratio_from_peaks(self.peak_amplitudes)

    @property
    def final_amplitude(self) -> float:
        """Amplitude of the last negative peak [m]."""
        return float(self.peak_amplitudes[-1])

    @property
    def effective_frequency(self) -> np.ndarray:
        """Effective eigenfrequency of each cycle, 1 / (t_n+1 - t_n) [Hz]."""
        return 1.0 / np.diff(self.peak_times)

    def amplitude_at(self, t: float) -> float:
        """Amplitude envelope at time ``t`` [m].

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


def _segment(x0: float, sigma: float, wn: float, tau: np.ndarray) -> np.ndarray:
    """x(tau) of ``x'' + 2 sigma x' + wn^2 x = 0`` from rest at x0, any damping."""
    wd2 = wn * wn - sigma * sigma
    if wd2 > 1e-12 * wn * wn:
        wd = math.sqrt(wd2)
        return x0 * np.exp(-sigma * tau) * (np.cos(wd * tau) + sigma / wd * np.sin(wd * tau))
    if wd2 < -1e-12 * wn * wn:
        q = math.sqrt(-wd2)
        return x0 * np.exp(-sigma * tau) * (np.cosh(q * tau) + sigma / q * np.sinh(q * tau))
    return x0 * np.exp(-sigma * tau) * (1.0 + sigma * tau)


def simulate_pseudo_force(model, structure, duration: float, initial_displacement: float,
                          sample_rate: float = 2000.0) -> FreeVibrationResult:
    """Free vibration with a :class:`~pdamper.coupling.PseudoForceDamper` (Sect. 4.1).

    The damper is evaluated at the minimum's amplitude and at the effective eigenfrequency
    ``sqrt(K / (M + m_eff)) / 2 pi``, which itself depends on m_eff: a short fixed-point
    iteration, started from the previous cycle's m_eff, settles both.
    """
    check_range("simulation.duration", duration, low=0.0, low_inclusive=False, unit="s")
    check_range("simulation.sample_rate", sample_rate, low=0.0, low_inclusive=False, unit="Hz")
    check_range("structure.initial_displacement", initial_displacement, unit="m")
    if duration * sample_rate > MAX_SAMPLES:
        raise InputError("simulation.duration",
                         f"duration x sample_rate must be <= {MAX_SAMPLES:.0e} samples, got "
                         f"{duration:g} s x {sample_rate:g} Hz")
    if initial_displacement >= 0:
        raise InputError("structure.initial_displacement",
                         f"must be < 0 m (released from a minimum), got {initial_displacement:g} m")
    m_s, d_s, k_s = structure.mass, structure.damping, structure.stiffness
    t_grid = np.arange(0.0, duration + 0.5 / sample_rate, 1.0 / sample_rate)
    x_grid = np.empty_like(t_grid)
    peaks_t, peaks_x, cycles = [0.0], [abs(initial_displacement)], []
    t0, x0 = 0.0, initial_displacement
    m_eff = 0.0
    while True:
        amp = abs(x0)
        m_eff, d, freq, resp = _update(model, structure, amp, m_eff)
        cycles.append(CycleUpdate(t0, amp, freq, MotionMode(int(resp.mode)), m_eff, d,
                                  float(resp.loss_factor)))
        m_tot = m_s + m_eff
        sigma = (d_s + d) / (2.0 * m_tot)
        wn = math.sqrt(k_s / m_tot)
        underdamped = sigma < wn
        period = 2.0 * math.pi / math.sqrt(wn * wn - sigma * sigma) if underdamped else math.inf
        t1 = t0 + period
        sel = (t_grid >= t0) & (t_grid < min(t1, duration + 1.0))
        x_grid[sel] = _segment(x0, sigma, wn, t_grid[sel] - t0)
        if t1 > duration:
            break
        x0 = float(_segment(x0, sigma, wn, np.array([period]))[0])
        t0 = t1
        peaks_t.append(t0)
        peaks_x.append(abs(x0))
        if abs(x0) < 1e-12:  # at rest
            x_grid[t_grid >= t0] = 0.0
            break
    return FreeVibrationResult(
        time=t_grid, displacement=x_grid, peak_times=np.array(peaks_t),
        peak_amplitudes=np.array(peaks_x), cycles=tuple(cycles), model=model.fidelity,
        inputs={"duration": duration, "initial_displacement": initial_displacement,
                "sample_rate": sample_rate},
    )


def _update(model, structure, amplitude: float, m_eff: float):
    freq = math.sqrt(structure.stiffness / (structure.mass + m_eff)) / (2.0 * math.pi)
    for _ in range(_FREQUENCY_ITERATIONS):
        m_new, d, resp = model.pseudo_force_coefficients(freq, amplitude)
        freq_new = math.sqrt(structure.stiffness / (structure.mass + m_new)) / (2.0 * math.pi)
        converged = abs(freq_new - freq) < 1e-9 * freq
        freq = freq_new
        if converged:
            break
    m_new, d, resp = model.pseudo_force_coefficients(freq, amplitude)
    return m_new, d, freq, resp


class Simulation:
    """A structure with a damper model, released from an initial deflection (Sect. 4.2).

    Parameters
    ----------
    structure
        The :class:`~pdamper.structure.SingleDOFStructure`.
    model
        Any :class:`~pdamper.coupling.DamperModel` (analytic, effective fields, DEM).
    initial_displacement
        x0 [m], negative (the paper's -58 mm).

    Examples
    --------
    >>> from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
    >>> from pdamper.coupling import AnalyticalDamper
    >>> res = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER)).run(2.0)
    >>> 0.005 < res.final_amplitude < 0.015
    True
    """

    def __init__(self, structure, model, initial_displacement: float = -0.058):
        self.structure = structure
        self.model = model
        self.initial_displacement = initial_displacement

    def run(self, duration: float, sample_rate: float = 2000.0) -> FreeVibrationResult:
        """Simulate ``duration`` [s]; the trajectory is sampled at ``sample_rate`` [Hz]."""
        return self.model.free_vibration(self.structure, duration, self.initial_displacement,
                                         sample_rate)
