"""Scalar contact physics of :mod:`pdamper.contact.forces`."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pdamper.contact.damping import restitution_from_damping_factor
from pdamper.contact.forces import (
    DAMPING_EXACT,
    DAMPING_GONTHIER,
    friction_magnitude,
    friction_per_slip,
    normal_force,
    onset_damping,
)
from pdamper.contact.hertz import hertz_stiffness


def test_normal_force_hertz_and_clipping():
    """Hertz-Gonthier law F = K delta^1.5 (1 + d delta_dot), no tension."""
    k, d = 2e9, 0.5
    f, fel = normal_force(1e-5, 0.2, k, d)
    assert fel == pytest.approx(k * 1e-5**1.5, rel=1e-14)
    assert f == pytest.approx(fel * (1 + d * 0.2), rel=1e-14)
    f, fel = normal_force(1e-5, -10.0, k, d)  # 1 + d v < 0: clipped
    assert f == 0.0 and fel > 0.0


def test_friction_tanh_regularisation():
    """Coulomb friction regularised by tanh(|v_t| / v_reg)."""
    assert friction_magnitude(0.1, 5.0, 1.0, 0.01) == pytest.approx(0.5, rel=1e-12)
    assert friction_magnitude(0.1, 5.0, 0.01, 0.01) == pytest.approx(0.5 * math.tanh(1.0))
    assert friction_magnitude(0.1, 5.0, 0.0, 0.01) == 0.0


def test_friction_law_is_tanh_to_the_last_bits():
    """The kernels' tanh (a rational form below |v_t| = 0.625 v_reg, exp above) equals
    ``math.tanh`` within 1e-15 (relative) from 1e-12 v_reg to beyond saturation, both sides
    of the split included, and the force per slip speed times the slip speed is the force."""
    v_reg = 0.01
    x = np.concatenate([np.logspace(-12, 2, 4001), np.linspace(0.62, 0.63, 1001),
                        [0.625, np.nextafter(0.625, 0.0), 19.999, 20.0, 20.001]])
    for xi in x:
        vt = xi * v_reg
        exact = 0.5 * math.tanh(xi)
        assert friction_magnitude(0.1, -5.0, vt, v_reg) == pytest.approx(exact, rel=1e-15)
        assert friction_per_slip(0.1, 5.0, vt * vt, v_reg) * vt == pytest.approx(exact,
                                                                                rel=1e-15)


def test_hertz_stiffness():
    """K = 4/3 E* sqrt(R*)."""
    assert hertz_stiffness(1e9, 0.0025) == pytest.approx(4 / 3 * 1e9 * 0.05)


@pytest.mark.parametrize("e", [0.3, 0.6, 0.85, 0.99])
def test_onset_damping_reproduces_cor_in_ode(e):
    """Exact COR relation: integrating m x'' = -K x^1.5 (1 + d x') gives back e."""
    v_nodes, e_nodes = np.array([0.0]), np.array([e])
    v0 = 0.7
    d = onset_damping(v0, v_nodes, e_nodes, DAMPING_EXACT, 1e-3)
    m, k = 4e-3, 3e8

    def rhs(t, y):
        x, v = y
        return [v, -k * max(x, 0.0) ** 1.5 * (1 + d * v) / m]

    def leave(t, y):
        return y[0]

    leave.terminal = True
    leave.direction = -1
    sol = solve_ivp(rhs, (0, 1e-2), [1e-14, v0], events=leave, rtol=1e-11, atol=1e-16,
                    method="DOP853")
    e_sim = -sol.y_events[0][0][1] / v0
    assert e_sim == pytest.approx(e, abs=2e-6)


def test_gonthier_option_differs_by_hundredths():
    """Gonthier's (1 - e^2)/e is the paper's approximation: off by ~0.03 near e = 0.8."""
    v_nodes, e_nodes = np.array([0.0]), np.array([0.8])
    d = onset_damping(1.0, v_nodes, e_nodes, DAMPING_GONTHIER, 1e-3)
    assert d == pytest.approx(0.45)
    e_actual = restitution_from_damping_factor(d * 1.0)
    assert 0.01 < 0.8 - e_actual < 0.06


def test_onset_speed_floor_and_velocity_dependent_curve():
    """The COR is read at the onset speed (floored at v_min) from the pair's curve."""
    v_nodes, e_nodes = np.array([0.1, 1.0]), np.array([0.9, 0.5])
    d_slow = onset_damping(1e-6, v_nodes, e_nodes, DAMPING_EXACT, 0.01)
    d_floor = onset_damping(0.01, v_nodes, e_nodes, DAMPING_EXACT, 0.01)
    assert d_slow == d_floor
    d_mid = onset_damping(0.55, v_nodes, e_nodes, DAMPING_EXACT, 0.01)
    assert restitution_from_damping_factor(d_mid * 0.55) == pytest.approx(0.7, abs=1e-9)
