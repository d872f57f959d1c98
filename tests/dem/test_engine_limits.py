"""Every DEM run is judged where its engine is built and run (:class:`DEMEngine`): the
physics limits of :mod:`pdamper.resources` (spheres of at least 0.1 mm, strokes within
10 m, quasi-static impacts within Hertz's law, excitations slower than a contact) and the
hard cost limits (what no machine can hold), so that every command and the API inherit
them."""

from __future__ import annotations

import numpy as np

from answers import memory_headroom, refused
from dem_inputs import engine, lattice, particles
from pdamper.dem import HarmonicMotion, StructureMotion
from pdamper.materials import S235


def test_a_run_longer_than_any_machine_holds_is_refused_before_allocating():
    """``run(1e12)`` used to end in numpy's MemoryError (or take the machine's memory)."""
    sim = engine(lattice(4), motion=HarmonicMotion(0.032, 10.0))
    with memory_headroom(2**30):
        refused(lambda: sim.run(1e12), "duration", "more than this machine has")
        refused(lambda: sim.run(1.0, sample_rate=1e13), "sample_rate")


def test_impacts_beyond_the_physics_limits_are_refused_when_the_engine_is_built():
    # 100 m stroke: the limit of `pdamper dem --amplitude 100m`
    refused(lambda: engine(lattice(4), motion=HarmonicMotion(100.0, 10.0)), "amplitude",
             "10 m")
    # 10 Hz x 5 m: impacts at ~630 m/s, above a tenth of PVC's bar wave speed
    refused(lambda: engine(lattice(4), motion=HarmonicMotion(5.0, 10.0)), "amplitude",
             "bar wave speed")
    # 200 Hz x 32 mm: the Hertz contact radius exceeds half the sphere radius
    refused(lambda: engine(lattice(4), motion=HarmonicMotion(0.032, 200.0)), "frequency",
             "contact radius")
    # single impacts at a given speed (pdamper cor)
    one = particles(np.array([[0.03, 0.03, 0.01]]))
    refused(lambda: engine(one, gravity=0.0, settle_time=0.0, reference_velocity=1000.0),
             "reference_velocity", "bar wave speed")
    # a released structure
    refused(lambda: engine(lattice(4), motion=StructureMotion(
        mass=10.0, damping=0.0, stiffness=1e5, x0=-20.0)), "x0", "10 m")


def test_spheres_below_a_tenth_of_a_millimetre_are_refused_by_the_engine():
    tiny = particles(np.array([[0.01, 0.01, 0.01]]), radius=1e-6, material=S235)
    refused(lambda: engine(tiny), "particles.radius", "0.1 mm")


def test_the_paper_corners_still_run():
    """The limits take nothing from the paper's envelope (20 Hz x 200 mm, 5 Hz x 1 mm)."""
    for f, x in ((20.0, 0.2), (5.0, 0.001)):
        engine(lattice(16), motion=HarmonicMotion(x, f))
