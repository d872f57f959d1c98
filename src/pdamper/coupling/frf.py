"""Forced response of a structure carrying a damper: frequency response under a harmonic load.

The structure (a :class:`~pdamper.structure.SingleDOFStructure` or an N-mode
:class:`~pdamper.structure.modal.ModalStructure`, mass-normalised modes) is loaded
harmonically at angular frequency W, by a force ``F cos(W t)`` at its load point
(:class:`HarmonicLoad` ``"force"``; the modes' ``load_shape``, by default the damper's
point), by a rotating unbalance ``m e`` there (``"unbalance"``: the force
``m e W^2 cos(W t)``, growing with the speed squared) or, for a one-mode structure, by a
base motion ``y = Y cos(W t)`` (``"base"``, given as displacement or acceleration
amplitude; its spring and dashpot pass the force ``(K + i W D) Y`` to the mass, Eq. 23 in
absolute coordinates).
The damper acts at its point as the pseudo force of Sect. 4.1, ``F_d = -(m_eff x'' + d x')``
with ``d = E~ / (pi W X^2)`` (Eq. 2), i.e. as the amplitude- and frequency-dependent complex
stiffness (the describing function of the complex power method, Eqs. 1-4)

    k_d(f, X) = -m_eff(f, X) W^2 + i W d(f, X).

Three solutions are computed:

**Linear FRF** (no particles): ``x_o = H_oL F`` with the receptances
``H_ab(W) = sum_i phi_a,i phi_b,i / (w_i^2 - W^2 + 2 i zeta_i w_i W)`` (``L`` the load
point); closed form.

**Harmonic balance** (models with the pseudo-force coupling): the load moves the damper
point as a force ``F_d = F H_dL / H_dd`` at the damper point would, so with the damper at
stroke X the damper point moves as ``x_d = F_d / (1 / H_dd + k_d)``, and the steady
amplitudes are the roots of

    G(X) = X |1 / H_dd(W) + k_d(f, X)| - |F_d| = 0,

found at each frequency by scanning X on a logarithmic grid (the describing function
tabulated there in one call of the model) and refining every sign change with Brent's
method on the model itself. *Every* root is reported: ``dG/dX > 0`` is a stable branch,
``dG/dX < 0`` an unstable one (the middle branch of an S-shaped amplitude curve, between
the two saddle-nodes where up and down sweeps jump). Where the model's describing function
is discontinuous in X (a motion-mode boundary of the analytical model) G can change sign
across the discontinuity without a root: such a crossing is reported as an *edge* point
(neither a steady solution nor a branch), where a real structure sits on the mode boundary.
The observation point follows as ``x_o = H_oL F - H_od k_d x_d``.

**Stepped sine** (every model): the load is stepped through the frequencies, each step
starting from the state the previous step ended in (the phase of the load continuous) and
running until the amplitude of the damper point, judged cycle by cycle by
:class:`~pdamper.analysis.stationarity.SteadyStateCriterion` (the criterion of the maps,
here on the per-cycle amplitude relative to its last value), is steady. Pseudo-force
models integrate the modal equations exactly between once-per-cycle updates of m_eff and d
(as the free vibration of :mod:`pdamper.coupling.modal`, here with the load as two more
states of a harmonic oscillator); the DEM integrates structure and particles together (the
co-simulation of model 1 with the load added). An up sweep that starts below a jump stays
on the lower branch until it ends, then jumps; a down sweep the other way round.

Limits: the describing function is the damper's response to a *harmonic* container motion
(Level II). Harmonic balance and the pseudo-force stepped sine therefore assume that the
damper point moves near-harmonically at the load's frequency: true near a resonance of a
lightly damped structure, not where higher harmonics or subharmonics of the structure's
motion are strong (far below resonance with the structure's higher modes excited by the
impacts, subharmonic bed motion near 2 f_0, or a damper that dominates the structure). The
DEM stepped sine makes no such assumption; docs/forced.md compares them.
"""

from __future__ import annotations

import dataclasses
import math
import re
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from pdamper.analysis.stationarity import SteadyStateCriterion
from pdamper.coupling.harmonicity import NEAR_HARMONIC_DEVIATION
from pdamper.coupling.registry import HARMONIC_SWEEP, CouplingView, coupling_of
from pdamper.errors import InputError, SimulationError, check_range

#: Strokes of the harmonic-balance scan and of the stepped sine's table per frequency.
DEFAULT_STROKES = 800
#: Default most cycles a frequency step of the stepped sine may take before it is reported
#: as not steady.
DEFAULT_MAX_CYCLES = 2000
#: Steady-state criterion of the stepped sine on the per-cycle amplitude over its last
#: value: the windows of the maps, tolerance 0.1 %.
DEFAULT_STEADY = SteadyStateCriterion(rtol=1e-3, atol=1e-3, quiet_window_cycles=0)
#: Most frequencies of one response (a typo guard: a 121-point response takes seconds).
MAX_FREQUENCIES = 100_000
#: Windows over which a stepped-sine step's amplitude scatter is reported (FRFCurve).
SCATTER_WINDOWS = 5
LOAD_KINDS = ("force", "base", "unbalance")
SWEEPS = ("up", "down", "both")
#: Smallest harmonic load amplitude, by unit, and why: below it the load is below what
#: any measurement resolves, and the solution's stroke grids underflow long before the
#: number itself does (a force of 1e-200 N).
MIN_LOAD = {"N": (1e-6, "below 1 uN, the weight of 0.1 mg, no measured load is resolved"),
            "m": (1e-9, "a base motion below 1 nm is below any meaningful displacement"),
            "m/s^2": (1e-6, "below 1e-6 m/s^2 (0.1 ug) no accelerometer resolves a base "
                            "motion"),
            "kg*m": (1e-9, "below 1e-9 kg m (1 mg at 1 mm) no balancing machine resolves an "
                           "unbalance")}


# ----------------------------------------------------------------------------- inputs
@dataclass(frozen=True)
class HarmonicLoad:
    """A harmonic load: ``kind`` ``"force"`` (``amplitude`` [N] at the structure's load
    point), ``"unbalance"`` (a rotating unbalance ``m e``, ``amplitude`` [kg m], at the load
    point: the force ``m e W^2``, W the speed [rad/s]) or ``"base"`` (base motion of a
    one-mode structure: ``amplitude`` [m] of displacement, or with ``acceleration=True``
    [m/s^2] of acceleration, the displacement being ``A / W^2`` at each frequency).

    >>> round(HarmonicLoad("unbalance", 1.76e-3).reference(2 * math.pi * 12.0), 3)
    10.005
    """

    kind: str
    amplitude: float
    acceleration: bool = False

    def __post_init__(self) -> None:
        if self.kind not in LOAD_KINDS:
            raise InputError("load", f"must be one of {', '.join(LOAD_KINDS)}, got {self.kind!r}")
        unit = self.unit
        low, why = MIN_LOAD[unit]
        try:
            check_range(self.kind, self.amplitude, low=low, unit=unit)
        except InputError as exc:
            raise InputError(exc.field, f"{exc.message} ({why})") from None
        object.__setattr__(self, "amplitude", float(self.amplitude))

    @property
    def unit(self) -> str:
        if self.kind in ("force", "unbalance"):
            return {"force": "N", "unbalance": "kg*m"}[self.kind]
        return "m/s^2" if self.acceleration else "m"

    @property
    def at_load_point(self) -> bool:
        """Whether the load is a force at the structure's load point (a force or an
        unbalance; base motion moves the structure's base)."""
        return self.kind != "base"

    @classmethod
    def parse(cls, text: str, kind: str | None = None, field: str | None = None) -> HarmonicLoad:
        """The load of a quantity with units: a force (``"2N"``) or a base motion, as
        displacement (``"1mm"``) or acceleration (``"0.3g"``: g is the standard gravity
        here, ``"3 m/s^2"``); ``kind`` ``"unbalance"`` reads an unbalance ``m e``
        (``"1.76 kg*mm"``), and restricts it as ``"force"`` and ``"base"`` do; ``field``
        names the input in errors (default the kind, or ``load``).

        >>> HarmonicLoad.parse("0.3g").amplitude
        2.941995
        """
        if field is None:
            return cls._parse(text, kind, kind or "load")
        try:
            return cls._parse(text, kind, field)
        except InputError as exc:  # the amplitude's own check names the kind
            if exc.field == field:
                raise
            raise InputError(field, exc.message) from None

    @classmethod
    def _parse(cls, text: str, kind: str | None, name: str) -> HarmonicLoad:
        from pdamper.units import parse_quantity

        if kind == "unbalance":
            try:
                return cls("unbalance", parse_quantity(text, "kg*m", name))
            except InputError as exc:
                if "convertible" not in exc.message:
                    raise
                raise InputError(name, f"must be an unbalance m e, a mass times its "
                                 f"eccentricity (e.g. '1.76 kg*mm', '50 g*cm'), got "
                                 f"{text!r}") from None
        if kind in (None, "force"):
            try:
                return cls("force", parse_quantity(text, "N", name))
            except InputError as exc:
                if kind == "force" or "convertible" not in exc.message:
                    raise
        try:
            return cls("base", parse_quantity(text, "m", name))
        except InputError as exc:
            if "convertible" not in exc.message:
                raise
        # "0.3g": g is the standard gravity (pint reads a bare g as gram)
        accel = re.sub(r"(?<=[\d.\s])g$", " g0", str(text).strip())
        try:
            value = parse_quantity(accel, "m/s^2", name)
        except InputError:
            if kind is None:  # an unbalance m e ("1.76kg*mm")?
                try:
                    return cls("unbalance", parse_quantity(text, "kg*m", name))
                except InputError as exc:
                    if "convertible" not in exc.message:
                        raise
            what = ("a force (e.g. '2N'), an unbalance (e.g. '1.76kg*mm'), or a base "
                    if kind is None else "a base ")
            raise InputError(name, f"must be {what}displacement (e.g. '1mm') or acceleration "
                             f"(e.g. '0.3g', '3m/s^2') amplitude, got {text!r}") from None
        return cls("base", value, acceleration=True)  # its range checked as every load's

    def reference(self, omega: float) -> float:
        """Amplitude of the reference signal the phase is measured against at the angular
        frequency ``omega`` [rad/s]: the force [N] (of an unbalance ``m e omega^2``) or the
        base displacement [m]."""
        if self.kind == "base" and self.acceleration:
            return self.amplitude / (omega * omega)
        if self.kind == "unbalance":
            return self.amplitude * omega * omega
        return self.amplitude

    def as_dict(self) -> dict:
        return {"kind": self.kind, "amplitude": self.amplitude, "unit": self.unit,
                "acceleration": self.acceleration}

    def describe(self) -> str:
        """The load in words with a readable unit (``"unbalance 1.76 kg mm"``)."""
        scale = {"N": ("N", 1.0), "m": ("mm", 1e3), "m/s^2": ("m/s^2", 1.0),
                 "kg*m": ("kg mm", 1e3)}[self.unit]
        return f"{self.kind} {self.amplitude * scale[1]:.4g} {scale[0]}"


