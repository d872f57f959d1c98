"""Closed forms of the elastic Hertz contact, without numba.

Effective modulus and radius, Hertz stiffness, the largest overlap and the duration of an
elastic impact, the Rayleigh time and the bar wave speed. This module imports no numba, so
that the scenario reader and the resource model (:mod:`pdamper.resources`) can judge what a
run implies (its time step, whether an excitation is faster than a contact) without loading
the DEM; :mod:`pdamper.contact.hertz` re-exports these functions and compiles the stiffness
for the kernels.

The normal force is ``F = K delta^(3/2)`` with ``K = 4/3 E* sqrt(R*)``.
"""

from __future__ import annotations

import math

from pdamper.materials import Material

HERTZ_EXPONENT = 1.5


def effective_modulus(a: Material, b: Material) -> float:
    """E* = [ (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b ]^-1 [Pa]."""
    return 1.0 / ((1 - a.poisson_ratio**2) / a.youngs_modulus
                  + (1 - b.poisson_ratio**2) / b.youngs_modulus)


def effective_shear_modulus(a: Material, b: Material) -> float:
    """G* = [ 2 (2 - nu_a)(1 + nu_a)/E_a + 2 (2 - nu_b)(1 + nu_b)/E_b ]^-1 [Pa]: Mindlin's
    tangential stiffness ``8 G* sqrt(R* delta)`` (LIGGGHTS' Hertz model, ``Geff``), i.e.
    ``G* = [(2 - nu_a)/G_a + (2 - nu_b)/G_b]^-1`` with ``G = E / (2 (1 + nu))``."""
    return 1.0 / (2.0 * (2.0 - a.poisson_ratio) * (1.0 + a.poisson_ratio) / a.youngs_modulus
                  + 2.0 * (2.0 - b.poisson_ratio) * (1.0 + b.poisson_ratio) / b.youngs_modulus)


def effective_radius(r_a: float, r_b: float = math.inf) -> float:
    """R* = (1/r_a + 1/r_b)^-1 [m]; ``r_b = inf`` for a flat wall."""
    return 1.0 / (1.0 / r_a + (0.0 if math.isinf(r_b) else 1.0 / r_b))


def hertz_stiffness(e_star, r_star):
    """Hertz stiffness K = 4/3 E* sqrt(R*) [N/m^1.5] (compiled for the kernels as
    :func:`pdamper.contact.hertz.hertz_stiffness`)."""
    return 4.0 / 3.0 * e_star * math.sqrt(r_star)


# 2 * int_0^1 (1 - u^(5/2))^(-1/2) du = (4/5) B(2/5, 1/2)
_HERTZ_TIME_FACTOR = 0.8 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)


def max_overlap(m_star: float, k: float, v_impact: float) -> float:
    """Maximum overlap of an elastic Hertz impact, (5 m* v^2 / (4 K))^(2/5) [m]."""
    return (5.0 * m_star * v_impact**2 / (4.0 * k)) ** 0.4


def contact_duration(m_star: float, k: float, v_impact: float) -> float:
    """Duration of an elastic Hertz impact [s].

    ``t_c = 2.9432 * delta_max / v``, from integrating the energy balance
    ``m v^2/2 = m v0^2/2 - 2/5 K delta^(5/2)`` over the approach and the rebound.
    """
    return _HERTZ_TIME_FACTOR * max_overlap(m_star, k, v_impact) / v_impact


def rayleigh_time(radius: float, material: Material) -> float:
    """Rayleigh wave time of a sphere, pi R sqrt(rho/G) / (0.1631 nu + 0.8766) [s]."""
    nu = material.poisson_ratio
    return (math.pi * radius * math.sqrt(material.density / material.shear_modulus)
            / (0.1631 * nu + 0.8766))


def bar_wave_speed(material: Material) -> float:
    """Longitudinal wave speed of a thin bar, sqrt(E / rho) [m/s]: the speed at which a
    solid passes an impact on; quasi-static (Hertz) contact needs impacts far slower."""
    return math.sqrt(material.youngs_modulus / material.density)
