"""A structure carrying a damper under a load history: a force on the structure or an
acceleration of its base (shocks, random records, measured operating loads).

The load is a sampled record (:class:`LoadHistory`, read by :func:`pdamper.io.loads.read_load`),
**linear between its samples** and zero after its last sample (the optional free tail).

Equations (pseudo-force coupling, Sect. 4.1 models 2 and 3). The damper acts at its point as
``F_d = -(m_eff a_c + d v_c)`` on the container's *absolute* motion (``a_c``, ``v_c``), with
m_eff and ``d = E~ / (pi W X^2)`` updated at each minimum of the container's displacement from
the swing of the last half cycle (``X`` = half the drop from the preceding maximum) and the
frequency of the last cycle (``1 / (t_min,k - t_min,k-1)``; the first cycle: half over the
duration of the first drop). Until the container completes its first drop (a structure at
rest at the start of the record) the bed, resting on the floor, moves with the container as
a rigid mass (``m_eff = m_bed``, ``d = 0``). Between updates the equations
are linear. For the 1-DOF of Eq. (23), in the coordinate x of the end-effector,

    force:  (M + m_eff) x'' + (D + d) x' + K x = F(t)
    base:   (M + m_eff) z'' + (D + d) z' + K z = -(M + m_eff) a_b(t) - d v_b(t)

with ``z = x - y_b`` the motion relative to the base and ``v_b`` the base velocity
(the record integrated from rest by the trapezoidal rule, its mean over the run removed: a
steady drift of the whole set-up carries no damper force). For N modes (mass-normalised,
:class:`~pdamper.structure.modal.ModalStructure`) the same with ``I``, ``diag(2 zeta w)``,
``diag(w^2)``, m_eff and d acting through the damper's mode shape ``phi_d``; the force acts
at the structure's load point (the modes file's ``load`` column, the beam's
``load_position``; default the release point, which defaults to the damper point). Base
motion (a translation of the base or clamp) loads mode i with ``-Gamma_i a_b``, its
participation factor ``Gamma_i = phi_i^T M r``: the beam's come from its FE model; a modes
file does not carry them, so it takes base motion with one mode only (``Gamma = 1 /
phi_d``, all the mass at the damper point, as the 1-DOF).

Each stretch between two updates is integrated exactly for an input linear between steps
(first-order hold: the state-transition matrices from one matrix exponential, Van Loan
1978), on the output grid ``1 / sample_rate``, refined by a whole factor where the record is
sampled finer (its median interval). An update acts from the step after the minimum that
triggers it (at most one step late).

The DEM (the ``co_simulation`` coupling, model 1) integrates the structure with the
particles under the same load: :func:`pdamper.coupling.cosimulation.co_simulate_load`.

Reported: the displacement of the output point (relative to the base for base motion), its
absolute acceleration, their peak (largest magnitude) and RMS over the run, the energy the
damper dissipates ``E_d = int d v_c^2 dt`` (the m_eff term is stored kinetic energy, nil at
the updates where v_c = 0), and for a force the input work and the structure's energy
balance (``E_d = W_in - Delta E - E_struct``, :attr:`LoadResponse.energy_balance_error`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from pdamper.coupling.pseudo_force import motion_mode, pseudo_force_coefficients
from pdamper.coupling.registry import (
    LOAD_HISTORY,
    MODES,
    CouplingView,
    coupling_of,
    has_load_cost,
)
from pdamper.coupling.results import CycleUpdate
from pdamper.errors import InputError, check_range

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

    from pdamper.models.base import DamperModel

#: Kinds of load history and the SI unit of their values.
LOAD_KINDS = {"force": "N", "base_acceleration": "m/s^2"}
#: Most memory [bytes] of the state history one run holds (every integration step).
MAX_BYTES = 2e9
#: Swings below this [m] do not update the damper (numerical rest, as in the free decay).
_REST = 1e-12


@dataclass(frozen=True)
class LoadHistory:
    """A sampled load, linear between samples, zero after the last.

    Parameters
    ----------
    time
        Sample times [s], strictly increasing; the run starts at ``time[0]`` (reported
        times count from there).
    values
        The force on the structure [N] or the base acceleration [m/s^2] at each sample.
    kind
        ``"force"`` or ``"base_acceleration"``.
    source
        Where it came from (a file name), for the record.

    Examples
    --------
    >>> h = LoadHistory([0.0, 1.0], [0.0, 2.0], "force")
    >>> float(h.at(0.25)), h.duration
    (0.5, 1.0)
    """

    time: np.ndarray
    values: np.ndarray
    kind: str = "force"
    source: str = ""

    def __post_init__(self) -> None:
        field_ = "load" if self.kind == "force" else "base_acceleration"
        if self.kind not in LOAD_KINDS:
            raise InputError("load", f"kind must be one of {', '.join(LOAD_KINDS)}, got "
                             f"{self.kind!r}")
        t = np.asarray(self.time, float).ravel()
        v = np.asarray(self.values, float).ravel()
        if t.size < 2 or t.size != v.size:
            raise InputError(field_, "needs at least 2 samples, as many times as values")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise InputError(field_, "times and values must be finite numbers")
        if np.any(np.diff(t) <= 0):
            raise InputError(field_, "time must increase from sample to sample")
        object.__setattr__(self, "time", t)
        object.__setattr__(self, "values", v)

    @property
    def duration(self) -> float:
        """Length of the record [s]."""
        return float(self.time[-1] - self.time[0])

    @property
    def unit(self) -> str:
        return LOAD_KINDS[self.kind]

    def at(self, t: float | np.ndarray) -> np.ndarray:
        """The load at ``t`` [s from the record's start]: linear between samples, 0 after
        the record."""
        t = np.asarray(t, float)
        return np.interp(t, self.time - self.time[0], self.values, left=0.0, right=0.0)

    @classmethod
    def harmonic(cls, amplitude: float, frequency: float, duration: float,
                 samples_per_period: int = 200, kind: str = "force") -> LoadHistory:
        """``amplitude sin(2 pi f t)`` sampled ``samples_per_period`` times a period."""
        n = int(math.ceil(duration * frequency * samples_per_period)) + 1
        t = np.linspace(0.0, duration, n)
        return cls(t, amplitude * np.sin(2.0 * math.pi * frequency * t), kind,
                   f"{amplitude:g} {LOAD_KINDS[kind]} sin(2 pi {frequency:g} Hz t)")


#: Where a force on the structure acts: its load point, or the damper's point.
LOAD_POINTS = ("load", "damper")


def acting_at(structure: Any, at: str = "load", field: str = "load.at") -> Any:
    """``structure`` with its forces acting at ``at``: ``"load"``, the structure's load
    point (itself), or ``"damper"``, the damper's point (a
    :class:`~pdamper.structure.modal.ModalStructure` whose load shape is its damper's; a
    1-DOF's force acts there anyway)."""
    if at not in LOAD_POINTS:
        raise InputError(field, f"must be one of {', '.join(LOAD_POINTS)}, got {at!r}")
    from pdamper.structure.modal import ModalStructure

    if at == "damper" and isinstance(structure, ModalStructure):
        import dataclasses

        return dataclasses.replace(structure, load_shape=structure.damper_shape)
    return structure


#: Samples per load period of a run-up's record at its highest speed: a sine linear
#: between 200 samples a period is within 1.2e-4 of its peak (``1 - cos(pi / 200)``).
RUN_UP_SAMPLES_PER_PERIOD = 200


@dataclass(frozen=True)
class RunUp:
    """A rotating unbalance ``m e`` on a machine whose speed runs linearly from ``start`` to
    ``stop`` over ``duration`` (a run-up, or a run-down where ``stop < start``; a constant
    speed where they are equal).

    The speed in revolutions per second is ``n(t) = start + (stop - start) t / T``, the
    angle of the unbalance ``phi(t) = 2 pi int_0^t n dt'`` (integrated from the ramp, so that
    a ramp is not a sequence of steady tones) and ``Omega = 2 pi n`` its angular speed. The
    vertical force of the unbalanced mass on the structure is the reaction to its
    acceleration, ``F(t) = m e (Omega^2 sin phi - Omega' cos phi)``: amplitude
    ``m e Omega^2`` at the instants where ``phi = pi/2 (mod 2 pi)``, the tangential term
    ``Omega' = 2 pi (stop - start) / T`` being small against it on any usual ramp. It
    acts at the structure's load point.

    Parameters
    ----------
    unbalance
        ``m e`` [kg m].
    start, stop
        Speeds at the ramp's start and end [Hz, revolutions per second; ``rpm`` at the
        edges], >= 0, not both 0.
    duration
        Length of the ramp T [s] (the record; after it the load is zero).

    Examples
    --------
    >>> r = RunUp(1.76e-3, 400 / 60, 2400 / 60, 20.0)
    >>> round(float(r.speed(10.0)) * 60)          # rpm half-way
    1400
    >>> t = r.instants_of_peak()[5]
    >>> bool(np.isclose(r.force(t), 1.76e-3 * (2 * np.pi * r.speed(t)) ** 2, rtol=1e-12))
    True
    """

    unbalance: float
    start: float
    stop: float
    duration: float

    def __post_init__(self) -> None:
        check_range("load.unbalance", self.unbalance, low=0.0, low_inclusive=False,
                    unit="kg*m")
        for name in ("start", "stop"):
            check_range("load.run_up", getattr(self, name), low=0.0, unit="Hz")
        if not max(self.start, self.stop) > 0:
            raise InputError("load.run_up", "the speed must be above 0 at one end of the ramp")
        check_range("load.run_up", self.duration, low=0.0, low_inclusive=False, unit="s")
        for name in ("unbalance", "start", "stop", "duration"):
            object.__setattr__(self, name, float(getattr(self, name)))

    @classmethod
    def parse(cls, unbalance: str | float, ramp: str, field: str = "load.run_up") -> RunUp:
        """From the text of an unbalance (``"1.76 kg*mm"``) and of a ramp
        ``"start:stop:duration"`` (``"400rpm:2400rpm:20s"``; speeds in any frequency unit,
        ``rpm`` included).

        >>> RunUp.parse("1.76kg*mm", "400rpm:2400rpm:20s").stop
        40.0
        """
        from pdamper.units import parse_quantity

        me = parse_quantity(unbalance, "kg*m", "load.unbalance")
        parts = str(ramp).split(":")
        if len(parts) != 3 or not all(p.strip() for p in parts):
            raise InputError(field, f"must be 'start:stop:duration', e.g. "
                             f"'400rpm:2400rpm:20s', got {ramp!r}")
        a, b = (parse_quantity(p, "Hz", field) for p in parts[:2])
        t = parse_quantity(parts[2], "s", field)
        try:
            return cls(me, a, b, t)
        except InputError as exc:
            raise InputError(exc.field if exc.field == "load.unbalance" else field,
                             exc.message) from None

    @property
    def acceleration(self) -> float:
        """``Omega'`` [rad/s^2]."""
        return 2.0 * math.pi * (self.stop - self.start) / self.duration

    def speed(self, t: float | np.ndarray) -> np.ndarray:
        """``n(t)`` [Hz, revolutions per second] over the ramp (held at ``stop`` after it)."""
        tt = np.clip(np.asarray(t, float), 0.0, self.duration)
        return self.start + (self.stop - self.start) * tt / self.duration

    def angle(self, t: float | np.ndarray) -> np.ndarray:
        """``phi(t) = 2 pi (start t + (stop - start) t^2 / (2 T))`` [rad] over the ramp."""
        tt = np.asarray(t, float)
        return 2.0 * math.pi * (self.start * tt + 0.5 * (self.stop - self.start) * tt * tt
                                / self.duration)

    def force(self, t: float | np.ndarray) -> np.ndarray:
        """``F(t) = m e (Omega^2 sin phi - Omega' cos phi)`` [N] over the ramp, 0 after."""
        tt = np.asarray(t, float)
        om = 2.0 * math.pi * self.speed(tt)
        ph = self.angle(tt)
        f = self.unbalance * (om * om * np.sin(ph) - self.acceleration * np.cos(ph))
        return np.where((tt >= 0.0) & (tt <= self.duration), f, 0.0)

    def instants_of_peak(self) -> np.ndarray:
        """The instants [s] where ``phi = pi/2 (mod 2 pi)``, where ``F = m e Omega^2``."""
        turns = self.angle(self.duration) / (2.0 * math.pi)
        k = np.arange(0, math.floor(turns - 0.25) + 1)
        target = 2.0 * math.pi * (k + 0.25)  # phi(t) = target: a quadratic in t
        a = math.pi * (self.stop - self.start) / self.duration
        b = 2.0 * math.pi * self.start
        if a == 0.0:
            return target / b
        return (-b + np.sqrt(b * b + 4.0 * a * target)) / (2.0 * a)

    def history(self, samples_per_period: int = RUN_UP_SAMPLES_PER_PERIOD) -> LoadHistory:
        """The force as a :class:`LoadHistory` sampled ``samples_per_period`` times per
        period at the highest speed (linear between samples: :data:`RUN_UP_SAMPLES_PER_PERIOD`
        keeps the peaks within 1.2e-4)."""
        top = max(self.start, self.stop)
        n = int(math.ceil(self.duration * top * samples_per_period)) + 1
        if n > 5e7:
            raise InputError("load.run_up", f"the ramp needs {n:.3g} samples "
                             f"({samples_per_period} per period at {top:g} Hz over "
                             f"{self.duration:g} s), more than 5e7: shorten it")
        t = np.linspace(0.0, self.duration, max(n, 2))
        return LoadHistory(t, self.force(t), "force", self.describe())

    def describe(self) -> str:
        """The load in words (``"unbalance 1.76 kg mm, run-up 400-2400 rpm in 20 s"``)."""
        way = "run-up" if self.stop > self.start else ("run-down" if self.stop < self.start
                                                        else "constant speed")
        return (f"unbalance {self.unbalance * 1e3:.4g} kg mm, {way} {self.start * 60:.5g}-"
                f"{self.stop * 60:.5g} rpm in {self.duration:g} s")

    def as_dict(self) -> dict:
        return {"kind": "unbalance", "unbalance": self.unbalance, "start_speed": self.start,
                "stop_speed": self.stop, "duration": self.duration,
                "units": {"unbalance": "kg*m", "start_speed": "Hz", "stop_speed": "Hz",
                          "duration": "s"}}


@dataclass(frozen=True)
class LoadResponse:
    """Response of the structure to a load history.

    Attributes
    ----------
    time
        Sample times from the record's start [s].
    displacement
        Output point [m]; relative to the base under base motion.
    acceleration
        Output point, absolute [m/s^2].
    load
        The load at the sample times [N or m/s^2].
    damper_displacement
        The container's displacement ``phi_d . q`` [m]; under base motion plus the base's
        displacement integrated from the record (its mean velocity removed).
    dissipated_energy
        Energy dissipated by the damper over the run, ``int d v_c^2 dt`` [J].
    input_work, structural_dissipation, energy_change
        For a force: the work of the load, the energy dissipated by the structure's own
        damping, the change of the structure's (and the particles' effective) kinetic and
        potential energy [J]; NaN under base motion.
    cycles
        The damper updates.
    model, kind, inputs
        Fidelity, load kind, the run's inputs.
    """

    time: np.ndarray
    displacement: np.ndarray
    acceleration: np.ndarray
    load: np.ndarray
    damper_displacement: np.ndarray
    dissipated_energy: float
    input_work: float
    structural_dissipation: float
    energy_change: float
    cycles: tuple[CycleUpdate, ...] = ()
    model: str = ""
    kind: str = "force"
    inputs: dict = field(default_factory=dict)
    details: Any = field(default=None, repr=False, compare=False)

    @property
    def peak(self) -> float:
        """Largest |displacement| of the output point [m]."""
        return float(np.max(np.abs(self.displacement)))

    @property
    def rms(self) -> float:
        """RMS displacement of the output point over the run (trapezoidal mean) [m]."""
        return _rms(self.time, self.displacement)

    @property
    def peak_acceleration(self) -> float:
        """Largest |acceleration| of the output point [m/s^2]."""
        return float(np.max(np.abs(self.acceleration)))

    @property
    def rms_acceleration(self) -> float:
        """RMS absolute acceleration of the output point [m/s^2]."""
        return _rms(self.time, self.acceleration)

    @property
    def energy_balance_error(self) -> float:
        """``(W_in - Delta E - E_struct - E_d) / W_in`` [-] (force only; NaN otherwise)."""
        if not math.isfinite(self.input_work) or self.input_work == 0.0:
            return math.nan
        return (self.input_work - self.energy_change - self.structural_dissipation
                - self.dissipated_energy) / self.input_work

    def window(self, start: float) -> tuple[float, float]:
        """(peak, RMS) of the displacement from ``start`` [s] on (e.g. the steady part)."""
        sel = self.time >= start
        return float(np.max(np.abs(self.displacement[sel]))), _rms(self.time[sel],
                                                                   self.displacement[sel])

    def not_applicable(self) -> dict[str, str]:
        """Why the energy terms that are not numbers are not applicable to this run."""
        if self.kind != "force":
            why = ("under base motion the load is the base's motion, whose work divides "
                   "between the structure and the damper's container (which moves with the "
                   "base); the energy balance is reported for a force")
            return dict.fromkeys(("input_work", "structural_dissipation", "energy_change",
                                  "energy_balance_error"), why)
        if not self.input_work != 0.0:
            return {"energy_balance_error": "the load did no work on the structure "
                                            "(input_work = 0): its relative error is undefined"}
        return {}

    def summary(self) -> dict:
        """Scalars of the run (SI units); the energy terms that do not apply are null, with
        the reason under ``not_applicable``."""
        from pdamper.coupling.results import with_reasons

        return with_reasons(
            {"peak": self.peak, "rms": self.rms, "peak_acceleration": self.peak_acceleration,
             "rms_acceleration": self.rms_acceleration,
             "dissipated_energy": self.dissipated_energy, "input_work": self.input_work,
             "structural_dissipation": self.structural_dissipation,
             "energy_change": self.energy_change,
             "energy_balance_error": self.energy_balance_error}, self.not_applicable())

    def to_dataset(self) -> xr.Dataset:
        """The response history as an :class:`xarray.Dataset` with units."""
        import xarray as xr

        return xr.Dataset(
            {
                "displacement": ("time", self.displacement,
                                 {"long_name": "output-point displacement"
                                  + (" relative to the base" if self.kind != "force" else ""),
                                  "units": "m"}),
                "acceleration": ("time", self.acceleration,
                                 {"long_name": "output-point absolute acceleration",
                                  "units": "m/s^2"}),
                "load": ("time", self.load, {"long_name": self.kind.replace("_", " "),
                                             "units": LOAD_KINDS[self.kind]}),
                "damper_displacement": ("time", self.damper_displacement,
                                        {"long_name": "container displacement",
                                         "units": "m"}),
            },
            coords={"time": ("time", self.time, {"units": "s"})},
            attrs={"model": self.model, "load_kind": self.kind,
                   "peak": self.peak, "rms": self.rms,
                   "dissipated_energy": self.dissipated_energy},
        )


def _rms(t: np.ndarray, x: np.ndarray) -> float:
    if t.size < 2 or t[-1] == t[0]:
        return float(np.sqrt(np.mean(x * x)))
    return float(math.sqrt(np.trapezoid(x * x, t) / (t[-1] - t[0])))


@dataclass(frozen=True)
class _System:
    """``Mq q'' + Cq q' + Kq q = b F - g a_b`` with the damper at ``phi``; ``out`` the
    output point's shape."""

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    phi: np.ndarray
    out: np.ndarray
    load_shape: np.ndarray
    base_shape: np.ndarray | None
    structure: Any

    @classmethod
    def of(cls, structure: Any) -> _System:
        from pdamper.structure import SingleDOFStructure
        from pdamper.structure.modal import ModalStructure

        if isinstance(structure, ModalStructure) and structure.modes == 1 \
                and structure.coincident and structure.participation is None:
            structure = structure.equivalent_single_dof()  # Eq. (23), as Simulation does
        if isinstance(structure, SingleDOFStructure):
            one = np.ones(1)
            return cls(np.array([[structure.mass]]), np.array([[structure.damping]]),
                       np.array([[structure.stiffness]]), one, one, one,
                       np.array([structure.mass]), structure)
        if isinstance(structure, ModalStructure):
            w = structure.angular_frequencies
            base = structure.participation
            if base is None and structure.modes == 1:  # all the mass at the damper point
                base = 1.0 / structure.damper_shape
            out, at = structure.output_shape, structure.load_shape
            assert out is not None and at is not None  # (filled in by __post_init__)
            return cls(np.eye(structure.modes), np.diag(2.0 * structure.damping_ratios * w),
                       np.diag(w * w), structure.damper_shape, out, at, base, structure)
        raise InputError("structure", "must be a SingleDOFStructure or a ModalStructure, got "
                         f"{type(structure).__name__}")

    def matrices(self, m_eff: float, d: float, kind: str) -> tuple[np.ndarray, np.ndarray]:
        """State matrix A (2N x 2N) and input matrix B (2N x 3) for u = (F, a_b, v_b)."""
        n = self.phi.size
        pp = np.outer(self.phi, self.phi)
        mt = self.mass + m_eff * pp
        ct = self.damping + d * pp
        minv = np.linalg.inv(mt)
        a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ self.stiffness, -minv @ ct]])
        cols = np.zeros((n, 3))
        if kind == "force":
            cols[:, 0] = self.load_shape
        else:
            assert self.base_shape is not None  # (simulate_load checked it)
            cols[:, 1] = -(self.base_shape + m_eff * self.phi)
            cols[:, 2] = -d * self.phi
        b = np.vstack([np.zeros((n, 3)), minv @ cols])
        return a, b


