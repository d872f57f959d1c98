"""Complex power method, paper Eqs. (1)-(4)."""

import math

import numpy as np
import pytest

from pdamper.analysis.complex_power import complex_amplitude, complex_power


def _signals(f=10.0, x=0.032, cycles=6, n=6001):
    w = 2 * math.pi * f
    t = np.linspace(0, cycles / f, n)
    return t, w, x * w * np.cos(w * t), -x * w * w * np.sin(w * t)


def test_viscous_damper_dissipates_pi_c_w_x2_per_cycle():
    """A dashpot c: E~ = pi c W X^2 (Eq. 2), effective mass |m + c/(iW)| (Eq. 4)."""
    t, w, v, a = _signals()
    m, c, m_con = 0.132, 2.0, 0.5
    r = complex_power(t, (m + m_con) * a + c * v, v, a, 10.0, bed_mass=m, container_mass=m_con)
    assert r.dissipated_energy_per_cycle == pytest.approx(math.pi * c * w * 0.032**2, rel=1e-6)
    assert r.effective_mass == pytest.approx(abs(m + c / (1j * w)), rel=1e-6)
    e_kin = 0.5 * m * (0.032 * w) ** 2
    assert r.loss_factor == pytest.approx(r.dissipated_energy_per_cycle / (2 * math.pi) / e_kin)


def test_optimal_collect_and_collide_energy_gives_eta_max():
    """NOTES.md check: E~ = 4 m V^2 gives eta = 4/pi."""
    t, w, v, a = _signals()
    m = 0.132
    V = 0.032 * w
    # a force in phase with velocity dissipating exactly 4 m V^2 per cycle
    c = 4 * m * V**2 / (math.pi * w * 0.032**2)
    r = complex_power(t, c * v, v, a, 10.0, bed_mass=m)
    assert r.loss_factor == pytest.approx(4 / math.pi, rel=1e-6)


def test_complex_amplitude_of_a_cosine():
    t, w, _, _ = _signals()
    z = complex_amplitude(t, 3.0 * np.cos(w * t + 0.4), 10.0)
    assert abs(z) == pytest.approx(3.0, rel=1e-6)
    assert np.angle(z) == pytest.approx(0.4, abs=1e-6)
