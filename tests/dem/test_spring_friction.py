"""The spring friction law (``friction_model = "spring"``): a tangential spring with a
Coulomb limit on a per-contact elastic tangential displacement, LIGGGHTS' ``tangential
history`` with its Hertz stiffness and damping (:mod:`pdamper.contact.forces`).

Sources of the checks:

* LIGGGHTS 3.8, ``tangential_model_history.h`` and ``normal_model_hertz.h``
  (CFDEMproject/LIGGGHTS-PUBLIC): ``k_t = 8 G* sqrt(R* delta)``, ``gamma_t = -2 sqrt(5/6)
  beta sqrt(k_t m*)``, ``beta = ln e / sqrt(ln^2 e + pi^2)``, ``1/G* = 2 (2 - nu_1)(1 +
  nu_1)/E_1 + 2 (2 - nu_2)(1 + nu_2)/E_2``; the displacement grows by ``v_t dt``, is
  projected onto the tangent plane and scaled back to ``mu |F_n| / k_t`` on slip.
* H. Y. Chung, J. Y. Ooi, Granular Matter 13 (2011) 643-656, tests 6/7 (oblique impacts,
  rigid-body closed forms in the sliding regime), and C. Thornton et al.'s observation
  that friction only dissipates.
* N. Maw, J. R. Barber, J. N. Fawcett, Wear 38 (1976) 101-114: with tangential elasticity
  the contact point of a sphere that sticks leaves with a tangential velocity of its own
  (rigid-body theory: zero), set by the ratio of the tangential oscillation's period to
  the contact time; here against an independent integration (scipy) of the same
  Hertz-Mindlin contact.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from dem_inputs import R, contact, container, engine, particles, random
from pdamper.contact.restitution import ConstantRestitution
from pdamper.errors import InputError
from pdamper.materials import PVC, S235

SPEED = 3.9  # m/s, Chung & Ooi's impact speed


def _g_star(a, b) -> float:
    """LIGGGHTS' Geff, written out (not the engine's helper)."""
    return 1.0 / (2 * (2 - a.poisson_ratio) * (1 + a.poisson_ratio) / a.youngs_modulus
                  + 2 * (2 - b.poisson_ratio) * (1 + b.poisson_ratio) / b.youngs_modulus)


def _e_star(a, b) -> float:
    return 1.0 / ((1 - a.poisson_ratio**2) / a.youngs_modulus
                  + (1 - b.poisson_ratio**2) / b.youngs_modulus)


def _oblique(theta_deg, mu, e, friction="spring", integrator="verlet", **kw):
    """A steel sphere hits the PVC floor at SPEED, theta from the normal, no gravity;
    returns (v_n, v_t, velocity and angular velocity after, result)."""
    th = math.radians(theta_deg)
    vn, vt = SPEED * math.cos(th), SPEED * math.sin(th)
    ps = particles(np.array([[3 * R, 3 * R, R + 1e-5]]), velocities=np.array([[vt, 0, -vn]]))
    cp = contact(restitution_pw=ConstantRestitution(e), friction_pw=mu, friction_model=friction)
    sim = engine(ps, container(box=(20 * R, 6 * R, 8 * R)), cp, integrator=integrator,
                 gravity=0.0, settle_time=0.0, reference_velocity=vn, **kw)
    res = sim.run(1e-5 / vn + 200e-6, sample_rate=1e5)
    return vn, vt, res.snapshot_velocities[-1, 0], res.snapshot_angular_velocities[-1, 0], res


# --------------------------------------------------------------------------------------
# the force function
# --------------------------------------------------------------------------------------

def _law(model=2):
    from pdamper.dem.kernels.state import Law
    return Law(model, 1, 0.01, 0.01, 1.25)


def test_spring_force_reproduces_liggghts_hertz_tangential_law():
    """One contact, sticking then sliding: the tangential force (added to the normal
    force), the stored displacement and the energies are LIGGGHTS' (the formulas of the
    module docstring, written out here):
    k_t = 8 G* sqrt(R* delta), gamma_t = 2 sqrt(5/6) |ln e| / sqrt(ln^2 e + pi^2)
    sqrt(k_t m*); the displacement's normal part is projected out; on slip |F_t| =
    mu |F_n| exactly and xi = -F_t / k_t. Relative tolerance 1e-12 (round-off)."""
    from pdamper.dem.kernels.forces import spring_tangential_force

    g = _g_star(S235, PVC)
    rstar, meff, delta, e, mu = R, 4.1e-3, 2e-6, 0.85, 0.3
    k = 4 / 3 * _e_star(S235, PVC) * math.sqrt(rstar)
    x = 2 * math.sqrt(5 / 6) * abs(math.log(e)) / math.sqrt(math.log(e) ** 2 + math.pi**2)
    n = np.array([0.0, 0.0, -1.0])
    u = np.array([0.02, -0.01, 0.0])  # tangential slip velocity, no normal speed
    xi = np.array([[1e-8, 2e-8, 5e-9, x]])  # a normal part (5e-9) to be projected out
    dt = 1e-7
    c = spring_tangential_force(delta, 0.0, *n, *u, k, 0.0, _law(), mu, g, rstar, meff, xi, 0,
                                dt, *u)
    kt = 8 * g * math.sqrt(rstar * delta)
    s = np.array([1e-8, 2e-8, 0.0]) + dt * u
    gt = x * math.sqrt(kt * meff)
    ft = -kt * s - gt * u
    fn = k * delta**1.5
    assert np.linalg.norm(ft) < mu * fn  # sticking
    np.testing.assert_allclose([c.fx, c.fy, c.fz], ft, rtol=1e-12)
    np.testing.assert_allclose(xi[0, :3], s, rtol=1e-12, atol=1e-30)
    assert c.p_fric == pytest.approx(gt * float(u @ u), rel=1e-12)
    assert c.e_el == pytest.approx(0.5 * kt * float(s @ s), rel=1e-12)
    np.testing.assert_allclose([c.cx, c.cy, c.cz], np.cross(n, ft), rtol=1e-12, atol=1e-30)
    # sliding: a displacement far beyond the limit is scaled back to it
    xi[0, :3] = [1e-5, 0.0, 0.0]
    c = spring_tangential_force(delta, 0.0, *n, 0.0, 0.0, 0.0, k, 0.0, _law(), mu, g, rstar,
                                meff, xi, 0, dt, 0.0, 0.0, 0.0)
    assert math.hypot(c.fx, c.fy) == pytest.approx(mu * fn, rel=1e-12)
    assert c.fx < 0.0
    assert xi[0, 0] == pytest.approx(mu * fn / kt, rel=1e-12)
    assert c.p_fric == pytest.approx(mu * fn * (1e-5 - mu * fn / kt) / dt, rel=1e-12)
    # an evaluation without a step (dt 0) leaves the displacement as it is
    before = xi.copy()
    spring_tangential_force(delta, 0.0, *n, 0.3, 0.0, 0.0, k, 0.0, _law(), mu, g, rstar, meff,
                            xi, 0, 0.0, 0.3, 0.0, 0.0)
    np.testing.assert_array_equal(xi, before)


def test_engine_tables_hold_liggghts_shear_modulus():
    """The pair tables carry G* of LIGGGHTS' formula for sphere pairs and sphere-wall."""
    from pdamper.dem.arrays import material_tables

    ps = particles(np.array([[3 * R, 3 * R, 3 * R]]))
    t = material_tables(ps, container(), contact(friction_model="spring"))
    assert t.pair_types.gstar[0] == pytest.approx(_g_star(S235, S235), rel=1e-14)
    assert t.pair_types.gstar[1] == pytest.approx(_g_star(S235, PVC), rel=1e-14)


