"""Thornton's coefficient of restitution of elastic-perfectly plastic spheres (Level I).

C. Thornton, "Coefficient of restitution for collinear collisions of elastic-perfectly
plastic spheres", J. Appl. Mech. 64 (1997) 383-386. The contact is Hertzian until the
contact pressure reaches the limiting pressure ``p_y``; beyond, the pressure is truncated at
``p_y`` and the force grows linearly with the overlap; unloading is Hertzian with an enlarged
radius of curvature. With ``x = V_y / V_i`` the model's COR is (Thornton's closed form)

    e = sqrt(6 sqrt(3) / 5) sqrt(1 - x^2 / 6)
        * [x / (x + 2 sqrt(6/5 - x^2/5))]^(1/4)          for V_i > V_y,   e = 1 below,

falling as ``1.185 x^(1/4)`` at high speed. The yield velocity follows from the energy that
the Hertz contact stores up to first yield, ``m* V_y^2 / 2 = 8/15 E* sqrt(R*) delta_y^(5/2)``
with ``delta_y = (pi p_y / (2 E*))^2 R*``:

    V_y^2 = (16/15) (pi/2)^5 p_y^5 R*^3 / (E*^4 m*),

which for a sphere on a rigid wall is Thornton's ``V_y = 1.56 (p_y^5 / (E*^4 rho))^(1/2)``.

pdamper takes the limiting pressure from the yield strength as ``p_y = 1.6 Y`` (first yield
below the surface of a Hertz contact under von Mises, nu ~ 0.3: Johnson, Contact Mechanics,
1985, Sect. 6.2) of the weaker of the two materials that have a yield strength, unless given.

Scope: plastic dissipation only. Viscoelastic losses (polymers, rubber) and elastic waves
are not in the model; for such pairs it is an upper bound of the COR: use measured curves.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pdamper.contact.restitution import ParametricRestitution
from pdamper.errors import InputError, check_range
from pdamper.materials import Material

#: Limiting contact pressure over yield strength, ``p_y = 1.6 Y`` (Johnson 1985) [-].
PRESSURE_FACTOR = 1.6


def thornton_cor(v, yield_velocity):
    """Thornton's closed-form COR at impact speeds ``v`` [m/s] for ``V_y`` [m/s]."""
    v = np.abs(np.asarray(v, float))
    x = np.divide(yield_velocity, v, out=np.full(v.shape, np.inf), where=v > 0)
    plastic = x < 1.0
    xp = np.where(plastic, x, 0.5)
    e = (math.sqrt(6.0 * math.sqrt(3.0) / 5.0) * np.sqrt(1.0 - xp**2 / 6.0)
         * (xp / (xp + 2.0 * np.sqrt(6.0 / 5.0 - xp**2 / 5.0))) ** 0.25)
    return np.where(plastic, e, 1.0)


def yield_velocity(limiting_pressure: float, effective_modulus: float, effective_radius: float,
                   effective_mass: float) -> float:
    """Impact speed at which the contact first yields, V_y [m/s].

    Parameters
    ----------
    limiting_pressure
        p_y [Pa].
    effective_modulus, effective_radius, effective_mass
        E* [Pa], R* [m], m* [kg] of the pair.
    """
    p, e, r, m = limiting_pressure, effective_modulus, effective_radius, effective_mass
    return math.sqrt(16.0 / 15.0 * (math.pi / 2.0) ** 5 * p**5 * r**3 / (e**4 * m))


def limiting_pressure(a: Material, b: Material, factor: float = PRESSURE_FACTOR,
                      field_name: str = "restitution") -> float:
    """``factor x`` the smaller known yield strength of ``a`` and ``b`` [Pa]."""
    known = [m.yield_strength for m in (a, b) if m.yield_strength is not None]
    if not known:
        raise InputError(field_name, f"Thornton's model needs a yield strength, and neither "
                         f"{a.name} nor {b.name} has one; give an inline material with "
                         "yield_strength, a limiting_pressure, or a measured table")
    return factor * min(known)


@dataclass(frozen=True)
class ThorntonRestitution(ParametricRestitution):
    """Thornton's (1997) COR of elastic-perfectly plastic spheres, a function of the impact
    speed through the yield velocity ``V_y`` alone (module docstring).

    Parameters
    ----------
    yield_velocity
        V_y [m/s], > 0 (:meth:`from_materials` computes it from material data).
    name
        Optional label (not compared).
    """

    yield_velocity: float
    name: str = field(default="", compare=False)

    PARAMETERS = ("yield_velocity",)
    UNITS = ("m/s",)
    BOUNDS = ((1e-9,), (1e3,))

    def __post_init__(self) -> None:
        check_range("restitution.yield_velocity", self.yield_velocity, low=0.0,
                    low_inclusive=False, unit="m/s")

    @staticmethod
    def function(v, yield_velocity):
        return thornton_cor(v, yield_velocity)

    def breakpoints(self) -> tuple[float, ...]:
        return (self.yield_velocity,)

    @classmethod
    def guess(cls, v, e):
        # high-speed asymptote e = 1.185 (V_y / v)^(1/4)
        fast = e < 0.95
        if not fast.any():
            return (float(np.max(v)),)
        return (float(np.median(v[fast] * (e[fast] / 1.185) ** 4)),)

    @classmethod
    def from_materials(cls, sphere: Material, partner: Material, radius: float,
                       partner_radius: float = math.inf, *,
                       pressure: float | None = None,
                       pressure_factor: float = PRESSURE_FACTOR) -> ThorntonRestitution:
        """The curve of a sphere of ``sphere`` material and ``radius`` [m] hitting a sphere
        of ``partner`` material and ``partner_radius`` [m] (``inf``: a fixed flat wall).

        ``pressure`` overrides the limiting pressure p_y [Pa]; otherwise
        ``pressure_factor x`` the weaker yield strength.
        """
        from pdamper.contact.hertz import effective_modulus, effective_radius

        r = check_range("particles.radius", radius, low=0.0, low_inclusive=False, unit="m")
        m_a = 4.0 / 3.0 * math.pi * r**3 * sphere.density
        if math.isinf(partner_radius):
            m_star = m_a
        else:
            rb = check_range("restitution.partner_radius", partner_radius, low=0.0,
                             low_inclusive=False, unit="m")
            m_b = 4.0 / 3.0 * math.pi * rb**3 * partner.density
            m_star = m_a * m_b / (m_a + m_b)
        p_y = (limiting_pressure(sphere, partner, pressure_factor) if pressure is None else
               check_range("restitution.limiting_pressure", pressure, low=0.0,
                           low_inclusive=False, unit="Pa"))
        v_y = yield_velocity(p_y, effective_modulus(sphere, partner),
                             effective_radius(r, partner_radius), m_star)
        kind = "wall" if math.isinf(partner_radius) else "sphere"
        return cls(v_y, name=f"Thornton {sphere.name}-{partner.name} {kind} "
                             f"(V_y = {v_y * 1e3:.3g} mm/s)")

    def describe(self) -> str:
        return self.name or f"Thornton (V_y = {self.yield_velocity * 1e3:.3g} mm/s)"


__all__ = ["PRESSURE_FACTOR", "ThorntonRestitution", "limiting_pressure", "thornton_cor",
           "yield_velocity"]
