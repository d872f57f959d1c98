"""Python orchestration of the DEM engine (paper Sect. 3, "Discrete element method").

:class:`DEMEngine` turns the inputs of :mod:`pdamper.dem.inputs` into the named bundles of
:mod:`pdamper.dem.kernels.state`, picks the time step from the contact time scale, settles
the particles under gravity in the resting container, then runs the excitation and returns
a :class:`~pdamper.dem.result.DEMResult`. Both phases run the chunk loop of
:mod:`pdamper.dem.driver`, which calls the numba kernels of :mod:`pdamper.dem.kernels` in
chunks of a fraction of a second of wall time (signals and early stops are handled between
chunks; the chunking does not change a single bit of the result); the arrays of a run are
built by :mod:`pdamper.dem.arrays`.
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

import numpy as np

from pdamper import resources
from pdamper.contact.hertz import rayleigh_time
from pdamper.contact.law import FRICTION_MODELS, ContactParameters, check_integrator_for
from pdamper.dem.arrays import allocate, contact_time, material_tables
from pdamper.dem.driver import (  # noqa: F401 (AUTO_*, SettledBed: importable from here too)
    AUTO_FIRST_SPAN,
    AUTO_MAX_SPAN,
    AUTO_WINDOW,
    KERNELS,
    AtRest,
    AutoSwitch,
    ChunkSizer,
    Controller,
    ErrorCheck,
    Phase,
    Run,
    SettledBed,
    StepProfile,
    StopRule,
    TransientTolerance,
    advance,
    collect_result,
    failure_message,
)
from pdamper.dem.drives import SampleGrid as _SampleGrid
from pdamper.dem.drives import describe_motion, excitation_drive
from pdamper.dem.drives import drive as _drive
from pdamper.dem.inputs import (
    INTEGRATORS,
    OVERLAP_WARNING_LIMIT,
    Container,
    HarmonicMotion,
    LargeOverlapWarning,
    ModalStructureMotion,
    ParticleSet,
    PrescribedMotion,
    StructureMotion,
)
from pdamper.dem.kernels import state as K
from pdamper.dem.result import DEMResult
from pdamper.dem.settings import AUTO_COST_RATIO, EngineSettings, gear_tolerance_for  # noqa: F401
from pdamper.errors import InputError, SimulationError, check_range

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
#: verification table of docs/verification.md (21 points, paired with 1) keeps every reproducible
#: point within 1 % (worst 0.61 %, the same as at 1) with 12-47 % fewer steps at the fast
#: points; Level III model 1 over random packings unchanged (21.5 +- 0.2 mm against
#: 21.6 +- 0.4). At 10 the slip no longer stops within a contact (1.7e-3,
#: tests/dem/test_dem_physics.py fails).
GEAR_FRICTION_CAP_FACTOR = 5.0
#: Settling beyond the free fall over the container height, the engine's default [s].
SETTLE_EXTRA = 0.05
#: Bed time between two checks of the rest rule of the settling (``settle_rest_speed``)
#: [s]: the settling then lands (and records a sample) at this interval.
SETTLE_CHECK_INTERVAL = 0.005


def free_fall_settling(height: float, gravity: float, extra: float = SETTLE_EXTRA) -> float:
    """Settling time [s]: the free fall over ``height`` [m] under ``gravity`` [m/s^2] plus
    ``extra`` [s]; 0 without gravity."""
    return math.sqrt(2.0 * height / gravity) + extra if gravity > 0 else 0.0


#: Target wall time of one kernel call [s]: Ctrl-C and ``stop`` take effect within it.
DEFAULT_CHUNK_SECONDS = 0.25


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
    settings
        :class:`~pdamper.dem.settings.EngineSettings`: integrator, step control, settling,
        stops (default: ``EngineSettings()``). Each setting is also an attribute of the
        engine (``engine.gear_tolerance``); the defaults left as None are resolved here
        (``skin``, ``settle_time``, ``max_overlap``, ``reference_velocity``,
        ``gear_transient_tolerance``).

    Examples
    --------
    >>> from pdamper.dem.settings import EngineSettings
    >>> EngineSettings(integrator="gear", gear_tolerance=1e-4).clone(safety=0.01).safety
    0.01
    """

    def __init__(self, particles: ParticleSet, container: Container,
                 contact: ContactParameters,
                 motion: HarmonicMotion | PrescribedMotion | StructureMotion | None = None,
                 settings: EngineSettings | None = None):
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
        if settings is None:
            settings = EngineSettings()
        if not isinstance(settings, EngineSettings):
            raise InputError("settings", f"must be an EngineSettings, got "
                             f"{type(settings).__name__}")
        #: The settings (checked on their construction); the engine reads them as its
        #: attributes (:meth:`__getattr__`), the resolved defaults below shadow them.
        self.settings = settings
        s = settings
        check_integrator_for(contact.friction_model, s.integrator)
        self.max_overlap = math.inf if s.max_overlap is None else s.max_overlap
        self.gear_tolerance = gear_tolerance_for(s.gear_tolerance)
        self.gear_transient_tolerance = (self.gear_tolerance if s.gear_transient_tolerance
                                         is None else s.gear_transient_tolerance)
        r = particles.radius
        self.skin = 0.2 * float(r.min()) if s.skin is None else s.skin
        lx, ly, lz = self.container.box
        self.settle_time = (free_fall_settling(lz, self.gravity) if s.settle_time is None
                            else s.settle_time)
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
        reference_velocity = s.reference_velocity
        self.reference_velocity = (self._default_reference_velocity() if reference_velocity is None
                                   else reference_velocity)
        #: Speed that sets the settling step [m/s]: the given reference speed, else the free
        #: fall over the container height (not the motion: one settled bed serves all).
        self.settle_reference_velocity = (self._fall_velocity() if reference_velocity is None
                                          else self.reference_velocity)
        self._check_physics(reference_velocity is not None)
        self.contact_time = self._contact_time(self.reference_velocity)
        self.rayleigh_time = min(rayleigh_time(float(ri), m)
                                 for ri, m in zip(r, particles.material, strict=True))
        self.time_step = self.safety * self.contact_time

    def __getattr__(self, name: str):
        # the settings as attributes (engine.integrator, engine.gear_tolerance, ...)
        settings = self.__dict__.get("settings")
        if settings is not None and name in type(settings).model_fields:
            return getattr(settings, name)
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

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
        self._tables = material_tables(self.particles, self.container, self.contact)

    def _contact_time(self, v: float) -> float:
        """Shortest elastic Hertz contact duration of the pair types at speed v [s]."""
        return contact_time(self.particles, self._tables, v)

    def _allocate(self, grid: _SampleGrid) -> Run:
        """Every array of a run, once: particles, contact lists, histories, work."""
        return allocate(self.particles, self.container, self.contact, self._tables,
                        self.gravity, self.skin, self._start_position())

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
        elif isinstance(m, ModalStructureMotion):  # each mode's speed, and the load's
            v += 2.0 * (m.release_speed + m.steady_speed())
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
        what: tuple = (self.particles, self.container.box, self.container.material,
                       self.contact, self.gravity, self.skin, self.settle_time,
                       self._first_kernel, stp._replace(half=0.0, nsamp=0),
                       self._start_position())
        if self._rest_rule:  # (the key of a plain settling unchanged)
            what = (*what, self.settle_rest_speed, self.settle_rest_time)
        return hashlib.sha256(pickle.dumps(what, protocol=4)).hexdigest()[:20]

    def _settled_run(self, bed: SettledBed) -> Run:
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
        return "verlet" if self.integrator == "verlet" or self._verlet_only else "gear"

    @property
    def _verlet_only(self) -> bool:
        """Whether only Verlet can run this contact law (the spring friction law: ``auto``
        then runs Verlet throughout)."""
        return self.contact.friction_model == "spring"

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

    @property
    def _rest_rule(self) -> bool:
        """Whether the settling can end at rest: ``settle_rest_speed`` given and
        ``settle_rest_time`` shorter than ``settle_time`` (else the settling runs on the
        grid it has without the rule, to the bit)."""
        return (self.settle_rest_speed is not None
                and self.settle_rest_time < self.settle_time)

    def _settle_grid(self) -> tuple[int, float]:
        """Samples and half sample interval [s] of the settling: 10 samples over
        ``settle_time``, or with the rest rule (``settle_rest_speed``) one sample per
        check (:data:`SETTLE_CHECK_INTERVAL`)."""
        if not self._rest_rule:
            return 11, self.settle_time / 20.0
        checks = max(1, int(math.ceil(self.settle_time / SETTLE_CHECK_INTERVAL - 1e-9)))
        return checks + 1, self.settle_time / (2.0 * checks)

    def _settle(self, run: Run, chunk_seconds: float) -> None:
        """Settling under gravity, the container at rest at its start position: for
        ``settle_time``, or until the bed is at rest (:class:`~pdamper.dem.driver.AtRest`,
        ``settle_rest_speed``) if that comes first."""
        nsamp, half = self._settle_grid()
        stp = self._stepping(0.0, half, nsamp, 0, self._first_kernel, settling=True)
        drive = _drive(K.MOTION_HARMONIC, z0=run.z_start)
        phase = Phase(stp, drive, K.empty_samples(nsamp), K.empty_snapshots(0, run.pos.shape[0]),
                      kernel=self._first_kernel)
        t1 = time.perf_counter()
        check = self._checker("settling")
        KERNELS[phase.kernel].start(run, phase)
        check(phase)
        rule = None
        if self._rest_rule:
            checks = max(1, int(math.ceil(self.settle_rest_time / (2.0 * half) - 1e-9)))
            rule = AtRest(run, self.settle_rest_speed, checks)
        j_end = 2 * (nsamp - 1)
        j = advance(run, phase, j_end, ChunkSizer(chunk_seconds),
                    () if rule is None else (rule,), check=check)
        run.settle_seconds = time.perf_counter() - t1
        run.settle_steps = int(phase.stats[0]["steps"])
        run.settle_simulated = j * half
        run.settle_stop = "at rest" if j < j_end else "time"
        #: the rest rule of the last settling (its trace: measurements, tests), or None
        self._last_settle: AtRest | None = rule
        log.info("settled %d particles in %d steps (%.3f s; %.4g s of bed time, %s)",
                 run.pos.shape[0], run.settle_steps, run.settle_seconds,
                 run.settle_simulated, run.settle_stop)

    def _excitation_phase(self, run: Run, grid: _SampleGrid) -> Phase:
        """The excitation's time grid, container motion, records and output arrays."""
        m = self.motion
        stp = self._stepping(0.0, 0.5 * grid.interval, grid.nsamp, grid.snap_every,
                             self._first_kernel)
        rs = K.record(K.RUN_STATE)
        drive = excitation_drive(m, grid)
        if isinstance(m, StructureMotion):  # the structure's state at the start
            rs[0]["zc"], rs[0]["vc"] = m.x0, m.v0
        nsnap = (grid.nsamp - 1) // grid.snap_every + 1
        return Phase(stp, drive, K.empty_samples(grid.nsamp),
                     K.empty_snapshots(nsnap, run.pos.shape[0]), rs, kernel=self._first_kernel)

    def _excite(self, run: Run, grid: _SampleGrid, stop, chunk_seconds: float,
                step_profile: bool = False) -> DEMResult:
        """The excitation phase, chunk by chunk, with the controllers that the run asks
        for (:mod:`pdamper.dem.driver`); the result of the recorded samples."""
        phase = self._excitation_phase(run, grid)
        j_end = 2 * (grid.nsamp - 1)
        check = self._checker("excitation")
        controllers: list[Controller] = []
        if stop is not None:
            def ask(j: int) -> bool:
                return bool(stop(collect_result(self, run, phase, grid, j // 2,
                                                time.perf_counter() - t1, profile)))
            controllers.append(StopRule(ask, 2 * grid.per_cycle, j_end))
        if self.transient_cycles > 0 and grid.per_cycle > 0:
            end = min(2 * grid.per_cycle * self.transient_cycles, j_end)
            controllers.append(TransientTolerance(phase, end, self.gear_transient_tolerance,
                                                  self.gear_tolerance))
        if self.integrator == "auto" and not self._verlet_only:
            controllers.append(AutoSwitch(self, run, phase, j_end, check))
        t1 = time.perf_counter()
        KERNELS[phase.kernel].start(run, phase)
        check(phase)
        recorder = StepProfile(phase, grid.nsamp, run.pos.shape[0]) if step_profile else None
        profile = None if recorder is None else recorder.table
        j = advance(run, phase, j_end, ChunkSizer(chunk_seconds, one_sample=step_profile),
                    (*controllers, *([recorder] if recorder else [])), check)
        wall = time.perf_counter() - t1
        log.info("%s: %d steps in %.3f s", self.integrator, phase.stats[0]["steps"], wall)
        if not math.isnan(phase.switch_time):
            log.info("auto: Gear handed over to Verlet at t = %.4g s", phase.switch_time)
        res = collect_result(self, run, phase, grid, j // 2, wall, profile)
        if res.max_overlap_ratio > OVERLAP_WARNING_LIMIT:
            # one message text: Python shows it once per place, not once per map point
            warnings.warn(f"DEM overlaps beyond {100 * OVERLAP_WARNING_LIMIT:g} % of the radius "
                          "(fast impacts; Hertz's contact outside its small-strain range, "
                          "real materials would yield): see DEMResult.max_overlap_ratio",
                          LargeOverlapWarning, stacklevel=3)
        return res

    def _checker(self, name: str) -> ErrorCheck:
        """The error check of the phase ``name`` after each kernel call."""
        return lambda phase: self._check(phase, name)

    def _check(self, phase: Phase, name: str) -> None:
        """Raise the kernel's error of phase ``name`` (:func:`failure_message`), if any."""
        if int(phase.stats[0]["error"]) != K.ERR_NONE:
            raise SimulationError(failure_message(self, phase, name))

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
            "friction_model": c.friction_model,
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
        d.update(describe_motion(m))
        return d


def warmup(integrators: tuple[str, ...] = INTEGRATORS,
           motions: tuple[str, ...] = ("harmonic", "structure"),
           friction_models: tuple[str, ...] = ("regularised",)) -> float:
    """Compile (or load from the numba cache) the kernels of ``integrators`` (default all
    of :data:`~pdamper.dem.inputs.INTEGRATORS`) for the container ``motions``
    (``"harmonic"``, ``"structure"``; default both) and the ``friction_models`` (default
    the tanh law; ``"spring"`` adds velocity Verlet's kernels of the spring law, about
    30 s of compilation, where ``integrators`` holds ``"verlet"``); returns seconds.

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
    kinds: dict[str, HarmonicMotion | StructureMotion] = {
        "harmonic": HarmonicMotion(0.001, 10.0), "structure": StructureMotion(1.0, 0.1, 100.0)}
    for name in motions:
        if name not in kinds:
            raise InputError("motions", f"must be among {', '.join(kinds)}, got {name!r}")
    for model in friction_models:
        if model not in FRICTION_MODELS:
            raise InputError("friction_models", f"must be among {', '.join(FRICTION_MODELS)}, "
                             f"got {model!r}")
    contact = ContactParameters(ConstantRestitution(0.8), ConstantRestitution(0.8), 0.1, 0.1)
    for integ in integrators:
        parts = ParticleSet(np.array([[0.02, 0.02, 0.006], [0.02, 0.02, 0.03]]), 0.005, S235)
        for motion in (kinds[m] for m in motions):
            # "auto" made to hand over to Verlet at its first judgement (5 ms) and to probe
            # Gear again one window later (10-15 ms): both resume kernels too
            DEMEngine(parts, Container((0.04, 0.04, 0.12), PVC), contact, motion,
                      EngineSettings(integrator=integ, settle_time=0.0,
                                     auto_cost_ratio=math.inf)).run(
                3.5 * AUTO_WINDOW if integ == "auto" else 0.002, sample_rate=1000.0)
    if "spring" in friction_models and "verlet" in integrators:
        # the spring law's state is an argument of the Verlet kernels: their own variant
        spring = ContactParameters(ConstantRestitution(0.8), ConstantRestitution(0.8), 0.1,
                                   0.1, friction_model="spring")
        parts = ParticleSet(np.array([[0.02, 0.02, 0.006], [0.02, 0.02, 0.03]]), 0.005, S235)
        DEMEngine(parts, Container((0.04, 0.04, 0.12), PVC), spring, kinds["harmonic"],
                  EngineSettings(integrator="verlet", settle_time=0.0)).run(
            0.002, sample_rate=1000.0)
    return time.perf_counter() - t0