#: The default frequencies of a forced response (:func:`default_frequencies`): the span
#: from this fraction of the first natural frequency to this multiple of the last; points
#: of the base grid over it; points per half-power bandwidth ``2 zeta_i f_i`` and
#: half-power bandwidths either side of each resonance in the refined grid.
DEFAULT_SPAN = (0.5, 1.5)
DEFAULT_BASE_POINTS = 61
POINTS_PER_BANDWIDTH = 4
REFINED_BANDWIDTHS = 5


def default_frequencies(structure, added_mass: float = 0.0) -> np.ndarray:
    """The frequencies [Hz] of a forced response of ``structure`` when none are given:
    every mode, each resonance resolved for its damping.

    A base grid of :data:`DEFAULT_BASE_POINTS` from ``0.5 f_1`` to ``1.5 f_N``
    (:data:`DEFAULT_SPAN`), and around each natural frequency f_i points
    ``2 zeta_i f_i / POINTS_PER_BANDWIDTH`` apart (``zeta_i f_i / 2``: four per half-power
    bandwidth ``2 zeta_i f_i``) over :data:`REFINED_BANDWIDTHS` bandwidths either side,
    reaching down to where ``added_mass`` [kg] at the damper's point (a bed that moves with
    the container) tunes the mode, ``f_i / sqrt(1 + m phi_d,i^2)``. A mode whose damping
    ratio is 0 is refined as if it were 1e-4 (a forced response refuses it anyway:
    :func:`check_damped`).

    >>> from pdamper.parameters import PAPER_STRUCTURE as s
    >>> f = default_frequencies(s)
    >>> bool(f[0] < 0.5 * 5.56 < 1.5 * 5.56 < f[-1] + 1e-9), bool(np.min(np.diff(f)) > 0)
    (True, True)
    >>> bool(np.max(np.diff(f[abs(f - 5.56) < 0.05])) <= 0.0052 * 5.56 / 2 + 1e-12)
    True
    """
    s = _modal(structure)
    fn = s.frequencies
    zeta = np.maximum(s.damping_ratios, 1e-4)
    lo, hi = DEFAULT_SPAN[0] * float(fn[0]), DEFAULT_SPAN[1] * float(fn[-1])
    parts = [np.linspace(lo, hi, DEFAULT_BASE_POINTS)]
    check_range("added_mass", added_mass, low=0.0, unit="kg")
    for f_i, z_i, phi in zip(fn, zeta, s.damper_shape, strict=True):
        step = 2.0 * z_i * f_i / POINTS_PER_BANDWIDTH
        half = REFINED_BANDWIDTHS * 2.0 * z_i * f_i
        tuned = f_i / math.sqrt(1.0 + added_mass * phi * phi)
        a, b = max(lo, min(f_i, tuned) - half), min(hi, f_i + half)
        parts.append(f_i + step * np.arange(math.floor((a - f_i) / step),
                                            math.ceil((b - f_i) / step) + 1))
    f = np.unique(np.concatenate(parts))
    f = f[(f >= lo * (1 - 1e-12)) & (f <= hi * (1 + 1e-12)) & (f > 0)]
    # points closer than a tenth of the finest step are one
    tol = 0.1 * float(np.min(2.0 * zeta * fn / POINTS_PER_BANDWIDTH))
    keep = np.concatenate([[True], np.diff(f) > tol])
    return f[keep]


def check_damped(structure) -> None:
    """Refuse a structure with an undamped mode for a forced response: at that mode's
    natural frequency the response without particles is unbounded (the receptance divides
    by ``2 zeta_i w_i W = 0``), and every bound of the damper's stroke with it. The free
    decay of an undamped structure is well defined and not judged here. Raises InputError
    naming the damping (``structure.damping`` of the 1-DOF, ``structure.damping_ratios``
    of the modes)."""
    from pdamper.structure import SingleDOFStructure

    if isinstance(structure, SingleDOFStructure):
        if not structure.damping > 0:
            raise InputError("structure.damping", "must be > 0 kg/s for a forced response "
                             "(damping ratio in (0, 1)): the undamped structure's response "
                             "at its natural frequency is unbounded; got 0 kg/s")
        return
    z = np.asarray(_modal(structure).damping_ratios, float)
    bad = np.flatnonzero(~(z > 0))
    if bad.size:
        raise InputError("structure.damping_ratios", f"must be in (0, 1) for a forced "
                         f"response: mode {int(bad[0]) + 1} is undamped (damping ratio 0), "
                         "its response at its natural frequency is unbounded")


def _modal(structure):
    """The :class:`ModalStructure` of ``structure`` (a 1-DOF as its one mode)."""
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure

    if isinstance(structure, SingleDOFStructure):
        return ModalStructure.from_single_dof(structure)
    if isinstance(structure, ModalStructure):
        return structure
    raise InputError("structure", "must be a SingleDOFStructure (e.g. "
                     "pdamper.parameters.PAPER_STRUCTURE) or a ModalStructure, got "
                     f"{type(structure).__name__}")


def receptance(structure, frequency, a: str = "damper", b: str = "damper") -> np.ndarray:
    """``H_ab(W)`` [m/N]: displacement of point ``a`` per unit force at point ``b``
    (``"damper"``, ``"output"`` or ``"load"``) at frequencies f [Hz], closed form over the
    modes.

    >>> from pdamper.parameters import PAPER_STRUCTURE as s
    >>> h = receptance(s, 0.0)
    >>> bool(np.isclose(h.real, 1 / s.stiffness))
    True
    """
    s = _modal(structure)
    w = s.angular_frequencies
    om = 2.0 * math.pi * np.asarray(frequency, float)[..., None]
    pa = getattr(s, f"{a}_shape")
    pb = getattr(s, f"{b}_shape")
    den = w * w - om * om + 2j * s.damping_ratios * w * om
    return np.sum(pa * pb / den, axis=-1)


def load_point(structure, load: HarmonicLoad) -> str:
    """The point of ``structure`` where ``load`` acts, as :func:`receptance` names it:
    ``"load"`` for a force or an unbalance (the structure's load point, by default its
    damper's point), ``"damper"`` for the equivalent force of a base motion."""
    return "load" if load.at_load_point else "damper"


def load_point_text(structure) -> str:
    """Where a force on ``structure`` acts, in words (for the record of a run)."""
    from pdamper.structure import SingleDOFStructure

    if isinstance(structure, SingleDOFStructure):
        return "the damper's point (the 1-DOF's end-effector)"
    if np.array_equal(structure.load_shape, structure.damper_shape):
        return "the damper's point (the structure names no other load point)"
    return "the structure's load point"


def load_force(structure, load: HarmonicLoad, frequency: float) -> complex:
    """Complex amplitude [N] of the force at the load point (:func:`load_point`),
    relative to the reference signal (:meth:`HarmonicLoad.reference`, phase 0)."""
    om = 2.0 * math.pi * frequency
    ref = load.reference(om)
    if load.at_load_point:
        return complex(ref)
    s = _modal(structure)
    if s.modes != 1 or not np.array_equal(s.damper_shape, s.output_shape):
        raise InputError("base", "a base motion needs a one-mode structure with the damper at "
                         "the output point (a 1-DOF); N-mode base excitation needs the modes' "
                         "participation factors, which the modal input does not carry")
    e = s.equivalent_single_dof()
    return complex(e.stiffness, om * e.damping) * ref


def linear_frf(structure, load: HarmonicLoad, frequency) -> np.ndarray:
    """Complex amplitude of the output point [m] without particles, closed form, relative
    to the load's reference signal (amplitude ``abs``, phase ``angle``)."""
    f = np.atleast_1d(np.asarray(frequency, float))
    force = np.array([load_force(structure, load, v) for v in f])
    return receptance(structure, f, "output", load_point(structure, load)) * force


def damper_force(structure, load: HarmonicLoad, frequency: float) -> complex:
    """The force at the damper's point that moves it as ``load`` does,
    ``F_d = F H_dL / H_dd`` [N] (``F`` itself where the load acts there)."""
    s = _modal(structure)
    force = load_force(s, load, frequency)
    pt = load_point(s, load)
    if pt == "damper" or np.array_equal(s.load_shape, s.damper_shape):
        return force
    h_dd = complex(receptance(s, frequency))
    return force * complex(receptance(s, frequency, "damper", pt)) / h_dd


