"""The analytical bed integrated event by event (pdamper.analysis.plastic_bed) against the
closed-form motion modes, the zero-gravity optimum and other codes' DEM."""

import math

import numpy as np
import pytest

from pdamper.analysis.analytical import bed_response
from pdamper.analysis.modes import EFFECTIVE_MASS_RATIO, MotionMode
from pdamper.analysis.plastic_bed import harmonic_plastic_bed

H, M = 0.1, 0.132  # the paper's 32 spheres: clearance [m], bed mass [kg]

#: 20 points over the closed forms' repetitive motion modes (f [Hz], X [m]): single and
#: double collect-and-collide, harmonic and subharmonic of orders 1-3.
POINTS = [
    (4.0, 0.020), (4.0, 0.032), (6.0, 0.010), (6.0, 0.020), (8.0, 0.005), (8.0, 0.010),
    (10.0, 0.005),                                                     # single, harmonic
    (4.0, 0.050), (6.0, 0.050), (8.0, 0.032), (10.0, 0.032), (14.0, 0.080),
    (18.0, 0.050), (25.0, 0.120),                                      # double, harmonic
    (8.0, 0.020), (10.0, 0.020), (14.0, 0.010), (25.0, 0.005),         # single, subharmonic
    (25.0, 0.020), (4.0, 0.120),                                       # double, sub / harm.
]


def test_the_twenty_points_cover_the_repetitive_modes():
    f, x = np.array(POINTS).T
    modes = {MotionMode(int(c)) for c in bed_response(f, x, H, M).mode}
    assert modes == {MotionMode.SINGLE_CAC_HARMONIC, MotionMode.DOUBLE_CAC_HARMONIC,
                     MotionMode.SINGLE_CAC_SUBHARMONIC, MotionMode.DOUBLE_CAC_SUBHARMONIC}
    assert len(POINTS) == 20


def test_event_driven_bed_reproduces_the_closed_form_loss_factor_within_2_percent():
    f, x = np.array(POINTS).T
    closed = bed_response(f, x, H, M)
    ev = harmonic_plastic_bed(f, x, H, M)
    rel = np.abs(ev.loss_factor / closed.loss_factor - 1.0)
    assert rel.max() < 0.02, rel
    # its orbit repeats with the closed form's period (1 + n_s cycles)
    np.testing.assert_array_equal(ev.period_cycles, closed.subharmonic_order + 1)
    # and the complex power of the bed's first harmonic gives the same eta (Eqs. 1-3)
    np.testing.assert_allclose(ev.loss_factor_complex_power, ev.loss_factor, rtol=1e-3)


def test_zero_gravity_optimum_is_four_over_pi():
    r = harmonic_plastic_bed(10.0, H / math.pi, H, M, gravity=0.0)
    assert float(r.loss_factor) == pytest.approx(4.0 / math.pi, rel=1e-4)  # Eq. (21)
    x = np.array([1.5, 2.0, 4.7]) * H / math.pi
    ref = bed_response(10.0, x, H, M, gravity=0.0).loss_factor  # (1 - cos phi_st)^2 / pi
    np.testing.assert_allclose(harmonic_plastic_bed(10.0, x, H, M, gravity=0.0).loss_factor,
                               ref, rtol=1e-4)


def test_solid_like_bed_rides_without_loss():
    r = harmonic_plastic_bed(4.0, 0.01, H, M)  # A / g = 0.64
    assert float(r.loss_factor) == 0.0 and float(r.effective_mass_ratio) == pytest.approx(1.0)
    # the closed forms' 1e-3 there is Eq. (8)'s convention
    assert float(bed_response(4.0, 0.01, H, M).loss_factor) == 1e-3


def test_scattering_cell_dissipates_where_eq_8_says_one_per_mille():
    """25 Hz / 10 mm: the closed forms find no repetitive trajectory and answer Eq. (8)'s
    1e-3; the plastic block dissipates as the DEM does there (0.13-0.3)."""
    closed = bed_response(25.0, 0.010, H, M)
    assert MotionMode(int(closed.mode)) is MotionMode.SCATTERING
    ev = harmonic_plastic_bed(25.0, 0.010, H, M)
    assert 0.1 < float(ev.loss_factor) < 0.4


def test_no_clearance_is_a_rigid_mass():
    r = harmonic_plastic_bed(20.0, 0.02, 0.0, M)
    assert float(r.loss_factor) == 0.0
    assert float(r.effective_mass_ratio) == pytest.approx(1.0, abs=1e-6)


