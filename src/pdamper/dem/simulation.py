"""Python orchestration of the DEM engine (paper Sect. 3, "Discrete element method").

:class:`DEMEngine` turns the inputs of :mod:`pdamper.dem.model` into the named bundles of
:mod:`pdamper.dem.kernels.state`, picks the time step from the contact time scale, settles
the particles under gravity in the resting container, then runs the excitation and returns
a :class:`DEMResult`. Both phases call the numba kernels of :mod:`pdamper.dem.kernels` in
chunks of a fraction of a second of wall time (signals and early stops are handled between
chunks; the chunking does not change a single bit of the result).
"""

from __future__ import annotations

import copy
import hashlib
import logging
import math
import pickle
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pdamper import resources
from pdamper.constants import STANDARD_GRAVITY
from pdamper.contact.forces import DAMPING_CODES
from pdamper.contact.hertz import (
    contact_duration,
    effective_modulus,
    hertz_stiffness,
    rayleigh_time,
)
from pdamper.contact.law import ContactParameters
from pdamper.dem.kernels import gear as _gear
from pdamper.dem.kernels import state as K
from pdamper.dem.kernels import verlet as _verlet
from pdamper.dem.model import (
    DEFAULT_GEAR_TOLERANCE,
    DEFAULT_GEAR_VELOCITY_SCALE,
    DEFAULT_SAFETY,
    INTEGRATORS,
    OVERLAP_WARNING_LIMIT,
    Container,
    HarmonicMotion,
    LargeOverlapWarning,
    ParticleSet,
    PrescribedMotion,
    StructureMotion,
)
from pdamper.errors import InputError, SimulationError, check_range, check_whole

log = logging.getLogger(__name__)

#: The Gear step may reach a new contact with up to GEAR_ONSET_FACTOR x the Verlet step when
#: ``gear_contact_bound`` is on; the error control (with rejection) takes over inside the
#: contact.
GEAR_ONSET_FACTOR = 6.0
#: The friction cap of variable-step Gear (no reversal of the slip within one step,
#: :mod:`pdamper.dem.kernels.forces`) is that of a step of GEAR_FRICTION_CAP_FACTOR x the
#: Verlet step dt0, however short Gear's steps are: a stuck contact is a viscous damper of
#: time constant ~2 x factor x dt0, which the error control resolves (at 1: 60-250 ns steps,
#: half the steps of a shaken bed). At 5 (oblique sphere-wall impacts, 0.3 and 3 m/s,
#: tangential / normal speed 0.1-3, against Verlet at safety 0.0025): rebound within
#: 1.6e-5 (2e-7 at 1), 140-167 instead of 528 steps per sticking impact at 3 m/s; the
#: verification table of docs/dem.md (21 points, paired with 1) keeps every reproducible
#: point within 1 % (worst 0.61 %, the same as at 1) with 12-47 % fewer steps at the fast
#: points; Level III model 1 over random packings unchanged (21.5 +- 0.2 mm against
#: 21.6 +- 0.4). At 10 the slip no longer stops within a contact (1.7e-3,
#: tests/dem/test_dem_physics.py fails).
GEAR_FRICTION_CAP_FACTOR = 5.0
#: Settling beyond the free fall over the container height, the engine's default [s].
SETTLE_EXTRA = 0.05


def free_fall_settling(height: float, gravity: float, extra: float = SETTLE_EXTRA) -> float:
    """Settling time [s]: the free fall over ``height`` [m] under ``gravity`` [m/s^2] plus
    ``extra`` [s]; 0 without gravity."""
    return math.sqrt(2.0 * height / gravity) + extra if gravity > 0 else 0.0


#: Target wall time of one kernel call [s]: Ctrl-C and ``stop`` take effect within it.
DEFAULT_CHUNK_SECONDS = 0.25
#: ``integrator="auto"`` runs Gear and hands over to velocity Verlet while Gear's mean step
#: over a judgement window of the excitation is below AUTO_COST_RATIO x the step Verlet would
#: take. At 1 the rule needs no cost model: Verlet then takes fewer steps, and each is
#: cheaper (a variable Gear step costs 1.6-2.4 Verlet steps: 2.4 at 32 spheres, 1.6 at 176,
#: where the force evaluation dominates). Gear's step falls below Verlet's where its
#: stability limit holds it, whatever its tolerance: a jammed bed (the full container,
#: 0.16 us against Verlet's 0.39 us). A ratio of 2.4 handed a Level III run of 176 spheres
#: (impacts and flights alternating within each structure period) to Verlet for 0.7 of its
#: 2 s and made it 14-80 % slower than Gear. Both integrators meet the verification table
#: of docs/dem.md.
AUTO_COST_RATIO = 1.0
#: The judgement window of "auto" [s of simulated time] (a whole number of landings: the
#: decisions do not depend on the chunking).
AUTO_WINDOW = 5e-3
#: Windows of Verlet before "auto" tries Gear again for one window (a probe: the regime may
#: have changed, e.g. a structure's vibration decays to a resting bed, or a burst of impacts
#: is over), doubled after each probe that hands back to Verlet, up to AUTO_MAX_SPAN; reset
#: when Gear stays. A first span of 4 windows kept a Level III run (176 spheres) in Verlet
#: through flights that Gear takes in long steps; 1 made it 11 % faster than Gear alone.
AUTO_FIRST_SPAN = 1
AUTO_MAX_SPAN = 64


