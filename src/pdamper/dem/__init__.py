"""Level II: the discrete element method (paper Sect. 3, "Discrete element method").

Spheres in a rectangular box container that moves vertically (prescribed, or as the end
effector of a 1-DOF structure), Hertz contacts with a nonlinear damping set from a
velocity-dependent coefficient of restitution, regularised Coulomb friction, a linked-cell
Verlet list and two integrators (velocity Verlet, variable-step fifth-order Gear).

Main entry points: :class:`DEMEngine` (``run(duration)`` -> :class:`DEMResult`) and the
input classes :class:`Container`, :class:`ParticleSet`,
:class:`~pdamper.contact.law.ContactParameters`, :class:`HarmonicMotion`,
:class:`PrescribedMotion`, :class:`StructureMotion`.

The numba kernels load on first use of :class:`DEMEngine` (attribute access below), so
that the input classes and :mod:`pdamper.dem.inputs` can be used without compiling anything.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

_EXPORTS = {
    "ContactParameters": "pdamper.contact.law",
    "Container": "pdamper.dem.inputs",
    "HarmonicMotion": "pdamper.dem.inputs",
    "ParticleSet": "pdamper.dem.inputs",
    "PrescribedMotion": "pdamper.dem.inputs",
    "StructureMotion": "pdamper.dem.inputs",
    "ModalStructureMotion": "pdamper.dem.inputs",
    "DEMEngine": "pdamper.dem.simulation",
    "EngineSettings": "pdamper.dem.settings",
    "DEMResult": "pdamper.dem.result",
    "SettledBed": "pdamper.dem.driver",
    "warmup": "pdamper.dem.simulation",
}

__all__ = [
    "ContactParameters",
    "Container",
    "DEMEngine",
    "DEMResult",
    "EngineSettings",
    "HarmonicMotion",
    "ParticleSet",
    "PrescribedMotion",
    "SettledBed",
    "StructureMotion",
    "ModalStructureMotion",
    "warmup",
]

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.contact.law import ContactParameters
    from pdamper.dem.driver import SettledBed
    from pdamper.dem.inputs import (
        Container,
        HarmonicMotion,
        ModalStructureMotion,
        ParticleSet,
        PrescribedMotion,
        StructureMotion,
    )
    from pdamper.dem.result import DEMResult
    from pdamper.dem.settings import EngineSettings
    from pdamper.dem.simulation import DEMEngine, warmup


def __getattr__(name: str):
    try:
        module = _EXPORTS[name]
    except KeyError:
        raise AttributeError(f"module 'pdamper.dem' has no attribute {name!r}") from None
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