# --------------------------------------------------------------------------------------
# oblique impacts
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("mu", [0.092, 0.5])
def test_sliding_regime_keeps_the_rigid_body_closed_forms(mu):
    """Chung & Ooi tests 6/7 with the spring law: where the sphere slides throughout
    (tan theta well above 7/2 mu (1 + e): 45-85 degrees at mu 0.092, 80-85 at 0.5) the
    spring sits at its Coulomb limit and the rigid-body forms hold, v_t' = v_t - mu (1 + e)
    v_n, omega' r = 5/2 mu (1 + e) v_n, v_n' = e v_n. Tolerance 2e-4 of v_t: the spring
    needs a few steps at the onset to load up to the limit (its displacement mu F_n / k_t
    grows from zero with the overlap), a Coulomb impulse missed over them; measured at
    most 1.1e-4. A friction coefficient 1 % off moves v_t' by 1.6e-4 v_t or more here."""
    e = 0.98
    angles = [45, 55, 65, 75, 85] if mu < 0.1 else [80, 85]
    for theta in angles:
        vn, vt, v, w, _ = _oblique(theta, mu, e)
        assert math.tan(math.radians(theta)) > 1.2 * 3.5 * mu * (1 + e)
        assert v[2] == pytest.approx(e * vn, rel=1e-4), theta
        assert v[0] == pytest.approx(vt - mu * (1 + e) * vn, abs=2e-4 * vt), theta
        assert w[1] * R == pytest.approx(2.5 * mu * (1 + e) * vn, abs=2e-4 * vt), theta