# ----------------------------------------------------------------------------- damper
@dataclass(frozen=True)
class DescribingFunction:
    """The damper's describing function at one frequency on a grid of strokes.

    Attributes
    ----------
    frequency
        f [Hz].
    stroke
        Strokes X [m], ascending (log-spaced).
    effective_mass
        m_eff [kg].
    damping
        d = E~ / (pi W X^2) [kg/s].
    loss_factor, mode
        eta [-] and the motion-mode codes.
    """

    frequency: float
    stroke: np.ndarray
    effective_mass: np.ndarray
    damping: np.ndarray
    loss_factor: np.ndarray
    mode: np.ndarray

    @property
    def omega(self) -> float:
        return 2.0 * math.pi * self.frequency

    def stiffness(self) -> np.ndarray:
        """k_d = -m_eff W^2 + i W d [N/m] on the grid."""
        w = self.omega
        return -self.effective_mass * w * w + 1j * w * self.damping

    def at(self, x: float) -> tuple[float, float, int, float]:
        """(m_eff, d, mode, eta) at stroke x, interpolated linearly in log X (clamped to
        the grid: below it the damper is as at its smallest stroke)."""
        g = self.stroke
        if x <= g[0]:
            i, w = 0, 0.0
        elif x >= g[-1]:
            i, w = g.size - 2, 1.0
        else:
            i = int(np.searchsorted(g, x)) - 1
            w = math.log(x / g[i]) / math.log(g[i + 1] / g[i])
        m = self.effective_mass[i] + w * (self.effective_mass[i + 1] - self.effective_mass[i])
        d = self.damping[i] + w * (self.damping[i + 1] - self.damping[i])
        e = self.loss_factor[i] + w * (self.loss_factor[i + 1] - self.loss_factor[i])
        return float(m), float(d), int(self.mode[i if w < 0.5 else i + 1]), float(e)


def _coefficients(model, frequency, stroke):
    """m_eff [kg], d [kg/s], eta, mode codes of ``model`` at (f, X) arrays (Sect. 4.1)."""
    f = np.asarray(frequency, float)
    x = np.asarray(stroke, float)
    if model.damper.count == 0:  # no particles: the damper adds nothing
        z = np.zeros(np.broadcast(f, x).shape)
        return z, z.copy(), z.copy(), np.full(z.shape, -1)
    r = model.response(f, x)
    w = 2.0 * math.pi * f
    d = np.asarray(r.dissipated_energy_per_cycle, float) / (math.pi * w * x * x)
    return (np.asarray(r.effective_mass, float), d, np.asarray(r.loss_factor, float),
            np.asarray(r.mode))


def stroke_bounds(structure, load: HarmonicLoad, model, frequency: float) -> tuple[float, float]:
    """Strokes that bracket every steady stroke of the damper point at ``frequency`` [m].

    Above: the particles add mass between 0 and m_bed and never negative damping, so the
    stroke is at most the largest ``|F| / |1/H_dd - m W^2|`` over m in [0, m_bed] (the
    bare structure's resonance bounds it when m_eff can tune it). Below: the damper force
    is at most about ``(1 + 4/pi) m_bed W^2 X`` (the zero-gravity optimum of Eq. 3), so the
    stroke is at least ``|F| / (|1/H_dd| + 3 m_bed W^2)``; both widened by two."""
    s = _modal(structure)
    om = 2.0 * math.pi * frequency
    force = abs(damper_force(s, load, frequency))
    applied = abs(load_force(s, load, frequency))
    h = complex(receptance(s, frequency))
    mb = model.bed_mass
    if s.modes == 1:  # the 1-DOF's resonance can be tuned by any mass in [0, m_bed]
        e = s.equivalent_single_dof()
        masses = np.linspace(0.0, mb, 65)
        den = np.abs(e.stiffness - (e.mass + masses) * om * om + 1j * om * e.damping)
        wm = e.stiffness / om**2 - e.mass
        if 0.0 <= wm <= mb:
            den = np.append(den, om * e.damping)
        upper = force / float(np.min(den))
    else:
        masses = np.linspace(0.0, mb, 65)
        den = np.abs(1.0 / h - masses * om * om)
        upper = force / float(np.min(den))
        # a mass may also tune another mode onto W: bound by the damped modal peaks
        phi = s.damper_shape
        psi = s.load_shape if load.at_load_point else phi
        w = s.angular_frequencies
        peaks = np.abs(phi * psi / (2.0 * np.maximum(s.damping_ratios, 1e-6) * w * om))
        upper = max(upper, applied * float(np.sum(peaks)))
    lower = force / (abs(1.0 / h) + 3.0 * mb * om * om)
    # a load point that hardly moves the damper's: the strokes start far below, never at 0
    lower = max(lower, 1e-12 * upper)
    return 0.5 * lower, 2.0 * upper


def describing_function(model, frequency: float, low: float, high: float,
                        points: int = DEFAULT_STROKES, field: str = "load") -> DescribingFunction:
    """The damper of ``model`` at ``frequency`` [Hz] on ``points`` log-spaced strokes in
    [low, high] [m], one call of the model (clipped to a map's range when its policy
    refuses points outside it); ``field`` names the load in errors."""
    lo, hi = low, high
    rng = getattr(model, "amplitude_range", None)
    if rng is not None and getattr(model, "extrapolation", "") == "error":
        lo, hi = max(lo, rng[0]), min(hi, rng[1])
        if not lo < hi:
            raise InputError("frequency", f"at {frequency:g} Hz the strokes the load can cause "
                             f"({low * 1e3:.3g}-{high * 1e3:.3g} mm) are outside the map's "
                             f"({rng[0] * 1e3:.3g}-{rng[1] * 1e3:.3g} mm); use a map over "
                             "these strokes or fields.extrapolation = 'analytic'")
    x = np.geomspace(lo, hi, points)
    try:
        m, d, eta, mode = _coefficients(model, np.full(points, frequency), x)
    except InputError as exc:  # the physics limits of the model's runs, judged on the load
        if exc.field not in ("amplitude", "frequency"):
            raise
        raise InputError(field, f"at {frequency:g} Hz the load can drive the damper through "
                         f"strokes up to {hi:.3g} m, outside the limits of the "
                         f"{model.fidelity} model ({exc.field}: {exc.message}); lower the "
                         "load or the frequencies") from None
    return DescribingFunction(frequency, x, m, d, eta, mode)


#: Points of the model per call when the tables of many frequencies are made together:
#: the analytical model's phase scan holds arrays of 256 samples per point.
TABLE_CHUNK = 2048


def describing_functions(model, frequency: Sequence[float], bounds: Sequence[tuple[float, float]],
                         points: int = DEFAULT_STROKES, field: str = "load"
                         ) -> list[DescribingFunction]:
    """:func:`describing_function` at every frequency (strokes in its ``bounds``), the model
    called on all of them together (in chunks of :data:`TABLE_CHUNK` points): the same
    tables, each point computed alone by the model as in one call per frequency. A refusal
    of the model is reported as :func:`describing_function` reports it, naming the
    frequency."""
    grids = []
    for f, (low, high) in zip(frequency, bounds, strict=True):
        lo, hi = low, high
        rng = getattr(model, "amplitude_range", None)
        if rng is not None and getattr(model, "extrapolation", "") == "error":
            lo, hi = max(lo, rng[0]), min(hi, rng[1])
            if not lo < hi:  # the message of describing_function
                return [describing_function(model, f, a, b, points, field)
                        for f, (a, b) in zip(frequency, bounds, strict=True)]
        grids.append(np.geomspace(lo, hi, points))
    if not grids:
        return []
    fs = np.repeat(np.asarray(frequency, float), points)
    xs = np.concatenate(grids)
    try:
        parts = [_coefficients(model, fs[i:i + TABLE_CHUNK], xs[i:i + TABLE_CHUNK])
                 for i in range(0, fs.size, TABLE_CHUNK)]
    except Exception:  # noqa: BLE001 - frequency by frequency: the first refusal, named
        return [describing_function(model, f, a, b, points, field)
                for f, (a, b) in zip(frequency, bounds, strict=True)]
    m, d, eta, mode = (np.concatenate([p[k] for p in parts]) for k in range(4))
    return [DescribingFunction(float(f), x, *(a[k * points:(k + 1) * points]
                                              for a in (m, d, eta, mode)))
            for k, (f, x) in enumerate(zip(frequency, grids, strict=True))]


def _brent(xa: float, xb: float, xtol: float, rtol: float, maxiter: int):
    """Brent's method on ``[xa, xb]`` as ``scipy.optimize.brentq`` runs it (its C code,
    step for step), written as a generator: it yields the strokes to evaluate, is sent
    the function's values and returns the root, so that many roots are found in lockstep
    with the function evaluated for all of them in one call (:func:`_brent_lockstep`)."""
    xpre, xcur = xa, xb
    xblk = fblk = spre = scur = 0.0
    fpre = yield xpre
    fcur = yield xcur
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if math.copysign(1.0, fpre) == math.copysign(1.0, fcur):
        raise ValueError("f(a) and f(b) must have different signs")
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and math.copysign(1.0, fpre) != math.copysign(1.0, fcur):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre, scur = scur, stry  # a good short step
            else:
                spre = scur = sbis  # bisect
        else:
            spre = scur = sbis  # bisect
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0 else -delta)
        fcur = yield xcur
    raise RuntimeError(f"failed to converge after {maxiter} iterations, value is {xcur}")


def _brent_lockstep(fn: Callable[[Sequence[int], Sequence[float]], Sequence[float]],
                    brackets: Sequence[tuple[float, float]], *, xtol: float, rtol: float,
                    maxiter: int) -> list[float]:
    """The root in each bracket by :func:`_brent`, all advanced together: each round
    evaluates ``fn(which, xs)`` (the brackets' indices and their strokes) once."""
    runs = [_brent(a, b, xtol, rtol, maxiter) for a, b in brackets]
    roots = [math.nan] * len(runs)
    want = {j: next(r) for j, r in enumerate(runs)}
    while want:
        which = list(want)
        xs = [want[j] for j in which]
        values = fn(which, xs)
        want = {}
        for j, x, v in zip(which, xs, values, strict=True):
            if math.isnan(v):  # as brentq says it
                raise ValueError(f"The function value at x={x:f} is NaN; solver cannot "
                                 "continue.")
            try:
                want[j] = runs[j].send(v)
            except StopIteration as stop:
                roots[j] = stop.value
    return roots


