"""Pseudo-force coupling on N modes (Sect. 4.1 beyond one mode): equal to Eq. (23) with
one mode, exact against independent solutions, and the one-mode-enough study."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pdamper.coupling import Simulation
from pdamper.coupling.modal import ModeCountStudy, mode_count_study
from pdamper.models import AnalyticalDamper, DamperModel, DamperResponse, DEMDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_INITIAL_DISPLACEMENT, paper_beam
from pdamper.structure.beam import modal_reduction
from pdamper.structure.modal import ModalStructure


class ConstantDamper(DamperModel):
    """Constant effective mass and viscous damping (a dashpot and a mass), for references."""

    fidelity = "constant"

    def __init__(self, m_eff, d):
        super().__init__(PAPER_DAMPER)
        self.m_eff, self.d = m_eff, d

    def response(self, frequency, amplitude):
        w = 2 * math.pi * np.asarray(frequency, float)
        x = np.asarray(amplitude, float)
        return DamperResponse(frequency, amplitude, np.asarray(0), np.asarray(0.0),
                              math.pi * self.d * w * x**2,
                              np.asarray(self.m_eff / self.bed_mass), self.bed_mass)


@pytest.fixture(scope="module")
def beam():
    b, tip = paper_beam()
    zeta = modal_reduction(b, tip).to_structure(0.55).damping_ratio
    return b, tip, zeta


@pytest.mark.parametrize("count", [32, 64])
def test_one_mode_with_the_damper_at_the_tip_is_the_1dof_result(beam, count):
    """The acceptance test: the FE beam reduced to one mode with the damper at the tip runs
    the same free vibration as Eq. (23) with (M_red, D, K_red) of that mode (trajectory,
    peaks, damper updates), although the N-mode coupling finds each minimum numerically."""
    b, tip, zeta = beam
    model = AnalyticalDamper(PAPER_DAMPER.with_count(count))
    one_dof = modal_reduction(b, tip).to_structure(damping=0.55)
    modal = ModalStructure.from_beam(b, tip, 1, damping_ratio=zeta)
    a = Simulation(one_dof, model, PAPER_INITIAL_DISPLACEMENT).run(2.0)
    m = Simulation(modal, model, PAPER_INITIAL_DISPLACEMENT).run(2.0)
    np.testing.assert_allclose(m.displacement, a.displacement, atol=1e-12)
    np.testing.assert_allclose(m.peak_times, a.peak_times, atol=1e-12)
    np.testing.assert_allclose(m.peak_amplitudes, a.peak_amplitudes, rtol=1e-10)
    assert [c.mode for c in m.cycles] == [c.mode for c in a.cycles]
    np.testing.assert_allclose([c.frequency for c in m.cycles], [c.frequency for c in a.cycles],
                               rtol=1e-10)


def test_no_damper_is_modal_superposition(beam):
    """Without particles each mode decays on its own: x(t) = sum_i psi_i q_i(0) e^{-z w t}
    (cos w_d t + z w / w_d sin w_d t), evaluated here independently."""
    b, tip, _ = beam
    s = ModalStructure.from_beam(b, tip, 3, damping_ratio=[0.005, 0.01, 0.02],
                                 release_position=0.4, output_position=0.6)
    res = Simulation(s, AnalyticalDamper(PAPER_DAMPER.with_count(0)), -0.02).run(0.5)
    q0 = s.release_state(-0.02)
    t = res.time
    x = np.zeros_like(t)
    for i in range(3):
        w = 2 * math.pi * s.frequencies[i]
        z = s.damping_ratios[i]
        wd = w * math.sqrt(1 - z * z)
        x += s.output_shape[i] * q0[i] * np.exp(-z * w * t) * (np.cos(wd * t)
                                                                + z * w / wd * np.sin(wd * t))
    np.testing.assert_allclose(res.displacement, x, atol=1e-12)


def test_constant_pseudo_force_on_three_modes_against_an_ode_solver(beam):
    """Constant m_eff and d at mid-span: the closed-form segments against scipy's RK45 on
    (I + m phi phi^T) q'' + (C + d phi phi^T) q' + W^2 q = 0."""
    b, tip, _ = beam
    s = ModalStructure.from_beam(b, tip, 3, damping_ratio=0.005, damper_position=0.4)
    m_eff, d = 0.3, 4.0
    res = Simulation(s, ConstantDamper(m_eff, d), -0.03).run(0.6)
    phi = s.damper_shape
    w = 2 * math.pi * s.frequencies
    mass = np.eye(3) + m_eff * np.outer(phi, phi)
    damp = np.diag(2 * 0.005 * w) + d * np.outer(phi, phi)
    minv = np.linalg.inv(mass)

    def rhs(_t, z):
        return np.concatenate([z[3:], -minv @ (w**2 * z[:3] + damp @ z[3:])])

    sol = solve_ivp(rhs, (0, 0.6), np.concatenate([s.release_state(-0.03), np.zeros(3)]),
                    t_eval=res.time, rtol=1e-10, atol=1e-13, method="DOP853")
    np.testing.assert_allclose(res.displacement, s.output_shape @ sol.y[:3], atol=1e-9)
    assert len(res.cycles) == len(res.details.update_times)


def test_the_dem_runs_on_n_modes_and_one_mode_as_its_1dof(beam):
    from pdamper.coupling.simulation import MODAL_COUPLINGS

    b, tip, zeta = beam
    two = Simulation(ModalStructure.from_beam(b, tip, 2), DEMDamper(PAPER_DAMPER), -0.058)
    assert two.coupling.name == "co_simulation" and two.structure.modes == 2
    assert "co_simulation" in MODAL_COUPLINGS
    sim = Simulation(ModalStructure.from_beam(b, tip, 1, damping_ratio=zeta),
                     DEMDamper(PAPER_DAMPER), -0.058)
    assert sim.structure.mass == pytest.approx(modal_reduction(b, tip).mass)


def test_when_one_mode_is_enough(beam):
    """Released at the tip (the paper's counterweight), the tip amplitude at 0.75 s changes
    by less than 1 % from one to three modes wherever the damper sits; released by a load at
    an interior point (0.2 m) the first mode alone is far off (> 20 %), and three modes agree
    with four within 3 %. Numbers: docs/structure.md."""
    b, tip, zeta = beam
    model = AnalyticalDamper(PAPER_DAMPER)

    def build(release):
        return lambda p, n: ModalStructure.from_beam(b, tip, n, damper_position=p,
                                                     damping_ratio=zeta,
                                                     release_position=release)

    tip_release = mode_count_study(model, build(None), [0.68, 0.51], modes=(1, 3), at=0.75)
    assert isinstance(tip_release, ModeCountStudy)
    assert np.all(tip_release.relative_change < 0.01)
    inner = mode_count_study(model, build(0.2), [0.68], modes=(1, 3, 4), at=0.75,
                             initial_displacement=-0.015)
    a = np.asarray(inner.amplitude[0])
    assert abs(a[0] / a[2] - 1) > 0.2
    assert a[1] == pytest.approx(a[2], rel=0.03)
