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