# ----------------------------------------------------------------------------- results
#: Branch kinds of the harmonic-balance points.
STABLE, UNSTABLE, EDGE = "stable", "unstable", "edge"


@dataclass(frozen=True)
class FRFCurve:
    """Per-frequency results of one solution (a harmonic-balance solution slot or a sweep).

    Arrays of shape (frequencies, solutions) for harmonic balance (NaN-padded where a
    frequency has fewer solutions), (frequencies,) for a sweep, in the order of
    ``frequency`` ascending.

    Attributes
    ----------
    amplitude, phase
        Output point's amplitude [m] and phase [rad] against the load's reference signal.
    stroke
        Damper point's (container's) amplitude [m].
    loss_factor, effective_mass, mode
        The damper there: eta [-], m_eff [kg], motion-mode code (-1: none).
    steady
        Whether the point is a steady state (harmonic balance: the stable branch; sweep:
        the stationarity criterion passed).
    branch
        Harmonic balance: ``"stable"``, ``"unstable"``, ``"edge"`` or ``""`` (padding).
    cycles
        Sweep: load cycles run at the frequency [-].
    amplitude_mean, amplitude_std
        Sweep: the output amplitude over the step's last :data:`SCATTER_WINDOWS` windows
        (each as long as the window ``amplitude`` is read from: one load cycle of a
        pseudo-force model, the judged cycles of the DEM, at least 3), their mean and sample
        standard deviation [m] (NaN with one window). On a steady step they agree with
        ``amplitude``; on a step that is not steady (a chaotic bed) the spread is the
        scatter the single ``amplitude`` carries.
    """

    amplitude: np.ndarray
    phase: np.ndarray
    stroke: np.ndarray
    loss_factor: np.ndarray
    effective_mass: np.ndarray
    mode: np.ndarray
    steady: np.ndarray
    branch: np.ndarray | None = None
    cycles: np.ndarray | None = None
    amplitude_mean: np.ndarray | None = None
    amplitude_std: np.ndarray | None = None
    diagnostics: dict = field(default_factory=dict, repr=False, compare=False)


@dataclass(frozen=True)
class FRFResult:
    """Frequency response of a structure with a damper (module docstring).

    Attributes
    ----------
    frequency
        f [Hz], ascending.
    load
        The :class:`HarmonicLoad`.
    linear
        Complex output amplitude without particles (closed form) [m].
    harmonic_balance
        :class:`FRFCurve` of every harmonic-balance solution, or None (models without the
        pseudo-force coupling).
    sweeps
        ``{"up": FRFCurve, "down": FRFCurve}`` of the stepped sines run.
    model
        Fidelity of the damper model.
    inputs
        What was run (for the record).
    wall_seconds
        ``{"harmonic_balance": s, "up": s, "down": s}``.
    """

    frequency: np.ndarray
    load: HarmonicLoad
    linear: np.ndarray
    harmonic_balance: FRFCurve | None
    sweeps: dict
    model: str
    inputs: dict = field(default_factory=dict)
    wall_seconds: dict = field(default_factory=dict)

    def peak(self, band: tuple[float, float] | None = None, source: str | None = None) -> float:
        """Largest steady output amplitude over ``band`` [Hz] (default all) [m]: of the
        sweeps (both directions) by default, of the harmonic balance's stable branches if
        there is no sweep or ``source="harmonic_balance"``."""
        return float(np.nanmax(self._band_values(band, source)))

    def rms(self, band: tuple[float, float] | None = None, source: str | None = None) -> float:
        """RMS over the frequencies in ``band`` of the largest steady output amplitude at
        each frequency [m] (amplitudes, not RMS values of the motion: divide by sqrt 2)."""
        v = self._band_values(band, source)
        return float(np.sqrt(np.nanmean(v**2)))

    def _band_values(self, band, source) -> np.ndarray:
        f = self.frequency
        sel = np.ones(f.shape, bool) if band is None else (f >= band[0]) & (f <= band[1])
        if not np.any(sel):
            raise InputError("optimization.band", f"holds none of the frequencies "
                             f"{f[0]:g}-{f[-1]:g} Hz")
        if source is None:
            source = "sweeps" if self.sweeps else "harmonic_balance"
        if source == "harmonic_balance":
            hb = self.harmonic_balance
            assert hb is not None  # the source without sweeps: harmonic balance was run
            a = np.where(hb.steady, hb.amplitude, np.nan)
            return np.nanmax(np.where(np.isnan(a).all(axis=1, keepdims=True), 0.0, a),
                             axis=1)[sel]
        per = [np.where(c.steady, c.amplitude, np.nan) for c in self.sweeps.values()]
        stack = np.vstack(per)
        stack = np.where(np.isnan(stack).all(axis=0), np.vstack([c.amplitude for c in
                                                                 self.sweeps.values()]).max(0),
                         stack)
        return np.nanmax(stack, axis=0)[sel]

    def to_dataset(self):
        """xarray Dataset (CF units) with dimensions ``frequency``, ``solution`` (harmonic
        balance) and ``sweep``."""
        import xarray as xr

        from pdamper import __version__

        ds = xr.Dataset(coords={"frequency": ("frequency", self.frequency,
                                              {"units": "Hz", "long_name": "load frequency"})})
        ds["linear_amplitude"] = ("frequency", np.abs(self.linear),
                                  {"units": "m", "long_name": "output amplitude without "
                                   "particles (closed form)"})
        ds["linear_phase"] = ("frequency", np.angle(self.linear),
                              {"units": "rad", "long_name": "output phase without particles"})
        meta = {
            "amplitude": ("m", "output point amplitude"),
            "phase": ("rad", "output point phase against the load's reference signal"),
            "stroke": ("m", "container (damper point) amplitude"),
            "loss_factor": ("1", "damper loss factor eta (Eq. 3)"),
            "effective_mass": ("kg", "damper effective mass (Eq. 4)"),
            "mode": ("1", "motion mode code (pdamper.analysis.modes.MotionMode; -1 none)"),
            "steady": ("1", "steady state"),
        }
        if self.harmonic_balance is not None:
            hb = self.harmonic_balance
            for k, (unit, name) in meta.items():
                v = getattr(hb, k)
                ds[f"hb_{k}"] = (("frequency", "solution"),
                                 v.astype("i1") if k == "steady" else v,
                                 {"units": unit, "long_name": f"harmonic balance: {name}"})
            assert hb.branch is not None  # harmonic balance labels every solution's branch
            ds["hb_branch"] = (("frequency", "solution"), hb.branch.astype(str),
                               {"long_name": "harmonic balance branch: stable, unstable, edge"})
            _assumption_variables(ds, "hb", ("frequency", "solution"), [hb])
        if self.sweeps:
            ds = ds.assign_coords(sweep=("sweep", list(self.sweeps)))
            extra = {"cycles": ("1", "load cycles run")}
            if all(c.amplitude_mean is not None for c in self.sweeps.values()):
                extra.update(amplitude_mean=("m", "output amplitude, mean over the last "
                                                  "windows"),
                             amplitude_std=("m", "output amplitude, sample standard "
                                                 "deviation over the last windows"))
            for k, (unit, name) in {**meta, **extra}.items():
                v = np.stack([getattr(c, k) for c in self.sweeps.values()])
                ds[f"sweep_{k}"] = (("sweep", "frequency"),
                                    v.astype("i1") if k == "steady" else v,
                                    {"units": unit, "long_name": f"stepped sine: {name}"})
            _assumption_variables(ds, "sweep", ("sweep", "frequency"),
                                  list(self.sweeps.values()))
            for key, name in (("harmonic_deviation", "RMS deviation of the damper point's "
                               "last cycle from the harmonic its describing function was "
                               "taken at, over that harmonic's RMS"),
                              ("distortion", "RMS of the damper point's motion less its "
                               "first harmonic, over the first harmonic's RMS")):
                if all(key in c.diagnostics for c in self.sweeps.values()):
                    ds[f"sweep_{key}"] = (("sweep", "frequency"), np.stack(
                        [np.asarray(c.diagnostics[key], float) for c in
                         self.sweeps.values()]), {"units": "1",
                                                  "long_name": f"stepped sine: {name}"})
        ds.attrs.update(title="pdamper forced response", model=self.model,
                        load_kind=self.load.kind, load_amplitude=self.load.amplitude,
                        load_unit=self.load.unit, pdamper_version=__version__,
                        Conventions="CF-1.8")
        return ds

    def as_dict(self) -> dict:
        """JSON-ready payload: one record per frequency and solution."""
        from pdamper.coupling.pseudo_force import motion_mode

        def rows(c: FRFCurve, i, j=None) -> dict:
            idx = (i,) if j is None else (i, j)
            m = motion_mode(c.mode[idx])
            out = {"amplitude": float(c.amplitude[idx]), "phase": float(c.phase[idx]),
                   "stroke": float(c.stroke[idx]), "loss_factor": float(c.loss_factor[idx]),
                   "effective_mass": float(c.effective_mass[idx]),
                   "mode": m.label if m is not None else "unclassified",
                   "steady": bool(c.steady[idx])}
            if c.branch is not None:
                out["branch"] = str(c.branch[idx])
            if c.cycles is not None:
                out["cycles"] = int(c.cycles[idx])
            if "harmonic_deviation" in c.diagnostics:  # a describing-function step
                dev = float(c.diagnostics["harmonic_deviation"][idx])
                out["harmonic_deviation"] = dev
                out["near_harmonic"] = bool(not dev > NEAR_HARMONIC_DEVIATION)
            elif "distortion" in c.diagnostics:  # the plastic block's step
                out["distortion"] = float(c.diagnostics["distortion"][idx])
            if "assumptions_hold" in c.diagnostics:  # the damper model's own check
                out["assumptions_hold"] = bool(c.diagnostics["assumptions_hold"][idx])
                out["assumptions"] = str(c.diagnostics["assumptions"][idx])
            if c.amplitude_mean is not None and c.amplitude_std is not None:
                from pdamper.coupling.results import with_reasons

                out.update(with_reasons(
                    {"amplitude_mean": float(c.amplitude_mean[idx]),
                     "amplitude_std": float(c.amplitude_std[idx])},
                    {"amplitude_std": "the step ran one window: no spread to report",
                     "amplitude_mean": "the step ran no whole window"}))
            return out

        points = []
        for i, f in enumerate(self.frequency):
            p: dict[str, Any] = {"frequency": float(f),
                                 "linear_amplitude": float(abs(self.linear[i])),
                                 "linear_phase": float(np.angle(self.linear[i]))}
            if self.harmonic_balance is not None:
                hb = self.harmonic_balance
                assert hb.branch is not None  # harmonic balance labels every solution's branch
                p["harmonic_balance"] = [rows(hb, i, j) for j in range(hb.amplitude.shape[1])
                                         if hb.branch[i, j]]
            for name, c in self.sweeps.items():
                p[name] = rows(c, i)
            points.append(p)
        out = {"model": self.model, "load": self.load.as_dict(), "points": points,
               "inputs": self.inputs, "wall_seconds": self.wall_seconds}
        marks = assumption_record(self)
        if marks is not None:
            out["assumptions"] = marks
        return out


