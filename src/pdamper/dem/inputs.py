"""Inputs of a DEM run: container, particles, container motion (the contact parameters are
:class:`pdamper.contact.law.ContactParameters`).

All quantities are SI floats. The container frame has ``x in [0, Lx]``, ``y in [0, Ly]``,
``z in [0, Lz]`` with ``z`` up (against gravity); particle positions given to
:class:`ParticleSet` are in that frame.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from pdamper.errors import InputError, check_range
from pdamper.materials import Material

#: Integrators of :class:`pdamper.dem.DEMEngine`: variable-step fifth-order Gear (the
#: paper's), fixed-step velocity Verlet, and "auto": Gear that hands the run over to Verlet
#: where Verlet is cheaper (``pdamper.dem.simulation.AUTO_COST_RATIO``).
INTEGRATORS = ("gear", "verlet", "auto")
#: Default safety factor: time step = safety x Hertz contact duration at the reference speed.
DEFAULT_SAFETY = 0.02
#: Default tolerance of the Gear integrator's local error estimate [-].
DEFAULT_GEAR_TOLERANCE = 1e-5
#: Default velocity scale of the Gear error norm [m/s].
DEFAULT_GEAR_VELOCITY_SCALE = 0.05
#: Overlap / radius above which a run warns (:class:`LargeOverlapWarning`): Hertz's
#: contact assumes strains small against one; at 5 % of the radius (a steel sphere on PVC
#: at about 8 m/s) real materials yield, while the model stays elastic. A regime, not an
#: error: the run goes on and reports ``max_overlap_ratio``.
OVERLAP_WARNING_LIMIT = 0.05


class LargeOverlapWarning(UserWarning):
    """A DEM run had overlaps beyond :data:`OVERLAP_WARNING_LIMIT` of a radius."""


def _floats(field: str, value, expected: str, ndmin: int = 0) -> np.ndarray:
    """``value`` as a float array, or an InputError saying what was expected."""
    if isinstance(value, str | bytes):
        raise InputError(field, f"must be {expected}, got {value!r}")
    try:
        return np.array(value, dtype=float, ndmin=ndmin)
    except (TypeError, ValueError):
        raise InputError(field, f"must be {expected}, got {value!r}") from None


@dataclass(frozen=True)
class Container:
    """A rectangular box container.

    Parameters
    ----------
    box
        Inner dimensions ``(Lx, Ly, Lz)`` [m]; ``Lz`` is vertical.
    material
        Wall material (all six walls).
    mass
        Container mass m_con [kg]; only enters the complex power's effective mass (Eq. 4).
    """

    box: tuple[float, float, float]
    material: Material
    mass: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.material, Material):
            raise InputError("container.material", f"must be a Material, got {self.material!r}")
        if isinstance(self.box, str | bytes) or not hasattr(self.box, "__len__") \
                or len(self.box) != 3:
            raise InputError("container.box", "needs three inner dimensions (Lx, Ly, Lz) in m, "
                             f"got {self.box!r}")
        for name, v in zip("xyz", self.box, strict=True):
            check_range(f"container.box.L{name}", v, low=0.0, low_inclusive=False, unit="m")
        check_range("container.mass", self.mass, low=0.0, unit="kg")
        object.__setattr__(self, "box", tuple(float(v) for v in self.box))


@dataclass
class ParticleSet:
    """Spheres with per-particle radius and material.

    Parameters
    ----------
    positions
        Centres in the container frame, shape ``(n, 3)`` [m].
    radius
        One radius or one per particle [m].
    material
        One material or one per particle.
    velocities, angular_velocities
        Initial values, shape ``(n, 3)`` [m/s], [rad/s]; zero if omitted.
    """

    # The fields' types are those after ``__post_init__`` has normalised them; the
    # constructor takes the wider ones that ``__init__`` below declares to the type checker.
    positions: np.ndarray
    radius: np.ndarray
    material: list[Material]
    velocities: np.ndarray = None  # type: ignore[assignment]  # None -> zeros (__post_init__)
    angular_velocities: np.ndarray = None  # type: ignore[assignment]  # None -> zeros

    if TYPE_CHECKING:
        def __init__(self, positions: np.ndarray | Sequence[Sequence[float]],
                     radius: float | Sequence[float] | np.ndarray,
                     material: Material | Sequence[Material],
                     velocities: np.ndarray | None = None,
                     angular_velocities: np.ndarray | None = None) -> None: ...

    def __post_init__(self) -> None:
        pos = _floats("particles.positions", self.positions, "an (n, 3) array of centres in m",
                      ndmin=2)
        if pos.ndim != 2 or pos.shape[1] != 3 or pos.shape[0] < 1:
            raise InputError("particles.positions", "must have shape (n, 3) with n >= 1")
        if not np.all(np.isfinite(pos)):
            raise InputError("particles.positions", "must be finite")
        n = pos.shape[0]
        self.positions = pos
        r = _floats("particles.radius", self.radius, f"one radius or {n} of them in m")
        if r.ndim > 1 or r.size not in (1, n):
            raise InputError("particles.radius", f"one radius or {n} of them in m, got shape "
                             f"{r.shape}")
        r = np.broadcast_to(r, (n,)).copy()
        if np.any(~np.isfinite(r)) or np.any(r <= 0):
            raise InputError("particles.radius", "must be finite and > 0 m")
        self.radius = r
        for name in ("velocities", "angular_velocities"):
            v = getattr(self, name)
            v = (np.zeros((n, 3)) if v is None else
                 _floats(f"particles.{name}", v, f"an ({n}, 3) array"))
            if v.shape != (n, 3) or not np.all(np.isfinite(v)):
                raise InputError(f"particles.{name}", f"must be finite with shape ({n}, 3)")
            setattr(self, name, v)
        material: Any = self.material  # as given: one Material or a sequence of them
        mats: list[Material]
        if isinstance(material, Material):
            mats = [material] * n
        elif isinstance(material, str | bytes) or not hasattr(material, "__iter__"):
            mats = []
        else:
            mats = list(material)
        if len(mats) != n or not all(isinstance(m, Material) for m in mats):
            raise InputError("particles.material", f"must be one Material or {n} of them "
                             f"(pdamper.materials), got {self.material!r}")
        self.material = mats

    @property
    def count(self) -> int:
        """Number of particles n."""
        return self.positions.shape[0]

    @property
    def masses(self) -> np.ndarray:
        """m = 4/3 pi r^3 rho [kg]."""
        rho = np.array([m.density for m in self.material])
        return 4.0 / 3.0 * math.pi * self.radius**3 * rho

    @property
    def inertia(self) -> np.ndarray:
        """Moment of inertia of a solid sphere, 2/5 m r^2 [kg m^2]."""
        return 0.4 * self.masses * self.radius**2

    @classmethod
    def lattice(cls, n: int, box: Sequence[float], radius: float, material: Material,
                gap: float = 0.0) -> ParticleSet:
        """Regular square-lattice layers from the floor (the paper's 4 x 4 layers in its
        benchmark box); see :func:`pdamper.dem.packing.lattice_layers`."""
        from pdamper.dem.packing import lattice_layers

        return cls(lattice_layers(n, radius, box, gap), radius, material)

    @classmethod
    def random(cls, n: int, box: Sequence[float], radius: float, material: Material,
               seed: int = 0) -> ParticleSet:
        """Random non-overlapping packing, reproducible from ``seed``."""
        from pdamper.dem.packing import random_packing

        return cls(random_packing(n, radius, box, seed), radius, material)


@dataclass(frozen=True)
class HarmonicMotion:
    """Prescribed harmonic container motion x_c = X sin(W t), W = 2 pi f (paper Sect. 3).

    Parameters
    ----------
    amplitude
        X [m] (>= 0; 0 keeps the container at rest).
    frequency
        f [Hz].
    """

    amplitude: float = 0.0
    frequency: float = 0.0

    def __post_init__(self) -> None:
        check_range("amplitude", self.amplitude, low=0.0, unit="m")
        check_range("frequency", self.frequency, low=0.0, unit="Hz")

    @property
    def angular_frequency(self) -> float:
        """W = 2 pi f [rad/s]."""
        return 2.0 * math.pi * self.frequency

    def state(self, t: float | np.ndarray) -> tuple[Any, Any, Any]:
        """(x_c, v_c, a_c) at time(s) t [s]."""
        w = self.angular_frequency
        return (self.amplitude * np.sin(w * t), self.amplitude * w * np.cos(w * t),
                -self.amplitude * w * w * np.sin(w * t))


@dataclass(frozen=True)
class PrescribedMotion:
    """Any prescribed container motion x_c(t) along z.

    The callables are sampled on a uniform grid of ``sample_interval`` for the kernels and
    interpolated linearly there. Missing derivatives are taken numerically.

    Parameters
    ----------
    position
        ``x_c(t)`` [m], vectorised over a numpy array of times [s].
    velocity, acceleration
        Optional ``v_c(t)`` [m/s], ``a_c(t)`` [m/s^2].
    sample_interval
        Grid step [s] (default 1e-6 s).
    """

    position: Callable
    velocity: Callable | None = None
    acceleration: Callable | None = None
    sample_interval: float = 1e-6

    def table(self, duration: float
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Sampled ``(t, z, v, a)`` over [0, duration]."""
        h = float(self.sample_interval)
        nt = int(math.ceil(duration / h)) + 3
        t = np.arange(nt) * h
        z = np.asarray(self.position(t), dtype=float) * np.ones(nt)
        v = (np.gradient(z, h) if self.velocity is None
             else np.asarray(self.velocity(t), dtype=float) * np.ones(nt))
        a = (np.gradient(v, h) if self.acceleration is None
             else np.asarray(self.acceleration(t), dtype=float) * np.ones(nt))
        if not (np.all(np.isfinite(z)) and np.all(np.isfinite(v)) and np.all(np.isfinite(a))):
            raise InputError("motion.position", "the container motion must be finite")
        return t, z, v, a