@pytest.mark.parametrize("mu", [0.1, 0.5, 1.0])
def test_spring_friction_never_adds_energy(mu):
    """Elastic normal law (e = 1, so no tangential damping either), 1-85 degrees, mu up to
    1: the kinetic plus rotational energy after the impact never exceeds the energy
    before (the spring gives back at most what it stored: the tangential recoil), and the
    friction work booked never decreases. Tolerance 1e-6 of the impact's energy (the
    explicit step's error of the elastic normal impact alone is ~1e-7 after it); the
    smallest margin measured is a loss of 2.8e-5 at 1 degree.

    What the law does not do (LIGGGHTS' law as it is): ``F_t = -k_t(delta) xi`` with
    ``k_t`` growing with the overlap is no potential force, so within the contact the
    kinetic, rotational and stored energies together exceed the initial energy by up to
    1e-3 (mu 0.1) to 6 % (mu 1, 45 degrees), and the booked friction work misses the
    energy lost by up to 0.06 % (mu 0.1) and 1.6 % (mu 1) of the impact's energy (measured;
    checked loosely below, 2 %, so that a sign error in the slip work, the order of the
    friction loss itself, fails)."""
    for theta in [1, 3, 5, 15, 25, 35, 45, 55, 65, 75, 85]:
        vn, vt, v, w, res = _oblique(theta, mu, 1.0)
        m = res.masses[0]
        e0 = 0.5 * m * SPEED**2
        after = 0.5 * m * float(v @ v) + 0.5 * 0.4 * m * R**2 * float(w @ w)
        assert after <= e0 * (1 + 1e-6), (theta, after / e0 - 1)
        friction = res.dissipated_friction
        assert np.all(np.diff(friction) >= -1e-15 * e0), theta
        assert friction[-1] == pytest.approx(e0 - after, abs=0.02 * e0), theta


def _sticking_reference(theta_deg: float, mu: float) -> float:
    """The contact point's tangential velocity after the impact over the one before, from
    an independent integration (scipy, DOP853, continuous time) of the elastic Hertz
    normal force and LIGGGHTS' spring (k_t = 8 G* sqrt(R* delta), Coulomb limit, no
    damping at e = 1) for a steel sphere on PVC."""
    from scipy.integrate import solve_ivp

    m = 4 / 3 * math.pi * R**3 * S235.density
    inertia = 0.4 * m * R**2
    k = 4 / 3 * _e_star(S235, PVC) * math.sqrt(R)
    g = _g_star(S235, PVC)
    th = math.radians(theta_deg)
    vn, vt = SPEED * math.cos(th), SPEED * math.sin(th)

    # slip holds k_t |xi| at mu F_n, i.e. |xi| at c delta (c = mu K / (8 G* sqrt(R*)))
    c = mu * k / (8 * g * math.sqrt(R))

    def rhs(t, y):
        d, dd, vx, w, xi = y
        dp = max(d, 0.0)
        fn = k * dp**1.5
        kt = 8 * g * math.sqrt(R * dp)
        u = vx - R * w
        if abs(xi) >= c * dp and u * xi > c * dd * abs(xi):
            dxi = math.copysign(c * dd, xi)  # sliding: the displacement rides the limit
            ft = -math.copysign(mu * fn, xi)
        else:
            dxi = u
            ft = -kt * xi
        return [dd, -fn / m, ft / m, -R * ft / inertia, dxi]

    def leave(t, y):
        return y[0] + (1.0 if t < 1e-9 else 0.0)

    leave.terminal, leave.direction = True, -1
    s = solve_ivp(rhs, [0, 1e-2], [0, vn, vt, 0, 0], events=leave, rtol=1e-11, atol=1e-16,
                  method="DOP853")
    vx, w = s.y[2, -1], s.y[3, -1]
    return (vx - R * w) / vt