def _assumption_variables(ds, prefix: str, dims: tuple[str, str], curves: list) -> None:
    """``<prefix>_assumptions_hold`` (0/1) and ``<prefix>_assumptions`` (the reasons) of
    ``curves`` in ``ds``, where the model reported them."""
    from pdamper.analysis.fields import ASSUMPTIONS_ATTRS, ASSUMPTIONS_HOLD_ATTRS

    if not all("assumptions_hold" in c.diagnostics for c in curves):
        return
    hold = np.stack([np.asarray(c.diagnostics["assumptions_hold"], bool) for c in curves])
    why = np.stack([np.asarray(c.diagnostics["assumptions"], object) for c in curves])
    if prefix == "hb":  # one curve of (frequency, solution)
        hold, why = hold[0], why[0]
    ds[f"{prefix}_assumptions_hold"] = (dims, hold.astype("i1"), dict(ASSUMPTIONS_HOLD_ATTRS))
    ds[f"{prefix}_assumptions"] = (dims, why.astype(str), dict(ASSUMPTIONS_ATTRS))


# ----------------------------------------------------------------------------- harmonic balance
def harmonic_balance(model, structure, load: HarmonicLoad, frequency,
                     strokes: int = DEFAULT_STROKES, tables: dict | None = None) -> FRFCurve:
    """Every steady solution of the describing-function equation at each frequency (module
    docstring); ``tables`` collects the :class:`DescribingFunction` per frequency.

    The model is called on all frequencies at once: the tables in one call
    (:func:`describing_functions`), then every sign change refined by Brent's method in
    lockstep (:func:`_brent_lockstep`, one call of the model per iteration for all roots),
    which gives the roots of ``scipy.optimize.brentq`` on each bracket, bit for bit.
    """
    s = _modal(structure)
    freqs = np.atleast_1d(np.asarray(frequency, float))
    rows = []
    for f in freqs:
        om = 2.0 * math.pi * f
        force = damper_force(s, load, f)
        rows.append((float(f), om, load_force(s, load, f), force, abs(force),
                     complex(receptance(s, f)), complex(receptance(s, f, "output", "damper")),
                     complex(receptance(s, f, "output", load_point(s, load))),
                     stroke_bounds(s, load, model, f)))
    found = describing_functions(model, [r[0] for r in rows], [r[8] for r in rows],
                                 strokes, load.kind)
    brackets: list[tuple[int, float, float, bool]] = []  # (row, a, b, G rises)
    for k, (f, _om, _, _, fa, h_dd, _, _, _) in enumerate(rows):
        table = found[k]
        if tables is not None:
            tables[f] = table
        x = table.stroke
        g = x * np.abs(1.0 / h_dd + table.stiffness()) - fa
        for i in np.flatnonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0):
            brackets.append((k, float(x[i]), float(x[i + 1]), bool(g[i + 1] > g[i])))

    def g_many(which: Sequence[int], xs: Sequence[float]) -> list[float]:
        """G(X) at the strokes ``xs`` of the brackets ``which``, one call of the model."""
        if not len(xs):
            return []
        ks = [brackets[j][0] for j in which]
        m, d, _, _ = _coefficients(model, np.array([rows[k][0] for k in ks]),
                                   np.array(xs, float))
        out = []
        for k, v, mi, di in zip(ks, xs, m, d, strict=True):
            _, om, _, _, fa, h_dd = rows[k][:6]
            mi, di = float(mi), float(di)
            out.append(v * abs(1.0 / h_dd - mi * om * om + 1j * om * di) - fa)
        return out

    roots = _brent_lockstep(g_many, [(a, b) for _, a, b, _ in brackets],
                            xtol=1e-14, rtol=1e-12, maxiter=200)
    # a root, or a jump of the describing function across zero (an edge)
    lows = [max(r - 1e-7 * r, a) for r, (_, a, _, _) in zip(roots, brackets, strict=True)]
    highs = [min(r + 1e-7 * r, b) for r, (_, _, b, _) in zip(roots, brackets, strict=True)]
    idx = list(range(len(brackets)))
    g_lh = g_many(idx + idx, lows + highs)
    coef = _coefficients(model, np.array([rows[k][0] for k, _, _, _ in brackets]),
                         np.array(roots, float)) if brackets else ()
    sols: list[list[tuple]] = [[] for _ in rows]
    for j, (k, _, _, rises) in enumerate(brackets):
        _, om, applied, force, fa, h_dd, h_od, h_ol, _ = rows[k]
        root = roots[j]
        ga, gb = g_lh[j], g_lh[len(brackets) + j]
        slope = (gb - ga) / (highs[j] - lows[j])
        scale = fa / root  # |dG/dX| of the bare linear problem
        kind = (EDGE if abs(gb - ga) > 1e-3 * fa and abs(slope) > 1e4 * scale
                else STABLE if rises else UNSTABLE)
        m, d, eta, mode = (np.asarray(v[j]).item() for v in coef)
        kd = -m * om * om + 1j * om * d
        xd = force / (1.0 / h_dd + kd)
        xd = xd * (root / abs(xd))  # on the root exactly
        xo = h_ol * applied - h_od * kd * xd if not s.coincident else xd
        sols[k].append((abs(xo), float(np.angle(xo / load.reference(om))), root, eta, m,
                        int(mode), kind == STABLE, kind))
    k = max(1, max(len(v) for v in sols))
    n = freqs.size
    arr = {name: np.full((n, k), np.nan) for name in ("amplitude", "phase", "stroke",
                                                       "loss_factor", "effective_mass")}
    mode = np.full((n, k), -1)
    steady = np.zeros((n, k), bool)
    branch = np.full((n, k), "", dtype=object)
    for row, here in enumerate(sols):
        for j, (a, ph, st, eta, m, md, ok, kind) in enumerate(sorted(here, key=lambda r: r[2])):
            arr["amplitude"][row, j], arr["phase"][row, j], arr["stroke"][row, j] = a, ph, st
            arr["loss_factor"][row, j], arr["effective_mass"][row, j] = eta, m
            mode[row, j], steady[row, j], branch[row, j] = md, ok, kind
    return FRFCurve(amplitude=arr["amplitude"], phase=arr["phase"], stroke=arr["stroke"],
                    loss_factor=arr["loss_factor"], effective_mass=arr["effective_mass"],
                    mode=mode, steady=steady, branch=branch.astype(str))


# ----------------------------------------------------------------------------- stepped sine
def _sweep_order(frequency: np.ndarray, direction: str) -> np.ndarray:
    order = np.argsort(frequency)
    return order if direction == "up" else order[::-1]


def judge_amplitudes(amplitudes: Sequence[float] | np.ndarray, criterion: SteadyStateCriterion):
    """The stationarity verdict on per-cycle amplitudes (relative to the last one, so that
    the criterion's tolerances are relative)."""
    a = np.asarray(amplitudes, float)
    if a.size == 0 or not a[-1] > 0:
        return criterion.evaluate(np.zeros(a.size))
    return criterion.evaluate(a / a[-1])


def steady_amplitudes(amplitudes: Sequence[float] | np.ndarray, criterion: SteadyStateCriterion) -> bool:
    """Whether per-cycle amplitudes are steady: every cycle of the criterion's full window
    within its ``rtol`` of the last (a structure's transient is a slow *beat* of free and
    forced motion, which the criterion's scatter allowance, made for chaotic beds, would
    pass), and :func:`judge_amplitudes` accepts them."""
    a = np.asarray(amplitudes, float)
    if a.size < criterion.min_cycles or not a[-1] > 0:
        return False
    tail = a[-criterion.span:] / a[-1]
    if np.max(np.abs(tail - 1.0)) > criterion.rtol:
        return False
    return bool(judge_amplitudes(a, criterion).stationary)


