"""The complex power method (paper Sect. 3, Eqs. 1-4).

For a container driven harmonically at angular frequency W, the complex amplitudes at W of
the driving force and of the container velocity and acceleration, taken over whole cycles,
give the dissipated energy per cycle, the effective loss factor and the effective particle
mass. Sign convention: the driving force is the container inertia plus the force that the
particles exert on the container in the driving direction (the force needed to move the
container), with the container velocity ``V cos(W t)``; then Re(P*) > 0 is the power the
damper dissipates. Check: the zero-gravity optimum E~ = 4 m_bed V^2 gives eta = 4/pi.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pdamper.errors import InputError, check_range


def complex_amplitude(t: np.ndarray, signal: np.ndarray, frequency: float) -> complex:
    """Complex amplitude at ``frequency`` [Hz] of ``signal`` sampled at times ``t`` [s].

    The single-bin discrete Fourier transform, ``2/T * int s(t) exp(-i W t) dt``,
    evaluated with the trapezoidal rule over the samples; ``t`` must span whole cycles.
    For ``s = S cos(W t + phi)`` it returns ``S exp(i phi)``.
    """
    t = np.asarray(t, float)
    s = np.asarray(signal, float)
    if t.shape != s.shape or t.size < 3:
        raise InputError("signal", "needs at least 3 samples, as many as time points")
    w = 2.0 * math.pi * frequency
    span = t[-1] - t[0]
    return complex(2.0 / span * np.trapezoid(s * np.exp(-1j * w * t), t))


def _samples(field: str, values, shape: tuple[int, ...] | None = None) -> np.ndarray:
    """A 1-D series of finite numbers (of ``shape``), or an InputError."""
    try:
        s = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a 1-D series of numbers, got {values!r:.60}") from None
    if s.ndim != 1 or (shape is not None and s.shape != shape):
        raise InputError(field, f"must be a 1-D series of {shape[0] if shape else 'n'} samples "
                         f"(one per time point), got shape {s.shape}")
    if not np.all(np.isfinite(s)):
        raise InputError(field, "must be finite")
    return s


@dataclass(frozen=True)
class ComplexPowerResult:
    """Result of the complex power method.

    Attributes
    ----------
    complex_power
        P* = 1/2 F* conj(V*) [W] (Eq. 1).
    dissipated_energy_per_cycle
        E~ = (2 pi / W) Re(P*) [J] (Eq. 2, the paper's tilde-E).
    loss_factor
        eta = E_diss / (1/2 m_bed |V*|^2), E_diss = E~ / (2 pi) [-] (Eq. 3).
    effective_mass
        |F*/A* - m_con| [kg] (Eq. 4).
    effective_mass_ratio
        effective_mass / m_bed [-].
    """

    complex_power: complex
    dissipated_energy_per_cycle: float
    loss_factor: float
    effective_mass: float
    effective_mass_ratio: float


def complex_power(
    t: np.ndarray,
    force: np.ndarray,
    velocity: np.ndarray,
    acceleration: np.ndarray,
    frequency: float,
    bed_mass: float,
    container_mass: float = 0.0,
) -> ComplexPowerResult:
    """Apply Eqs. (1)-(4) to sampled signals over whole cycles.

    Parameters
    ----------
    t
        Sample times [s], spanning an integer number of cycles.
    force
        Driving force on the container [N] (container inertia + particle force in the
        driving direction). With ``container_mass = 0`` pass the particle force alone.
    velocity, acceleration
        Container velocity [m/s] and acceleration [m/s^2].
    frequency
        Driving frequency f [Hz].
    bed_mass
        m_bed, mass of all particles [kg].
    container_mass
        m_con [kg], subtracted in Eq. (4).
    """
    check_range("frequency", frequency, low=0.0, low_inclusive=False, unit="Hz")
    check_range("bed_mass", bed_mass, low=0.0, low_inclusive=False, unit="kg")
    check_range("container_mass", container_mass, low=0.0, unit="kg")
    t = _samples("t", t)
    force, velocity, acceleration = (
        _samples(name, s, t.shape) for name, s in (("force", force), ("velocity", velocity),
                                                   ("acceleration", acceleration)))
    w = 2.0 * math.pi * frequency
    f_star = complex_amplitude(t, force, frequency)
    v_star = complex_amplitude(t, velocity, frequency)
    a_star = complex_amplitude(t, acceleration, frequency)
    p_star = 0.5 * f_star * np.conj(v_star)
    e_tilde = 2.0 * math.pi / w * p_star.real
    loss = (e_tilde / (2.0 * math.pi)) / (0.5 * bed_mass * abs(v_star) ** 2)
    m_eff = abs(f_star / a_star - container_mass)
    return ComplexPowerResult(complex(p_star), float(e_tilde), float(loss), float(m_eff),
                              float(m_eff / bed_mass))
