"""Public DEM verification cases against their closed forms.

Sources:

* MFIX-DEM verification problems: R. Garg, J. Galvin, T. Li, S. Pannala, "Documentation of
  open-source MFIX-DEM software for gas-solids flows", NETL (2012), and "Open-source MFIX-DEM
  software for gas-solids flows: Part I - Verification studies", Powder Technology 220
  (2012) 122-137: the freely falling, bouncing particle and the two stacked, compressed
  particles. (Their third case, a sphere slipping on a rough plane until it rolls, is
  ``tests/dem/test_dem_physics.py::test_sliding_sphere_starts_rolling_at_five_sevenths``.)
* H. Y. Chung, J. Y. Ooi, "Benchmark tests for verifying discrete element modelling codes at
  particle impact level", Granular Matter 13 (2011) 643-656, tests 6 and 7: oblique
  sphere-wall impacts at a constant speed, incidence angle 0-90 degrees, rebound tangential
  velocity and spin against incidence (their sphere: alumina, 3.9 m/s, e = 0.98, mu = 0.092,
  after the experiment of Kharaz, Gorham, Salman, Powder Technology 120 (2001) 281-291).
* The energy-conservation check of a separating contact (a sphere thrown off a floor that
  decelerates faster than g, the "ball thrown from a hand"): not one of Chung & Ooi's tests;
  its closed forms are those of a rigid contact and Newton's free flight.

The closed forms are those of rigid-body impact theory with a constant COR e and Coulomb
friction mu; the DEM resolves the contact with Hertz's law, its COR-calibrated damping and
the tanh-regularised friction, so each tolerance below says what separates the two.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_inputs import R, contact, container, engine, particles
from pdamper.contact.elastic import contact_duration
from pdamper.contact.restitution import ConstantRestitution
from pdamper.dem import PrescribedMotion
from pdamper.materials import PVC, S235

G = 9.81
INTEGRATORS = ["verlet", "gear"]


def _e_star(a, b) -> float:
    """Hertz's effective modulus, written out here so that the check does not reuse the
    engine's own helper: 1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b."""
    return 1.0 / ((1 - a.poisson_ratio**2) / a.youngs_modulus
                  + (1 - b.poisson_ratio**2) / b.youngs_modulus)


def _hertz_overlap(force: float, e_star: float, r_star: float) -> float:
    """Static Hertz overlap delta = (3 F / (4 E* sqrt(R*)))^(2/3) [m]."""
    return (3 * force / (4 * e_star * math.sqrt(r_star))) ** (2 / 3)


# --------------------------------------------------------------------------------------
# MFIX-DEM case 1: bouncing particle
# --------------------------------------------------------------------------------------

def _apex_heights(e: float, integrator: str, h0: float, bounces: int):
    """Drop a sphere from an apex h0 (gap between sphere and floor) on the floor of a
    container at rest under gravity; returns the apex heights of the flights and the mass."""
    ps = particles(np.array([[0.02, 0.02, R + h0]]))
    cp = contact(restitution_pw=ConstantRestitution(e), friction_pw=0.0)
    sim = engine(ps, container(box=(0.04, 0.04, 0.06)), cp, integrator=integrator,
                 settle_time=0.0)
    v0 = math.sqrt(2 * G * h0)
    duration = (v0 / G + sum(2 * e**k * v0 / G for k in range(1, bounces + 1))
                + 0.5 * e ** (bounces + 1) * v0 / G)
    res = sim.run(duration, sample_rate=2000.0, snapshot_rate=2000.0)
    z = res.snapshot_positions[:, 0, 2]
    vz = res.snapshot_velocities[:, 0, 2]
    # a flight starts where the vertical velocity turns from down to up (a bounce)
    flight = np.cumsum(np.r_[0, (vz[1:] > 0) & (vz[:-1] < 0)])
    free = z > R + 1e-5
    # in free flight z + vz^2 / 2g is the apex of the parabola at every sample (the engine
    # integrates free flight exactly, test_free_flight_parabola), so no sample needs to
    # land on the apex itself
    apex = z - R + vz**2 / (2 * G)
    heights = np.array([np.median(apex[free & (flight == k)]) for k in range(bounces + 1)])
    return heights, res.masses[0]