def stepped_sine_pseudo_force(model, structure, load: HarmonicLoad, frequency,
                              direction: str, *, tables: dict | None = None,
                              criterion: SteadyStateCriterion = DEFAULT_STEADY,
                              max_cycles: int = DEFAULT_MAX_CYCLES,
                              strokes: int = DEFAULT_STROKES) -> FRFCurve:
    """Stepped sine of a pseudo-force model (module docstring), in ``direction`` ``"up"``
    or ``"down"``; results in ascending frequency order.

    m_eff and d are held over each load cycle, taken at the damper point's first-harmonic
    amplitude of the previous cycle (interpolated in the damper's describing function at
    the frequency, :class:`DescribingFunction`). Over a cycle the modal state
    ``z = (q, q')`` then obeys ``z' = A z + Re(b e^{i W t})`` exactly: ``z(t) =
    Re(Z e^{i W t}) + e^{A t} (z_0 - Re Z)`` with ``Z = (i W - A)^-1 b``, and its first
    harmonic over the cycle is ``Z + (2 / T) (A - i W)^-1 (e^{A T} - 1)(z_0 - Re Z)``: no
    time step, no sampling. Cycles start at load phase 0, so the load's phase runs on
    continuously from one frequency to the next. A step is steady when
    :func:`steady_amplitudes` accepts the per-cycle amplitudes (the maps'
    :class:`~pdamper.analysis.stationarity.SteadyStateCriterion`, every cycle of the window
    within ``rtol`` of the last) and the transient left, ``z_0 - Re Z``, is below ``rtol``
    of the steady motion in the modal energy norm ``sqrt(sum w_i^2 q_i^2 + q_i'^2)``: on a
    lightly damped structure the beat of free and forced motion near resonance is slower
    than any window of cycles.
    """
    s = _modal(structure)
    n = s.modes
    freqs = np.atleast_1d(np.asarray(frequency, float))
    w = s.angular_frequencies
    phi, psi = s.damper_shape, s.output_shape
    at = s.load_shape if load.at_load_point else phi  # where the force acts
    c0 = np.diag(2.0 * s.damping_ratios * w)
    k0 = np.diag(w * w)
    # the matrix cycle's constants: modes, I_n, phi phi^T, K, C, the force's shape, I_2n, w
    mats = (n, np.eye(n), np.outer(phi, phi), k0, c0, at, np.eye(2 * n), w)
    z = np.zeros(2 * n)
    out = {k: np.full(freqs.size, np.nan) for k in ("amplitude", "phase", "stroke",
                                                    "loss_factor", "effective_mass")}
    mode = np.full(freqs.size, -1)
    steady = np.zeros(freqs.size, bool)
    cycles = np.zeros(freqs.size, int)
    spread = (np.full(freqs.size, np.nan), np.full(freqs.size, np.nan))
    deviation = np.full(freqs.size, np.nan)
    x_prev = 0.0
    for i in _sweep_order(freqs, direction):
        f = float(freqs[i])
        om = 2.0 * math.pi * f
        force = load_force(s, load, f)
        table = None if tables is None else tables.get(f)
        if table is None:
            lo, hi = stroke_bounds(s, load, model, f)
            table = describing_function(model, f, lo, hi, strokes, load.kind)
            if tables is not None:
                tables[f] = table
        amps: list[float] = []
        outs: list[float] = []  # the output point's amplitude per cycle
        held: dict = {}  # the cycle's state-free part per (m_eff, d) of this step
        xo_hat = xd_hat = 0j
        ok = False
        m = dm = eta = 0.0
        md = -1
        z_start, x_used = z, x_prev
        for _ in range(max_cycles):
            z_start, x_used = z, max(x_prev, table.stroke[0])
            m, dm, md, eta = table.at(x_used)
            z, hat, transient, forced = _matrix_cycle(mats, m, dm, force, om, f, z, held)
            xd_hat, xo_hat = complex(phi @ hat[:n]), complex(psi @ hat[:n])
            x_prev = abs(xd_hat)
            amps.append(x_prev)
            outs.append(abs(xo_hat))
            if transient <= criterion.rtol * forced and steady_amplitudes(amps, criterion):
                ok = True
                break
        cycles[i] = len(amps)
        steady[i] = ok
        spread[0][i], spread[1][i] = _scatter(outs[-SCATTER_WINDOWS:])
        out["amplitude"][i] = abs(xo_hat)
        out["phase"][i] = float(np.angle(xo_hat))  # against the reference signal
        out["stroke"][i] = abs(xd_hat)
        out["loss_factor"][i], out["effective_mass"][i], mode[i] = eta, m, md
        deviation[i] = _last_cycle_deviation(mats, phi, m, dm, force, om, z_start, x_used)
    return FRFCurve(amplitude=out["amplitude"], phase=out["phase"], stroke=out["stroke"],
                    loss_factor=out["loss_factor"], effective_mass=out["effective_mass"],
                    mode=mode, steady=steady, cycles=cycles, amplitude_mean=spread[0],
                    amplitude_std=spread[1],
                    diagnostics={"harmonic_deviation": deviation})


# --- the near-harmonic measure of a describing-function step ---------------------------
def _last_cycle_deviation(mats: tuple, phi: np.ndarray, m: float, dm: float, force: complex,
                          om: float, z0: np.ndarray, stroke: float) -> float:
    """The deviation of the damper point's motion over a step's last load cycle from the
    harmonic at the stroke its describing function was taken at
    (:func:`pdamper.coupling.harmonicity.cycle_deviation`), from that cycle's exact
    solution with m_eff ``m`` and ``d`` = ``dm`` held, starting from the state ``z0``
    (``phi``: the damper point's shape)."""
    from pdamper.coupling.harmonicity import cycle_deviation

    a, zp = _held_state_matrix(mats, m, dm, force, om)
    return cycle_deviation(a, zp, z0, phi, om, stroke)
# --- end of the near-harmonic measure ---------------------------------------------------


def _held_state_matrix(mats: tuple, m: float, dm: float, force: complex, om: float
                       ) -> tuple[np.ndarray, np.ndarray]:
    """The N-mode state matrix ``A`` with m_eff ``m`` and ``d`` = ``dm`` held at the damper
    point, and the steady state ``Z`` of ``z' = A z + b e^{i om t}`` under the load
    (:func:`stepped_sine_pseudo_force`'s exact solution)."""
    n, eye_n, pp, k0, c0, at, eye, _w = mats
    minv = np.linalg.inv(eye_n + m * pp)
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = eye_n
    a[n:, :n] = -minv @ k0
    a[n:, n:] = -minv @ (c0 + dm * pp)
    b = np.concatenate([np.zeros(n), minv @ at * force])
    return a, np.linalg.solve(1j * om * eye - a, b)


def _matrix_cycle(mats: tuple, m: float, dm: float, force: complex, om: float, f: float,
                  z: np.ndarray, held: dict | None = None
                  ) -> tuple[np.ndarray, np.ndarray, float, float]:
    """One load cycle of :func:`stepped_sine_pseudo_force` on N modes with m_eff ``m`` and
    ``d`` = ``dm`` held (its docstring's exact solution): the state after the cycle, the
    first harmonic of the state over it, and the transient's and the steady motion's
    energy norms.

    ``held`` keeps, per (m, d) of one frequency step, what does not depend on the state
    (the steady motion ``Z`` and its norm, the propagators): a step's cycles often return
    to an (m, d) already seen (a stroke outside the table's grid, an interpolation that
    settles), and the same inputs give the same numbers, bit for bit."""
    n, *_, eye, w = mats
    period = 1.0 / f
    fixed = None if held is None else held.get((m, dm))
    if fixed is None:
        a, zp = _held_state_matrix(mats, m, dm, force, om)
        forced = math.sqrt(float(np.sum(w * w * np.abs(zp[:n]) ** 2 + np.abs(zp[n:]) ** 2)))
        e, g = _propagators(a, period, om, eye)
        fixed = (zp, forced, e, g)
        if held is not None:
            held[(m, dm)] = fixed
    zp, forced, e, g = fixed
    h0 = z - zp.real
    # what is left of the transient: its energy norm against the steady motion's
    transient = math.sqrt(float(np.sum(w * w * h0[:n] ** 2 + h0[n:] ** 2)))
    hat = zp + (2.0 / period) * (g @ h0)
    z = zp.real + e @ h0
    if not np.all(np.isfinite(z)):
        raise SimulationError(f"the stepped sine diverged at {f:g} Hz")
    return z, hat, transient, forced


def _scatter(values: Sequence[float]) -> tuple[float, float]:
    """Mean and sample standard deviation of window amplitudes (NaN: too few)."""
    v = np.asarray(values, float)
    mean = float(np.mean(v)) if v.size else math.nan
    return mean, float(np.std(v, ddof=1)) if v.size > 1 else math.nan


def _propagators(a: np.ndarray, period: float, om: float, eye: np.ndarray):
    """``e^{A T}`` and ``(A - i W)^-1 (e^{A T} - 1)`` from the eigen-decomposition of A
    (a matrix exponential if A is defective: critical damping)."""
    lam, vec = np.linalg.eig(a)
    if np.linalg.cond(vec) < 1e10:
        vinv = np.linalg.inv(vec)
        ex = np.exp(lam * period)
        e = ((vec * ex) @ vinv).real
        g = (vec * ((ex - 1.0) / (lam - 1j * om))) @ vinv
        return e, g
    import scipy.linalg

    e = scipy.linalg.expm(a * period)
    return e, np.linalg.solve(a - 1j * om * eye, e - eye)


