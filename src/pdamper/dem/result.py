"""The result of a DEM run: :class:`DEMResult` (time series, snapshots, counters) and
:meth:`DEMResult.summary`, the one scalar summary that the ``dem`` command, the map and
their JSON report.

Every quantity is SI. The step counts and wall times of a run come in two parts, named
apart: the excitation (the attributes ``steps``, ``wall_seconds``) and the settling before
it (``settle_steps``, ``settle_seconds``). In :meth:`DEMResult.summary` (the JSON of
``pdamper dem`` and the map's diagnostics) the keys ``steps`` and ``wall_seconds`` are the
whole run, settling included; ``excitation_steps``, ``excitation_wall_seconds`` the
excitation's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pdamper.errors import InputError, check_whole

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

    from pdamper.analysis.complex_power import ComplexPowerResult

#: The wall-time keys of :meth:`DEMResult.summary` [s]: the only ones that differ between
#: two runs of the same inputs (``wall_seconds``: the whole run, settling included).
WALL_TIME_KEYS = ("wall_seconds", "excitation_wall_seconds", "settle_seconds",
                  "total_wall_seconds")


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
    settle_simulated_time : float [s]
        Bed time of the settling the run started from (its own or the reused bed's):
        ``settle_time``, or less where the bed came to rest first (``settle_rest_speed``).
    settle_stop : str
        Why that settling ended: ``"time"``, ``"at rest"``, or ``""`` (none).
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
    settle_simulated_time: float = 0.0
    settle_stop: str = ""
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

    def complex_power(self, skip_cycles: int = 2,
                      cycles: int | None = None) -> ComplexPowerResult:
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
        assert self.frequency is not None  # (window() raised otherwise)
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

    def step_profile(self, bins: int = 20, skip_cycles: int = 0) -> xr.Dataset:
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

    # ------------------------------------------------------------------ summary
    def summary(self) -> dict:
        """The scalar summary of the run, one meaning per key (SI units, plain values):
        what ``pdamper dem --json`` and the map's diagnostics report of a run.

        The work of a run comes in two phases, each named: the excitation
        (``excitation_steps``, ``excitation_wall_seconds``: the attributes ``steps`` and
        ``wall_seconds``) and the settling before it (``settle_steps``, ``settle_seconds``;
        0 when the run started from a :class:`~pdamper.dem.SettledBed`, ``settle_reused``;
        ``settle_simulated_time`` [s] its bed time and ``settle_stop`` why it ended, of the
        bed the run started from either way).
        ``steps`` and ``wall_seconds`` are the whole run, settling included, as everywhere
        pdamper reports them (a map's diagnostics too); ``total_steps`` and
        ``total_wall_seconds`` are the same sums under their older names.

        Also: ``integrator``, ``simulated_time`` [s], ``stopped_early``, ``time_step`` [s]
        (the last step of velocity Verlet, Gear's first), ``min_step``, ``max_step`` [s],
        ``contact_time`` [s], ``rejected_steps``, ``rebuilds``, ``contact_onsets``,
        ``energy_balance_error`` [-], ``max_overlap_ratio`` [-], ``max_impact_velocity``
        [m/s], ``stepped_fraction`` [-], ``integrator_switches`` and ``verlet_time`` [s].
        """
        steps, settle_steps = int(self.steps), int(self.settle_steps)
        wall, settle_wall = float(self.wall_seconds), float(self.settle_seconds)
        return {
            "steps": steps + settle_steps,
            "wall_seconds": wall + settle_wall,
            "excitation_steps": steps,
            "excitation_wall_seconds": wall,
            "settle_steps": settle_steps,
            "settle_seconds": settle_wall,
            "settle_reused": bool(self.settle_reused),
            "settle_simulated_time": float(self.settle_simulated_time),
            "settle_stop": self.settle_stop,
            "total_steps": steps + settle_steps,
            "total_wall_seconds": wall + settle_wall,
            "integrator": self.integrator,
            "simulated_time": self.simulated_time,
            "stopped_early": bool(self.stopped_early),
            "time_step": float(self.time_step),
            "min_step": float(self.min_step),
            "max_step": float(self.max_step),
            "contact_time": float(self.contact_time),
            "rejected_steps": int(self.rejected_steps),
            "rebuilds": int(self.rebuilds),
            "contact_onsets": int(self.contact_onsets),
            "energy_balance_error": float(self.energy_balance_error()),
            "max_overlap_ratio": float(self.max_overlap_ratio),
            "max_impact_velocity": float(self.max_impact_velocity),
            "stepped_fraction": float(self.stepped_fraction),
            "integrator_switches": int(self.integrator_switches),
            "verlet_time": float(self.verlet_time),
        }

    # ------------------------------------------------------------------ export
    def to_dataset(self) -> xr.Dataset:
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
        s = self.summary()  # the step counts and wall times under the summary's meanings
        attrs.update(integrator=self.integrator,
                     **{k: s[k] for k in ("steps", "wall_seconds", "excitation_steps",
                                          "excitation_wall_seconds")},
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



@dataclass
class ModalDEMResult(DEMResult):
    """A DEM run on a structure of N modes (:class:`~pdamper.dem.ModalStructureMotion`):
    a :class:`DEMResult` with the modal coordinates at the samples.

    Attributes
    ----------
    modal_coordinates : (N, ns) [m sqrt(kg)]
        q_j at the sample times, relative to the base, from the equilibrium of the
        structure without the particles.
    modal_velocities : (N, ns) [m sqrt(kg)/s]
        q_j'.
    modal_accelerations : (N, ns) [m sqrt(kg)/s^2]
        q_j'' (at the step's prediction, as ``container_acceleration``).
    """

    modal_coordinates: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    modal_velocities: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    modal_accelerations: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