@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("e", [0.8, 0.95])
def test_mfix_bouncing_sphere_apex_heights(integrator, e):
    """MFIX-DEM verification case 1 (Garg et al. 2012), a freely falling particle bouncing
    on a floor at rest with a constant COR e: the apex height after n bounces is
    h_n = e^(2n) h_0 (the rebound speed is e times the impact speed sqrt(2 g h)).

    Tolerance: the closed form treats the impact as instantaneous; the DEM's contact lasts
    t_c (Hertz), during which gravity's impulse m g t_c is not part of the COR calibration
    (made without gravity). That changes a rebound speed v by at most g t_c, i.e. the height
    of flight n by at most 2 sum_k g t_c(v_k) / (e v_k) relative (first order), 0.4 % after
    the first bounce and 4 % after the fifth at e = 0.8 (measured: 0.1 % and 0.9 %). A COR
    off by 1 % moves h_n by 2n %, beyond this bound at every bounce (checked below)."""
    h0, bounces = 0.02, 5
    heights, m = _apex_heights(e, integrator, h0, bounces)
    n = np.arange(bounces + 1)
    closed = e ** (2 * n) * h0
    v = e**n[:-1] * math.sqrt(2 * G * h0)  # impact speeds of bounces 1..n
    k_hertz = 4 / 3 * _e_star(S235, PVC) * math.sqrt(R)
    gtc = np.array([G * contact_duration(m, k_hertz, vk) / (e * vk) for vk in v])
    bound = np.r_[1e-9, 2 * np.cumsum(gtc)]
    err = heights / closed - 1
    assert np.all(np.abs(err) <= bound), (err, bound)
    # the bound is tight enough to tell a COR off by 1 %: (1.01^(2n) - 1) > bound
    assert np.all(1.01 ** (2 * n[1:]) - 1 > bound[1:] + np.abs(err[1:]))


# --------------------------------------------------------------------------------------
# Chung & Ooi tests 6/7: oblique sphere-wall impacts
# --------------------------------------------------------------------------------------

SPEED = 3.9  # m/s, Chung & Ooi's resultant impact speed
ANGLES = [5, 15, 25, 35, 45, 55, 65, 75, 85]  # incidence from the wall normal [deg]


def _oblique(theta_deg: float, mu: float, e: float, integrator: str = "gear",
             spin: float = 0.0):
    """A sphere hits the floor at SPEED, theta from the normal, without gravity; returns
    (v_n, v_t, velocity, angular velocity after the impact, result)."""
    th = math.radians(theta_deg)
    vn, vt = SPEED * math.cos(th), SPEED * math.sin(th)
    ps = particles(np.array([[3 * R, 3 * R, R + 1e-5]]), velocities=np.array([[vt, 0, -vn]]),
                   angular_velocities=np.array([[0.0, spin, 0.0]]))
    cp = contact(restitution_pw=ConstantRestitution(e), friction_pw=mu)
    sim = engine(ps, container(box=(20 * R, 6 * R, 8 * R)), cp, integrator=integrator,
                 gravity=0.0, settle_time=0.0, reference_velocity=vn)
    res = sim.run(1e-5 / vn + 200e-6, sample_rate=1e5)
    return vn, vt, res.snapshot_velocities[-1, 0], res.snapshot_angular_velocities[-1, 0], res


@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("mu", [0.1, 0.5, 1.0])
def test_friction_never_adds_energy_in_oblique_impacts(integrator, mu):
    """Friction only dissipates (Chung & Ooi 2011, tests 6/7, here with mu up to 1): in
    oblique sphere-wall impacts at 5-85 degrees, without gravity, with an elastic normal
    law (e = 1) so that friction alone can change the kinetic energy, the tangential plus
    rotational kinetic energy after the impact does not exceed the tangential kinetic
    energy before, 1/2 m v_t'^2 + 1/2 I omega'^2 <= 1/2 m v_t^2, the friction work that the
    engine books never decreases, and its total equals the loss of that energy (the two
    are computed independently: velocities vs the kernel's friction power).

    Tolerances: the energy inequality holds to round-off (1e-12 of the kinetic energy;
    the smallest margin measured is the 2.2e-3 lost at 5 degrees). The booked friction
    work is a quadrature of the friction power over the steps, so it carries the
    integration error: within 1e-4 (Verlet; measured 2.2e-5) and 1e-3 (Gear, whose
    variable steps are coarser; measured 4.5e-4) of the impact's kinetic energy. A friction
    force along the slip, or a spin from a missing factor r in the torque,
    breaks the inequality by the order of the friction loss itself, 0.2-27 % here."""
    e = 1.0
    for theta in ANGLES:
        vn, vt, v, w, res = _oblique(theta, mu, e, integrator)
        m = res.masses[0]
        inertia = 0.4 * m * R**2
        before = 0.5 * m * vt**2
        after = 0.5 * m * (v[0] ** 2 + v[1] ** 2) + 0.5 * inertia * float(w @ w)
        ke0 = 0.5 * m * SPEED**2
        assert after <= before + 1e-12 * ke0, (theta, after / before - 1)
        friction = res.dissipated_friction
        assert np.all(np.diff(friction) >= -1e-15 * ke0), theta
        ledger_tol = 1e-4 if integrator == "verlet" else 1e-3
        assert friction[-1] == pytest.approx(before - after, abs=ledger_tol * ke0), theta