# ----------------------------------------------------------------------------- the DEM
def stepped_sine_co_simulation(model, structure, load: HarmonicLoad, frequency,
                               direction: str, *, criterion: SteadyStateCriterion | None = None,
                               max_cycles: int = 60, sample_rate_per_cycle: int = 64,
                               progress: Callable[[float, dict], None] | None = None,
                               **_) -> FRFCurve:
    """Stepped sine of the DEM (model 1): structure and particles integrated together
    with the load on the structure; each step continues from the previous step's particles
    and structure state, and runs until the container's per-cycle amplitude is steady or
    ``max_cycles`` load cycles have run. On N modes (or one mode whose points differ) the
    DEM runs on the modes (:mod:`pdamper.coupling.cosimulation`), the force at the load
    point; the output point's amplitude is read from the modal coordinates over the
    window judged."""
    from pdamper.dem import ModalStructureMotion, StructureMotion

    s = _modal(structure)
    # -- the DEM on N modes (its state: the modal coordinates); one coincident mode: 1-DOF
    modal = s.modes != 1 or not s.coincident
    q = qd = np.zeros(s.modes)
    e = None if modal else s.equivalent_single_dof()
    criterion = criterion or SteadyStateCriterion(rtol=0.02, atol=0.02, quiet_window_cycles=0,
                                                  window_cycles=3, skip_cycles=2)
    freqs = np.atleast_1d(np.asarray(frequency, float))
    out = {k: np.full(freqs.size, np.nan) for k in ("amplitude", "phase", "stroke",
                                                    "loss_factor", "effective_mass")}
    mode = np.full(freqs.size, -1)
    steady = np.zeros(freqs.size, bool)
    cycles = np.zeros(freqs.size, int)
    spread = (np.full(freqs.size, np.nan), np.full(freqs.size, np.nan))
    walls = np.zeros(freqs.size)
    steps = np.zeros(freqs.size)
    particles = None
    x0 = v0 = 0.0
    phase0 = 0.0
    for i in _sweep_order(freqs, direction):
        f = float(freqs[i])
        force = load_force(s, load, f)
        motion: StructureMotion
        if modal:
            motion = ModalStructureMotion.of(s, q, qd, force_amplitude=abs(force),
                                             force_frequency=f,
                                             force_phase=phase0 + float(np.angle(force)))
        else:
            assert e is not None
            motion = StructureMotion(mass=e.mass, damping=e.damping, stiffness=e.stiffness,
                                     x0=x0, v0=v0, force_amplitude=abs(force),
                                     force_frequency=f,
                                     force_phase=phase0 + float(np.angle(force)))
        if particles is None:
            engine = model.build_engine(motion)
            settle = True
        else:
            engine = model._engine(particles, motion)
            settle = False
        period = 1.0 / f
        t0 = time.perf_counter()
        stop = _steady_stop(period, f, criterion)
        res = engine.run(max_cycles * period, sample_rate=sample_rate_per_cycle * f,
                         settle=settle, stop=stop)
        walls[i] = time.perf_counter() - t0
        steps[i] = res.steps
        step = _co_simulation_step(res, model, f, phase0, criterion)
        # steady only where the stop rule ended the step: one that ran to the cap is not
        cycles[i], steady[i], mode[i] = step.cycles, step.steady and stop.fired, step.mode
        spread[0][i], spread[1][i] = step.window_mean, step.window_std
        out["amplitude"][i] = out["stroke"][i] = abs(step.hat)
        out["phase"][i] = float(np.angle(step.hat))  # against the reference signal
        if modal:  # the output point over the window judged, and the modes' state
            hat, mean_std = _modal_output(res, s, f, phase0, criterion)
            out["amplitude"][i], out["phase"][i] = abs(hat), float(np.angle(hat))
            spread[0][i], spread[1][i] = mean_std
            q, qd = res.modal_coordinates[:, -1].copy(), res.modal_velocities[:, -1].copy()
        out["loss_factor"][i], out["effective_mass"][i] = step.loss_factor, step.effective_mass
        # the next step starts where this one ended
        particles = _final_particles(engine, res)
        x0, v0 = float(res.container_position[-1]), float(res.container_velocity[-1])
        phase0 = step.phase_end
        if progress is not None:
            progress(f, {"cycles": step.cycles, "steady": bool(steady[i]),
                         "wall_seconds": walls[i]})
    return FRFCurve(amplitude=out["amplitude"], phase=out["phase"], stroke=out["stroke"],
                    loss_factor=out["loss_factor"], effective_mass=out["effective_mass"],
                    mode=mode, steady=steady, cycles=cycles, amplitude_mean=spread[0],
                    amplitude_std=spread[1],
                    diagnostics={"wall_seconds": walls, "steps": steps})


def _modal_output(res: Any, s: Any, f: float, phase0: float, criterion: SteadyStateCriterion
                  ) -> tuple[complex, tuple[float, float]]:
    """The output point's first harmonic (complex amplitude against the load's reference
    signal) over the whole cycles that :func:`_co_simulation_step` judges, and the scatter
    of its windows, from the modal coordinates of a DEM run on N modes."""
    om = 2.0 * math.pi * f
    period = 1.0 / f
    t = res.time
    k = int((t[-1] - t[0]) / period + 1e-9)
    verdict = judge_amplitudes(_cycle_amplitudes(t, res.container_position, f, k), criterion)
    last = max(1, min(k, verdict.last_cycle - verdict.first_cycle + 1 if
                      verdict.stationary else 3))
    x = s.output_shape @ res.modal_coordinates
    sel = (t >= t[0] + (k - last) * period - 1e-12) & (t <= t[0] + k * period + 1e-12)
    tt = t[sel]
    hat = 2.0 / (tt[-1] - tt[0]) * np.trapezoid(x[sel] * np.exp(-1j * (om * (tt - t[0])
                                                                        + phase0)), tt)
    return complex(hat), _scatter(_window_amplitudes(t, x, f, phase0, k, last))


class _SteadyStop:
    """The engine's stop rule of a co-simulation step at ``f`` [Hz]: the container's
    per-cycle amplitudes are steady (:func:`steady_amplitudes`). The engine asks it at the
    end of every whole load cycle before the cap; ``fired`` says whether it ended the step
    (a step that ran to the cap was never judged steady there)."""

    def __init__(self, period: float, f: float, criterion: SteadyStateCriterion) -> None:
        self.period, self.f, self.criterion = period, f, criterion
        self.fired = False

    def __call__(self, res: Any) -> bool:
        t = res.time
        k = int((t[-1] - t[0]) / self.period + 1e-9)
        if k < self.criterion.min_cycles:
            return False
        amps = _cycle_amplitudes(t, res.container_position, self.f, k)
        self.fired = steady_amplitudes(amps, self.criterion)
        return self.fired


def _steady_stop(period: float, f: float, criterion: SteadyStateCriterion) -> _SteadyStop:
    """The stop rule of a co-simulation step (:class:`_SteadyStop`)."""
    return _SteadyStop(period, f, criterion)


class _Step(NamedTuple):
    """What one co-simulation step at a frequency gave."""

    cycles: int            # whole load cycles run
    steady: bool           # per-cycle amplitudes steady (steady_amplitudes)
    hat: complex           # container's first harmonic over the last cycles [m]
    loss_factor: float     # eta over the same cycles (Eq. 3; NaN: too few samples)
    effective_mass: float  # m_eff over the same cycles [kg] (Eq. 4; NaN: too few samples)
    mode: int              # motion-mode code (-1: none)
    phase_end: float       # load phase at the run's end, in [0, 2 pi) [rad]
    window_mean: float = math.nan  # amplitude over the last windows: mean [m]
    window_std: float = math.nan   # and sample standard deviation [m] (NaN: one window)


def _co_simulation_step(res: Any, model: Any, f: float, phase0: float,
                        criterion: SteadyStateCriterion) -> _Step:
    """The verdict and the response of the run ``res`` of a step at ``f`` [Hz] whose load
    started at phase ``phase0`` [rad], over its last whole cycles (the window judged)."""
    from pdamper.analysis.complex_power import complex_power

    om = 2.0 * math.pi * f
    period = 1.0 / f
    t = res.time
    k = int((t[-1] - t[0]) / period + 1e-9)
    amps = _cycle_amplitudes(t, res.container_position, f, k)
    verdict = judge_amplitudes(amps, criterion)
    # the last whole cycles (the window judged) for the amplitudes and the damper
    last = max(1, min(k, verdict.last_cycle - verdict.first_cycle + 1 if
                      verdict.stationary else 3))
    sel = t >= t[0] + (k - last) * period - 1e-12
    sel &= t <= t[0] + k * period + 1e-12
    tt = t[sel]
    th = om * (tt - t[0]) + phase0  # load phase at the samples
    x = res.container_position[sel]
    hat = 2.0 / (tt[-1] - tt[0]) * np.trapezoid(x * np.exp(-1j * th), tt)
    eta = m_eff = math.nan
    try:  # Eqs. (1)-(4) over the same cycles, the particles' force on the container
        cp = complex_power(tt, -res.force[sel, 2], res.container_velocity[sel],
                           res.container_acceleration[sel], f, model.bed_mass)
        eta, m_eff = cp.loss_factor, cp.effective_mass
    except InputError:  # too few samples: left NaN
        pass
    mean, std = _scatter(_window_amplitudes(t, res.container_position, f, phase0, k, last))
    return _Step(k, steady_amplitudes(amps, criterion), hat, eta, m_eff,
                 _dem_mode(res, f, k, last),
                 float(th[-1] + om * (t[-1] - tt[-1])) % (2 * math.pi), mean, std)


def _window_amplitudes(t: np.ndarray, x: np.ndarray, f: float, phase0: float, k: int,
                       last: int) -> list[float]:
    """First-harmonic amplitude of ``x`` over each of the last :data:`SCATTER_WINDOWS`
    windows of ``last`` whole cycles (at least 3) ending at cycle ``k``, latest first."""
    om = 2.0 * math.pi * f
    width = max(3, last)
    out = []
    for w in range(SCATTER_WINDOWS):
        end = k - w * width
        start = end - width
        if start < 0:
            break
        sel = (t >= t[0] + start / f - 1e-12) & (t <= t[0] + end / f + 1e-12)
        if np.count_nonzero(sel) < 3:
            break
        tt = t[sel]
        th = om * (tt - t[0]) + phase0
        out.append(abs(2.0 / (tt[-1] - tt[0]) * np.trapezoid(x[sel] * np.exp(-1j * th), tt)))
    return out


def _dem_mode(res, f: float, cycles: int, last: int) -> int:
    """Motion-mode code of the bed over the last ``last`` of ``cycles`` load cycles (the
    DEM classifier of the maps, :mod:`pdamper.analysis.dem_modes`); -1 if it cannot say."""
    from pdamper.analysis.dem_modes import BedSignals, classify_motion
    from pdamper.constants import STANDARD_GRAVITY

    box = res.attrs.get("box_m")
    if box is None or cycles < 1:
        return -1
    try:
        sig = BedSignals(time=np.asarray(res.time),
                         height=np.asarray(res.center_of_mass[:, 2] - res.container_position),
                         force_z=np.asarray(res.force[:, 2]), frequency=f,
                         bed_mass=float(res.bed_mass), particle_radius=float(np.max(res.radius)),
                         container_height=float(box[2]),
                         gravity=float(res.attrs.get("gravity_m_s2", STANDARD_GRAVITY)))
        return int(classify_motion(sig, cycles - last + 1, cycles).mode)
    except InputError:
        return -1