@dataclass(frozen=True)
class StructureMotion:
    """The container as the end effector of a 1-DOF structure (the paper's model 1).

    ``M x'' + D x' + K x = F_z``, where ``F_z`` is the force that the particles exert on
    the container; the structure is integrated together with the particles. ``x`` is measured
    from the static equilibrium of the structure without particles, so gravity does not act
    on M (the particles' weight acts through F_z).

    Under a load history (``force`` and/or ``base_acceleration``) the spring and the
    damper hang from a base at ``z_b(t)`` and a force ``F(t)`` acts on M:

        M z'' + D (z' - v_b) + K (z - z_b) = F_z + F(t)

    with ``z`` the container's *absolute* position: the particles feel the container's
    absolute motion (gravity stays constant in the inertial frame). In the coordinate
    relative to the base, ``y = z - z_b``, this is ``M y'' + D y' + K y = F_z + F - M a_b``.
    The base starts at rest at 0 (``z_b``, ``v_b`` integrated exactly from ``a_b`` linear
    between samples), so ``x0``, ``v0`` are then also relative to the base.

    Parameters
    ----------
    mass, damping, stiffness
        M [kg], D [kg/s], K [N/m] (the paper's: ``pdamper.parameters.PAPER_STRUCTURE``).
    x0, v0
        Initial position [m] and velocity [m/s] at release.
    force_amplitude, force_frequency, force_phase
        A harmonic load ``F cos(2 pi f t + phi)`` on the structure, t from the start of the
        run: F [N] (default 0: free vibration), f [Hz], phi [rad] (the forced response,
        :mod:`pdamper.coupling.frf`).
    force, base_acceleration
        Optional load histories ``(dt, values)``: samples every ``dt`` [s] from the start
        of the excitation of the force on M [N] or of the base acceleration [m/s^2],
        linear between samples, zero after the last.
    """

    mass: float
    damping: float
    stiffness: float
    x0: float = 0.0
    v0: float = 0.0
    force_amplitude: float = 0.0
    force_frequency: float = 0.0
    force_phase: float = 0.0
    force: tuple | None = field(default=None, compare=False)
    base_acceleration: tuple | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        check_range("structure.mass", self.mass, low=0.0, low_inclusive=False, unit="kg")
        check_range("structure.damping", self.damping, low=0.0, unit="kg/s")
        check_range("structure.stiffness", self.stiffness, low=0.0, unit="N/m")
        check_range("structure.x0", self.x0, unit="m")
        check_range("structure.v0", self.v0, unit="m/s")
        check_range("force", self.force_amplitude, low=0.0, unit="N")
        check_range("frequency", self.force_frequency, low=0.0, unit="Hz")
        check_range("force_phase", self.force_phase, unit="rad")
        for name in ("force", "base_acceleration"):
            rec = getattr(self, name)
            if rec is None:
                continue
            if isinstance(rec, str | bytes) or not hasattr(rec, "__len__") or len(rec) != 2:
                raise InputError(f"structure.{name}", "must be (dt, values): a sample "
                                 f"interval in s and the samples, got {rec!r}")
            dt = check_range(f"structure.{name}", rec[0], low=0.0, low_inclusive=False,
                             unit="s")
            v = _floats(f"structure.{name}", rec[1], "a sequence of finite samples", ndmin=1)
            if v.ndim != 1 or v.size < 2 or not np.all(np.isfinite(v)):
                raise InputError(f"structure.{name}", "needs at least 2 finite samples in a "
                                 "1-D sequence")
            object.__setattr__(self, name, (float(dt), v))
        if self.force_amplitude > 0 and self.loaded:  # the kernels take one or the other
            raise InputError("structure.force", "a harmonic load and a load history cannot "
                             "act together; give one of them")

    @property
    def loaded(self) -> bool:
        """Whether a load history acts (a force or a base motion)."""
        return self.force is not None or self.base_acceleration is not None

    def load_tables(self, duration: float):
        """The kernels' tables over ``[0, duration]``: ``(h, z_b, v_b, F)`` on the uniform
        step ``h`` (the finer of the records' intervals): base position [m] and velocity
        [m/s] integrated exactly from rest for an acceleration linear between its samples,
        and the force [N]."""
        steps = [r[0] for r in (self.force, self.base_acceleration) if r is not None]
        h = min(steps)
        nt = int(math.ceil(duration / h)) + 3
        t = np.arange(nt) * h
        f = np.zeros(nt)
        a = np.zeros(nt)
        for rec, out in ((self.force, f), (self.base_acceleration, a)):
            if rec is not None:
                dt, v = rec
                out[:] = np.interp(t, np.arange(v.size) * dt, v, left=0.0, right=0.0)
        # exact integrals of a piecewise-linear acceleration
        vb = np.concatenate([[0.0], np.cumsum(0.5 * h * (a[:-1] + a[1:]))])
        zb = np.concatenate([[0.0], np.cumsum(h * vb[:-1] + h * h * (2.0 * a[:-1] + a[1:])
                                              / 6.0)])
        return h, zb, vb, f

    @property
    def natural_frequency(self) -> float:
        """sqrt(K/M) / (2 pi) [Hz]."""
        return math.sqrt(self.stiffness / self.mass) / (2.0 * math.pi)