@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("mu", [0.092, 0.1, 0.5, 1.0])
def test_chung_ooi_oblique_sweep_rebound_and_spin(integrator, mu):
    """Chung & Ooi (2011), tests 6/7: a sphere hits a wall at a constant speed (3.9 m/s) at
    incidence angles theta = 5-85 degrees from the normal, e = 0.98 and mu = 0.092 (their
    alumina sphere) and mu up to 1.
    Rigid-body impact theory with Coulomb friction gives, with v_n = V cos theta and
    v_t = V sin theta:

    * sticking (slip stops within the contact), tan theta < 7/2 mu (1 + e):
      v_t' = omega' r = 5/7 v_t;
    * sliding throughout, tan theta >= 7/2 mu (1 + e):
      v_t' = v_t - mu (1 + e) v_n,  omega' r = 5/2 mu (1 + e) v_n;
    * v_n' = e v_n and the rebound angle tan theta' = v_t' / v_n'.

    The transition lies at 32.5 (mu 0.092), 34.7 (0.1), 73.9 (0.5) and 81.8 degrees (1.0),
    so the sweep
    covers both regimes on both sides of it. Tolerance 1e-4 of v_t (5e-4 of tan theta'):
    the tanh-regularised friction (v_reg = 0.01 m/s) acts as a viscous damper only once the
    slip is below ~2 v_reg, i.e. within the last percent of the slip's decay, and pdamper
    has no tangential spring (no elastic tangential recoil, which the closed forms do not
    have either); measured: 3.2e-5 of v_t at worst (35 degrees, mu = 0.1, next to the
    transition), below 6e-6 elsewhere. A friction coefficient off by 1 % moves v_t' in the
    sliding regime by mu (1 + e) v_n / 100, 1.6e-4 of v_t or more here (least at 85 degrees,
    mu = 0.092), a missing (1 + e) factor by half of the change, and a sticking sphere that
    did not reach rolling (5/7) would leave a slip far above 1e-4 v_t."""
    e = 0.98
    tan_transition = 3.5 * mu * (1 + e)
    for theta in ANGLES:
        vn, vt, v, w, _ = _oblique(theta, mu, e, integrator)
        if math.tan(math.radians(theta)) < tan_transition:
            vt_out, wr_out = 5 / 7 * vt, 5 / 7 * vt
        else:
            vt_out, wr_out = vt - mu * (1 + e) * vn, 2.5 * mu * (1 + e) * vn
        assert v[2] == pytest.approx(e * vn, rel=1e-4), theta
        assert v[0] == pytest.approx(vt_out, abs=1e-4 * vt), theta
        assert w[1] * R == pytest.approx(wr_out, abs=1e-4 * vt), theta
        assert v[0] / v[2] == pytest.approx(vt_out / (e * vn), rel=5e-4), theta


