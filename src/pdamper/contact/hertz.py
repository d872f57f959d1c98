"""Hertz contact of spheres and of a sphere on a flat wall.

The normal force is ``F = K delta^(3/2)`` with ``K = 4/3 E* sqrt(R*)``. The closed forms
live in :mod:`pdamper.contact.elastic` (no numba, for the scenario reader and the resource
model); this module re-exports them and compiles the stiffness for the kernels.
"""

from __future__ import annotations

from numba import njit

from pdamper.contact import elastic
from pdamper.contact.elastic import (
    HERTZ_EXPONENT,
    contact_duration,
    effective_modulus,
    effective_radius,
    max_overlap,
    rayleigh_time,
)

__all__ = ["HERTZ_EXPONENT", "contact_duration", "effective_modulus", "effective_radius",
           "hertz_stiffness", "max_overlap", "rayleigh_time"]

#: Hertz stiffness K = 4/3 E* sqrt(R*) [N/m^1.5]; numba-compiled, callable from Python and
#: from the DEM kernels (the formula's home is :func:`pdamper.contact.elastic.hertz_stiffness`).
hertz_stiffness = njit(cache=True)(elastic.hertz_stiffness)
