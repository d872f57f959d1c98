"""The settling's rest rule (``settle_rest_speed``, ``settle_rest_time``): the settling ends
once the bed's rms speed has stayed below the declared speed for the declared time, at a
landing that does not depend on the chunking; without it the settling runs its time."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_inputs import engine, lattice, random
from pdamper.dem import HarmonicMotion
from pdamper.dem.simulation import SETTLE_CHECK_INTERVAL
from pdamper.errors import InputError

MOTION = HarmonicMotion(0.01, 20.0)


def test_a_bed_at_rest_ends_its_settling_early_and_is_at_rest():
    """A random bed of 24 spheres given 1 s to settle: with the rest rule at 1 mm/s over
    20 ms it stops well before, at a whole number of checks, with the bed's rms speed
    below 1 mm/s at the end (its kinetic energy below 1/2 m_bed (1 mm/s)^2)."""
    eng = engine(random(24, seed=1), motion=MOTION, integrator="gear", settle_time=1.0,
                 settle_rest_speed=1e-3, settle_rest_time=0.02)
    bed = eng.settle()
    assert bed.stop == "at rest" and bed.simulated < 0.9
    checks = bed.simulated / SETTLE_CHECK_INTERVAL
    assert math.isclose(checks, round(checks), rel_tol=1e-9)
    m_bed = float(np.sum(eng.particles.masses))
    translational = 0.5 * float(np.dot(eng.particles.masses, np.sum(bed.state.vel ** 2, 1)))
    assert translational < 0.5 * m_bed * 1e-3 ** 2
    trace = eng._last_settle.trace
    assert len(trace) >= 4 and all(rms < 1e-3 for _, rms, _ in trace[-4:])
    assert trace[-5][1] >= 1e-3  # the rule ends at the fourth quiet check in a row
    res = eng.run(0.05, sample_rate=2000.0)
    assert res.settle_stop == "at rest" and res.settle_simulated_time == bed.simulated
    assert res.settle_steps == bed.steps


def test_the_rest_rule_does_not_depend_on_the_chunking():
    """The same landing, steps and state whether the settling runs in one kernel call or
    in the smallest chunks."""
    def settle(chunk):
        eng = engine(random(24, seed=1), motion=MOTION, integrator="gear", settle_time=1.0,
                     settle_rest_speed=1e-3, settle_rest_time=0.02)
        return eng.settle(chunk_seconds=chunk)

    whole, small = settle(math.inf), settle(1e-9)
    assert whole.simulated == small.simulated and whole.steps == small.steps
    assert np.array_equal(whole.state.pos, small.state.pos)
    assert np.array_equal(whole.state.vel, small.state.vel)


def test_without_the_rule_the_settling_runs_its_time_and_keeps_its_key():
    """``settle_rest_speed`` None (the engine's default): the settling runs
    ``settle_time`` (``stop`` "time") on the grid it always had; the rule, when on, is
    part of the settled bed's key (a bed of one rule is refused by an engine of another)."""
    plain = engine(lattice(8), motion=MOTION, integrator="verlet", settle_time=0.1)
    bed = plain.settle()
    assert bed.stop == "time" and math.isclose(bed.simulated, 0.1)
    rest = engine(lattice(8), motion=MOTION, integrator="verlet", settle_time=0.1,
                  settle_rest_speed=1e-3)
    assert rest.settle_key != plain.settle_key
    with pytest.raises(InputError, match="^start:"):
        rest.run(0.01, start=bed)


@pytest.mark.parametrize("field, value", [("settle_rest_speed", 0.0),
                                          ("settle_rest_speed", -1e-3),
                                          ("settle_rest_time", 0.0)])
def test_the_rest_rule_settings_are_checked(field, value):
    with pytest.raises(InputError, match=f"^{field}: "):
        engine(lattice(2), **{field: value})


def test_level2_runs_settle_their_whole_time_unless_the_rest_rule_is_asked_for():
    """The DEM damper's Level II runs settle for the free fall + 1 s by default (the rule
    is off: their answers as before); with ``settle_rest_speed`` = 1 mm/s a random bed of
    the paper's damper ends its settling at rest well within that."""
    from pdamper.models import DEMDamper
    from pdamper.parameters import PAPER_DAMPER

    cap = math.sqrt(2 * PAPER_DAMPER.box[2] / 9.80665) + 1.0
    plain = DEMDamper(PAPER_DAMPER, packing="random", seed=0, cycles=3, skip_cycles=1
                      ).steady_run(10.0, 0.032).result
    assert plain.settle_stop == "time"
    assert plain.settle_simulated_time == pytest.approx(cap, rel=1e-3)
    rest = DEMDamper(PAPER_DAMPER, packing="random", seed=0, cycles=3, skip_cycles=1,
                     settle_rest_speed=1e-3).steady_run(10.0, 0.032).result
    assert rest.settle_stop == "at rest" and rest.settle_simulated_time < 0.8 * cap
    assert rest.settle_steps + rest.steps > 0 and rest.attrs["settle_time_s"] == pytest.approx(
        cap, rel=1e-3)  # the cap: the settling time it would have run
