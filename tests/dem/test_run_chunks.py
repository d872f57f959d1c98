"""Chunked runs of :class:`pdamper.dem.DEMEngine`: the kernels return to Python between
chunks (signals, early stops) without changing a single bit of the result."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_inputs import engine, lattice, random
from pdamper.dem import HarmonicMotion, StructureMotion
from pdamper.parameters import PAPER_STRUCTURE

SERIES = ("time", "container_position", "container_velocity", "container_acceleration", "force",
          "center_of_mass", "kinetic_energy", "rotational_energy", "potential_energy",
          "elastic_energy", "dissipated_normal", "dissipated_friction", "container_work",
          "snapshot_time", "snapshot_positions", "snapshot_velocities",
          "snapshot_angular_velocities")
COUNTS = ("steps", "settle_steps", "rebuilds", "contact_onsets", "rejected_steps",
          "max_overlap_ratio", "min_step", "max_step")


def assert_identical(a, b):
    for name in SERIES + COUNTS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def _structure():
    s = PAPER_STRUCTURE
    return StructureMotion(mass=s.mass, damping=s.damping, stiffness=s.stiffness, x0=-0.058)


@pytest.mark.parametrize("integrator", ["gear", "verlet"])
@pytest.mark.parametrize("motion", ["harmonic", "structure"])
def test_chunked_run_is_bit_identical(integrator, motion):
    """Chunks of two landings (the smallest) give the bits of one kernel call."""
    m = HarmonicMotion(0.02, 15.0) if motion == "harmonic" else _structure()
    dur = 0.1 if integrator == "gear" else 0.02
    runs = [engine(random(24, seed=3), motion=m, integrator=integrator, settle_time=0.05)
            .run(dur, sample_rate=1500.0, snapshot_rate=500.0, chunk_seconds=cs)
            for cs in (math.inf, 1e-9)]
    assert runs[0].steps > 100
    assert_identical(*runs)


@pytest.mark.parametrize("integrator", ["gear", "verlet"])
def test_stopped_run_equals_a_shorter_run(integrator):
    """``stop`` ends the run on a whole cycle; the result is the run of that length."""
    f = 20.0
    seen = []

    def stop(partial):
        seen.append(partial.simulated_time)
        assert not partial.stopped_early or partial.simulated_time < 3 / f
        return partial.simulated_time >= 2 / f - 1e-12

    def sim():
        return engine(lattice(16), motion=HarmonicMotion(0.01, f), integrator=integrator,
                      settle_time=0.02)

    a = sim().run(5 / f, sample_rate=2000.0, stop=stop, chunk_seconds=1e-9)
    b = sim().run(2 / f, sample_rate=2000.0)
    assert a.stopped_early and not b.stopped_early
    assert a.requested_duration == 5 / f and a.simulated_time == pytest.approx(2 / f)
    # asked only at the ends of whole cycles
    assert seen == pytest.approx([1 / f, 2 / f])
    assert_identical(a, b)


def test_stop_never_true_runs_to_the_end():
    res = engine(lattice(16), motion=HarmonicMotion(0.01, 20.0), settle_time=0.0).run(
        0.1, sample_rate=1000.0, stop=lambda partial: False, chunk_seconds=1e-9)
    assert not res.stopped_early and res.simulated_time == pytest.approx(0.1)
