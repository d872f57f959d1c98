"""Thornton's (1997) COR of elastic-perfectly plastic spheres against its own contact law,
its published yield velocity and asymptote."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from pdamper.contact.hertz import effective_modulus
from pdamper.contact.thornton import (
    PRESSURE_FACTOR,
    ThorntonRestitution,
    thornton_cor,
    yield_velocity,
)
from pdamper.errors import InputError
from pdamper.materials import PVC, S235, Material, get_material

# an arbitrary contact: E* [Pa], R* [m], p_y [Pa], m* [kg]
E_STAR, R_STAR, P_Y, M_STAR = 1e10, 2e-3, 3e8, 4e-3


def _loading_force(d):
    """Thornton's loading: Hertz up to first yield, then the pressure is capped at p_y and
    the force grows with the contact area pi (a^2 - a_y^2), a^2 = R* delta."""
    a_y = math.pi * P_Y * R_STAR / (2 * E_STAR)
    d_y = a_y**2 / R_STAR
    k = 4.0 / 3.0 * E_STAR * math.sqrt(R_STAR)
    if d <= d_y:
        return k * d**1.5
    return k * d_y**1.5 + math.pi * P_Y * R_STAR * (d - d_y)


def _rebound_cor(v):
    """COR from the force-displacement law, integrated numerically: loading work equals the
    impact energy; unloading is Hertzian with the radius that matches the contact radius
    and force at the turning point; the work recovered gives e^2."""
    a_y = math.pi * P_Y * R_STAR / (2 * E_STAR)
    d_y = a_y**2 / R_STAR
    kinetic = 0.5 * M_STAR * v**2

    def work(d):
        return quad(_loading_force, 0.0, d, points=[d_y] if d > d_y else None,
                    epsabs=0, epsrel=1e-13)[0]

    d_max = brentq(lambda d: work(d) - kinetic, 0.0, 1e3 * d_y * (1 + v), xtol=1e-18, rtol=1e-14)
    f_max = _loading_force(d_max)
    a_max = math.sqrt(R_STAR * max(d_max, d_y))
    r_p = 4.0 * E_STAR * a_max**3 / (3.0 * f_max)
    k_p = 4.0 / 3.0 * E_STAR * math.sqrt(r_p)
    d_e = (f_max / k_p) ** (2.0 / 3.0)
    recovered = quad(lambda s: k_p * s**1.5, 0.0, d_e, epsabs=0, epsrel=1e-13)[0]
    return math.sqrt(recovered / kinetic)


def test_yield_velocity_is_the_energy_to_first_yield():
    """m* V_y^2 / 2 equals the Hertz work up to the yield overlap."""
    a_y = math.pi * P_Y * R_STAR / (2 * E_STAR)
    w = quad(_loading_force, 0.0, a_y**2 / R_STAR, epsrel=1e-13)[0]
    assert yield_velocity(P_Y, E_STAR, R_STAR, M_STAR) == pytest.approx(
        math.sqrt(2 * w / M_STAR), rel=1e-8)


def test_yield_velocity_of_a_sphere_on_a_wall_is_thorntons():
    """Thornton 1997: V_y = 1.56 (p_y^5 / (E*^4 rho))^(1/2) for a sphere on a rigid wall."""
    rho, r = 7900.0, 0.005
    m = 4.0 / 3.0 * math.pi * r**3 * rho
    v = yield_velocity(P_Y, E_STAR, r, m)
    assert v / math.sqrt(P_Y**5 / (E_STAR**4 * rho)) == pytest.approx(1.56, abs=0.005)


@pytest.mark.parametrize("ratio", [1.0 + 1e-9, 1.01, 1.5, 2.0, 5.0, 10.0, 100.0, 1e3, 1e4])
def test_closed_form_equals_the_contact_law(ratio):
    """Thornton's closed form e(V_i / V_y) equals the rebound of his force-displacement law
    integrated numerically, from first yield to 1e4 V_y."""
    v_y = yield_velocity(P_Y, E_STAR, R_STAR, M_STAR)
    v = ratio * v_y
    assert float(thornton_cor(v, v_y)) == pytest.approx(_rebound_cor(v), abs=1e-7)


def test_elastic_below_yield_and_the_high_speed_asymptote():
    """e = 1 up to V_y; e -> 1.185 (V_y / V_i)^(1/4) far above (Thornton 1997)."""
    assert thornton_cor(np.array([0.0, 0.5, 1.0]), 1.0).tolist() == [1.0, 1.0, 1.0]
    x = 1e-8
    assert float(thornton_cor(1.0, x)) / x**0.25 == pytest.approx(1.185, abs=1e-3)
    e = thornton_cor(np.geomspace(1.0, 1e4, 200), 1.0)
    assert np.all(np.diff(e) < 0)


def test_from_materials():
    """Sphere-sphere uses R* = r/2 and m* = m/2 (so V_y is half that of a sphere on a rigid
    wall of the same E*); p_y = 1.6 x the weaker yield strength."""
    r = 0.005
    m = 4.0 / 3.0 * math.pi * r**3 * S235.density
    es = effective_modulus(S235, S235)
    ss = ThorntonRestitution.from_materials(S235, S235, r, r)
    p_y = PRESSURE_FACTOR * S235.yield_strength
    assert ss.yield_velocity == pytest.approx(yield_velocity(p_y, es, r / 2, m / 2), rel=1e-12)
    assert ss.yield_velocity == pytest.approx(0.5 * yield_velocity(p_y, es, r, m), rel=1e-12)
    sw = ThorntonRestitution.from_materials(S235, PVC, r)  # PVC yields first
    assert sw.yield_velocity == pytest.approx(
        yield_velocity(PRESSURE_FACTOR * PVC.yield_strength, effective_modulus(S235, PVC), r, m))
    given = ThorntonRestitution.from_materials(S235, PVC, r, pressure=1e8)
    assert given.yield_velocity == pytest.approx(
        yield_velocity(1e8, effective_modulus(S235, PVC), r, m))


def test_needs_a_yield_strength():
    glass = get_material("glass")
    with pytest.raises(InputError, match="neither soda-lime glass nor alumina has one"):
        ThorntonRestitution.from_materials(glass, get_material("alumina"), 0.005, 0.005)
    # a brittle partner: the metal's yield strength limits the pressure
    assert ThorntonRestitution.from_materials(glass, S235, 0.005).yield_velocity > 0
    with pytest.raises(InputError):
        Material("x", 1e9, 0.3, 1000.0, -1.0)