def _cycle_amplitudes(t: np.ndarray, x: np.ndarray, f: float, k: int) -> list[float]:
    """First-harmonic amplitude of ``x`` over each of the ``k`` whole cycles of ``t``."""
    om = 2.0 * math.pi * f
    out = []
    for c in range(k):
        sel = (t >= t[0] + c / f - 1e-12) & (t <= t[0] + (c + 1) / f + 1e-12)
        if np.count_nonzero(sel) < 3:
            continue
        tt = t[sel]
        out.append(abs(2.0 * f * np.trapezoid(x[sel] * np.exp(-1j * om * tt), tt)))
    return out


def _final_particles(engine, res):
    """The spheres where ``res`` ended, in the container frame (the next step's start)."""
    from pdamper.dem.inputs import ParticleSet

    p = engine.particles
    pos = np.array(res.snapshot_positions[-1], float)
    pos[:, 2] -= float(res.container_position[-1])
    return ParticleSet(pos, p.radius, p.material, velocities=np.array(res.snapshot_velocities[-1]),
                       angular_velocities=np.array(res.snapshot_angular_velocities[-1]))


# ----------------------------------------------------------------------------- validity
def _with_assumptions(model, frequency: np.ndarray, curve: FRFCurve | None) -> FRFCurve | None:
    """``curve`` with ``assumptions_hold`` (bool) and ``assumptions`` (the reasons, ""
    where they hold) in its ``diagnostics``: the model's own check
    (:func:`~pdamper.analysis.analytical.assumption_checks`) at the stroke of each answer
    found. Models that report no such check (``reports_assumptions``), a damper without
    particles and padding (no stroke) are left as they are (they hold)."""
    if curve is None or not getattr(model, "reports_assumptions", False) \
            or model.damper.count == 0:
        return curve
    x = np.asarray(curve.stroke, float)
    f = np.broadcast_to(frequency.reshape((-1,) + (1,) * (x.ndim - 1)), x.shape)
    ok = np.isfinite(x) & (x > 0)
    hold = np.ones(x.shape, bool)
    why = np.full(x.shape, "", dtype=object)
    if ok.any():
        diag = model.response(f[ok], x[ok]).diagnostics
        hold[ok] = np.asarray(diag["assumptions_hold"], bool)
        why[ok] = np.asarray(diag["assumptions"], object)
    return dataclasses.replace(curve, diagnostics={**curve.diagnostics,
                                                   "assumptions_hold": hold,
                                                   "assumptions": why})


def assumption_record(res: FRFResult) -> dict | None:
    """Whether the answers of ``res`` rest on the damper model's assumptions: the
    :func:`~pdamper.analysis.analytical.assumption_summary` over every answer found (the
    stepped sines' points and the harmonic balance's solutions), the answers and flagged
    ones per source (``by_source``) and the frequencies with a flagged answer
    (``frequencies`` [Hz]); None where the model reports no such check."""
    from pdamper.analysis.analytical import assumption_summary

    curves = dict(res.sweeps)
    if res.harmonic_balance is not None:
        curves["harmonic_balance"] = res.harmonic_balance
    holds: list[np.ndarray] = []
    whys: list[np.ndarray] = []
    by_source: dict[str, dict] = {}
    flagged_f: set[float] = set()
    for name, c in curves.items():
        if "assumptions_hold" not in c.diagnostics:
            continue
        found = np.isfinite(np.asarray(c.stroke, float))
        if c.branch is not None:
            found &= c.branch != ""
        h = np.asarray(c.diagnostics["assumptions_hold"], bool)
        holds.append(h[found])
        whys.append(np.asarray(c.diagnostics["assumptions"], object)[found])
        by_source[name] = {"points": int(found.sum()), "flagged": int((found & ~h).sum())}
        rows = (found & ~h) if h.ndim == 1 else (found & ~h).any(axis=1)
        flagged_f.update(float(v) for v in res.frequency[rows])
    if not holds:
        return None
    out = assumption_summary(np.concatenate(holds), np.concatenate(whys))
    out["by_source"] = by_source
    out["frequencies"] = sorted(flagged_f)
    return out


# ----------------------------------------------------------------------------- driver
#: Stepped-sine strategies by the model's coupling name (a view of the coupling table,
#: :data:`pdamper.coupling.registry.COUPLINGS`).
STEPPED_SINES = CouplingView(lambda c: c.stepped_sine, lambda c: c.runs(HARMONIC_SWEEP))
#: Couplings whose damper has a describing function cheap enough for harmonic balance.
HARMONIC_BALANCE = CouplingView(lambda c: c.name, lambda c: c.harmonic_balance)


def sweep_strategy(model):
    """The coupling strategy (:class:`~pdamper.coupling.registry.Coupling`) that runs the
    stepped sines of ``model``; InputError (field ``model``) where its coupling has none."""
    return coupling_of(model, HARMONIC_SWEEP, missing=lambda m: (
        f"coupling {m.coupling!r} of {type(m).__name__} has no stepped sine; available: "
        f"{', '.join(STEPPED_SINES)}"))


def frequency_response(model, structure, load: HarmonicLoad, frequency, *,
                       sweep: str = "both", with_harmonic_balance: bool = True,
                       strokes: int = DEFAULT_STROKES, max_cycles: int | None = None,
                       criterion: SteadyStateCriterion | None = None,
                       progress: Callable | None = None) -> FRFResult:
    """The forced response of ``structure`` carrying ``model`` under ``load`` at
    ``frequency`` [Hz] (module docstring): the linear FRF, harmonic balance (where the
    model's coupling has one) and the stepped sines of ``sweep`` (``"up"``, ``"down"``,
    ``"both"`` or ``"none"``).

    Parameters
    ----------
    model
        Any :class:`~pdamper.models.DamperModel`; its coupling's strategy
        (:data:`pdamper.coupling.registry.COUPLINGS`) runs the stepped sine and says
        whether harmonic balance runs.
    structure
        :class:`~pdamper.structure.SingleDOFStructure` or
        :class:`~pdamper.structure.modal.ModalStructure`.
    load
        The :class:`HarmonicLoad`.
    with_harmonic_balance
        Solve harmonic balance too (default).
    strokes
        Strokes of the describing-function table per frequency.
    max_cycles, criterion
        Most load cycles per step and the steady-state criterion of the stepped sine
        (defaults: :data:`DEFAULT_MAX_CYCLES`, :data:`DEFAULT_STEADY`; the DEM 60 cycles
        and 2 %).
    progress
        ``progress(frequency, info)`` after each DEM step.

    Examples
    --------
    >>> from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
    >>> from pdamper.models import AnalyticalDamper
    >>> r = frequency_response(AnalyticalDamper(PAPER_DAMPER.with_count(0)), PAPER_STRUCTURE,
    ...                        HarmonicLoad("force", 2.0), [5.0], sweep="none")
    >>> bool(np.isclose(r.harmonic_balance.amplitude[0, 0], abs(r.linear[0]), rtol=1e-9))
    True
    """
    from pdamper.models.base import DamperModel

    if not isinstance(model, DamperModel):
        raise InputError("model", "must be a DamperModel (e.g. AnalyticalDamper(damper)), "
                         f"got {type(model).__name__}")
    if not isinstance(load, HarmonicLoad):
        raise InputError("load", f"must be a HarmonicLoad, got {type(load).__name__}")
    check_damped(structure)
    s = _modal(structure)
    f = np.atleast_1d(np.asarray(frequency, float))
    if f.ndim != 1 or f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise InputError("frequency", "must be one or more finite frequencies > 0 Hz")
    f = np.unique(f)
    if f.size > MAX_FREQUENCIES:
        raise InputError("frequency", f"at most {MAX_FREQUENCIES} frequencies, got {f.size}")
    if sweep not in (*SWEEPS, "none"):
        raise InputError("sweep", f"must be up, down or both, got {sweep!r}")
    strategy = sweep_strategy(model)
    load_force(s, load, float(f[0]))  # a base motion on N modes is refused before any run
    lin = linear_frf(s, load, f)
    tables: dict = {}
    walls: dict = {}
    hb = None
    if with_harmonic_balance and strategy.harmonic_balance:
        t0 = time.perf_counter()
        hb = harmonic_balance(model, s, load, f, strokes=strokes, tables=tables)
        walls["harmonic_balance"] = time.perf_counter() - t0
    directions = {"both": ("up", "down"), "none": ()}.get(sweep, (sweep,))
    sweeps = {}
    options: dict[str, Any] = {}
    if max_cycles is not None:
        options["max_cycles"] = max_cycles
    if criterion is not None:
        options["criterion"] = criterion
    if strategy.harmonic_balance:
        options.update(tables=tables, strokes=strokes)
    elif progress is not None:
        options["progress"] = progress
    for d in directions:
        t0 = time.perf_counter()
        sweeps[d] = _with_assumptions(model, f, strategy.stepped_sine(
            model, s, load, f, d, **options))
        walls[d] = time.perf_counter() - t0
    hb = _with_assumptions(model, f, hb)
    return FRFResult(frequency=f, load=load, linear=lin, harmonic_balance=hb, sweeps=sweeps,
                     model=model.fidelity, wall_seconds=walls,
                     inputs={"frequency": f.tolist(), "sweep": sweep, "load": load.as_dict(),
                             "load_point": (load_point_text(structure) if load.at_load_point
                                            else "the base"),
                             "modes": s.modes, "strokes": strokes,
                             "particles": model.damper.count})
