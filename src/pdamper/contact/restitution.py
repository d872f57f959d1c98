"""Velocity-dependent coefficient of restitution (COR) curves, one per material pair (Level I).

A curve is a callable ``e(v_impact)`` [-] of the normal impact speed [m/s]. The paper's DEM
sets the damping of each contact from the curve of its material pair at its impact speed
(Sect. 2-3); the kinds of COR curve here are

* :class:`ConstantRestitution`: one value;
* :class:`TabulatedRestitution`: points interpolated linearly (what the kernels evaluate);
* :class:`MeasuredRestitution`: measured or FE points (velocity, COR[, std]), monotone
  piecewise-cubic (PCHIP) interpolation, held constant beyond the measured range;
* :class:`ExponentialRestitution`, :class:`LinearRestitution`: empirical forms (the paper's
  reconstructed Fig. 2 curves, :mod:`pdamper.parameters.vertical_dampers_paper`, and fits);
* :class:`pdamper.contact.thornton.ThorntonRestitution`: elastic-plastic spheres (Thornton
  1997) from material data;
* :class:`ScaledRestitution`: ``e -> 1 - s (1 - e)`` of any of them (sensitivity studies).

For the numba kernels every curve is handed over as two plain arrays ``(v_nodes, e_nodes)``
(:meth:`RestitutionCurve.tabulate`), interpolated linearly between the nodes and held
constant beyond the ends (:func:`pdamper.contact.forces.cor_at`). Smooth curves are
tabulated on ``[0, 20] m/s`` with nodes refined until linear interpolation deviates from the
curve by less than :data:`TABULATION_TOLERANCE` = 1e-4 (a hundredth of the 0.01 a DEM
calibration is held to, ``pdamper cor``); above 20 m/s the kernels hold ``e(20 m/s)``.

This module imports no numba and no scipy at import time, so that design objects and
scenario files can hold curves cheaply.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar

import numpy as np

from pdamper.errors import InputError, check_range

#: Velocity range over which smooth curves are tabulated for the kernels [m/s].
TABULATION_RANGE = (0.0, 20.0)
#: Largest deviation of the kernels' linear interpolation from a smooth curve [-].
TABULATION_TOLERANCE = 1e-4
#: Largest impact speed a COR table may give [m/s]: above the bar wave speed sqrt(E/rho)
#: of every material of the library (at most 9.8 km/s, alumina), where nothing rebounds;
#: the impacts a COR describes are a hundred times slower (the quasi-static limit of
#: :mod:`pdamper.resources` is 0.1 of that speed). Tables beyond it are unit mistakes.
MAX_TABLE_VELOCITY = 1e4


def _out(v, e):
    """``e`` as float for scalar ``v``, else as array."""
    return float(e) if np.ndim(v) == 0 else np.asarray(e, float)


def _cached_names(cls: type) -> frozenset[str]:
    """Names of the :func:`functools.cached_property` attributes of ``cls``."""
    return frozenset(name for klass in cls.__mro__ for name, value in vars(klass).items()
                     if isinstance(value, cached_property))


class RestitutionCurve:
    """Base class: a COR [-] as a function of the normal impact speed [m/s].

    A curve pickles as its defining fields alone: what it caches (tabulated nodes,
    interpolants) is derived, may not pickle (closures), and must not change the bytes of
    a pickle, which cross processes on the sweep engine and key the settled-bed cache
    (:attr:`pdamper.dem.DEMEngine.settle_key`): a curve pickles the same before and after
    its first evaluation.
    """

    def __getstate__(self) -> dict:
        cached = _cached_names(type(self))
        return {k: v for k, v in self.__dict__.items() if k not in cached}

    def __call__(self, v):
        v_nodes, e_nodes = self.tabulate()
        return _out(v, np.interp(np.abs(np.asarray(v, float)), v_nodes, e_nodes))

    def tabulate(self) -> tuple[np.ndarray, np.ndarray]:
        """``(v_nodes [m/s], e_nodes [-])`` for the kernels (linear between, held outside)."""
        raise NotImplementedError

    def describe(self) -> str:
        """A one-line description (tables, plots, results)."""
        return type(self).__name__

    def scaled(self, scale: float) -> RestitutionCurve:
        """The curve ``1 - scale (1 - e(v))`` (:class:`ScaledRestitution`); itself for 1."""
        if float(scale) == 1.0:
            return self
        return ScaledRestitution(self, scale)

    def minimum(self) -> float:
        """Smallest COR the kernels see (over the tabulated nodes) [-]."""
        return float(np.min(self.tabulate()[1]))


def _check_cor(field_name: str, e) -> None:
    for x in np.ravel(np.asarray(e, float)):
        check_range(field_name, x, low=0.0, high=1.0, low_inclusive=False)


def _check_table(velocity, restitution) -> tuple[np.ndarray, np.ndarray]:
    """A COR table as arrays: strictly increasing velocities >= 0 [m/s], one COR in (0, 1]
    each."""
    v = np.asarray(velocity, float)
    e = np.asarray(restitution, float)
    if v.ndim != 1 or v.shape != e.shape or v.size < 1:
        raise InputError("restitution.velocity", "needs as many velocities as COR values (>= 1)")
    if np.any(~np.isfinite(v)) or np.any(v < 0) or np.any(np.diff(v) <= 0):
        raise InputError("restitution.velocity", "must be finite, >= 0 m/s and strictly increasing")
    if v[-1] > MAX_TABLE_VELOCITY:
        raise InputError("restitution.velocity", f"must be <= {MAX_TABLE_VELOCITY:g} m/s, got "
                         f"{v[-1]:.3g} m/s: faster than sound in any solid, no impact a COR "
                         "describes (check the unit of the velocity column)")
    _check_cor("restitution.restitution", e)
    return v, e


@dataclass(frozen=True)
class ConstantRestitution(RestitutionCurve):
    """The same COR ``e`` [-] at every impact velocity."""

    e: float

    def __post_init__(self) -> None:
        check_range("restitution", self.e, low=0.0, high=1.0, low_inclusive=False)

    def __call__(self, v):
        return _out(v, np.full(np.shape(v), float(self.e)))

    def tabulate(self) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([float(self.e)])

    def describe(self) -> str:
        return f"constant {self.e:g}"


@dataclass(frozen=True)
class TabulatedRestitution(RestitutionCurve):
    """A curve through the points ``(velocity[i], restitution[i])``, interpolated linearly
    and held constant outside the given velocity range (exactly what the kernels do)."""

    velocity: tuple[float, ...]
    restitution: tuple[float, ...]

    def __post_init__(self) -> None:
        _check_table(self.velocity, self.restitution)

    def tabulate(self) -> tuple[np.ndarray, np.ndarray]:
        return np.asarray(self.velocity, float), np.asarray(self.restitution, float)

    def describe(self) -> str:
        return f"table of {len(self.velocity)} points (linear)"


# ------------------------------------------------------------------------- smooth curves
def tabulate_function(f, breakpoints=(), v_range=TABULATION_RANGE,
                      tolerance: float = TABULATION_TOLERANCE) -> tuple[np.ndarray, np.ndarray]:
    """Nodes on which linear interpolation follows the vectorised ``f(v)`` within
    ``tolerance``: segments are halved while the deviation at their quarter points exceeds
    ``tolerance / 2`` (for a smooth segment the largest deviation is about the midpoint's).

    ``breakpoints`` are velocities where ``f`` has a kink (always nodes).
    """
    lo, hi = map(float, v_range)
    start = np.geomspace(max(lo, 1e-4), hi, 33) if hi > 1e-4 else np.array([hi])
    nodes = np.unique(np.concatenate([[lo, hi], start,
                                      [b for b in breakpoints if lo < b < hi]]))
    for _ in range(60):
        a, b = nodes[:-1], nodes[1:]
        fa, fb = f(a), f(b)
        err = np.zeros(a.shape)
        for t in (0.25, 0.5, 0.75):
            err = np.maximum(err, np.abs(f(a + t * (b - a)) - (fa + t * (fb - fa))))
        bad = (err > 0.5 * tolerance) & (b - a > 1e-12 * max(hi, 1.0))
        if not bad.any():
            break
        nodes = np.sort(np.concatenate([nodes, 0.5 * (a[bad] + b[bad])]))
        if nodes.size > 20000:  # pragma: no cover - a curve no COR resembles
            raise InputError("restitution", "curve too rough to tabulate")
    return nodes, np.asarray(f(nodes), float)


class SmoothRestitution(RestitutionCurve):
    """A curve given by a function ``evaluate(v)``; tabulated adaptively for the kernels."""

    def evaluate(self, v: np.ndarray) -> np.ndarray:
        """``e(v)`` for an array of speeds ``v >= 0`` [m/s]."""
        raise NotImplementedError

    def breakpoints(self) -> tuple[float, ...]:
        """Velocities where the curve has a kink [m/s]."""
        return ()

    def __call__(self, v):
        return _out(v, self.evaluate(np.abs(np.asarray(v, float))))

    @cached_property
    def _table(self) -> tuple[np.ndarray, np.ndarray]:
        return tabulate_function(self.evaluate, self.breakpoints())

    def tabulate(self) -> tuple[np.ndarray, np.ndarray]:
        v, e = self._table
        return v.copy(), e.copy()


class ParametricRestitution(SmoothRestitution):
    """A smooth curve with named parameters, fittable to measured points
    (:func:`pdamper.contact.fit.fit_restitution`).

    Subclasses define ``PARAMETERS`` (names), ``UNITS``, ``BOUNDS`` (for the fit),
    :meth:`function` (vectorised ``e(v, *p)``), :meth:`guess` and :meth:`from_fit`.
    """

    PARAMETERS: ClassVar[tuple[str, ...]] = ()
    UNITS: ClassVar[tuple[str, ...]] = ()
    BOUNDS: ClassVar[tuple[tuple[float, ...], tuple[float, ...]]] = ((), ())

    @staticmethod
    def function(v, *p):  # pragma: no cover - abstract
        raise NotImplementedError

    @classmethod
    def guess(cls, v: np.ndarray, e: np.ndarray) -> tuple[float, ...]:  # pragma: no cover
        raise NotImplementedError

    @classmethod
    def from_fit(cls, params, v: np.ndarray, name: str = "") -> ParametricRestitution:
        """The curve with fitted ``params`` for data measured at speeds ``v``."""
        # every concrete curve is a dataclass with a ``name`` field after its parameters
        return cls(*params, name=name)  # type: ignore[call-arg]

    @property
    def parameters(self) -> tuple[float, ...]:
        return tuple(float(getattr(self, p)) for p in self.PARAMETERS)

    def evaluate(self, v):
        return self.function(v, *self.parameters)

    def describe(self) -> str:
        name = getattr(self, "name", "")
        if name:
            return str(name)
        pars = ", ".join(f"{p} = {x:.4g}{' ' + u if u else ''}"
                         for p, x, u in zip(self.PARAMETERS, self.parameters, self.UNITS,
                                            strict=True))
        return f"{type(self).__name__.removesuffix('Restitution').lower()} ({pars})"


@dataclass(frozen=True)
class ExponentialRestitution(ParametricRestitution):
    """``e(v) = e_inf + (e0 - e_inf) exp(-v / v_c)``: near ``e0`` at low speed, settling to
    ``e_inf`` above a few ``v_c`` (the shape of the paper's steel-steel curve, Fig. 2).

    Parameters
    ----------
    e0, e_inf
        COR at zero and at high speed [-], in (0, 1].
    v_c
        Velocity scale of the drop [m/s], > 0.
    name
        Optional label (not compared).
    """

    e0: float
    e_inf: float
    v_c: float
    name: str = field(default="", compare=False)

    PARAMETERS: ClassVar = ("e0", "e_inf", "v_c")
    UNITS: ClassVar = ("", "", "m/s")
    BOUNDS: ClassVar = ((1e-6, 1e-6, 1e-6), (1.0, 1.0, 1e3))

    def __post_init__(self) -> None:
        check_range("restitution.e0", self.e0, low=0.0, high=1.0, low_inclusive=False)
        check_range("restitution.e_inf", self.e_inf, low=0.0, high=1.0, low_inclusive=False)
        check_range("restitution.v_c", self.v_c, low=0.0, low_inclusive=False, unit="m/s")

    @staticmethod
    def function(v, e0, e_inf, v_c):
        return e_inf + (e0 - e_inf) * np.exp(-np.asarray(v, float) / v_c)

    @classmethod
    def guess(cls, v, e):
        i = np.argsort(v)
        v, e = v[i], e[i]
        e0, e_inf = float(min(e[0], 1.0)), float(e[-1])
        half = e_inf + 0.5 * (e0 - e_inf)
        k = int(np.argmax(e <= half)) if np.any(e <= half) else len(v) - 1
        return e0, e_inf, max(float(v[k]) / math.log(2.0), 1e-3)


@dataclass(frozen=True)
class LinearRestitution(ParametricRestitution):
    """``e(v) = e0 - slope * min(v, v_hold)``: linear, held constant beyond ``v_hold`` (the
    shape of the paper's steel-PVC curve, Fig. 2).

    Parameters
    ----------
    e0
        COR at zero speed [-], in (0, 1].
    slope
        Decrease per unit speed [s/m].
    v_hold
        Speed beyond which the COR is held [m/s] (for a fit: the highest measured speed);
        infinite only for ``slope <= 0``.
    """

    e0: float
    slope: float
    v_hold: float = math.inf
    name: str = field(default="", compare=False)

    PARAMETERS: ClassVar = ("e0", "slope")
    UNITS: ClassVar = ("", "s/m")
    BOUNDS: ClassVar = ((1e-6, -1e3), (1.0, 1e3))

    def __post_init__(self) -> None:
        check_range("restitution.e0", self.e0, low=0.0, high=1.0, low_inclusive=False)
        check_range("restitution.slope", self.slope, unit="s/m")
        if not self.v_hold > 0:
            raise InputError("restitution.v_hold", f"must be > 0 m/s, got {self.v_hold!r}")
        end = self.e0 - self.slope * self.v_hold if math.isfinite(self.v_hold) else (
            -math.inf if self.slope > 0 else (math.inf if self.slope < 0 else self.e0))
        if not 0.0 < end <= 1.0:
            raise InputError("restitution.slope", f"gives e = {end:.4g} at v_hold = "
                             f"{self.v_hold:g} m/s; the COR must stay in (0, 1]")

    @staticmethod
    def function(v, e0, slope, v_hold=math.inf):
        return e0 - slope * np.minimum(np.asarray(v, float), v_hold)

    def evaluate(self, v):
        return self.function(v, self.e0, self.slope, self.v_hold)

    def breakpoints(self) -> tuple[float, ...]:
        return (self.v_hold,) if math.isfinite(self.v_hold) else ()

    @classmethod
    def guess(cls, v, e):
        slope, e0 = np.polyfit(v, e, 1)
        return float(min(max(e0, 1e-3), 1.0)), float(-slope)

    @classmethod
    def from_fit(cls, params, v, name: str = ""):
        # ``params`` holds the two fitted values (e0, slope) only
        return cls(*params, v_hold=float(np.max(v)), name=name)  # type: ignore[misc]

    def describe(self) -> str:
        if self.name:
            return self.name
        hold = f", held beyond {self.v_hold:g} m/s" if math.isfinite(self.v_hold) else ""
        return f"linear (e0 = {self.e0:.4g}, slope = {self.slope:.4g} s/m{hold})"


# ---------------------------------------------------------------------- measured points
@dataclass(frozen=True)
class MeasuredRestitution(SmoothRestitution):
    """Measured or FE points ``(velocity, restitution[, std])``.

    Interpolation: monotone piecewise-cubic Hermite (PCHIP, Fritsch-Carlson): it passes
    through every point, never overshoots between two of them (a monotone stretch of the
    data stays monotone; the COR stays within the data's range), and is smooth.
    Extrapolation: the end values are held, below the lowest and above the highest measured
    speed: the measurement says nothing there, and a held value never leaves (0, 1]. One
    point gives a constant.

    Parameters
    ----------
    velocity
        Impact speeds [m/s], >= 0, strictly increasing.
    restitution
        COR at those speeds [-], in (0, 1].
    std
        Standard deviation of each COR [-] (optional; used by fits).
    source
        Where the points come from (a file name), for descriptions.
    """

    velocity: tuple[float, ...]
    restitution: tuple[float, ...]
    std: tuple[float, ...] | None = None
    source: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        v, _ = _check_table(self.velocity, self.restitution)
        if self.std is not None:
            s = np.asarray(self.std, float)
            if s.shape != v.shape or np.any(~np.isfinite(s)) or np.any(s < 0):
                raise InputError("restitution.std", "needs one finite value >= 0 per point")
        for name in ("velocity", "restitution", "std"):
            val = getattr(self, name)
            if val is not None:
                object.__setattr__(self, name, tuple(float(x) for x in val))
        with np.errstate(over="ignore", divide="ignore"):  # PCHIP's coefficients ~ de / dv^2
            if v.size > 1 and not np.all(np.isfinite(1.0 / np.diff(v) ** 2)):
                raise InputError("restitution.velocity", f"{self.source or 'the table'}: "
                                 "velocities too close together to interpolate (spacing "
                                 f"{float(np.min(np.diff(v))):.3g} m/s)")

    @cached_property
    def _interpolant(self):
        v = np.asarray(self.velocity)
        e = np.asarray(self.restitution)
        if v.size == 1:
            return lambda x: np.full(np.shape(x), e[0])
        from scipy.interpolate import PchipInterpolator

        # nodes orders of magnitude apart overflow PCHIP's harmonic mean of the slopes
        # (a zero, admissible derivative); what is not finite then is refused
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            p = PchipInterpolator(v, e, extrapolate=False)
        if not np.all(np.isfinite(p.c)):
            raise InputError("restitution.velocity", f"{self.source or 'the table'}: "
                             "velocities too close together to interpolate (spacing "
                             f"{float(np.min(np.diff(v))):.3g} m/s)")
        return lambda x: p(np.clip(x, v[0], v[-1]))

    def evaluate(self, v):
        return np.asarray(self._interpolant(np.asarray(v, float)), float)

    def breakpoints(self) -> tuple[float, ...]:
        return tuple(self.velocity)

    def describe(self) -> str:
        src = f" {self.source}" if self.source else ""
        return f"table{src} ({len(self.velocity)} points, PCHIP, held beyond " \
               f"{self.velocity[0]:g}-{self.velocity[-1]:g} m/s)"


# ------------------------------------------------------------------------------ scaling
@dataclass(frozen=True)
class ScaledRestitution(RestitutionCurve):
    """``e_s(v) = 1 - scale (1 - e(v))``: the dissipation ``1 - e`` of ``base`` times
    ``scale`` (0: elastic; 1: ``base``; > 1: more dissipative), for sensitivity studies.

    ``scale`` must keep the COR positive: ``0 <= scale < 1 / (1 - min e)``.
    """

    base: RestitutionCurve
    scale: float

    def __post_init__(self) -> None:
        if not isinstance(self.base, RestitutionCurve):
            raise InputError("restitution.scale", f"scales a RestitutionCurve, got {self.base!r}")
        s = check_range("restitution.scale", self.scale, low=0.0)
        e_min = self.base.minimum()
        if 1.0 - s * (1.0 - e_min) <= 0.0:
            raise InputError("restitution.scale", f"must be in [0, {1.0 / (1.0 - e_min):.4g}) "
                             f"for {self.base.describe()} (its COR falls to {e_min:.4g}), got {s:g}")

    def __call__(self, v):
        return _out(v, 1.0 - self.scale * (1.0 - np.asarray(self.base(v), float)))

    def tabulate(self) -> tuple[np.ndarray, np.ndarray]:
        # linear in e: scaling the nodes scales the interpolant exactly
        v, e = self.base.tabulate()
        return v, 1.0 - self.scale * (1.0 - e)

    def describe(self) -> str:
        return f"{self.base.describe()}, dissipation x {self.scale:g}"


__all__ = [
    "ConstantRestitution",
    "ExponentialRestitution",
    "LinearRestitution",
    "MeasuredRestitution",
    "ParametricRestitution",
    "RestitutionCurve",
    "ScaledRestitution",
    "SmoothRestitution",
    "TABULATION_RANGE",
    "MAX_TABLE_VELOCITY",
    "TABULATION_TOLERANCE",
    "TabulatedRestitution",
    "tabulate_function",
]