# --------------------------------------------------------------------------------------
# MFIX-DEM case 2: two stacked, compressed spheres
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_mfix_two_stacked_spheres_hertz_overlaps(integrator):
    """MFIX-DEM verification case 2 (Garg et al. 2012), two stacked particles compressed
    (here by gravity) on a floor at rest: at equilibrium the top contact carries m g and the
    bottom contact 2 m g, so with Hertz's law the overlaps are
    delta = (3 F / (4 E* sqrt(R*)))^(2/3): sphere-sphere R* = R/2, E* of steel on steel;
    sphere-floor R* = R, E* of steel on PVC.

    The spheres start touching at zero overlap and ring down (COR 0.5); after 0.1 s the
    residual oscillation is below 1e-5 of the overlaps (Gear; Verlet: none). Tolerance
    1e-4 (measured: 1.6e-6 Gear, 3e-11 Verlet): a load off by one sphere weight changes
    an overlap by 2^(2/3) (37-59 %), R* = R instead of R/2 for the sphere pair by 2^(1/3)
    (21 %), the sphere-sphere instead of the sphere-wall E* by far more (steel vs PVC)."""
    m = particles(np.array([[0.02, 0.02, R]])).masses[0]
    ps = particles(np.array([[0.02, 0.02, R], [0.02, 0.02, 3 * R]]))
    cp = contact(restitution_pp=ConstantRestitution(0.5), restitution_pw=ConstantRestitution(0.5),
                 friction_pp=0.0, friction_pw=0.0)
    sim = engine(ps, container(box=(0.04, 0.04, 0.06)), cp, integrator=integrator,
                 settle_time=0.0)
    res = sim.run(0.1, sample_rate=1000.0, snapshot_rate=1000.0)
    z = res.snapshot_positions[-1, :, 2]
    bottom = R - z[0]
    top = 2 * R - (z[1] - z[0])
    assert bottom == pytest.approx(_hertz_overlap(2 * m * G, _e_star(S235, PVC), R), rel=1e-4)
    assert top == pytest.approx(_hertz_overlap(m * G, _e_star(S235, S235), R / 2), rel=1e-4)
    # at rest: the last 10 ms move the spheres by less than 1e-4 of the overlaps
    late = res.snapshot_positions[-10:, :, 2]
    assert np.ptp(late, axis=0).max() < 1e-4 * top


