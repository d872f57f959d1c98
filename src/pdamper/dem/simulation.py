"""Python orchestration of the DEM engine (paper Sect. 3, "Discrete element method").

:class:`DEMEngine` turns the inputs of :mod:`pdamper.dem.model` into flat arrays, picks
the time step from the contact time scale, settles the particles under gravity in the
resting container, then runs the excitation with one call of a numba kernel of
:mod:`pdamper.dem.kernels` and returns a :class:`DEMResult`.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pdamper.constants import STANDARD_GRAVITY
from pdamper.contact.forces import DAMPING_EXACT, DAMPING_GONTHIER
from pdamper.contact.hertz import (
    contact_duration,
    effective_modulus,
    hertz_stiffness,
    rayleigh_time,
)
from pdamper.contact.law import ContactParameters
from pdamper.dem import kernels as K
from pdamper.dem.model import (
    DEFAULT_GEAR_TOLERANCE,
    DEFAULT_GEAR_VELOCITY_SCALE,
    DEFAULT_SAFETY,
    INTEGRATORS,
    Container,
    HarmonicMotion,
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
    frequency: float | None = None
    container_mass: float = 0.0
    attrs: dict = field(default_factory=dict)

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
                     energy_balance_error=self.energy_balance_error())
        ds.attrs.update(attrs)
        return ds

    def write_netcdf(self, path: str | Path, attrs: dict | None = None) -> Path:
        """Write :meth:`to_dataset` to NetCDF (h5netcdf) atomically (temp file + rename),
        with extra global ``attrs`` (e.g. the inputs of the run)."""
        from pdamper.files import atomic_write

        ds = self.to_dataset()
        ds.attrs.update(attrs or {})
        return atomic_write(path, lambda p: ds.to_netcdf(p, engine="h5netcdf"))

    def write_vtk(self, directory: str | Path) -> Path:
        """Write the snapshots as a ParaView series (.vtp files + .pvd index)."""
        from pdamper.dem.vtk import write_vtk_series

        return write_vtk_series(directory, self.snapshot_time, self.snapshot_positions,
                                self.snapshot_velocities, self.radius,
                                self.snapshot_angular_velocities)


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
        ``"verlet"`` (fixed-step velocity Verlet) or ``"gear"`` (variable-step fifth-order
        Gear predictor-corrector, the paper's).
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
        Largest allowed overlap / radius before the run stops [-] (default 0.05).
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
    """

    def __init__(self, particles: ParticleSet, container: Container,
                 contact: ContactParameters,
                 motion: HarmonicMotion | PrescribedMotion | StructureMotion | None = None,
                 integrator: str = "verlet", safety: float = DEFAULT_SAFETY,
                 gravity: float = STANDARD_GRAVITY, gear_tolerance: float = DEFAULT_GEAR_TOLERANCE,
                 gear_velocity_scale: float = DEFAULT_GEAR_VELOCITY_SCALE,
                 gear_adaptive: bool = True, max_step: float = 1e-4,
                 skin: float | None = None, settle_time: float | None = None,
                 max_overlap: float = 0.05, reference_velocity: float | None = None,
                 gear_contact_bound: bool = False, seed: int | None = None):
        for name, value, cls in (("particles", particles, ParticleSet),
                                 ("container", container, Container),
                                 ("contact", contact, ContactParameters)):
            if not isinstance(value, cls):
                raise InputError(name, f"must be a {cls.__name__}, got {type(value).__name__}")
        self.particles = particles
        self.container = container
        self.contact = contact
        self.motion = motion or HarmonicMotion()
        if integrator not in INTEGRATORS:
            raise InputError("integrator", f"must be 'gear' or 'verlet', got {integrator!r}")
        self.integrator = integrator
        self.safety = check_range("safety", safety, low=0.0, high=1.0, low_inclusive=False)
        self.gravity = check_range("gravity", gravity, low=0.0, unit="m/s^2")
        self.gear_tolerance = check_range("gear_tolerance", gear_tolerance, low=0.0,
                                          low_inclusive=False)
        self.gear_velocity_scale = check_range("gear_velocity_scale", gear_velocity_scale,
                                               low=0.0, low_inclusive=False, unit="m/s")
        self.gear_adaptive = bool(gear_adaptive)
        self.max_step = check_range("max_step", max_step, low=0.0, low_inclusive=False, unit="s")
        self.max_overlap = check_range("max_overlap", max_overlap, low=0.0, high=1.0,
                                       low_inclusive=False)
        self.gear_contact_bound = bool(gear_contact_bound)
        self.seed = seed
        r = particles.radius
        self.skin = (0.2 * float(r.min()) if skin is None
                     else check_range("skin", skin, low=0.0, low_inclusive=False, unit="m"))
        lx, ly, lz = self.container.box
        if settle_time is None:
            settle_time = (math.sqrt(2.0 * lz / self.gravity) + 0.05) if self.gravity > 0 else 0.0
        self.settle_time = check_range("settle_time", settle_time, low=0.0, unit="s")
        pos = particles.positions
        tol = self.max_overlap * r  # initial overlaps with the walls up to max_overlap
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
        self.contact_time = self._contact_time(self.reference_velocity)
        self.rayleigh_time = min(rayleigh_time(float(ri), m)
                                 for ri, m in zip(r, particles.material, strict=True))
        self.time_step = self.safety * self.contact_time

    # ------------------------------------------------------------------ set-up
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
        self._mats = (estar, mu, cor_v, cor_e, cor_n, np.full((npair, 2), -1.0))
        self._kwall = np.array([hertz_stiffness(estar[nm * nm + a], float(ri))
                                for a, ri in zip(self._pmat, p.radius, strict=True)])

    def _default_reference_velocity(self) -> float:
        lz = self.container.box[2]
        v = math.sqrt(2.0 * self.gravity * lz)
        m = self.motion
        if isinstance(m, HarmonicMotion):
            v += 2.0 * m.amplitude * m.angular_frequency
        elif isinstance(m, StructureMotion):
            v += 2.0 * (abs(m.x0) * 2 * math.pi * m.natural_frequency + abs(m.v0))
        elif isinstance(m, PrescribedMotion):
            _, _, vv, _ = m.table(0.5)
            v += 2.0 * float(np.max(np.abs(vv)))
        v0 = float(np.max(np.linalg.norm(self.particles.velocities, axis=1)))
        return max(v, 2.0 * v0, 0.5)

    def _contact_time(self, v: float) -> float:
        """Shortest elastic Hertz contact duration of the pair types at speed v [s]."""
        p = self.particles
        estar = self._mats[0]
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
            snapshot_rate: float | None = None, settle: bool = True) -> DEMResult:
        """Settle, then run the excitation for ``duration`` [s].

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
        """
        check_range("duration", duration, low=0.0, low_inclusive=False, unit="s")
        check_range("sample_rate", sample_rate, low=0.0, low_inclusive=False, unit="Hz")
        m = self.motion
        freq = m.frequency if isinstance(m, HarmonicMotion) and m.frequency > 0 else None
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
        nsnap = (nsamp - 1) // snap_every + 1

        p = self.particles
        n = p.count
        self._mats[5][:] = -1.0  # the onset-damping memo starts empty in every run
        lx, ly, lz = self.container.box
        rmax = float(p.radius.max())
        rmin = float(p.radius.min())
        cell = 2.0 * rmax + self.skin
        ncx, ncy, ncz = (max(1, int(lx // cell)), max(1, int(ly // cell)), max(1, int(lz // cell)))
        bound = ((2 * rmax + self.skin + rmin) / rmin) ** 3
        cap = int(n * math.ceil(min(bound, n)) + 16)
        lists = (np.zeros(n + 1, np.int64), np.zeros(cap, np.int64), np.zeros(cap, np.int64),
                 np.zeros(cap), np.zeros(cap), np.zeros(cap),
                 np.zeros(n + 1, np.int64), np.zeros(cap, np.int64), np.zeros(cap, np.int64),
                 np.zeros(cap), np.zeros(cap), np.zeros(cap),
                 np.zeros(ncx * ncy * ncz, np.int64), np.zeros(n, np.int64), np.zeros((n, 3)))
        wall_hist = (np.zeros((n, 6), np.int64), np.zeros((n, 6)), np.zeros(4 * n + 64, np.int64),
                     np.zeros((n, 6)))
        part = (p.radius.copy(), p.masses, p.inertia, self._kwall, self._pmat, 1.0 / p.masses,
                1.0 / p.inertia)
        work = (np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)),
                np.zeros(K.NOUT), np.zeros(3), np.zeros(3))
        gwork = (np.zeros((6, n, 3)), np.zeros((5, n, 3)), np.zeros(6),
                 np.zeros((6, n, 3)), np.zeros((5, n, 3)), np.zeros(6))

        fp = np.zeros(K.NFP)
        fp[K.FP_G] = self.gravity
        fp[K.FP_VREG] = self.contact.regularisation_velocity
        fp[K.FP_VMIN] = self.contact.min_impact_velocity
        fp[K.FP_REIMPACT] = self.contact.reimpact_factor
        fp[K.FP_LX], fp[K.FP_LY], fp[K.FP_LZ] = lx, ly, lz
        fp[K.FP_SKIN] = self.skin
        fp[K.FP_CELL] = cell
        fp[K.FP_MAXOVL] = self.max_overlap
        fp[K.FP_VLIMIT] = 20.0 * self.reference_velocity + 10.0
        fp[K.FP_TOL] = self.gear_tolerance
        fp[K.FP_VSCALE] = self.gear_velocity_scale
        ip = np.zeros(K.NIP, np.int64)
        ip[K.IP_MODEL] = DAMPING_EXACT if self.contact.damping_model == "exact" else DAMPING_GONTHIER
        ip[K.IP_NMAT] = len(self._mats_list)
        ip[K.IP_NCX], ip[K.IP_NCY], ip[K.IP_NCZ] = ncx, ncy, ncz

        tab_dummy = (np.zeros(2), np.zeros(2), np.zeros(2))
        cstate = np.zeros(3)
        if isinstance(m, StructureMotion):
            z_start = m.x0
        elif isinstance(m, PrescribedMotion):
            tt, tz, tv, ta = m.table(duration + 2 * interval)
            z_start = float(tz[0])
        else:
            z_start = 0.0

        pos = p.positions.copy()
        pos[:, 2] += z_start
        vel = p.velocities.copy()
        omg = p.angular_velocities.copy()
        stats = np.zeros(K.NSTATS, np.int64)
        fstats = np.zeros(K.NFSTATS)

        # ---------------- settling (container at rest at its start position)
        settle_steps = 0
        settle_seconds = 0.0
        if settle and self.settle_time > 0:
            half_s = self.settle_time / 20.0
            fp_s = fp.copy()
            ip_s = ip.copy()
            ip_s[K.IP_MOTION] = K.MOTION_HARMONIC
            fp_s[K.FP_Z0] = z_start
            ip_s[K.IP_NSAMP] = 11
            self._set_steps(fp_s, half_s)
            samples_s, snaps_s = K.empty_samples(11, 0, n)
            t1 = time.perf_counter()
            self._call(pos, vel, omg, cstate, part, lists, wall_hist, fp_s, ip_s, tab_dummy,
                       work, gwork, samples_s, snaps_s, stats, fstats, phase="settling")
            settle_seconds = time.perf_counter() - t1
            settle_steps = int(stats[K.S_STEPS])
            log.info("settled %d particles in %d steps (%.3f s)", n, settle_steps,
                     settle_seconds)
            stats[:] = 0
            fstats[:] = 0.0

        # ---------------- excitation
        fp[K.FP_T0] = 0.0
        self._set_steps(fp, 0.5 * interval)
        ip[K.IP_NSAMP] = nsamp
        ip[K.IP_SNAPEVERY] = snap_every
        tab = tab_dummy
        if isinstance(m, HarmonicMotion):
            ip[K.IP_MOTION] = K.MOTION_HARMONIC
            fp[K.FP_Z0] = 0.0
            fp[K.FP_X] = m.amplitude
            fp[K.FP_W] = m.angular_frequency
        elif isinstance(m, PrescribedMotion):
            ip[K.IP_MOTION] = K.MOTION_TABLE
            fp[K.FP_TABDT] = m.sample_interval
            tab = (tz, tv, ta)
        else:
            ip[K.IP_MOTION] = K.MOTION_STRUCTURE
            fp[K.FP_SM], fp[K.FP_SD], fp[K.FP_SK] = m.mass, m.damping, m.stiffness
            cstate[0], cstate[1] = m.x0, m.v0
        samples, snaps = K.empty_samples(nsamp, nsnap, n)
        t1 = time.perf_counter()
        self._call(pos, vel, omg, cstate, part, lists, wall_hist, fp, ip, tab, work, gwork,
                   samples, snaps, stats, fstats, phase="excitation")
        wall = time.perf_counter() - t1
        ts, cont, fpc, com, en = samples
        log.info("%s: %d steps in %.3f s", self.integrator, stats[K.S_STEPS], wall)
        dt_lo = float(fstats[K.F_DTLO])
        dt_hi = float(fstats[K.F_DTHI])
        return DEMResult(
            time=ts, container_position=cont[:, 0].copy(), container_velocity=cont[:, 1].copy(),
            container_acceleration=cont[:, 2].copy(), force=fpc, center_of_mass=com,
            kinetic_energy=en[:, 0].copy(), rotational_energy=en[:, 1].copy(),
            potential_energy=en[:, 2].copy(), elastic_energy=en[:, 3].copy(),
            dissipated_normal=en[:, 4].copy(), dissipated_friction=en[:, 5].copy(),
            container_work=en[:, 6].copy(),
            snapshot_time=ts[::snap_every][:nsnap].copy(), snapshot_positions=snaps[0],
            snapshot_velocities=snaps[1], snapshot_angular_velocities=snaps[2],
            radius=p.radius.copy(), masses=p.masses, integrator=self.integrator,
            steps=int(stats[K.S_STEPS]), settle_steps=settle_steps,
            rebuilds=int(stats[K.S_REBUILDS]), contact_onsets=int(stats[K.S_ONSETS]),
            rejected_steps=int(stats[K.S_REJECTS]),
            wall_seconds=wall, settle_seconds=settle_seconds, time_step=float(fp[K.FP_DT]),
            min_step=dt_lo, max_step=dt_hi, contact_time=self.contact_time,
            max_overlap_ratio=float(fstats[K.F_OVL]), frequency=freq,
            container_mass=self.container.mass, attrs=self.describe())

    def _set_steps(self, fp: np.ndarray, half: float) -> None:
        """Fix the step so that it divides the half sample interval (Verlet), Gear bounds."""
        dt0 = self.time_step
        fp[K.FP_HALF] = half
        if self.integrator == "verlet" or not self.gear_adaptive:
            m = max(1, int(math.ceil(half / dt0 - 1e-9)))
            fp[K.FP_DT] = half / m
        else:
            fp[K.FP_DT] = min(dt0, half)
        fp[K.FP_DTC] = dt0 * (GEAR_ONSET_FACTOR if self.integrator == "gear" else 1.0)
        fp[K.FP_DTMIN] = 1e-3 * dt0
        fp[K.FP_DTMAX] = max(self.max_step, dt0)
        # variable-step Gear: the friction cap never stiffer than at the Verlet step dt0
        adaptive_gear = self.integrator == "gear" and self.gear_adaptive
        fp[K.FP_HCAP] = dt0 if adaptive_gear else 0.0

    def _call(self, pos, vel, omg, cstate, part, lists, wall_hist, fp, ip, tab, work, gwork,
              samples, snaps, stats, fstats, phase: str) -> None:
        ip[K.IP_ADAPTIVE] = 1 if self.gear_adaptive else 0
        # The kernels can bound the Gear step by the time to the next contact (IP_TTC);
        # off: in a dense bed some pair is always about to touch and the bound doubled the
        # steps at unchanged accuracy; the error control with rejection handles onsets
        # and the skin bound (skin / (4 v_max)) caps the entry depth (docs/dem.md).
        ip[K.IP_TTC] = 1 if (self.integrator == "gear" and self.gear_adaptive
                             and self.gear_contact_bound) else 0
        if self.integrator == "verlet":
            K.run_verlet(pos, vel, omg, cstate, part, self._mats, lists, wall_hist, fp, ip, tab,
                         work, samples, snaps, stats, fstats)
        else:
            K.run_gear(pos, vel, omg, cstate, part, self._mats, lists, wall_hist, fp, ip, tab,
                       work, gwork, samples, snaps, stats, fstats)
        err = int(stats[K.S_ERR])
        if err != K.ERR_NONE:
            raise SimulationError(self._explain(err, float(fstats[K.F_TERR]),
                                                float(fstats[K.F_ERRVAL]), fp, phase))

    def _explain(self, err: int, t: float, val: float, fp: np.ndarray, phase: str) -> str:
        dt = fp[K.FP_DT]
        tc = self.contact_time
        hint = (f"time step {dt:.3g} s too large for the contact time {tc:.3g} s; lower the "
                f"safety factor (now {self.safety:g})" if self.integrator == "verlet" else
                f"lower the Gear tolerance (now {self.gear_tolerance:g}) or the safety factor "
                f"(now {self.safety:g}, contact time {tc:.3g} s)")
        where = f"{phase} at t = {t:.6g} s"
        if err == K.ERR_NAN:
            return f"unstable DEM run: non-finite state ({where}); {hint}"
        if err == K.ERR_OVERLAP:
            return (f"unstable DEM run: overlap {100 * val:.3g} % of the radius exceeds "
                    f"{100 * self.max_overlap:g} % ({where}); {hint}, or impacts are faster "
                    f"than the reference speed {self.reference_velocity:.3g} m/s")
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
            "skin_m": self.skin,
            "motion": type(m).__name__,
        }
        if self.integrator == "gear":
            d.update(gear_tolerance=self.gear_tolerance,
                     gear_velocity_scale_m_s=self.gear_velocity_scale,
                     gear_adaptive=int(self.gear_adaptive), max_step_s=self.max_step)
        if isinstance(m, HarmonicMotion):
            d.update(amplitude_m=m.amplitude, frequency_hz=m.frequency)
        elif isinstance(m, StructureMotion):
            d.update(structure_mass_kg=m.mass, structure_damping_kg_s=m.damping,
                     structure_stiffness_n_m=m.stiffness, structure_x0_m=m.x0,
                     structure_v0_m_s=m.v0)
        return d


def warmup() -> float:
    """Compile (or load from the numba cache) both integrator kernels; returns seconds."""
    t0 = time.perf_counter()
    from pdamper.contact.restitution import ConstantRestitution
    from pdamper.materials import PVC, S235

    contact = ContactParameters(ConstantRestitution(0.8), ConstantRestitution(0.8), 0.1, 0.1)
    for integ in INTEGRATORS:
        parts = ParticleSet(np.array([[0.02, 0.02, 0.006], [0.02, 0.02, 0.03]]), 0.005, S235)
        for motion in (HarmonicMotion(0.001, 10.0), StructureMotion(1.0, 0.1, 100.0)):
            DEMEngine(parts, Container((0.04, 0.04, 0.12), PVC), contact, motion,
                      integrator=integ, settle_time=0.0).run(0.002, sample_rate=1000.0)
    return time.perf_counter() - t0
