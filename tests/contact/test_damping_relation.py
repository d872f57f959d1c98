"""COR <-> damping relation of F = K delta^n (1 + d delta_dot) (Level I contact law)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pdamper.contact.damping import damping_factor, restitution_from_damping_factor
from pdamper.errors import InputError


def _simulated_cor(x, n=1.5, k=1e9, m=4e-3, v0=0.7):
    """Integrate one impact of m delta'' = -K delta^n (1 + d delta') and return e."""
    d = x / v0

    def rhs(_, y):
        delta, v = y
        return [v, -k * max(delta, 0.0) ** n * (1 + d * v) / m]

    def leave(_, y):
        return y[0]

    leave.terminal, leave.direction = True, -1
    t_end = 50 * (m / k) ** 0.4 * v0**-0.2
    sol = solve_ivp(rhs, (0, t_end), [0.0, v0], events=leave, rtol=1e-11, atol=1e-15,
                    first_step=t_end * 1e-6, max_step=t_end / 2000)
    return -sol.y_events[0][0][1] / v0


@pytest.mark.parametrize("e", [0.3, 0.6, 0.8, 0.85, 0.95])
@pytest.mark.parametrize("n", [1.0, 1.5])
def test_exact_relation_reproduces_the_cor_of_an_integrated_impact(e, n):
    """The closed-form root x = d v0 gives exactly e, whatever K and n (Eq. (*))."""
    x = damping_factor(e)
    assert _simulated_cor(x, n=n) == pytest.approx(e, abs=2e-5)


def test_gonthier_is_off_by_a_few_hundredths_near_0p8():
    """Gonthier's x = (1 - e^2)/e gives e = 0.77 when 0.8 is asked for."""
    got = _simulated_cor(damping_factor(0.8, "gonthier"))
    assert 0.02 < 0.8 - got < 0.04
    assert restitution_from_damping_factor(damping_factor(0.8, "gonthier")) == pytest.approx(got, abs=1e-4)


def test_relation_limits():
    """e -> 1: x -> 3 (1 - e) / 2, the Hunt-Crossley small-dissipation limit (series of
    Eq. (*): x^2 (1 - e^2)/2 - x^3 (1 + e^3)/3 = 0); Gonthier's tends to 2 (1 - e)."""
    assert damping_factor(1.0) == 0.0
    assert damping_factor(0.9999) == pytest.approx(1.5 * 1e-4, rel=1e-3)
    assert damping_factor(0.9999, "gonthier") == pytest.approx(2.0 * 1e-4, rel=1e-3)
    xs = damping_factor(np.array([0.2, 0.5, 0.9]))
    assert np.all(np.diff(xs) < 0)
    assert math.isfinite(damping_factor(0.01))


@pytest.mark.parametrize("e", [0.0, -0.1, 1.2, float("nan")])
def test_bad_restitution(e):
    with pytest.raises(InputError, match="restitution"):
        damping_factor(e)


def _tsuji_cor(e, limit_force=False):
    """Integrate u'' = -u^1.5 - a u^0.25 u' (Tsuji's law in units where K = m* = v0 = 1;
    a = 2 sqrt(5/6) |beta| sqrt(3/2)) with scipy; ``limit_force``: F clipped at zero."""
    from pdamper.contact.damping import tsuji_damping_ratio_scalar

    a = tsuji_damping_ratio_scalar(e) * math.sqrt(1.5)

    def rhs(_, y):
        u = max(y[0], 0.0)
        f = -(u**1.5) - a * u**0.25 * y[1]
        return [y[1], min(f, 0.0) if limit_force else f]

    def leave(_, y):
        return y[0]

    leave.terminal, leave.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 50.0), [0.0, 1.0], events=leave, method="DOP853", rtol=1e-12,
                    atol=1e-14, first_step=1e-6, max_step=0.01)
    return -sol.y_events[0][0][1]


@pytest.mark.parametrize("e", [0.1, 0.3, 0.6, 0.85, 0.99])
def test_tsuji_law_restitutes_the_nominal_cor_unless_clipped(e):
    """Tsuji's law (LIGGGHTS/EDEM "Hertz with COR", beta = ln e / sqrt(ln^2 e + pi^2) of
    the linear spring, factor 2 sqrt(5/6)): integrated, its COR is e itself (to 1e-9) when
    the force may turn attractive (LIGGGHTS' default, pdamper's law); clipped at zero it
    restitutes more (its known deviation: +0.097 at e = 0.3, +0.032 at 0.6)."""
    assert _tsuji_cor(e) == pytest.approx(e, abs=1e-9)
    clipped = _tsuji_cor(e, limit_force=True)
    assert clipped > e
    if e == 0.3:
        assert clipped - e == pytest.approx(0.097, abs=0.002)
    if e == 0.6:
        assert clipped - e == pytest.approx(0.032, abs=0.002)


def test_tsuji_damping_ratio():
    """2 sqrt(5/6) |ln e| / sqrt(ln^2 e + pi^2); 0 for e = 1."""
    assert damping_factor(1.0, "tsuji") == 0.0
    le = math.log(0.6)
    assert damping_factor(0.6, "tsuji") == pytest.approx(2 * math.sqrt(5 / 6) * -le
                                                         / math.hypot(le, math.pi))
