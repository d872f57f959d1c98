"""Pseudo-force coupling of a damper model to a 1-DOF structure (paper Sect. 4.1, models
2 and 3).

The damper acts as ``F = -(m_eff x'' + d x')`` with ``d = E~ / (pi W X^2)``, both updated
once per cycle at each minimum of the end-effector from that minimum's amplitude X and the
system's (effective) eigenfrequency. Between two updates the equation of motion is linear,

    (M + m_eff) x'' + (D + d) x' + K x = 0,

and is solved in closed form from one minimum (where x' = 0) to the next, one damped period
later. The solution is exact: no time step.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from pdamper.analysis.modes import MotionMode
from pdamper.coupling.results import CycleUpdate, FreeVibrationResult
from pdamper.errors import InputError, check_range

logger = logging.getLogger(__name__)

#: Largest stored trajectory [samples] (a longer run is a typo, not a design question).
MAX_SAMPLES = 2e7

#: Fixed-point iterations between the effective eigenfrequency and the effective mass.
_FREQUENCY_ITERATIONS = 3


def motion_mode(code) -> MotionMode | None:
    """The :class:`MotionMode` of a response's mode code; None for unclassified (-1) or
    codes this version does not know."""
    try:
        return MotionMode(int(code))
    except ValueError:
        return None


def pseudo_force_coefficients(model, frequency: float, amplitude: float):
    """Effective mass m_eff [kg], viscous damping d = E~ / (pi W X^2) [kg/s] and the
    response of ``model`` at one (f [Hz], X [m]) point (Sect. 4.1)."""
    r = model.response(frequency, amplitude)
    w = 2.0 * math.pi * frequency
    d = float(r.dissipated_energy_per_cycle) / (math.pi * w * amplitude**2)
    return float(r.effective_mass), d, r


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
    """Free vibration of ``structure`` carrying ``model``, released from rest at
    ``initial_displacement`` [m] (Sect. 4.1, models 2 and 3).

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
        cycles.append(CycleUpdate(t0, amp, freq, motion_mode(resp.mode), m_eff, d,
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
    """m_eff, d, the effective frequency and the response at ``amplitude``: a short fixed
    point between the frequency (``structure.effective_frequency(m_eff)``) and m_eff."""
    freq = structure.effective_frequency(m_eff)
    for _ in range(_FREQUENCY_ITERATIONS):
        m_new, d, resp = pseudo_force_coefficients(model, freq, amplitude)
        freq_new = structure.effective_frequency(m_new)
        converged = abs(freq_new - freq) < 1e-9 * freq
        freq = freq_new
        if converged:
            break
    m_new, d, resp = pseudo_force_coefficients(model, freq, amplitude)
    return m_new, d, freq, resp