def test_small_incidence_tangential_elasticity():
    """Maw, Barber & Fawcett (1976): at small incidence a sphere with tangential
    elasticity sticks and its contact point leaves with a velocity of its own, set by the
    tangential oscillation (period against contact time; for steel on PVC the spring
    turns through about 1.8 pi within the contact, so the contact point leaves forward at
    0.84 of its incident velocity in full stick; Maw et al.: the sign depends on that
    ratio of period to contact time, a reversal needs about one half-period), not the
    rigid-body zero of rolling;
    the ratio falls as the angle grows (slip at the contact's ends). The
    DEM (spring law, e = 1, mu 0.092, Verlet at safety 0.01) against an independent
    integration of the same contact (scipy): within 0.005 of the incident tangential
    velocity (measured 2.4e-3, the same at safety 0.005: the discrete slip limit at the
    contact's end; at the default 0.02, 0.011). The tanh law gives the rigid-body zero here
    (rolling), so the test tells the two apart by 0.8."""
    ratios = []
    for theta in [1.0, 2.0, 3.0]:
        vn, vt, v, w, _ = _oblique(theta, 0.092, 1.0, safety=0.01)
        dem = (v[0] - w[1] * R) / vt
        ref = _sticking_reference(theta, 0.092)
        assert dem == pytest.approx(ref, abs=0.005), (theta, dem, ref)
        ratios.append(dem)
    # Maw's trend: from the full-stick value (0.844 here) down as the angle and with it the
    # slip at the contact's ends grow, towards the rigid-body regime
    assert ratios[0] > ratios[1] > ratios[2] > 0.5
    vn, vt, v, w, _ = _oblique(1.0, 0.092, 1.0, friction="regularised")
    assert abs(v[0] - w[1] * R) / vt < 0.01  # the tanh law: rolling


# --------------------------------------------------------------------------------------
# sticking
# --------------------------------------------------------------------------------------

def _wedged(friction: str):
    """A steel sphere squeezed between the two x walls of a PVC box (overlap delta0 each,
    normal force N = K delta0^1.5 = 0.4 N), gravity down, the floor far below: friction
    holds it while 2 mu N = 0.08 N > m g = 0.041 N (mu = 0.1); 0.05 s. Both friction
    forces point up at opposite ends of a diameter: their torques cancel, so the sphere
    cannot roll (on one plane it would: no law can hold a free sphere on an incline)."""
    k = 4 / 3 * _e_star(S235, PVC) * math.sqrt(R)
    n_force = 0.4
    d0 = (n_force / k) ** (2 / 3)
    lx = 2 * R - 2 * d0
    ps = particles(np.array([[lx / 2, 3 * R, 6 * R]]))
    cp = contact(friction_pw=0.1, friction_model=friction)
    sim = engine(ps, container(box=(2 * R, 6 * R, 12 * R)), cp, integrator="verlet",
                 settle_time=0.0, reference_velocity=0.1)
    # the engine refuses a sphere wider than its box (an input error); the squeeze is
    # made by narrowing the box after those checks, before the run builds its arrays
    sim.container = container(box=(lx, 6 * R, 12 * R))
    sim._build_tables()
    res = sim.run(0.05, sample_rate=2000.0)
    kt = 8 * _g_star(S235, PVC) * math.sqrt(R * d0)
    return res, kt


def test_sphere_held_by_friction_sticks_with_the_spring_and_creeps_with_tanh():
    """Below the friction limit the spring law holds the sphere: it sinks by its elastic
    tangential displacement, m g / (2 k_t) = 51 nm at rest, and no further: at the end
    within 2 % of it (measured 0.1 %), at no time beyond 1.5 times it (the start's
    overshoot, damped by gamma_t; measured 1.13). The tanh law cannot hold it: it slips at
    the speed where 2 mu N tanh(v / v_reg) = m g, v = v_reg atanh(0.51) = 5.6 mm/s, 0.28 mm
    in 0.05 s (within 5 %: the first instants at rest; measured -1.2 %), 5500 times the
    spring's displacement."""
    res, kt = _wedged("spring")
    m = res.masses[0]
    static = m * 9.81 / (2 * kt)
    drop = res.center_of_mass[0, 2] - res.center_of_mass[:, 2]
    assert drop.max() <= 1.5 * static, drop.max() / static
    assert drop[-1] == pytest.approx(static, rel=0.02), drop[-1] / static
    res_t, _ = _wedged("regularised")
    creep = 0.01 * math.atanh(m * 9.81 / (2 * 0.1 * 0.4)) * 0.05
    drop_t = res_t.center_of_mass[0, 2] - res_t.center_of_mass[-1, 2]
    assert drop_t == pytest.approx(creep, rel=0.05), drop_t / creep


# --------------------------------------------------------------------------------------
# integrators and settings
# --------------------------------------------------------------------------------------

def test_gear_refuses_the_spring_law_and_auto_runs_verlet():
    """Gear has no tangential displacement history: the engine refuses the combination
    with a one-line error naming the field and the allowed values; ``auto`` runs Verlet
    throughout (the same result as ``verlet``, to the bit)."""
    with pytest.raises(InputError, match=r"integrator.*verlet or auto"):
        _oblique(45, 0.1, 0.9, integrator="gear")
    *_, v_auto, w_auto, _ = _oblique(20, 0.1, 0.9, integrator="auto")
    *_, v_ver, w_ver, _ = _oblique(20, 0.1, 0.9, integrator="verlet")
    np.testing.assert_array_equal(v_auto, v_ver)
    np.testing.assert_array_equal(w_auto, w_ver)