# --------------------------------------------------------------------------------------
# A contact pulled apart by a receding wall: the energy ledger through the separation
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_receding_floor_separates_the_contact_and_the_ledger_closes(integrator):
    """The energy-conservation check of a separating contact: a sphere rests on the floor
    (at its static Hertz overlap delta_0, gravity) of a container that starts from rest
    with x_c = X (W t - sin W t), W = 2 pi f, so v_c = X W (1 - cos W t) >= 0 and
    a_c = X W^2 sin W t (smooth start: x_c, v_c, a_c all 0 at t = 0). The floor lifts the
    sphere, then decelerates; with Gamma = X W^2 / g = 2 its deceleration passes g at

        W t_s = pi + arcsin(1 / Gamma),

    where the contact force m (g + a_c) of a rigid contact reaches zero and the floor
    recedes from the sphere (it decelerates faster than g until W t = 2 pi - arcsin(1 /
    Gamma), the end of the run, so the gap only grows). Closed forms (rigid contact):

    * launch: v_s = v_c(t_s) = X W (1 + cos(arcsin(1 / Gamma))), z_s = z_0 + delta_0 + x_c(t_s);
    * free flight: z = z_s + v_s (t - t_s) - g (t - t_s)^2 / 2, v_z = v_s - g (t - t_s);
    * the walls' work W_wall = 1/2 m v_s^2 + m g x_c(t_s) (the floor force m (g + a_c)
      times v_c integrates to it), and none after t_s;
    * the ledger W_wall = dE_mech + D_n + D_f at every sample.

    Tolerances. The ledger is computed by the engine from independent pieces (the walls'
    work is the kernel's trapezoidal quadrature of wall force times wall velocity; the
    energies are of the state): its residual stays below 1e-8 of W_wall with Verlet
    (measured 6e-10), 1e-5 with Gear (measured 2.7e-6: Gear's error-controlled steps are
    far longer, 1 008 against 84 180, and the work is a quadrature over them). The free
    flight and W_wall carry what the rigid closed form ignores, the Hertz contact's
    compliance: the quasi-static overlap (m (g + a_c) / k)^(2/3) would have to close
    infinitely fast at t_s, so the sphere's inertia takes over a time tau before, where
    the needed acceleration equals the vanishing effective gravity j (t_s - t),
    j = |da_c/dt|: tau = (m / k)^(2/7) j^(-1/7), and the launch velocity is off by the
    order of dv = j tau^2 (here 1.4e-4 m/s, 5e-4 of v_s; the measured offset is 0.83 dv
    at 10-40 Hz and Gamma 2-4 alike). Tolerance 1.5 dv on the velocity,
    1.5 dv (t - t_s) + delta_max on the height, and m v_s 1.5 dv + m g delta_max + D_n on
    W_wall (the elastic energy 2/5 m g delta_0 and the lift delta_0 it releases are below
    that); measured: 0.55 of the velocity bound, 0.48 of the height bound, W_wall 3.8e-4
    above the closed form against a bound of 7.2e-4.

    Would fail: without the walls' work booked the ledger would be off by all of W_wall
    (the sphere's whole energy change, 0.39 mJ), 1e5 times the Gear tolerance (checked
    below); a floor that kept pushing after t_s would show as elastic energy or a change
    of W_wall in the flight (both checked to be exactly zero); a launch speed off by 1 %
    is 14 times the velocity bound."""
    f, gamma = 20.0, 2.0
    w = 2 * math.pi * f
    x = gamma * G / w**2
    motion = PrescribedMotion(lambda t: x * (w * t - np.sin(w * t)),
                              lambda t: x * w * (1 - np.cos(w * t)),
                              lambda t: x * w * w * np.sin(w * t))
    m = particles(np.array([[0.02, 0.02, R]])).masses[0]
    e_star = _e_star(S235, PVC)
    k = 4 / 3 * e_star * math.sqrt(R)
    delta0 = _hertz_overlap(m * G, e_star, R)
    delta_max = _hertz_overlap(m * G * (1 + gamma), e_star, R)
    z0 = R - delta0
    ps = particles(np.array([[0.02, 0.02, z0]]))
    sim = engine(ps, container(box=(0.04, 0.04, 0.06)), contact(), integrator=integrator,
                 settle_time=0.0, motion=motion)
    ts = (math.pi + math.asin(1 / gamma)) / w
    t_end = (2 * math.pi - math.asin(1 / gamma)) / w
    res = sim.run(t_end, sample_rate=4000.0, snapshot_rate=4000.0)

    xs = x * (w * ts - math.sin(w * ts))
    vs = x * w * (1 - math.cos(w * ts))
    work = 0.5 * m * vs**2 + m * G * xs
    j = x * w**3 * abs(math.cos(w * ts))
    tau = (m / k) ** (2 / 7) * j ** (-1 / 7)
    dv = 1.5 * j * tau**2

    # the ledger closes at every sample, through the loading, the separation and the flight
    residual = res.energy_balance_residual()
    tol = 1e-8 if integrator == "verlet" else 1e-5
    assert np.abs(residual).max() < tol * work
    # ... and would not without the walls' work (the residual would be all of it)
    assert np.abs(residual - res.container_work)[-1] > 0.9 * work > 1e4 * tol * work

    # the walls' work is the rigid closed form's, and stops at the separation
    d_n = res.dissipated_normal[-1]
    assert res.container_work[-1] == pytest.approx(
        work, abs=m * abs(vs) * dv + m * G * delta_max + d_n)
    flight = res.time > ts + 2 * tau
    assert np.all(res.elastic_energy[flight] == 0.0)
    assert np.ptp(res.container_work[flight]) == 0.0
    mech = res.mechanical_energy[flight]
    assert np.ptp(mech) < tol * work

    # the free flight is the closed form's parabola, clear of the receding floor
    t = res.snapshot_time
    after = t > ts + 2 * tau
    z = res.snapshot_positions[after, 0, 2]
    vz = res.snapshot_velocities[after, 0, 2]
    ta = t[after] - ts
    np.testing.assert_allclose(vz, vs - G * ta, rtol=0, atol=dv)
    z_closed = z0 + delta0 + xs + vs * ta - 0.5 * G * ta**2
    assert np.all(np.abs(z - z_closed) <= dv * ta + delta_max)
    gap = z - R - x * (w * t[after] - np.sin(w * t[after]))
    assert np.all(gap > 0) and np.all(np.diff(gap) > 0)


# --------------------------------------------------------------------------------------
# Chung & Ooi test 6 against the experiment: Kharaz, Gorham & Salman (2001)
# --------------------------------------------------------------------------------------

#: Kharaz, Gorham, Salman, Powder Technology 120 (2001) 281-291, Figs. 6-8: 5 mm alumina
#: spheres on a thick soda-lime glass anvil at 3.9 m/s; incidence from the normal [deg]
#: and the measured value (as read off the figures and tabulated with the oblique-impact
#: example of the Lethe DEM code, after the MFIX-DEM verification problem DEM05)
KHARAZ_TANGENTIAL_COR = [(1.84, 0.793), (3.703, 0.745), (9.496, 0.673), (20.012, 0.597),
                         (30.127, 0.688), (39.382, 0.771), (49.694, 0.848), (60.02, 0.901)]
