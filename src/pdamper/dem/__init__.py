"""Level II: the discrete element method (paper Sect. 3, "Discrete element method").

Spheres in a rectangular box container that moves vertically (prescribed, or as the end
effector of a 1-DOF structure), Hertz contacts with Gonthier's nonlinear damping set from a
velocity-dependent coefficient of restitution, regularised Coulomb friction, a linked-cell
Verlet list and two integrators (velocity Verlet, variable-step fifth-order Gear).

Main entry points: :class:`DEMSimulation` (``run(duration)`` -> :class:`DEMResult`) and the
input classes :class:`Container`, :class:`ParticleSet`, :class:`ContactParameters`,
:class:`HarmonicMotion`, :class:`PrescribedMotion`, :class:`StructureMotion`.
"""

from pdamper.dem.model import (
    BENCHMARK_BOX,
    BENCHMARK_RADIUS,
    ContactParameters,
    Container,
    HarmonicMotion,
    ParticleSet,
    PrescribedMotion,
    StructureMotion,
)
from pdamper.dem.simulation import DEMResult, DEMSimulation, warmup

__all__ = [
    "BENCHMARK_BOX",
    "BENCHMARK_RADIUS",
    "Container",
    "ContactParameters",
    "DEMResult",
    "DEMSimulation",
    "HarmonicMotion",
    "ParticleSet",
    "PrescribedMotion",
    "StructureMotion",
    "warmup",
]