def test_friction_model_setting_is_declared_and_checked():
    """``friction_model`` is a declared choice of the DEM damper's settings: the scenario
    key and the ``dem`` flag follow; a wrong value or Gear with the spring is refused,
    naming the field."""
    from pdamper.contact.law import ContactParameters
    from pdamper.models import DEMDamper
    from pdamper.models.settings import DEMSettings
    from pdamper.parameters import PAPER_DAMPER

    assert DEMSettings().friction_model == "regularised"
    with pytest.raises(InputError, match="friction_model"):
        DEMSettings(friction_model="viscous")
    with pytest.raises(InputError, match="friction_model"):
        ContactParameters(ConstantRestitution(0.5), ConstantRestitution(0.5), 0.1, 0.1,
                          friction_model="viscous")
    with pytest.raises(InputError, match=r"dem\.integrator"):
        DEMDamper(PAPER_DAMPER, friction_model="spring")
    model = DEMDamper(PAPER_DAMPER, friction_model="spring", integrator="auto")
    assert model.contact.friction_model == "spring"


def test_dem_command_runs_the_spring_law_and_refuses_it_with_gear(capsys):
    """``pdamper dem --friction-model spring``: runs with Verlet and records the law; with
    the damper's default integrator (Gear) or an unknown law, a one-line error naming the
    field and a non-zero exit."""
    from pdamper.cli import main

    args = ["dem", "--frequency", "10Hz", "--amplitude", "20mm", "--particles", "16",
            "--cycles", "3", "--skip-cycles", "1", "--json"]
    assert main([*args, "--friction-model", "spring", "--integrator", "verlet"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["inputs"]["dem"]["friction_model"] == "spring"
    assert data["loss_factor"] > 0.0
    assert main([*args, "--friction-model", "spring"]) != 0
    err = capsys.readouterr().err.strip()
    assert "dem.integrator" in err and "verlet or auto" in err and len(err.splitlines()) == 1
    assert main([*args, "--friction-model", "viscous", "--integrator", "verlet"]) != 0
    err = capsys.readouterr().err.strip()
    assert "friction_model" in err and "regularised, spring" in err


def test_shaken_bed_with_the_spring_law_is_chunk_invariant_and_balanced():
    """A shaken random bed of 16 spheres (10 Hz / 20 mm, 0.15 s, list rebuilds, oblique
    contacts)
    with the spring law: the tangential displacements live in the run's arrays, so a run
    cut into the smallest chunks is bit-identical to one call; the energy ledger closes to
    1 % of the energy the container put in (the law's unbooked work, see
    ``test_spring_friction_never_adds_energy``; measured 0.45 %, the tanh law's 0.07 %),
    and the law is active: the container's work differs from the tanh law's (by 4 %; a
    perfect lattice would not tell, its contacts are head-on)."""
    from pdamper.dem import HarmonicMotion

    def sim(friction):
        return engine(random(16, seed=1), container(), contact(friction_model=friction),
                      HarmonicMotion(0.02, 10.0), integrator="verlet", settle_time=0.02)

    a = sim("spring").run(0.15, sample_rate=2000.0)
    b = sim("spring").run(0.15, sample_rate=2000.0, chunk_seconds=1e-9)
    np.testing.assert_array_equal(a.snapshot_positions, b.snapshot_positions)
    np.testing.assert_array_equal(a.force, b.force)
    assert a.rebuilds > 0
    work = a.container_work[-1]
    ledger = (a.kinetic_energy + a.rotational_energy + a.potential_energy + a.elastic_energy
              + a.dissipated_normal + a.dissipated_friction - a.container_work)
    assert abs(ledger[-1] - ledger[0]) <= 0.01 * abs(work), (ledger[-1] - ledger[0]) / work
    c = sim("regularised").run(0.15, sample_rate=2000.0)
    assert abs(c.container_work[-1] / work - 1) > 1e-3


def test_warmup_names_a_bad_friction_model():
    """``warmup(friction_models=...)`` (the test session's kernel warm-up compiles the
    spring law's Verlet kernels with it) checks its names before compiling anything."""
    from pdamper.dem import warmup

    with pytest.raises(InputError) as exc:
        warmup(("verlet",), friction_models=("coulomb",))
    assert exc.value.field == "friction_models"
    assert "regularised, spring" in exc.value.message