@dataclass(frozen=True)
class ModalStructureMotion(StructureMotion):
    """The container on a structure of N mass-normalised modes (the co-simulation on N
    modes, :mod:`pdamper.dem.kernels.modes`).

    ``q_j'' + 2 zeta_j w_j q_j' + w_j^2 q_j = phi_c,j F_z + phi_L,j F(t) - Gamma_j a_b(t)``
    with the container at ``z = phi_c . q + z_b`` (absolute; ``q`` relative to the base),
    ``F_z`` the force of the particles on the container, ``F`` the force at the load
    point (a harmonic load ``force_amplitude`` ... or the history ``force``), ``a_b`` the
    base acceleration (``base_acceleration``: the tables as :class:`StructureMotion`'s).
    ``q`` is measured from the structure's equilibrium without the particles (their
    weight acts through ``F_z``), as the 1-DOF's ``x``.

    Build it with :meth:`of`. The inherited ``mass``, ``damping``, ``stiffness``, ``x0``,
    ``v0`` describe the container point for the engine's estimates (its start, the
    reference speed): the point's static stiffness ``1 / sum(phi_c^2 / w^2)``, its mass
    ``1 / sum(phi_c^2)``, the first mode's damping ratio; ``x0 = phi_c . q0``.

    Parameters
    ----------
    angular_frequencies
        w_j [rad/s].
    damping_ratios
        zeta_j [-].
    damper_shape, load_shape
        phi_c,j, phi_L,j [1/sqrt(kg)].
    participation
        Gamma_j [sqrt(kg)] (base motion; zeros without).
    q0, qd0
        Modal coordinates [m sqrt(kg)] and their rates at the start of the excitation.
    """

    angular_frequencies: Any = field(default=None, compare=False)  # an array after __post_init__
    damping_ratios: Any = field(default=None, compare=False)  # an array after __post_init__
    damper_shape: Any = field(default=None, compare=False)  # an array after __post_init__
    load_shape: Any = field(default=None, compare=False)  # an array after __post_init__
    participation: Any = field(default=None, compare=False)  # an array after __post_init__
    q0: Any = field(default=None, compare=False)  # an array after __post_init__
    qd0: Any = field(default=None, compare=False)  # an array after __post_init__

    def __post_init__(self) -> None:
        super().__post_init__()
        w = np.atleast_1d(np.asarray(self.angular_frequencies, float))
        n = w.size
        if n < 1 or not np.all(np.isfinite(w)) or np.any(w <= 0):
            raise InputError("structure.frequencies", "must be one or more finite positive "
                             "frequencies")
        object.__setattr__(self, "angular_frequencies", w)
        for name, default in (("damping_ratios", 0.0), ("damper_shape", None),
                              ("load_shape", None), ("participation", 0.0), ("q0", 0.0),
                              ("qd0", 0.0)):
            v = getattr(self, name)
            if v is None:
                v = self.damper_shape if name == "load_shape" else default
            if v is None:
                raise InputError(f"structure.{name}", f"must hold {n} values, one per mode")
            a = np.broadcast_to(np.asarray(v, float), (n,)).copy()
            if not np.all(np.isfinite(a)):
                raise InputError(f"structure.{name}", f"must hold {n} finite values")
            object.__setattr__(self, name, a)
        if np.any(self.damping_ratios < 0):
            raise InputError("structure.damping_ratios", "must be >= 0")

    @classmethod
    def of(cls, structure, q0, qd0=None, *, force_amplitude: float = 0.0,
           force_frequency: float = 0.0, force_phase: float = 0.0, force=None,
           base_acceleration=None) -> ModalStructureMotion:
        """The motion of a :class:`~pdamper.structure.modal.ModalStructure` started at the
        modal coordinates ``q0`` with rates ``qd0`` (default rest); the loads as
        :class:`StructureMotion`'s. Base motion needs the structure's participation
        factors (:meth:`~pdamper.structure.modal.ModalStructure.from_beam` has them; one
        mode without them: ``1 / phi_c``, all the mass at the container)."""
        w = np.asarray(structure.angular_frequencies, float)
        phi = np.asarray(structure.damper_shape, float)
        zeta = np.asarray(structure.damping_ratios, float)
        gamma = structure.participation
        if gamma is None:
            if base_acceleration is not None and structure.modes > 1:
                raise InputError("base_acceleration", "base motion needs each mode's "
                                 "participation factor, which a modes file does not give: "
                                 "use one mode, the 1-DOF or [structure] beam, or a force "
                                 "(--load) at the load point")
            gamma = 1.0 / phi if structure.modes == 1 else np.zeros(w.size)
        q0 = np.asarray(q0, float)
        qd0 = np.zeros(w.size) if qd0 is None else np.asarray(qd0, float)
        flex = float(np.sum(phi**2 / w**2))
        k = 1.0 / flex
        m = 1.0 / float(np.sum(phi**2))
        return cls(mass=m, damping=2.0 * float(zeta[0]) * math.sqrt(k * m), stiffness=k,
                   x0=float(phi @ q0), v0=float(phi @ qd0), force_amplitude=force_amplitude,
                   force_frequency=force_frequency, force_phase=force_phase, force=force,
                   base_acceleration=base_acceleration, angular_frequencies=w,
                   damping_ratios=zeta, damper_shape=phi, load_shape=structure.load_shape,
                   participation=np.asarray(gamma, float), q0=q0, qd0=qd0)

    @property
    def modes(self) -> int:
        """N [-]."""
        return int(self.angular_frequencies.size)

    @property
    def release_speed(self) -> float:
        """Largest speed of the container point that the start state implies, ``sum_j
        |phi_c,j| sqrt((w_j q0_j)^2 + qd0_j^2)`` [m/s] (each mode's amplitude of speed)."""
        return float(np.sum(np.abs(self.damper_shape) * np.hypot(
            self.angular_frequencies * self.q0, self.qd0)))

    def steady_speed(self) -> float:
        """Steady speed amplitude of the container point under the harmonic load without
        particles, ``F W |sum_j phi_c,j phi_L,j / (w_j^2 - W^2 + 2 i zeta_j w_j W)|``
        [m/s] (0 without the load)."""
        if not self.force_amplitude > 0:
            return 0.0
        big = 2.0 * math.pi * self.force_frequency
        w = self.angular_frequencies
        h = np.sum(self.damper_shape * self.load_shape
                   / (w * w - big * big + 2j * self.damping_ratios * w * big))
        return float(self.force_amplitude * big * abs(h))

    def modal_tables(self, duration: float):
        """:meth:`StructureMotion.load_tables` and the base acceleration on the same step:
        ``(h, z_b, v_b, F, a_b)``."""
        h, zb, vb, f = self.load_tables(duration)
        a = np.zeros(zb.size)
        if self.base_acceleration is not None:
            dt, v = self.base_acceleration
            a[:] = np.interp(np.arange(zb.size) * h, np.arange(v.size) * dt, v, left=0.0,
                             right=0.0)
        return h, zb, vb, f, a


Motion = HarmonicMotion | PrescribedMotion | StructureMotion