@dataclass
class DEMResult:
    """Time series and snapshots of a DEM run (all SI units).

    Attributes
    ----------
    time : (ns,) [s]
        Sample times, from the start of the excitation.
    container_position, container_velocity, container_acceleration : (ns,)
        Container state along z [m], [m/s], [m/s^2].
    force : (ns, 3) [N]
        Force that the particles exert on the container, averaged over the sample window
        centred on each sample (the driving force is the container inertia minus this).
    center_of_mass : (ns, 3) [m]
        Centre of mass of the bed (inertial frame).
    kinetic_energy, rotational_energy, potential_energy, elastic_energy : (ns,) [J]
        Translational and rotational kinetic energy, gravitational potential (zero at
        z = 0 of the inertial frame) and elastic Hertz energy of the particles.
    dissipated_normal, dissipated_friction, container_work : (ns,) [J]
        Running integrals since the start of the excitation of the power dissipated by the
        normal damping, by friction, and of the work done by the container walls on the
        particles.
    snapshot_time : (nq,) [s]; snapshot_positions, snapshot_velocities,
    snapshot_angular_velocities : (nq, n, 3)
        Particle snapshots (positions in the inertial frame).
    max_overlap_ratio : float [-]
        Largest overlap / radius (of the smaller sphere) of the run.
    max_impact_velocity : float [m/s]
        Fastest impact: the largest normal approach speed at a contact onset (or re-impact).
    requested_duration : float [s]
        The duration asked of :meth:`DEMEngine.run`.
    stopped_early : bool
        True when the run was ended by its ``stop`` callable before ``requested_duration``:
        the series then cover only :attr:`simulated_time`.
    integrator_switch_time : float [s]
        When ``integrator="auto"`` first handed the run from Gear over to velocity Verlet
        (NaN: never).
    integrator_switches : int
        Hand-overs of ``"auto"``, both ways (Verlet hands back to Gear to probe whether
        Gear has become the cheaper).
    verlet_time : float [s]
        Simulated time of the excitation run by velocity Verlet.
    stepped_fraction : float [-]
        Mean share of the spheres that a Gear step of the excitation integrated (the others
        in free flight, :mod:`pdamper.dem.kernels.flights`); 1 without free flights.
    regroups : int
        Times the free flights were regrouped (each sample, after list rebuilds and speed
        limit violations).
    settle_reused : bool
        The run started from a :class:`SettledBed` settled earlier (``settle_steps`` and
        ``settle_seconds`` are then 0: this run spent none).
    steps_per_sample, stepped_per_sample, rejected_per_sample : (ns,) int arrays or None
        With ``DEMEngine.run(..., step_profile=True)``: the accepted steps, the sphere-steps
        (spheres integrated, summed over those steps; velocity Verlet integrates all) and
        the rejected steps of the sample interval that ends at each sample (0 at the
        first); None otherwise. :meth:`step_profile` bins them over the cycle.
    kernel_seconds_per_sample : (ns,) [s] or None
        Wall time of the integrator over each sample interval, its call's dispatch
        included (with ``step_profile``).
    """

    time: np.ndarray
    container_position: np.ndarray
    container_velocity: np.ndarray
    container_acceleration: np.ndarray
    force: np.ndarray
    center_of_mass: np.ndarray
    kinetic_energy: np.ndarray
    rotational_energy: np.ndarray
    potential_energy: np.ndarray
    elastic_energy: np.ndarray
    dissipated_normal: np.ndarray
    dissipated_friction: np.ndarray
    container_work: np.ndarray
    snapshot_time: np.ndarray
    snapshot_positions: np.ndarray
    snapshot_velocities: np.ndarray
    snapshot_angular_velocities: np.ndarray
    radius: np.ndarray
    masses: np.ndarray
    integrator: str
    steps: int
    settle_steps: int
    rebuilds: int
    contact_onsets: int
    rejected_steps: int
    wall_seconds: float
    settle_seconds: float
    time_step: float
    min_step: float
    max_step: float
    contact_time: float
    max_overlap_ratio: float
    max_impact_velocity: float
    frequency: float | None = None
    container_mass: float = 0.0
    requested_duration: float | None = None
    stopped_early: bool = False
    integrator_switch_time: float = math.nan
    integrator_switches: int = 0
    verlet_time: float = 0.0
    stepped_fraction: float = 1.0
    regroups: int = 0
    settle_reused: bool = False
    attrs: dict = field(default_factory=dict)
    steps_per_sample: np.ndarray | None = None
    stepped_per_sample: np.ndarray | None = None
    rejected_per_sample: np.ndarray | None = None
    kernel_seconds_per_sample: np.ndarray | None = None

    # ------------------------------------------------------------------ derived values
    @property
    def bed_mass(self) -> float:
        """m_bed, mass of all particles [kg]."""
        return float(np.sum(self.masses))

    @property
    def mechanical_energy(self) -> np.ndarray:
        """Kinetic + rotational + potential + elastic energy [J]."""
        return (self.kinetic_energy + self.rotational_energy + self.potential_energy
                + self.elastic_energy)

    @property
    def simulated_time(self) -> float:
        """Duration of the excitation phase [s]."""
        return float(self.time[-1] - self.time[0])

    def energy_balance_residual(self) -> np.ndarray:
        """W_container - (dE_mech + D_normal + D_friction) at each sample [J]."""
        de = self.mechanical_energy - self.mechanical_energy[0]
        return self.container_work - (de + self.dissipated_normal + self.dissipated_friction)

    def energy_balance_error(self) -> float:
        """Relative closure error of the energy ledger over the whole run [-].

        ``|W - dE - D| / max(|W|, D, |dE|)`` at the end of the run, with the work W of the
        container, the change dE of mechanical energy and the dissipation D (normal +
        friction).
        """
        de = self.mechanical_energy[-1] - self.mechanical_energy[0]
        d = self.dissipated_normal[-1] + self.dissipated_friction[-1]
        w = self.container_work[-1]
        scale = max(abs(w), abs(d), abs(de))
        if scale == 0.0:
            return 0.0
        return float(abs(w - de - d) / scale)

    def window(self, skip_cycles: int = 2, cycles: int | None = None) -> np.ndarray:
        """Boolean mask of the samples in whole cycles ``skip_cycles + 1 ...`` (harmonic)."""
        skip_cycles = check_whole("skip_cycles", skip_cycles)
        cycles = None if cycles is None else check_whole("cycles", cycles)
        if self.frequency is None or self.frequency <= 0:
            raise InputError("skip_cycles", "the complex power needs a harmonic excitation")
        period = 1.0 / self.frequency
        total = int(math.floor(self.simulated_time / period + 1e-9))
        if skip_cycles < 0 or skip_cycles >= total:
            raise InputError("skip_cycles", f"must be in [0, {total - 1}] for a run of "
                             f"{total} cycles, got {skip_cycles}")
        n = total - skip_cycles if cycles is None else cycles
        if n < 1 or skip_cycles + n > total:
            raise InputError("cycles", f"must be in [1, {total - skip_cycles}], got {n}")
        t_a = skip_cycles * period
        t_b = (skip_cycles + n) * period
        eps = 1e-9 * period
        return (self.time >= t_a - eps) & (self.time <= t_b + eps)

    def complex_power(self, skip_cycles: int = 2, cycles: int | None = None):
        """Complex power method, Eqs. (1)-(4), over whole cycles after ``skip_cycles``.

        The driving force in z is the container inertia minus the force of the particles on
        the container; the container mass is subtracted again in Eq. (4), so the particle
        part ``-force[:, 2]`` is passed with ``container_mass = 0``.

        Returns
        -------
        pdamper.analysis.complex_power.ComplexPowerResult
        """
        from pdamper.analysis.complex_power import complex_power

        m = self.window(skip_cycles, cycles)
        return complex_power(self.time[m], -self.force[m, 2], self.container_velocity[m],
                             self.container_acceleration[m], self.frequency, self.bed_mass,
                             container_mass=0.0)

    def ledger_per_cycle(self, skip_cycles: int = 2, cycles: int | None = None) -> dict:
        """Container work and dissipation per cycle over the same window [J]."""
        m = np.flatnonzero(self.window(skip_cycles, cycles))
        a, b = m[0], m[-1]
        nc = (self.time[b] - self.time[a]) * self.frequency
        d = (self.dissipated_normal + self.dissipated_friction)
        return {"container_work": float((self.container_work[b] - self.container_work[a]) / nc),
                "dissipated": float((d[b] - d[a]) / nc),
                "mechanical_energy_change": float(
                    (self.mechanical_energy[b] - self.mechanical_energy[a]) / nc)}

    def step_profile(self, bins: int = 20, skip_cycles: int = 0):
        """Where the integrator's steps and wall time go within the excitation cycle.

        The per-sample counts of a ``DEMEngine.run(..., step_profile=True)`` run, binned
        by the phase ``(t mod T) / T`` of each sample interval's midpoint (``z_c = X sin(2
        pi f t)``: 0.25 is the top of the stroke, where the container decelerates hardest
        and throws the bed against its lid) over the whole cycles after ``skip_cycles``.

        Parameters
        ----------
        bins
            Phase bins of the cycle [-], >= 1.
        skip_cycles
            Whole cycles left out at the start [-] (the start from rest).

        Returns
        -------
        xarray.Dataset
            Over ``phase`` (bin centres [-]): ``steps`` (accepted steps per cycle),
            ``step_share`` and ``wall_share`` (of the window's steps and integrator wall
            time), ``mean_step`` [s], ``stepped_spheres`` (spheres integrated per step),
            ``rejected`` (rejected steps per cycle) and ``container_acceleration`` [m/s^2]
            (bin mean); attributes ``cycles``, ``steps``, ``kernel_seconds``,
            ``particles``, ``integrator``.

        Raises
        ------
        InputError
            ``step_profile`` when the run recorded none; ``bins``, ``skip_cycles`` out of
            range.
        """
        import xarray as xr

        if self.steps_per_sample is None:
            raise InputError("step_profile", "the run recorded no step profile: run it with "
                             "DEMEngine.run(..., step_profile=True)")
        if self.frequency is None or self.frequency <= 0:
            raise InputError("step_profile", "binning over the cycle needs a harmonic "
                             "excitation (a structure's motion has no fixed cycle)")
        bins = check_whole("bins", bins, low=1)
        mask = self.window(skip_cycles)
        # interval k is (t[k-1], t[k]]: in the window when both of its ends are
        inside = np.flatnonzero(mask[1:] & mask[:-1]) + 1
        t = self.time
        f = float(self.frequency)
        cycles = int(round((t[inside[-1]] - t[inside[0] - 1]) * f))
        phase = np.mod(0.5 * (t[inside - 1] + t[inside]) * f, 1.0)
        idx = np.minimum((phase * bins).astype(int), bins - 1)

        def per_bin(values):
            return np.bincount(idx, weights=np.asarray(values, float)[inside], minlength=bins)

        steps = per_bin(self.steps_per_sample)
        stepped = per_bin(self.stepped_per_sample)
        wall = per_bin(self.kernel_seconds_per_sample)
        count = np.bincount(idx, minlength=bins)
        acc = per_bin(self.container_acceleration) / np.maximum(count, 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            mean_step = np.where(steps > 0, cycles / (f * bins) / steps, np.nan)
            per_step = np.where(steps > 0, stepped / steps, np.nan)

        def v(data, units, desc):
            return xr.Variable(("phase",), np.asarray(data), {"units": units, "long_name": desc})

        return xr.Dataset(
            {"steps": v(steps / cycles, "1", "accepted integrator steps per cycle"),
             "step_share": v(steps / max(steps.sum(), 1.0), "1", "share of the steps"),
             "wall_share": v(wall / wall.sum() if wall.sum() > 0 else np.zeros(bins), "1",
                             "share of the integrator's wall time"),
             "mean_step": v(mean_step, "s", "mean step"),
             "stepped_spheres": v(per_step, "1", "spheres integrated per step"),
             "rejected": v(per_bin(self.rejected_per_sample) / cycles, "1",
                           "rejected steps per cycle"),
             "container_acceleration": v(acc, "m/s^2", "container acceleration (bin mean)")},
            coords={"phase": ("phase", (np.arange(bins) + 0.5) / bins,
                              {"units": "1", "long_name": "phase of z_c = X sin(2 pi f t)"})},
            attrs={"cycles": cycles, "steps": int(steps.sum()),
                   "kernel_seconds": float(wall.sum()), "particles": len(self.radius),
                   "integrator": self.integrator})

    # ------------------------------------------------------------------ export
    def to_dataset(self):
        """The time series as an ``xarray.Dataset`` with units in the attributes."""
        import xarray as xr

        def v(data, units, desc, dims=("time",)):
            return xr.Variable(dims, np.asarray(data), {"units": units, "long_name": desc})

        ds = xr.Dataset(
            {
                "container_position": v(self.container_position, "m", "container position z_c"),
                "container_velocity": v(self.container_velocity, "m/s", "container velocity"),
                "container_acceleration": v(self.container_acceleration, "m/s^2",
                                            "container acceleration"),
                "force": v(self.force, "N", "force of the particles on the container "
                           "(window mean)", ("time", "component")),
                "force_z": v(self.force[:, 2], "N", "force of the particles on the container "
                             "in the driving direction z"),
                "center_of_mass": v(self.center_of_mass, "m", "centre of mass of the bed",
                                    ("time", "component")),
                "kinetic_energy": v(self.kinetic_energy, "J", "translational kinetic energy"),
                "rotational_energy": v(self.rotational_energy, "J", "rotational kinetic energy"),
                "potential_energy": v(self.potential_energy, "J", "gravitational potential energy"),
                "elastic_energy": v(self.elastic_energy, "J", "elastic Hertz energy"),
                "dissipated_normal": v(self.dissipated_normal, "J",
                                       "energy dissipated in normal contacts (cumulative)"),
                "dissipated_friction": v(self.dissipated_friction, "J",
                                         "energy dissipated by friction (cumulative)"),
                "container_work": v(self.container_work, "J",
                                    "work done by the container on the particles (cumulative)"),
            },
            coords={"time": ("time", self.time, {"units": "s"}),
                    "component": ("component", ["x", "y", "z"])},
        )
        attrs = {k: (str(val) if isinstance(val, dict | list | tuple) or val is None else val)
                 for k, val in self.attrs.items()}
        attrs.update(integrator=self.integrator, steps=self.steps, wall_seconds=self.wall_seconds,
                     bed_mass_kg=self.bed_mass, particles=len(self.radius),
                     energy_balance_error=self.energy_balance_error(),
                     max_overlap_ratio=self.max_overlap_ratio,
                     max_impact_velocity_m_s=self.max_impact_velocity,
                     stopped_early=int(self.stopped_early),
                     integrator_switch_time=self.integrator_switch_time,
                     integrator_switches=self.integrator_switches,
                     verlet_time=self.verlet_time)
        ds.attrs.update(attrs)
        return ds

    def write_netcdf(self, path: str | Path, attrs: dict | None = None) -> Path:
        """Write :meth:`to_dataset` to NetCDF (h5netcdf) atomically (temp file + rename),
        with extra global ``attrs`` (e.g. the inputs of the run)."""
        from pdamper.files import atomic_write_netcdf

        ds = self.to_dataset()
        ds.attrs.update(attrs or {})
        return atomic_write_netcdf(path, ds)

    def write_vtk(self, directory: str | Path) -> Path:
        """Write the snapshots as a ParaView series (.vtp files + .pvd index)."""
        from pdamper.dem.vtk import write_vtk_series

        return write_vtk_series(directory, self.snapshot_time, self.snapshot_positions,
                                self.snapshot_velocities, self.radius,
                                self.snapshot_angular_velocities)


@dataclass(frozen=True)
class _SampleGrid:
    """Sampling of the excitation phase."""

    duration: float
    interval: float           # sample interval [s]
    nsamp: int
    snap_every: int
    per_cycle: int            # samples per excitation cycle (harmonic motion), else 0
    frequency: float | None
    snapshots_requested: bool


@dataclass
class _Run:
    """The arrays of one run, shared by its phases."""

    pos: np.ndarray
    vel: np.ndarray
    omg: np.ndarray
    world: K.World
    law: K.Law
    part: K.Particles
    nbrs: K.Neighbours
    walls: K.WallContacts
    work: K.Work
    nord: K.Nordsieck
    flights: K.Flights
    z_start: float
    settle_steps: int = 0
    settle_seconds: float = 0.0
    pair_types: K.PairTypes | None = None
    settle_reused: bool = False

    def kernel_args(self, phase: _Phase) -> tuple:
        """The arguments shared by every kernel entry point, in their order."""
        return (self.pos, self.vel, self.omg, self.world, self.law, self.part, self.pair_types,
                self.nbrs, self.walls, phase.drive, phase.stepping, self.work)


@dataclass(frozen=True)
class SettledBed:
    """Particles settled under gravity in the resting container (:meth:`DEMEngine.settle`).

    The settling does not depend on the excitation (the container rests at its start
    position, the step is set by the free fall over the container height, not by the
    motion), so one bed serves every run of the same particles, container, contact law and
    step settings, whatever its frequency and amplitude: a map settles once instead of at
    every point. A run started from it (``DEMEngine.run(start=bed)``) is bit-identical to a
    run that settles by itself.

    Attributes
    ----------
    key
        Digest of everything the settling depended on; :meth:`DEMEngine.run` refuses a bed
        whose key differs from its own.
    steps
        Steps the settling took [-].
    seconds
        Wall time the settling took [s].
    """

    key: str
    steps: int
    seconds: float
    state: _Run = field(repr=False, compare=False)

    @property
    def kinetic_energy(self) -> float:
        """Kinetic energy left in the bed, translational and rotational [J]: how far from
        rest the settling brought it."""
        st = self.state
        m = np.asarray(st.part.mass)
        r = np.asarray(st.part.rad)
        return float(0.5 * np.sum(m * np.sum(st.vel**2, axis=1))
                     + 0.2 * np.sum(m * r**2 * np.sum(st.omg**2, axis=1)))


@dataclass
class _Phase:
    """Settling or excitation: time grid, motion, records and output arrays."""

    stepping: K.Stepping
    drive: K.Drive
    samples: K.Samples
    snaps: K.Snapshots
    state: np.ndarray = field(default_factory=lambda: K.record(K.RUN_STATE))
    ledger: np.ndarray = field(default_factory=lambda: K.record(K.LEDGER))
    stats: np.ndarray = field(default_factory=lambda: K.record(K.STATS))
    kernel: str = "gear"             # the integrator running now
    switch_time: float = math.nan    # when "auto" first handed over to Verlet [s]
    switches: int = 0                # hand-overs of "auto", both ways
    # landings run by each kernel: the running sum of -j at its starts and +j at its ends
    kernel_landings: dict = field(default_factory=dict)


_EMPTY = np.zeros(2)


def _drive(kind: int, z0: float = 0.0, amplitude: float = 0.0, omega: float = 0.0,
           table_dt: float = 1.0, table=(_EMPTY, _EMPTY, _EMPTY), mass: float = 1.0,
           damping: float = 0.0, stiffness: float = 0.0) -> K.Drive:
    return K.Drive(int(kind), float(z0), float(amplitude), float(omega), float(table_dt),
                   *table, float(mass), float(damping), float(stiffness))


class DEMEngine:
    """A DEM run of spheres in a moving box (paper Sect. 3).

    Parameters
    ----------
    particles
        The spheres (positions in the container frame).
    container
        The box and its wall material.
    contact
        Contact law parameters.
    motion
        :class:`HarmonicMotion` (default: at rest), :class:`PrescribedMotion` or
        :class:`StructureMotion`.
    integrator
        ``"verlet"`` (fixed-step velocity Verlet), ``"gear"`` (variable-step fifth-order
        Gear predictor-corrector, the paper's) or ``"auto"`` (Gear, handing the excitation
        over to Verlet where Gear's steps fall below :data:`AUTO_COST_RATIO` x Verlet's).
    safety
        Time step = ``safety`` x Hertz contact duration at the reference speed (the Gear
        integrator uses it as the step at a contact onset) [-].
    gravity
        g [m/s^2], acting along -z.
    gear_tolerance, gear_velocity_scale
        Error tolerance [-] and velocity scale [m/s] of the Gear step control.
    gear_adaptive
        False keeps the Gear step fixed (for convergence studies).
    max_step
        Upper bound of the Gear step [s] (default: 1e-4 s).
    skin
        Verlet-list skin [m] (default 0.2 x smallest radius).
    settle_time
        Settling under gravity in the resting container before the excitation [s]
        (default sqrt(2 Lz / g) + 0.05 s; 0 to skip).
    max_overlap
        Overlap / radius at which the run stops [-] (default None: never; large overlaps
        are a regime of fast impacts, reported as ``max_overlap_ratio`` and warned about
        above ``OVERLAP_WARNING_LIMIT``).
    reference_velocity
        Impact speed at which the contact duration is evaluated [m/s] (default from the
        excitation and the free fall over the container height).
    gear_contact_bound
        Bound the Gear step by the time to the next contact (never below
        ``GEAR_ONSET_FACTOR`` x the Verlet step). Off by default: in a dense bed some pair
        is always about to touch, and the bound doubled the steps at unchanged accuracy;
        the error control with rejection resolves onsets (docs/dem.md).
    seed
        Recorded in the results (the engine itself is deterministic).
    auto_cost_ratio
        ``integrator="auto"`` hands over to Verlet when Gear's mean step falls below this
        times Verlet's [-] (default :data:`AUTO_COST_RATIO`; ``inf``: at the first
        judgement, 0: never).
    gear_free_flight
        Take the spheres that cannot touch anything before a horizon out of the Gear step
        (multiple time stepping; their free flight is an exact parabola): the same physics
        at a lower cost per step where few spheres are in contact (default True;
        :mod:`pdamper.dem.kernels.flights`, docs/dem.md).
    transient_cycles, gear_transient_tolerance
        The first ``transient_cycles`` cycles of a harmonic excitation (the start from rest,
        which the averaged window of a Level II run skips) run at the Gear tolerance
        ``gear_transient_tolerance`` [-] instead of ``gear_tolerance`` (default 0: none;
        the tolerance defaults to ``gear_tolerance``). The averaged window sees only the
        motion after them, which for a chaotic bed starts another realisation
        (docs/fields.md, section 1).
    """

    def __init__(self, particles: ParticleSet, container: Container,
                 contact: ContactParameters,
                 motion: HarmonicMotion | PrescribedMotion | StructureMotion | None = None,
                 integrator: str = "verlet", safety: float = DEFAULT_SAFETY,
                 gravity: float = STANDARD_GRAVITY, gear_tolerance: float = DEFAULT_GEAR_TOLERANCE,
                 gear_velocity_scale: float = DEFAULT_GEAR_VELOCITY_SCALE,
                 gear_adaptive: bool = True, max_step: float = 1e-4,
                 skin: float | None = None, settle_time: float | None = None,
                 max_overlap: float | None = None, reference_velocity: float | None = None,
                 gear_contact_bound: bool = False, seed: int | None = None,
                 auto_cost_ratio: float = AUTO_COST_RATIO, gear_free_flight: bool = True,
                 transient_cycles: int = 0, gear_transient_tolerance: float | None = None):
        for name, value, cls in (("particles", particles, ParticleSet),
                                 ("container", container, Container),
                                 ("contact", contact, ContactParameters)):
            if not isinstance(value, cls):
                raise InputError(name, f"must be a {cls.__name__}, got {type(value).__name__}")
        self.particles = particles
        self.container = container
        self.contact = contact
        motions = (HarmonicMotion, PrescribedMotion, StructureMotion)
        if motion is not None and not isinstance(motion, motions):
            raise InputError("motion", f"must be one of {', '.join(m.__name__ for m in motions)} "
                             f"or None (at rest), got {motion!r}")
        self.motion = motion or HarmonicMotion()
        if integrator not in INTEGRATORS:
            raise InputError("integrator", f"must be one of {', '.join(INTEGRATORS)}, "
                             f"got {integrator!r}")
        self.integrator = integrator
        self.safety = check_range("safety", safety, low=0.0, high=1.0, low_inclusive=False)
        self.gravity = check_range("gravity", gravity, low=0.0, unit="m/s^2")
        self.gear_tolerance = check_range("gear_tolerance", gear_tolerance, low=0.0,
                                          low_inclusive=False)
        self.gear_velocity_scale = check_range("gear_velocity_scale", gear_velocity_scale,
                                               low=0.0, low_inclusive=False, unit="m/s")
        self.gear_adaptive = bool(gear_adaptive)
        self.max_step = check_range("max_step", max_step, low=0.0, low_inclusive=False, unit="s")
        self.max_overlap = (math.inf if max_overlap is None else
                            check_range("max_overlap", max_overlap, low=0.0, high=1.0,
                                        low_inclusive=False))
        self.gear_contact_bound = bool(gear_contact_bound)
        self.gear_free_flight = bool(gear_free_flight)
        self.transient_cycles = check_whole("transient_cycles", transient_cycles, low=0)
        self.gear_transient_tolerance = (
            self.gear_tolerance if gear_transient_tolerance is None else
            check_range("gear_transient_tolerance", gear_transient_tolerance, low=0.0,
                        low_inclusive=False))
        self.auto_cost_ratio = (math.inf if auto_cost_ratio == math.inf else
                                check_range("auto_cost_ratio", auto_cost_ratio, low=0.0))
        self.seed = seed
        r = particles.radius
        self.skin = (0.2 * float(r.min()) if skin is None
                     else check_range("skin", skin, low=0.0, low_inclusive=False, unit="m"))
        lx, ly, lz = self.container.box
        if settle_time is None:
            settle_time = free_fall_settling(lz, self.gravity)
        self.settle_time = check_range("settle_time", settle_time, low=0.0, unit="s")
        pos = particles.positions
        tol = min(self.max_overlap, OVERLAP_WARNING_LIMIT) * r  # initial wall overlaps up to it
        lo = pos - r[:, None] + tol[:, None]
        hi = pos + r[:, None] - tol[:, None]
        if np.any(lo < 0.0) or np.any(hi > np.array(self.container.box)):
            raise InputError("particles.positions", "every sphere must lie inside the container "
                             f"box {self.container.box} m")
        if 2 * r.max() > min(lx, ly, lz):
            raise InputError("particles.radius", "the spheres must fit into the container")
        self._build_tables()
        self.reference_velocity = (self._default_reference_velocity() if reference_velocity is None
                                   else check_range("reference_velocity", reference_velocity,
                                                    low=0.0, low_inclusive=False, unit="m/s"))
        #: Speed that sets the settling step [m/s]: the given reference speed, else the free
        #: fall over the container height (not the motion: one settled bed serves all).
        self.settle_reference_velocity = (self._fall_velocity() if reference_velocity is None
                                          else self.reference_velocity)
        self._check_physics(reference_velocity is not None)
        self.contact_time = self._contact_time(self.reference_velocity)
        self.rayleigh_time = min(rayleigh_time(float(ri), m)
                                 for ri, m in zip(r, particles.material, strict=True))
        self.time_step = self.safety * self.contact_time

    # ------------------------------------------------------------------ set-up
    def _check_physics(self, given_speed: bool) -> None:
        """Refuse a run without physical meaning (:func:`pdamper.resources.check_impacts`):
        spheres below 0.1 mm, strokes above 10 m, impacts at the reference speed (the
        fastest the motion implies) above a tenth of the bar wave speed or with a Hertz
        contact radius above half the sphere radius, an excitation faster than a contact.
        Every DEM run of every command and of the API passes here, before anything runs."""
        m = self.motion
        frequency, speed_field, frequency_field = None, "reference_velocity", "frequency"
        remedy = "lower reference_velocity"
        if isinstance(m, HarmonicMotion):
            resources.check_stroke(m.amplitude, "amplitude")
            frequency = m.frequency if m.frequency > 0 else None
            if not given_speed:  # the motion sets the speed: name the input further off
                speed_field = max((("frequency", m.frequency / 10.0),
                                   ("amplitude", m.amplitude / 0.032)), key=lambda d: d[1])[0]
                remedy = "lower the frequency or the amplitude"
        elif isinstance(m, StructureMotion):
            resources.check_stroke(m.x0, "x0", "the release deflection")
            frequency, frequency_field = m.natural_frequency, "stiffness"
            if not given_speed:
                speed_field, remedy = "x0", "lower x0 or the stiffness"
        elif not given_speed:
            speed_field, remedy = "motion", "slow the motion down"
        p = self.particles
        spheres = [(float(r), mat) for r, mat in zip(p.radius, p.material, strict=True)]
        resources.check_impacts(spheres, self.container.material, self.reference_velocity,
                                speed_field=speed_field, frequency=frequency,
                                frequency_field=frequency_field, radius_field="particles.radius",
                                between_spheres=p.count > 1, remedy=remedy)

    def _build_tables(self) -> None:
        p = self.particles
        names: list[str] = []
        mats = []
        for m in p.material:
            if m.name not in names:
                names.append(m.name)
                mats.append(m)
        nm = len(mats)
        self._pmat = np.array([names.index(m.name) for m in p.material], dtype=np.int64)
        npair = nm * nm + nm
        wall = self.container.material
        c = self.contact
        curves = []
        estar = np.zeros(npair)
        mu = np.zeros(npair)
        for a in range(nm):
            for b in range(nm):
                q = a * nm + b
                estar[q] = effective_modulus(mats[a], mats[b])
                mu[q] = c.friction_pp
                curves.append(c.curve(mats[a].name, mats[b].name, wall=False))
        for a in range(nm):
            q = nm * nm + a
            estar[q] = effective_modulus(mats[a], wall)
            mu[q] = c.friction_pw
            curves.append(c.curve(mats[a].name, wall.name, wall=True))
        tabs = [cv.tabulate() for cv in curves]
        nmax = max(len(v) for v, _ in tabs)
        cor_v = np.zeros((npair, nmax))
        cor_e = np.ones((npair, nmax))
        cor_n = np.zeros(npair, dtype=np.int64)
        for q, (v, e) in enumerate(tabs):
            cor_v[q, :len(v)] = v
            cor_e[q, :len(e)] = e
            cor_n[q] = len(v)
        self._mats_list = mats
        # last entry: memo (COR, damping factor) per pair type for the kernels, emptied (-1)
        # at the start of every run (run()), so that no state carries over between runs
        self._pair_types = K.PairTypes(estar, mu, cor_v, cor_e, cor_n, np.full((npair, 2), -1.0))
        self._kwall = np.array([hertz_stiffness(estar[nm * nm + a], float(ri))
                                for a, ri in zip(self._pmat, p.radius, strict=True)])

    def _fall_velocity(self) -> float:
        """Reference speed without the motion: free fall over the container height, the
        initial speeds [m/s]."""
        v0 = float(np.max(np.linalg.norm(self.particles.velocities, axis=1)))
        return max(math.sqrt(2.0 * self.gravity * self.container.box[2]), 2.0 * v0, 0.5)

    def _default_reference_velocity(self) -> float:
        v = math.sqrt(2.0 * self.gravity * self.container.box[2])
        m = self.motion
        if isinstance(m, HarmonicMotion):
            v += 2.0 * m.amplitude * m.angular_frequency
        elif isinstance(m, StructureMotion):
            v += 2.0 * (abs(m.x0) * 2 * math.pi * m.natural_frequency + abs(m.v0))
            if m.force_amplitude > 0:  # the load's steady speed without particles
                w = 2.0 * math.pi * m.force_frequency
                v += 2.0 * m.force_amplitude * w / abs(complex(m.stiffness - m.mass * w * w,
                                                               w * m.damping))
        elif isinstance(m, PrescribedMotion):
            _, _, vv, _ = m.table(0.5)
            v += 2.0 * float(np.max(np.abs(vv)))
        return max(v, self._fall_velocity())

    def _contact_time(self, v: float) -> float:
        """Shortest elastic Hertz contact duration of the pair types at speed v [s]."""
        p = self.particles
        estar = self._pair_types.estar
        nm = len(self._mats_list)
        masses = p.masses
        tc = math.inf
        i_small = int(np.argmin(masses))
        for i in {i_small, int(np.argmin(p.radius))}:
            m, r, a = float(masses[i]), float(p.radius[i]), int(self._pmat[i])
            for b in range(nm):
                k = hertz_stiffness(estar[a * nm + b], 0.5 * r)
                tc = min(tc, contact_duration(0.5 * m, k, v))
            k = hertz_stiffness(estar[nm * nm + a], r)
            tc = min(tc, contact_duration(m, k, v))
        return tc

    # ------------------------------------------------------------------ run
    def run(self, duration: float, sample_rate: float = 2000.0,
            snapshot_rate: float | None = None, settle: bool = True, *,
            stop: Callable[[DEMResult], bool] | None = None,
            chunk_seconds: float = DEFAULT_CHUNK_SECONDS,
            start: SettledBed | None = None, step_profile: bool = False) -> DEMResult:
        """Settle, then run the excitation for ``duration`` [s].

        The kernels run in chunks of about ``chunk_seconds`` of wall time; between chunks
        Python handles signals (Ctrl-C ends a run within about that time) and asks
        ``stop``. The chunking does not change the result (bit-identical to one call).

        Parameters
        ----------
        duration
            Simulated time of the excitation [s].
        sample_rate
            Samples per second of the time series [Hz]; with a harmonic motion it is
            rounded so that a cycle holds a whole number of samples.
        snapshot_rate
            Particle snapshots per second [Hz] (default: none except the first and last).
        settle
            Run the settling phase first (``settle_time``).
        stop
            Called after each chunk of the excitation with the partial result (the samples
            recorded so far); True ends the run there. With a harmonic motion it is asked
            only at the end of whole excitation cycles. A stopped run returns the recorded
            part (``stopped_early``; its ``duration`` is shorter than asked), exactly what a
            run of that length gives.
        chunk_seconds
            Target wall time of one kernel call [s] (``math.inf``: one call per phase).
        start
            A bed this engine's settling would give (:meth:`settle`, possibly of another
            engine of the same particles, container, contact law and step settings): the
            excitation starts from it instead of settling (``settle`` is then ignored).
        step_profile
            Record the steps, sphere-steps, rejected steps and integrator wall time of each
            sample interval (``DEMResult.steps_per_sample`` ..., binned over the cycle by
            :meth:`DEMResult.step_profile`): the excitation then runs one sample per kernel
            call, a call's dispatch (~40 us here) per sample, included in its wall time
            (+3 % CPU at 20 Hz / 200 mm, +30 % at 10 Hz / 32 mm with the 4 kHz sampling of
            Level II runs); the result is otherwise the same to the bit (the chunking does
            not change it).
        """
        grid = self._sample_grid(duration, sample_rate, snapshot_rate)
        self._require(grid, settle and start is None)
        if start is not None:
            run = self._settled_run(start)
        else:
            run = self._allocate(grid)
            if settle and self.settle_time > 0:
                self._settle(run, chunk_seconds)
        return self._excite(run, grid, stop, chunk_seconds, bool(step_profile))

    def settle(self, chunk_seconds: float = DEFAULT_CHUNK_SECONDS) -> SettledBed:
        """Settle the particles under gravity (``settle_time``), the container at rest at
        its start position; the :class:`SettledBed` that :meth:`run` can start from."""
        run = self._allocate(self._sample_grid(self.settle_time or 1.0, 2.0, None))
        if self.settle_time > 0:
            self._settle(run, chunk_seconds)
        return SettledBed(self.settle_key, run.settle_steps, run.settle_seconds,
                          copy.deepcopy(run))

    @property
    def settle_key(self) -> str:
        """Digest of what the settling depends on: particles, container, contact law, step
        settings and the container's start position, not the rest of the motion."""
        stp = self._stepping(0.0, 1.0, 2, 0, self._first_kernel, settling=True)
        what = (self.particles, self.container.box, self.container.material, self.contact,
                self.gravity, self.skin, self.settle_time, self._first_kernel,
                stp._replace(half=0.0, nsamp=0), self._start_position())
        return hashlib.sha256(pickle.dumps(what, protocol=4)).hexdigest()[:20]

    def _settled_run(self, bed: SettledBed) -> _Run:
        """A copy of the run state of ``bed`` (checked to be this engine's settling)."""
        if not isinstance(bed, SettledBed):
            raise InputError("start", f"must be a SettledBed, got {type(bed).__name__}")
        if bed.key != self.settle_key:
            raise InputError("start", "the bed was settled with other particles, container, "
                             "contact law, step settings or start position than this run's; "
                             "settle it with this engine (DEMEngine.settle)")
        run = copy.deepcopy(bed.state)
        run.settle_steps, run.settle_seconds, run.settle_reused = 0, 0.0, True
        return run

    def _sample_grid(self, duration: float, sample_rate: float,
                     snapshot_rate: float | None) -> _SampleGrid:
        check_range("duration", duration, low=0.0, low_inclusive=False, unit="s")
        check_range("sample_rate", sample_rate, low=0.0, low_inclusive=False, unit="Hz")
        m = self.motion
        freq = m.frequency if isinstance(m, HarmonicMotion) and m.frequency > 0 else None
        per_cycle = 0
        if freq is not None:
            per_cycle = max(4, int(round(sample_rate / freq)))
            interval = 1.0 / (freq * per_cycle)
        else:
            interval = 1.0 / sample_rate
        nsamp = int(math.floor(duration / interval + 1e-9)) + 1
        if nsamp < 2:
            raise InputError("sample_rate", f"gives fewer than 2 samples in {duration} s")
        if snapshot_rate is None:
            snap_every = nsamp - 1
        else:
            check_range("snapshot_rate", snapshot_rate, low=0.0, low_inclusive=False, unit="Hz")
            snap_every = max(1, int(round(1.0 / (snapshot_rate * interval))))
        return _SampleGrid(duration=duration, interval=interval, nsamp=nsamp,
                           snap_every=snap_every, per_cycle=per_cycle, frequency=freq,
                           snapshots_requested=snapshot_rate is not None)

    def _require(self, grid: _SampleGrid, settle: bool) -> None:
        """Refuse a run that no machine can do (:func:`pdamper.resources.require`, hard
        limits: more memory than this machine has, months of computing), judged from the
        sample grid's numbers before any array is allocated."""
        snapshots = grid.nsamp / grid.snap_every + 2
        simulated = grid.duration + (self.settle_time if settle else 0.0)
        resources.require(resources.dem_run_cost(
            self.particles.count, grid.duration, simulated, self.time_step, grid.nsamp,
            snapshots, drivers=(("duration", grid.duration / 1.0),
                                ("sample_rate", grid.nsamp / grid.duration / 2000.0),
                                ("snapshot_rate", snapshots / grid.duration / 2000.0))),
            force=True)

    def _allocate(self, grid: _SampleGrid) -> _Run:
        """Every array of a run, once: particles, contact lists, histories, work."""
        p = self.particles
        n = p.count
        self._pair_types.memo[:] = -1.0  # the onset-damping memo starts empty in every run
        lx, ly, lz = self.container.box
        rmax = float(p.radius.max())
        rmin = float(p.radius.min())
        cell = 2.0 * rmax + self.skin
        ncx, ncy, ncz = (max(1, int(lx // cell)), max(1, int(ly // cell)), max(1, int(lz // cell)))
        bound = ((2 * rmax + self.skin + rmin) / rmin) ** 3
        cap = int(n * math.ceil(min(bound, n)) + 16)
        world = K.World(float(lx), float(ly), float(lz), float(self.gravity), float(self.skin),
                        float(cell), ncx, ncy, ncz)
        c = self.contact
        law = K.Law(DAMPING_CODES[c.damping_model], len(self._mats_list),
                    float(c.regularisation_velocity), float(c.min_impact_velocity),
                    float(c.reimpact_factor))
        part = K.Particles(p.radius.copy(), p.masses, p.inertia, self._kwall, self._pmat,
                           1.0 / p.masses, 1.0 / p.inertia)
        nbrs = K.Neighbours(K.empty_pair_contacts(n, cap), K.empty_pair_contacts(n, cap),
                            np.zeros(ncx * ncy * ncz, np.int64), np.zeros(n, np.int64),
                            np.zeros((n, 3)))
        walls = K.WallContacts(np.zeros((n, 6), np.int64), np.zeros((n, 6)), np.zeros((n, 6)),
                               np.zeros(4 * n + 64, np.int64))
        work = K.Work(np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)))
        nord = K.Nordsieck(np.zeros((6, n, 3)), np.zeros((5, n, 3)), np.zeros(6), np.zeros(6))
        flights = K.empty_flights(n)
        z_start = self._start_position()
        pos = p.positions.copy()
        pos[:, 2] += z_start
        return _Run(pos=pos, vel=p.velocities.copy(), omg=p.angular_velocities.copy(),
                    world=world, law=law, part=part, nbrs=nbrs, walls=walls, work=work,
                    nord=nord, flights=flights, z_start=z_start,
                    pair_types=self._pair_types)

    def _start_position(self) -> float:
        """Container position at the start of the excitation [m]."""
        m = self.motion
        if isinstance(m, StructureMotion):
            return float(m.x0)
        if isinstance(m, PrescribedMotion):
            return float(m.table(2 * m.sample_interval)[1][0])
        return 0.0

    @property
    def _first_kernel(self) -> str:
        return "verlet" if self.integrator == "verlet" else "gear"

    def _stepping(self, t0: float, half: float, nsamp: int, snap_every: int,
                  kernel: str, settling: bool = False) -> K.Stepping:
        """Step of a phase run by ``kernel``: Verlet's divides the half sample interval;
        Gear's bounds. ``settling``: from :attr:`settle_reference_velocity`, not from the
        motion, so that a settled bed serves every motion (:class:`SettledBed`)."""
        v_design = self.settle_reference_velocity if settling else self.reference_velocity
        dt0 = (self.safety * self._contact_time(v_design) if settling else self.time_step)
        verlet_like = kernel == "verlet" or not self.gear_adaptive
        if verlet_like:
            dt = half / max(1, int(math.ceil(half / dt0 - 1e-9)))
        else:
            dt = min(dt0, half)
        adaptive_gear = kernel == "gear" and self.gear_adaptive
        return K.Stepping(
            t0=float(t0), half=float(half), nsamp=int(nsamp), snap_every=int(snap_every),
            dt=float(dt), dt_min=1e-3 * dt0, dt_max=float(max(self.max_step, dt0)),
            dt_contact=dt0 * (GEAR_ONSET_FACTOR if kernel == "gear" else 1.0),
            # variable-step Gear: the friction cap never stiffer than at a step of
            # GEAR_FRICTION_CAP_FACTOR x dt0 (the Verlet step)
            h_cap=float(GEAR_FRICTION_CAP_FACTOR * dt0 if adaptive_gear else 0.0),
            tol=float(self.gear_tolerance), v_scale=float(self.gear_velocity_scale),
            adaptive=1 if self.gear_adaptive else 0,
            # The kernels can bound the Gear step by the time to the next contact; off by
            # default: in a dense bed some pair is always about to touch and the bound
            # doubled the steps at unchanged accuracy (docs/dem.md).
            contact_bound=1 if adaptive_gear and self.gear_contact_bound else 0,
            v_design=float(v_design), dt_design=float(dt0),
            follow_impacts=1 if (kernel == "verlet" or adaptive_gear) else 0,
            v_limit=20.0 * v_design + 10.0,
            max_overlap=float(self.max_overlap),  # inf unless the user asks for a stop
            free_flight=1 if adaptive_gear and self.gear_free_flight else 0)

    def _settle(self, run: _Run, chunk_seconds: float) -> None:
        """Settling under gravity, the container at rest at its start position."""
        nsamp = 11
        stp = self._stepping(0.0, self.settle_time / 20.0, nsamp, 0, self._first_kernel,
                             settling=True)
        drive = _drive(K.MOTION_HARMONIC, z0=run.z_start)
        phase = _Phase(stp, drive, K.empty_samples(nsamp), K.empty_snapshots(0, run.pos.shape[0]),
                       kernel=self._first_kernel)
        t1 = time.perf_counter()
        self._start(run, phase, "settling")
        self._advance(run, phase, 2 * (nsamp - 1), chunk_seconds, None, 0, "settling")
        run.settle_seconds = time.perf_counter() - t1
        run.settle_steps = int(phase.stats[0]["steps"])
        log.info("settled %d particles in %d steps (%.3f s)", run.pos.shape[0],
                 run.settle_steps, run.settle_seconds)

    def _excite(self, run: _Run, grid: _SampleGrid, stop, chunk_seconds: float,
                step_profile: bool = False) -> DEMResult:
        """The excitation phase, chunk by chunk; the result of the recorded samples."""
        m = self.motion
        stp = self._stepping(0.0, 0.5 * grid.interval, grid.nsamp, grid.snap_every,
                             self._first_kernel)
        transient_end = 0  # landing where the transient tolerance ends
        if self.transient_cycles > 0 and grid.per_cycle > 0:
            transient_end = min(2 * grid.per_cycle * self.transient_cycles, 2 * (grid.nsamp - 1))
            stp = stp._replace(tol=float(self.gear_transient_tolerance))
        rs = K.record(K.RUN_STATE)
        if isinstance(m, HarmonicMotion):
            drive = _drive(K.MOTION_HARMONIC, amplitude=m.amplitude, omega=m.angular_frequency)
        elif isinstance(m, PrescribedMotion):
            _, tz, tv, ta = m.table(grid.duration + 2 * grid.interval)
            drive = _drive(K.MOTION_TABLE, table_dt=m.sample_interval, table=(tz, tv, ta))
        else:
            # a harmonic load rides on the harmonic fields (amplitude [N], omega, phase)
            drive = _drive(K.MOTION_STRUCTURE, mass=m.mass, damping=m.damping,
                           stiffness=m.stiffness, amplitude=m.force_amplitude,
                           omega=2.0 * math.pi * m.force_frequency, z0=m.force_phase)
            rs[0]["zc"], rs[0]["vc"] = m.x0, m.v0
        nsnap = (grid.nsamp - 1) // grid.snap_every + 1
        phase = _Phase(stp, drive, K.empty_samples(grid.nsamp),
                       K.empty_snapshots(nsnap, run.pos.shape[0]), rs, kernel=self._first_kernel)
        t1 = time.perf_counter()
        self._start(run, phase, "excitation")
        # per sample interval: steps, sphere-steps, rejected steps, kernel wall time
        profile = np.zeros((4, grid.nsamp)) if step_profile else None
        check = None
        if stop is not None:
            def check(j: int) -> bool:
                return bool(stop(self._result(run, phase, grid, j // 2, time.perf_counter() - t1,
                                              profile)))
        j = self._advance(run, phase, 2 * (grid.nsamp - 1), chunk_seconds, check,
                          2 * grid.per_cycle if stop is not None else 0, "excitation",
                          transient_end, profile)
        wall = time.perf_counter() - t1
        log.info("%s: %d steps in %.3f s", self.integrator, phase.stats[0]["steps"], wall)
        if not math.isnan(phase.switch_time):
            log.info("auto: Gear handed over to Verlet at t = %.4g s", phase.switch_time)
        res = self._result(run, phase, grid, j // 2, wall, profile)
        if res.max_overlap_ratio > OVERLAP_WARNING_LIMIT:
            # one message text: Python shows it once per place, not once per map point
            warnings.warn(f"DEM overlaps beyond {100 * OVERLAP_WARNING_LIMIT:g} % of the radius "
                          "(fast impacts; Hertz's contact outside its small-strain range, "
                          "real materials would yield): see DEMResult.max_overlap_ratio",
                          LargeOverlapWarning, stacklevel=3)
        return res

    def _start(self, run: _Run, phase: _Phase, name: str) -> None:
        a = run.kernel_args(phase)
        if phase.kernel == "verlet":
            _verlet.verlet_start(*a[:12], phase.ledger, phase.state, phase.stats, phase.samples,
                           phase.snaps)
        else:
            _gear.gear_start(*a[:12], run.nord, run.flights, phase.ledger, phase.state, phase.stats,
                         phase.samples, phase.snaps)
        self._check(phase, name)

    def _advance(self, run: _Run, phase: _Phase, j_end: int, chunk_seconds: float, check,
                 cycle: int, name: str, transient_end: int = 0,
                 profile: np.ndarray | None = None) -> int:
        """Advance to landing ``j_end`` in chunks of about ``chunk_seconds`` of wall time,
        ending on samples (even landings); ``check(j)`` after each chunk (only at the ends
        of whole cycles of ``cycle`` landings when ``cycle > 0``). At landing
        ``transient_end`` (even, > 0) the Gear tolerance becomes ``gear_tolerance``.
        With ``profile`` (4 x samples) the chunks are one sample each, and its columns get
        the steps, sphere-steps, rejected steps and kernel wall time of each.
        Returns the last landing reached."""
        a = run.kernel_args(phase)
        tail = (phase.ledger, phase.state, phase.stats, phase.samples, phase.snaps)
        j = 0
        size = 2  # landings of the first chunk; then sized from the measured rate
        # "auto": decisions at fixed landings of the excitation (module constants AUTO_*)
        half = phase.stepping.half
        window = 2 * max(1, int(round(AUTO_WINDOW / (2.0 * half))))
        auto = self.integrator == "auto" and name == "excitation"
        decide = window          # landing of the next decision
        span = AUTO_FIRST_SPAN   # windows of Verlet before the next probe of Gear
        last = (0, 0)            # landing and steps at the start of the Gear window
        count = run.pos.shape[0]
        while j < j_end:
            target = (j_end if math.isinf(chunk_seconds) and profile is None
                      else min(j_end, j + size))
            if cycle > 0 and target < j_end:
                nxt = (j // cycle + 1) * cycle
                target = min(target, nxt) if nxt > j else target
            if auto:
                target = min(target, decide)
            if j < transient_end:
                target = min(target, transient_end)
            target += target % 2
            target = min(target, j_end)
            if profile is not None:
                st = phase.stats[0]
                before = (int(st["steps"]), int(st["gear_steps"]), int(st["stepped"]),
                          int(st["rejects"]))
            t1 = time.perf_counter()
            if phase.kernel == "verlet":
                _verlet.verlet_advance(*a[:12], *tail, target)
            else:
                _gear.gear_advance(*a[:12], run.nord, run.flights, *tail, target)
            spent = time.perf_counter() - t1
            if profile is not None:
                steps = int(st["steps"]) - before[0]
                gear = int(st["gear_steps"]) - before[1]
                # Gear counts the spheres it stepped; velocity Verlet steps them all
                profile[:, target // 2] = (steps, int(st["stepped"]) - before[2]
                                           + (steps - gear) * count,
                                           int(st["rejects"]) - before[3], spent)
            self._check(phase, name)
            done = target - j
            j = target
            if j == transient_end:
                phase.stepping = phase.stepping._replace(tol=float(self.gear_tolerance))
                a = run.kernel_args(phase)
            if auto and j == decide and j < j_end:
                steps = int(phase.stats[0]["steps"])
                if phase.kernel == "gear":
                    mean_step = (j - last[0]) * half / max(steps - last[1], 1)
                    if mean_step < self.auto_cost_ratio * self._verlet_step(phase):
                        self._switch(run, phase, name, "verlet", j, half)
                        decide = j + span * window
                        span = min(2 * span, AUTO_MAX_SPAN)
                    else:
                        span = AUTO_FIRST_SPAN
                        decide = j + window
                else:  # probe: Gear for one window
                    self._switch(run, phase, name, "gear", j, half)
                    decide = j + window
                last = (j, int(phase.stats[0]["steps"]))
                a = run.kernel_args(phase)
            if not math.isinf(chunk_seconds) and profile is None:
                rate = spent / done
                size = max(2, min(4 * done, int(chunk_seconds / rate) if rate > 0 else 4 * done))
            if check is not None and j < j_end and (cycle <= 0 or j % cycle == 0) and check(j):
                break
        return j

    def _verlet_step(self, phase: _Phase) -> float:
        """The step velocity Verlet would take now in ``phase``: the design step, made
        shorter for the fastest impact so far as :func:`verlet_advance` does it."""
        half = phase.stepping.half
        vi = float(phase.stats[0]["max_impact"])
        v = 1.25 * vi if vi > self.reference_velocity else self.reference_velocity
        dt = self.time_step * (self.reference_velocity / v) ** 0.2
        return half / max(1, int(math.ceil(half / dt - 1e-9)))

    def _switch(self, run: _Run, phase: _Phase, name: str, kernel: str, j: int,
                half: float) -> None:
        """Continue ``phase`` with ``kernel`` from landing ``j`` (``integrator="auto"``)."""
        old = phase.stepping
        # (the tolerance of the moment: a transient one stays until its landing)
        phase.stepping = self._stepping(old.t0, half, old.nsamp, old.snap_every,
                                        kernel)._replace(tol=old.tol)
        phase.kernel = kernel
        if kernel == "verlet":
            if math.isnan(phase.switch_time):
                phase.switch_time = float(phase.state[0]["t"])
            _verlet.verlet_resume(*run.kernel_args(phase), phase.ledger, phase.state,
                                  phase.stats)
        else:
            # Gear's first step: Verlet's, from which its error control grows it
            _gear.gear_resume(*run.kernel_args(phase), run.nord, run.flights, phase.ledger, phase.state,
                              phase.stats, float(phase.state[0]["dt"]))
        phase.switches += 1
        phase.kernel_landings[kernel] = phase.kernel_landings.get(kernel, 0) - j
        other = "gear" if kernel == "verlet" else "verlet"
        phase.kernel_landings[other] = phase.kernel_landings.get(other, 0) + j
        self._check(phase, name)

    def _check(self, phase: _Phase, name: str) -> None:
        st = phase.stats[0]
        err = int(st["error"])
        if err != K.ERR_NONE:
            raise SimulationError(self._explain(err, float(st["t_error"]),
                                                float(st["error_value"]), phase.stepping, name,
                                                phase.kernel))

    def _result(self, run: _Run, phase: _Phase, grid: _SampleGrid, k: int,
                wall: float, profile: np.ndarray | None = None) -> DEMResult:
        """The result of samples ``0 .. k`` (k < nsamp - 1: a run stopped early, whose last
        force window is closed as at the end of a run)."""
        s = phase.samples
        st = phase.stats[0]
        ns = k + 1
        last = ns == grid.nsamp
        force = s.force[:ns].copy()
        if not last:
            lg = phase.ledger[0]
            span = s.time[k] - phase.state[0]["t_win"]
            if span > 0.0:
                force[k] = (lg["imp_x"] / span, lg["imp_y"] / span, lg["imp_z"] / span)
        every = grid.snap_every
        nq = k // every + 1
        snap_t = s.time[:ns:every][:nq].copy()
        snaps = [a[:nq].copy() for a in phase.snaps]
        if not last and not grid.snapshots_requested:  # first and last, as a whole run
            snap_t = np.append(snap_t, s.time[k])
            snaps = [np.concatenate([a, b[None]]) for a, b in
                     zip(snaps, (run.pos, run.vel, run.omg), strict=True)]
        p = self.particles
        return DEMResult(
            time=s.time[:ns].copy(), container_position=s.zc[:ns].copy(),
            container_velocity=s.vc[:ns].copy(), container_acceleration=s.ac[:ns].copy(),
            force=force, center_of_mass=s.com[:ns].copy(),
            kinetic_energy=s.kinetic[:ns].copy(), rotational_energy=s.rotational[:ns].copy(),
            potential_energy=s.potential[:ns].copy(), elastic_energy=s.elastic[:ns].copy(),
            dissipated_normal=s.dissipated_normal[:ns].copy(),
            dissipated_friction=s.dissipated_friction[:ns].copy(),
            container_work=s.container_work[:ns].copy(),
            snapshot_time=snap_t, snapshot_positions=snaps[0], snapshot_velocities=snaps[1],
            snapshot_angular_velocities=snaps[2],
            radius=p.radius.copy(), masses=p.masses, integrator=self.integrator,
            steps=int(st["steps"]), settle_steps=run.settle_steps,
            rebuilds=int(st["rebuilds"]), contact_onsets=int(st["onsets"]),
            rejected_steps=int(st["rejects"]), wall_seconds=wall,
            settle_seconds=run.settle_seconds, settle_reused=run.settle_reused,
            time_step=(float(phase.state[0]["dt"]) if phase.kernel == "verlet"
                       else phase.stepping.dt),
            integrator_switch_time=phase.switch_time,
            integrator_switches=phase.switches,
            verlet_time=phase.stepping.half * (phase.kernel_landings.get("verlet", 0)
                                               + (2 * k if phase.kernel == "verlet" else 0)),
            stepped_fraction=(float(st["stepped"]) / (p.count * float(st["gear_steps"]))
                              if st["gear_steps"] > 0 else 1.0),
            regroups=int(st["regroups"]),
            min_step=float(st["dt_lo"]), max_step=float(st["dt_hi"]),
            contact_time=self.contact_time, max_overlap_ratio=float(st["max_overlap"]),
            max_impact_velocity=float(st["max_impact"]),
            frequency=grid.frequency, container_mass=self.container.mass,
            requested_duration=grid.duration, stopped_early=not last, attrs=self.describe(),
            **({} if profile is None else {
                "steps_per_sample": profile[0, :ns].astype(np.int64),
                "stepped_per_sample": profile[1, :ns].astype(np.int64),
                "rejected_per_sample": profile[2, :ns].astype(np.int64),
                "kernel_seconds_per_sample": profile[3, :ns].copy()}))

    def _explain(self, err: int, t: float, val: float, stp: K.Stepping, phase: str,
                 kernel: str) -> str:
        dt = stp.dt
        tc = self.contact_time
        hint = (f"time step {dt:.3g} s too large for the contact time {tc:.3g} s; lower the "
                f"safety factor (now {self.safety:g})" if kernel == "verlet" else
                f"lower the Gear tolerance (now {self.gear_tolerance:g}) or the safety factor "
                f"(now {self.safety:g}, contact time {tc:.3g} s)")
        where = f"{phase} at t = {t:.6g} s"
        if err == K.ERR_NAN:
            return f"unstable DEM run: non-finite state ({where}); {hint}"
        if err == K.ERR_OVERLAP:
            return (f"DEM run stopped: overlap {100 * val:.3g} % of the radius exceeds the "
                    f"requested max_overlap {100 * self.max_overlap:g} % ({where}); large "
                    "overlaps are a regime of fast impacts (max_overlap=None runs on)")
        if err == K.ERR_ESCAPE:
            return f"unstable DEM run: a particle left the container ({where}); {hint}"
        if err == K.ERR_SPEED:
            return (f"unstable DEM run: particle speed {val:.3g} m/s beyond any physical value "
                    f"(energy blow-up, {where}); {hint}")
        if err == K.ERR_ENERGY:
            return (f"unstable DEM run: the energy ledger no longer closes (energy blow-up, "
                    f"{where}); {hint}")
        if err == K.ERR_LIST:
            return (f"unstable DEM run: neighbour list overflow, particles interpenetrate "
                    f"({where}); {hint}")
        return f"DEM run failed with code {err} ({where})"

    def describe(self) -> dict:
        """Inputs of the run as plain values (recorded in the results)."""
        from pdamper import __version__

        m = self.motion
        c = self.contact
        d = {
            "pdamper_version": __version__,
            "seed": -1 if self.seed is None else int(self.seed),
            "particles": int(self.particles.count),
            "integrator": self.integrator,
            "safety": self.safety,
            "time_step_s": self.time_step,
            "contact_time_s": self.contact_time,
            "rayleigh_time_s": self.rayleigh_time,
            "reference_velocity_m_s": self.reference_velocity,
            "gravity_m_s2": self.gravity,
            "box_m": list(self.container.box),
            "wall_material": self.container.material.name,
            "friction_pp": c.friction_pp,
            "friction_pw": c.friction_pw,
            "damping_model": c.damping_model,
            "regularisation_velocity_m_s": c.regularisation_velocity,
            "min_impact_velocity_m_s": c.min_impact_velocity,
            "restitution_pp": repr(c.restitution_pp),
            "restitution_pw": repr(c.restitution_pw),
            "settle_time_s": self.settle_time,
            "settle_reference_velocity_m_s": self.settle_reference_velocity,
            "skin_m": self.skin,
            "motion": type(m).__name__,
        }
        if self.integrator in ("gear", "auto"):
            d.update(gear_free_flight=int(self.gear_free_flight),
                     gear_tolerance=self.gear_tolerance,
                     gear_velocity_scale_m_s=self.gear_velocity_scale,
                     gear_adaptive=int(self.gear_adaptive), max_step_s=self.max_step)
            if self.transient_cycles > 0:
                d.update(transient_cycles=self.transient_cycles,
                         gear_transient_tolerance=self.gear_transient_tolerance)
        if isinstance(m, HarmonicMotion):
            d.update(amplitude_m=m.amplitude, frequency_hz=m.frequency)
        elif isinstance(m, StructureMotion):
            d.update(structure_mass_kg=m.mass, structure_damping_kg_s=m.damping,
                     structure_stiffness_n_m=m.stiffness, structure_x0_m=m.x0,
                     structure_v0_m_s=m.v0)
            if m.force_amplitude > 0:
                d.update(structure_force_n=m.force_amplitude,
                         structure_force_frequency_hz=m.force_frequency,
                         structure_force_phase_rad=m.force_phase)
        return d


def warmup(integrators: tuple[str, ...] = INTEGRATORS,
           motions: tuple[str, ...] = ("harmonic", "structure")) -> float:
    """Compile (or load from the numba cache) the kernels of ``integrators`` (default all
    of :data:`~pdamper.dem.model.INTEGRATORS`) for the container ``motions``
    (``"harmonic"``, ``"structure"``; default both); returns seconds.

    A run loads only the kernels it calls, when it first calls them; this loads them ahead
    (all of them: to fill the cache, or to leave compilation out of a timing). Loading every
    variant costs several times what one run's start-up loads (the variable-step kernels
    of Gear, the fixed-step ones of Verlet, ``auto``'s resume, each per motion).

    Separate processes may warm different integrators at once ("gear" in one, "verlet" in
    another): numba writes its cache files under temporary names and renames them. "auto"
    adds only its hand-over to the kernels of the other two."""
    t0 = time.perf_counter()
    from pdamper.contact.restitution import ConstantRestitution
    from pdamper.materials import PVC, S235

    for name in integrators:
        if name not in INTEGRATORS:
            raise InputError("integrators", f"must be among {', '.join(INTEGRATORS)}, got {name!r}")
    kinds = {"harmonic": HarmonicMotion(0.001, 10.0), "structure": StructureMotion(1.0, 0.1, 100.0)}
    for name in motions:
        if name not in kinds:
            raise InputError("motions", f"must be among {', '.join(kinds)}, got {name!r}")
    contact = ContactParameters(ConstantRestitution(0.8), ConstantRestitution(0.8), 0.1, 0.1)
    for integ in integrators:
        parts = ParticleSet(np.array([[0.02, 0.02, 0.006], [0.02, 0.02, 0.03]]), 0.005, S235)
        for motion in (kinds[m] for m in motions):
            # "auto" made to hand over to Verlet at its first judgement (5 ms) and to probe
            # Gear again one window later (10-15 ms): both resume kernels too
            DEMEngine(parts, Container((0.04, 0.04, 0.12), PVC), contact, motion,
                      integrator=integ, settle_time=0.0, auto_cost_ratio=math.inf).run(
                3.5 * AUTO_WINDOW if integ == "auto" else 0.002, sample_rate=1000.0)
    return time.perf_counter() - t0