KHARAZ_SPIN = [(6.143, 136.2), (10.991, 265.7), (21.251, 577.7), (31.157, 612.9),
               (39.143, 595.5), (50.348, 453.2), (60.328, 382.1)]          # [rad/s]
KHARAZ_REBOUND_ANGLE = [(2.15, 1.733), (4.096, 2.962), (9.826, 6.518), (20.567, 12.208),
                        (30.29, 21.67), (39.535, 32.613), (49.747, 45.125), (60.208, 57.474)]
ALUMINA_RADIUS = 2.5e-3


def _kharaz(theta_deg: float, friction: str, integrator: str):
    """Kharaz's impact in the DEM: alumina (380 GPa, 0.23, 4000 kg/m^3, r = 2.5 mm) on
    soda-lime glass (70 GPa, 0.25), 3.9 m/s, e = 0.98, mu = 0.092 (Chung & Ooi's values
    of the experiment); returns (v_t' / v_t, rebound angle [deg], spin [rad/s])."""
    from pdamper.materials import Material

    alumina = Material("alumina", 380e9, 0.23, 4000.0)
    glass = Material("soda-lime glass", 70e9, 0.25, 2500.0)
    r = ALUMINA_RADIUS
    th = math.radians(theta_deg)
    vn, vt = SPEED * math.cos(th), SPEED * math.sin(th)
    ps = particles(np.array([[3 * r, 3 * r, r + 1e-6]]), radius=r, material=alumina,
                   velocities=np.array([[vt, 0, -vn]]))
    cp = contact(restitution_pw=ConstantRestitution(0.98), friction_pw=0.092,
                 friction_model=friction)
    sim = engine(ps, container(box=(40 * r, 6 * r, 8 * r), material=glass), cp,
                 integrator=integrator, gravity=0.0, settle_time=0.0, reference_velocity=vn)
    res = sim.run(1e-6 / vn + 100e-6, sample_rate=1e5)
    v = res.snapshot_velocities[-1, 0]
    w = res.snapshot_angular_velocities[-1, 0]
    return v[0] / vt, math.degrees(math.atan2(v[0], v[2])), abs(w[1])


@pytest.mark.parametrize("friction, integrator", [("regularised", "gear"),
                                                  ("spring", "verlet")])
def test_sliding_impacts_meet_the_kharaz_experiment(friction, integrator):
    """Chung & Ooi (2011) test 6 against the experiment it was built on (Kharaz, Gorham,
    Salman 2001, alumina on glass at 3.9 m/s): in the sliding regime (incidence 39-61
    degrees, beyond the rigid-body transition at 32.5 degrees for mu = 0.092, e = 0.98)
    both friction laws meet the measured tangential COR v_t'/v_t within 0.01 and the
    rebound angle within 1 degree (measured: 0.001-0.007 and 0.3-0.5 degrees off), and
    the spin within 10 % (measured: +1.4 % at 50 degrees, -7.8 % and -7.1 % at 39 and 60
    degrees: the experiment's spin lies above rigid-body sliding there, 5/2 mu (1 + e)
    v_n / r, as Kharaz et al. note). Nearer the normal the tanh law gives the rigid
    sticking value 5/7 = 0.714 for every angle, where the experiment dips to 0.597 at
    20 degrees (tangential compliance, Maw et al. 1976); the spring law follows the dip:
    within 0.03 at 20 and 30 degrees (measured 0.623 against 0.597, 0.686 against 0.688;
    the tanh law 0.715 and 0.716). Below 10 degrees neither law reaches the measured
    0.75-0.79 (the spring 0.98, the tanh law 0.714)."""
    for theta, measured in KHARAZ_TANGENTIAL_COR:
        ratio = _kharaz(theta, friction, integrator)[0]
        if theta > 35:
            assert ratio == pytest.approx(measured, abs=0.01), theta
        elif theta > 15 and friction == "spring":
            assert ratio == pytest.approx(measured, abs=0.03), theta
        elif friction == "regularised":
            assert ratio == pytest.approx(5 / 7, abs=3e-3), theta
    for theta, measured in KHARAZ_REBOUND_ANGLE:
        if theta > 35:
            assert _kharaz(theta, friction, integrator)[1] == pytest.approx(measured, abs=1.0)
    for theta, measured in KHARAZ_SPIN:
        if theta > 35:
            assert _kharaz(theta, friction, integrator)[2] == pytest.approx(measured, rel=0.10)
