"""Velocity-dependent coefficient of restitution (COR) curves, one per material pair.

A curve is a callable ``e(v_impact)``. For the numba kernels every curve is handed over as
two plain arrays ``(v_nodes, e_nodes)`` (:meth:`RestitutionCurve.tabulate`) and evaluated
with :func:`pdamper.contact.forces.cor_at` (linear interpolation, constant beyond the ends).
This module imports no numba, so that the design objects can hold curves cheaply.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdamper.errors import InputError, check_range


class RestitutionCurve:
    """Base class: a COR as a function of the normal impact velocity [m/s]."""

    def __call__(self, v):
        v_nodes, e_nodes = self.tabulate()
        return np.interp(np.abs(np.asarray(v, float)), v_nodes, e_nodes)

    def tabulate(self) -> tuple[np.ndarray, np.ndarray]:
        """Return ``(v_nodes [m/s], e_nodes [-])`` for the kernels."""
        raise NotImplementedError


@dataclass(frozen=True)
class ConstantRestitution(RestitutionCurve):
    """The same COR ``e`` [-] at every impact velocity."""

    e: float

    def __post_init__(self) -> None:
        check_range("restitution", self.e, low=0.0, high=1.0, low_inclusive=False)

    def tabulate(self) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([float(self.e)])


@dataclass(frozen=True)
class TabulatedRestitution(RestitutionCurve):
    """A measured or computed curve through the points ``(velocity[i], restitution[i])``.

    Interpolated linearly and held constant outside the given velocity range.
    """

    velocity: tuple[float, ...]
    restitution: tuple[float, ...]

    def __post_init__(self) -> None:
        v = np.asarray(self.velocity, float)
        e = np.asarray(self.restitution, float)
        if v.ndim != 1 or v.shape != e.shape or v.size < 1:
            raise InputError("restitution.velocity", "needs as many velocities as COR values (>= 1)")
        if np.any(~np.isfinite(v)) or np.any(v < 0) or np.any(np.diff(v) <= 0):
            raise InputError("restitution.velocity", "must be finite, >= 0 m/s and strictly increasing")
        for x in e:
            check_range("restitution.restitution", x, low=0.0, high=1.0, low_inclusive=False)

    def tabulate(self) -> tuple[np.ndarray, np.ndarray]:
        return np.asarray(self.velocity, float), np.asarray(self.restitution, float)