def _hold(a: np.ndarray, b: np.ndarray, h: float
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact step of ``z' = A z + B u`` for u linear over the step h (first-order hold):
    ``z1 = P z0 + G0 u0 + G1 (u1 - u0)`` from one matrix exponential (Van Loan)."""
    import scipy.linalg

    n, m = b.shape
    e = np.zeros((n + 2 * m, n + 2 * m))
    e[:n, :n] = a * h
    e[:n, n:n + m] = b * h
    e[n:n + m, n + m:] = np.eye(m)
    x = scipy.linalg.expm(e)
    return (np.ascontiguousarray(x[:n, :n]), np.ascontiguousarray(x[:n, n:n + m]),
            np.ascontiguousarray(x[:n, n + m:]))


def simulate_load(model: DamperModel, structure: Any, load: LoadHistory, sample_rate: float = 2000.0,
                  tail: float = 0.0) -> LoadResponse:
    """Response of ``structure`` carrying ``model`` (a pseudo-force damper model: analytic,
    effective fields) to ``load``, from rest, over the record plus ``tail`` [s] of free
    vibration (module docstring).

    Examples
    --------
    >>> from pdamper.parameters import PAPER_STRUCTURE, PAPER_DAMPER
    >>> from pdamper.models import AnalyticalDamper
    >>> h = LoadHistory.harmonic(2.0, 5.0, 4.0)
    >>> r = simulate_load(AnalyticalDamper(PAPER_DAMPER), PAPER_STRUCTURE, h)
    >>> 0.001 < r.peak < 0.05 and r.dissipated_energy > 0
    True
    """
    check_range("simulation.sample_rate", sample_rate, low=0.0, low_inclusive=False, unit="Hz")
    check_range("load.tail", tail, low=0.0, unit="s")
    if not isinstance(load, LoadHistory):
        raise InputError("load", f"must be a LoadHistory, got {type(load).__name__}")
    sys_ = _System.of(structure)
    kind = load.kind
    if kind == "base_acceleration" and sys_.base_shape is None:
        raise InputError("base_acceleration", "base motion needs each mode's participation "
                         "factor, which a modes file does not give: use one mode, the 1-DOF "
                         "or [structure] beam, or a force (--load) at the load point")
    t, h, sub, steps = _time_grid(load, tail, sample_rate, sys_.phi.size)
    u, lv, v_b, y_b = _inputs(load, t)
    n = sys_.phi.size
    phi = sys_.phi
    z, zdot, dd, me, cycles = _march(model, sys_, kind, t, u, y_b, h, steps)
    q, qd, qdd = z[:, :n].T, z[:, n:].T, zdot[:, n:].T
    v_c = phi @ qd + v_b
    dissipated = float(np.trapezoid(dd * v_c * v_c, t))
    a_out = sys_.out @ qdd + (u[:, 1] if kind != "force" else 0.0)
    if kind == "force":
        w_in = float(np.trapezoid(lv * (sys_.load_shape @ qd), t))
        w_struct = float(np.trapezoid(np.einsum("it,ij,jt->t", qd, sys_.damping, qd), t))
        e_end = 0.5 * (qd[:, -1] @ sys_.mass @ qd[:, -1] + q[:, -1] @ sys_.stiffness @ q[:, -1]
                       + me[-1] * v_c[-1] ** 2)
    else:
        w_in = w_struct = e_end = math.nan
    keep = slice(None, None, sub)
    return LoadResponse(
        time=t[keep], displacement=(sys_.out @ q)[keep], acceleration=a_out[keep],
        load=lv[keep], damper_displacement=(phi @ q + y_b)[keep],
        dissipated_energy=dissipated, input_work=w_in, structural_dissipation=w_struct,
        energy_change=e_end, cycles=tuple(cycles), model=model.fidelity, kind=kind,
        inputs={"load": load.source, "load_kind": kind, "record_duration": load.duration,
                "tail": tail, "sample_rate": sample_rate, "integration_step": h,
                "interpolation": "linear", "steps": steps})


def _time_grid(load: LoadHistory, tail: float, sample_rate: float,
               n_modes: int) -> tuple[np.ndarray, float, int, int]:
    """The integration grid ``t`` (step ``h``: the sample interval split ``sub`` times to
    resolve the record, ``steps`` steps) over the record plus ``tail``, or an InputError if
    its arrays would exceed :data:`MAX_BYTES`."""
    duration = load.duration + tail
    h_out = 1.0 / sample_rate
    fine = float(np.median(np.diff(load.time)))
    sub = max(1, math.ceil(h_out / fine * (1.0 - 1e-9)))
    h = h_out / sub
    steps_f = duration / h
    need = (steps_f + 1) * 8.0 * (4 * n_modes + 12)  # z, z', inputs, d, m_eff, outputs
    if not need <= MAX_BYTES:
        raise InputError("simulation.sample_rate", f"the run needs {steps_f:.3g} steps "
                         f"({duration:g} s at {1.0 / h:.4g} Hz, the finer of the sample rate "
                         f"and the record's) and {need / 2**30:.3g} GiB, more than "
                         f"{MAX_BYTES / 2**30:.3g} GiB: lower the sample rate, shorten the "
                         "record or its tail")
    steps = math.ceil(steps_f * (1.0 - 1e-12))
    return np.arange(steps + 1) * h, h, sub, steps


def _inputs(load: LoadHistory, t: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The inputs ``u = (F, a_b, v_b)`` at the times ``t``, the load's values there, the
    base velocity and the container's displacement from rest carried by the base (zero
    for a force)."""
    u = np.zeros((t.size, 3))
    lv = load.at(t)
    y_b = np.zeros(t.size)
    if load.kind == "force":
        u[:, 0] = lv
        v_b = np.zeros(t.size)
    else:
        u[:, 1] = lv
        from scipy.integrate import cumulative_trapezoid

        v_b = cumulative_trapezoid(lv, t, initial=0.0)
        v_b -= np.trapezoid(v_b, t) / (t[-1] - t[0])  # a steady drift carries no damper force
        u[:, 2] = v_b
        # (relative to the base's own mean drift)
        y_b = cumulative_trapezoid(v_b, t, initial=0.0)
    return u, lv, v_b, y_b


def _march(model: DamperModel, sys_: _System, kind: str, t: np.ndarray, u: np.ndarray,
           y_b: np.ndarray, h: float, steps: int
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[CycleUpdate]]:
    """The state ``z``, its derivative, d and m_eff at each sample and the cycle updates:
    exact steps between the container's minima, where the pseudo-force coefficients are
    updated from the last half cycle."""
    n = sys_.phi.size
    z = np.zeros((t.size, 2 * n))
    zdot = np.zeros((t.size, 2 * n))
    dd = np.zeros(t.size)  # d in force at each sample
    me = np.zeros(t.size)
    # until the first update the bed rests on the floor and is carried along: a rigid mass
    # that dissipates nothing
    m_eff, d = float(model.bed_mass), 0.0
    a_mat, b_mat = sys_.matrices(m_eff, d, kind)
    p_mat, g0, g1 = _hold(a_mat, b_mat, h)
    zdot[0] = a_mat @ z[0] + b_mat @ u[0]
    phi = sys_.phi
    # detection state: the container's two previous samples, the last maximum, the last
    # minimum's time (NaN: none yet)
    det = np.array([0.0, 0.0, math.nan, math.nan, math.nan, math.nan])
    cycles: list[CycleUpdate] = []
    k = 0
    from pdamper.coupling._load_kernel import advance

    while k < steps:
        k = advance(z, zdot, u, y_b, phi, p_mat, g0, g1, a_mat, b_mat, dd, me, d, m_eff,
                    k, steps, det, h)
        if k >= steps:
            break
        # a minimum at sample k - 1 (found on stepping to k)
        t_max, x_max, t_min_last = det[2], det[3], det[4]
        amp = 0.5 * (x_max - det[5])
        t_k = t[k - 1]
        det[4] = t_k
        if not amp > _REST:
            continue
        freq = 1.0 / (t_k - t_min_last) if math.isfinite(t_min_last) else 0.5 / (t_k - t_max)
        m_eff, d, resp = pseudo_force_coefficients(model, freq, amp)
        cycles.append(CycleUpdate(float(t_k), amp, freq, motion_mode(resp.mode), m_eff, d,
                                  float(resp.loss_factor)))
        a_mat, b_mat = sys_.matrices(m_eff, d, kind)
        p_mat, g0, g1 = _hold(a_mat, b_mat, h)
        # the state at k stays; its derivative follows the new coefficients
        zdot[k] = a_mat @ z[k] + b_mat @ u[k]
        dd[k], me[k] = d, m_eff
    return z, zdot, dd, me, cycles


#: Load-history strategies by coupling name (a view of the coupling table,
#: :data:`pdamper.coupling.registry.COUPLINGS`, where a new coupling is one row).
LOAD_COUPLINGS = CouplingView(lambda c: c.load, lambda c: c.runs(LOAD_HISTORY))
#: What a load history costs by coupling name, where it is more than seconds:
#: ``f(model, structure, load, sample_rate, tail) -> resources.Cost``.
LOAD_COSTS = CouplingView(lambda c: c.load_cost,
                          lambda c: c.runs(LOAD_HISTORY) and has_load_cost(c))
#: What a coupling's load history needs of the structure, where it is more than any:
#: ``f(structure)`` raises InputError otherwise (the DEM: a 1-DOF or N modes).
LOAD_STRUCTURES = CouplingView(
    lambda c: functools.partial(c.check_load_structure, None),
    lambda c: c.runs(LOAD_HISTORY) and (MODES not in c.answers[LOAD_HISTORY]
                                        or c.checks_load_structure))


def _no_load_form(model: Any) -> str:
    return (f"the {model.coupling} coupling of {type(model).__name__} has no load-history "
            "form yet; use a pseudo-force model (analytic, fields) for --load / "
            "--base-acceleration")


def load_strategy(model: Any, structure: Any = None):
    """The coupling strategy (:class:`~pdamper.coupling.registry.Coupling`) that runs
    ``model`` under a load history (on ``structure``, if given); InputError otherwise."""
    strategy = coupling_of(model, LOAD_HISTORY, field="simulation.model",
                           missing=_no_load_form)
    if structure is not None:
        strategy.check_load_structure(model, structure)
    return strategy


def check_model(model: Any, structure: Any = None) -> None:
    """Raise InputError if ``model``'s coupling has no load-history form (or none for
    ``structure``, if given)."""
    load_strategy(model, structure)


def check_cost(model, structure, load: LoadHistory, sample_rate: float, tail: float,
               force: bool = False) -> None:
    """Refuse a load history whose run ``model`` cannot afford
    (:func:`pdamper.resources.require`; ``force`` lifts the usual limits)."""
    cost = load_strategy(model).load_cost(model, structure, load, sample_rate, tail)
    if cost is not None:
        from pdamper import resources

        resources.require(cost, force)


def run_load(model: DamperModel, structure: Any, load: LoadHistory, sample_rate: float = 2000.0,
             tail: float = 0.0) -> LoadResponse:
    """:func:`simulate_load` through the model's coupling; a model whose coupling has no
    load-history form is an error naming it."""
    return load_strategy(model).load(model, structure, load, sample_rate, tail)
