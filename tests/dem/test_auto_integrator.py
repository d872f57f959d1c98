"""``integrator="auto"``: Gear hands a run over to velocity Verlet where Gear's steps fall
below ``AUTO_COST_RATIO`` x Verlet's (its stability limit in a jammed bed). The hand-over is
checked against closed forms (a free-flight parabola across it, the energy ledger) and
against the runs of either integrator alone."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_inputs import engine, engine_at, particles
from pdamper.dem import simulation as S
from pdamper.errors import InputError

#: makes "auto" hand over at its first judgement
ALWAYS = {"auto_cost_ratio": math.inf}


def test_hand_over_keeps_a_free_flight_on_its_parabola():
    """Free flight under gravity, z0 + v0 t - g t^2 / 2, before and after the hand-over at
    t = AUTO_WINDOW: both integrators are exact on a parabola, so is the hand-over (its
    time bookkeeping, the resumed step and the samples)."""
    z0, vz, vx = 0.06, 0.5, 0.1
    ps = particles(np.array([[0.015, 0.02, z0]]), velocities=np.array([[vx, 0.0, vz]]))
    res = engine(ps, integrator="auto", settle_time=0.0, **ALWAYS).run(0.05, sample_rate=1000.0,
                                                              snapshot_rate=1000.0)
    assert res.integrator_switch_time == pytest.approx(S.AUTO_WINDOW)
    t = res.snapshot_time
    assert t[-1] == pytest.approx(0.05)
    np.testing.assert_allclose(res.snapshot_positions[:, 0, 2], z0 + vz * t - 0.5 * 9.81 * t**2,
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.snapshot_positions[:, 0, 0], 0.015 + vx * t, rtol=0,
                               atol=1e-12)


def test_hand_over_in_a_shaken_bed_closes_the_ledger_and_matches_verlet():
    """32 spheres at 10 Hz / 32 mm, two cycles, handed over after 5 ms: the energy ledger
    closes as in a pure Verlet run, and the loss factor and effective mass are those of a pure
    Verlet run of the same bed to the accuracy of the verification table (1 %)."""
    auto = engine_at(32, 10.0, 0.032, integrator="auto", settle_time=0.05, **ALWAYS).run(
        0.2, sample_rate=4000.0)
    verlet = engine_at(32, 10.0, 0.032, integrator="verlet", settle_time=0.05).run(
        0.2, sample_rate=4000.0)
    assert auto.integrator_switch_time == pytest.approx(S.AUTO_WINDOW)
    # (Verlet's own ledger closes to ~1e-3 here, Gear's to ~2e-4)
    assert auto.energy_balance_error() < 1.5 * verlet.energy_balance_error()
    a, v = auto.complex_power(1, 1), verlet.complex_power(1, 1)
    assert a.loss_factor == pytest.approx(v.loss_factor, rel=0.01)
    assert a.effective_mass_ratio == pytest.approx(v.effective_mass_ratio, rel=0.01)
    # the time series go on across the hand-over without a jump
    dt = np.diff(auto.time)
    np.testing.assert_allclose(dt, dt[0], rtol=1e-9)
    assert np.all(np.diff(auto.container_work) > -1e-9 * np.abs(auto.container_work).max())


def test_auto_stays_gear_where_gear_is_cheaper():
    """The tuned point (32 spheres, lattice, 10 Hz / 32 mm): Gear's steps are ~4x Verlet's,
    so "auto" never hands over and equals "gear" to the bit."""
    auto = engine_at(32, 10.0, 0.032, integrator="auto", settle_time=0.05).run(
        0.1, sample_rate=4000.0)
    gear = engine_at(32, 10.0, 0.032, integrator="gear", settle_time=0.05).run(
        0.1, sample_rate=4000.0)
    assert math.isnan(auto.integrator_switch_time)
    np.testing.assert_array_equal(auto.force, gear.force)
    assert auto.steps == gear.steps


@pytest.mark.long
def test_auto_hands_the_jammed_full_container_to_verlet():
    """The full container (192 spheres, no clearance) at 20 Hz / 32 mm: Gear is held by its
    stability limit (mean step ~0.16 us against Verlet's ~0.39 us), so "auto" hands over at
    its first judgement, and the solid-like bed's mass ratio equals Verlet's."""
    kw = dict(settle_time=0.01)
    auto = engine_at(192, 20.0, 0.032, integrator="auto", **kw).run(0.05, sample_rate=4000.0)
    verlet = engine_at(192, 20.0, 0.032, integrator="verlet", **kw).run(0.05,
                                                                       sample_rate=4000.0)
    assert auto.integrator_switch_time == pytest.approx(S.AUTO_WINDOW)
    a, v = auto.complex_power(0, 1), verlet.complex_power(0, 1)
    assert a.effective_mass_ratio == pytest.approx(v.effective_mass_ratio, rel=1e-3)
    assert a.loss_factor == pytest.approx(v.loss_factor, abs=1e-3)


def test_auto_is_independent_of_the_chunking():
    """The hand-over happens at a fixed landing, not at a chunk end: one kernel call per
    phase and the default chunks give the same run to the bit."""
    def run(chunk):
        return engine_at(16, 20.0, 0.01, integrator="auto", settle_time=0.02, **ALWAYS).run(
            0.03, sample_rate=4000.0, chunk_seconds=chunk)

    a, b = run(math.inf), run(1e-4)
    np.testing.assert_array_equal(a.force, b.force)
    assert a.integrator_switch_time == b.integrator_switch_time


def test_unknown_integrator_and_bad_ratio_name_their_field():
    with pytest.raises(InputError, match="gear, verlet, auto"):
        engine_at(4, 10.0, 0.01, integrator="rk4")
    with pytest.raises(InputError, match="auto_cost_ratio"):
        engine_at(4, 10.0, 0.01, integrator="auto", auto_cost_ratio=-1.0)
    with pytest.raises(InputError, match="auto_cost_ratio"):
        engine_at(4, 10.0, 0.01, integrator="auto", auto_cost_ratio=math.nan)


def test_hand_over_is_recorded_in_the_results():
    res = engine_at(4, 10.0, 0.01, integrator="auto", settle_time=0.0, **ALWAYS).run(
        0.02, sample_rate=2000.0)
    ds = res.to_dataset()
    assert ds.attrs["integrator"] == "auto"
    assert ds.attrs["integrator_switch_time"] == pytest.approx(S.AUTO_WINDOW)


def test_hand_over_under_a_structure_keeps_its_frequency():
    """Level III model 1: a 1-DOF structure carrying a resting bed of 16 spheres, handed
    over after 5 ms, oscillates at f = sqrt(K / (M + m_bed)) / (2 pi) (the bed moves
    rigidly): the structure's state crosses the hand-over intact."""
    from dem_inputs import lattice
    from pdamper.dem import StructureMotion

    ps = lattice(16)
    m, k = 1.514, 1848.0

    def run(integrator):
        return engine(ps, motion=StructureMotion(mass=m, damping=0.0, stiffness=k, x0=-0.001),
                      integrator=integrator, settle_time=0.05, **ALWAYS).run(
            0.5, sample_rate=4000.0)

    res, gear = run("auto"), run("gear")
    assert res.integrator_switch_time == pytest.approx(S.AUTO_WINDOW)
    x = res.container_position - res.container_position.mean()
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    tz = res.time[up] - x[up] / (x[up + 1] - x[up]) * (res.time[up + 1] - res.time[up])
    f = (len(tz) - 1) / (tz[-1] - tz[0])
    assert f == pytest.approx(np.sqrt(k / (m + ps.masses.sum())) / (2 * np.pi), rel=2e-3)
    # undamped structure, resting bed: the amplitude of the pure Gear run
    xg = gear.container_position - gear.container_position.mean()
    assert np.abs(x).max() == pytest.approx(np.abs(xg).max(), rel=1e-3)


def test_auto_probes_gear_again_with_a_doubling_span():
    """Where Verlet stays the cheaper (forced here), "auto" tries Gear again for one window
    after 1, 2, 4, 8 ... windows of Verlet: Gear runs 0-5, 10-15, 25-30, 50-55, 95-100 and
    180-185 ms of 0.2 s (11 hand-overs), Verlet the rest."""
    res = engine_at(4, 10.0, 0.01, integrator="auto", settle_time=0.0, **ALWAYS).run(
        0.2, sample_rate=2000.0)
    assert S.AUTO_FIRST_SPAN == 1 and S.AUTO_WINDOW == 5e-3
    assert res.integrator_switches == 11
    assert res.verlet_time == pytest.approx(0.2 - 6 * S.AUTO_WINDOW)
    never = engine_at(4, 10.0, 0.01, integrator="auto", settle_time=0.0,
                      auto_cost_ratio=0.0).run(0.2, sample_rate=2000.0)
    assert never.integrator_switches == 0 and never.verlet_time == 0.0
    verlet = engine_at(4, 10.0, 0.01, integrator="verlet", settle_time=0.0).run(
        0.2, sample_rate=2000.0)
    assert verlet.verlet_time == pytest.approx(0.2)


def test_a_motion_that_is_no_motion_object_names_the_field():
    """``motion="harmonic"`` was accepted (and failed later, or ran at rest)."""
    from dem_inputs import engine, lattice
    from pdamper.dem import HarmonicMotion

    for bad in ("harmonic", 10.0, (0.01, 10.0)):
        with pytest.raises(InputError, match="^motion: must be one of HarmonicMotion, "
                                             "PrescribedMotion, StructureMotion or None"):
            engine(lattice(4), motion=bad)
    assert engine(lattice(4)).motion == HarmonicMotion()  # None: at rest