#: Random beds of the paper's damper in LIGGGHTS and Yade, their pooled m_eff/m_bed (Eq. 4)
#: from docs/agreement.md, "Random beds".
DEM_EFFECTIVE_MASS = {(5.0, 0.080): 1.24, (10.0, 0.032): 1.13, (15.0, 0.032): 1.19,
                      (20.0, 0.032): 1.16, (10.0, 0.010): 0.45, (15.0, 0.010): 0.20,
                      (10.0, 0.080): 1.24, (15.0, 0.080): 1.24}


def test_effective_mass_is_nearer_the_dem_than_eq_22s_table():
    """Eq. (4)'s |F*/A*| of the plastic block against other codes' DEM: within 12 % at
    every point, where the per-mode table of Eq. (22) is off by more than 25 % at most."""
    pts = list(DEM_EFFECTIVE_MASS)
    f, x = np.array(pts).T
    dem = np.array([DEM_EFFECTIVE_MASS[p] for p in pts])
    ev = harmonic_plastic_bed(f, x, H, M).effective_mass_ratio
    table = np.array([EFFECTIVE_MASS_RATIO[MotionMode(int(c))]
                      for c in bed_response(f, x, H, M).mode])
    assert np.all(np.abs(ev / dem - 1.0) < 0.12), ev / dem
    assert np.sum(np.abs(table / dem - 1.0) > 0.25) >= 5


def test_bed_on_a_structure_closes_its_energy_balance_and_decays_as_the_pseudo_force():
    """The paper's structure released from -58 mm with the plastic bed at its end: the
    structure's energy at release = its damping + the impacts' losses + what is left (to
    1e-4), and the amplitude at 0.8 s within 5 % of the closed forms' pseudo force."""
    from pdamper.analysis.plastic_bed import PlasticBedSystem
    from pdamper.coupling import Simulation
    from pdamper.coupling.decrement import negative_peaks
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

    s = PAPER_STRUCTURE
    m, h, g = PAPER_DAMPER.bed_mass, PAPER_DAMPER.clearance, 9.81
    sys_ = PlasticBedSystem([[s.mass]], [[s.damping]], [[s.stiffness]], [1.0], [1.0], None,
                            m, h, g)
    dt, n = 1e-4, 10000
    u = np.zeros((n + 1, 3))
    u[:, 2] = 1.0
    r = sys_.run(dt, u, np.zeros(n + 1), np.zeros(n + 1), q0=np.array([-0.058]))
    x, v = r.q[0], r.qdot[0]
    e = (0.5 * s.mass * v**2 + 0.5 * s.stiffness * x**2 + 0.5 * m * r.bed_velocity**2
         + m * g * (r.bed_position - x))
    w_struct = np.trapezoid(s.damping * v * v, r.time)
    assert r.impact_times.size > 5
    assert abs(e[0] - e[-1] - w_struct - r.dissipated_energy) < 1e-4 * e[0]
    tp, ap = negative_peaks(r.time, x)
    ours = ap[tp < 0.8][-1]
    ref = Simulation(s, AnalyticalDamper(PAPER_DAMPER), -0.058).run(1.0)
    theirs = ref.peak_amplitudes[ref.peak_times < 0.8][-1]
    assert ours == pytest.approx(theirs, rel=0.05)


def test_analytical_answers_carry_whether_their_assumptions_hold():
    import dataclasses

    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER

    ok = AnalyticalDamper(PAPER_DAMPER).response([10.0, 25.0], [0.032, 0.010]).diagnostics
    assert ok["assumptions_hold"].tolist() == [True, False]  # 25 Hz / 10 mm: scattering
    assert "scattering" in ok["assumptions"][1] and "use dem" in ok["assumptions"][1]
    # one 40 mm ball in a 41 mm box: n_max = 1 gives h = 0, the geometry 1 mm
    ball = dataclasses.replace(PAPER_DAMPER, length=0.041, width=0.041, depth=0.041,
                               particle_radius=0.02, count=1)
    one = AnalyticalDamper(ball).response(10.0, 0.01).diagnostics
    assert not bool(one["assumptions_hold"])
    assert "not a collected bed" in str(one["assumptions"]) and "clearance" in str(
        one["assumptions"])
    # zero gravity below h / pi: no collect-and-collide
    zg = AnalyticalDamper(PAPER_DAMPER, gravity=0.0).response(10.0, 0.5 * H / math.pi)
    assert not bool(zg.diagnostics["assumptions_hold"])
