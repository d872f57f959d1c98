"""The driver of a DEM run: one :func:`advance` loop and the small controllers around it.

A phase (settling or excitation) runs from landing 0 to its last landing (landings are the
half-sample grid of :mod:`pdamper.dem.kernels`) in chunks: each kernel call integrates up
to a target landing, then Python decides what happens next. :func:`advance` is that loop;
every feature that needs a say between chunks is a :class:`Controller`:

* :class:`ChunkSizer`: how far the next call goes (about ``chunk_seconds`` of wall time);
* :class:`StopRule`: the ``stop`` callable of :meth:`DEMEngine.run`, asked at the ends of
  whole cycles;
* :class:`TransientTolerance`: the Gear tolerance of the first cycles, restored at their
  end;
* :class:`AutoSwitch`: ``integrator="auto"``'s hand-overs between Gear and velocity Verlet;
* :class:`StepProfile`: the steps and wall time of each sample interval.

A controller can end the next chunk earlier (:meth:`Controller.limit`: its decisions fall
on fixed landings, so that the chunking never changes a bit of the result), act when a
chunk lands (:meth:`Controller.landed`) and end the run (:meth:`Controller.stop`).

The kernels are entered through :data:`KERNELS`, with the named bundles of the run
(:class:`Run`: particles, contact lists, work arrays) and of the phase (:class:`Phase`:
time grid, motion, records, outputs).
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from pdamper.dem.kernels import gear as _gear
from pdamper.dem.kernels import state as K
from pdamper.dem.kernels import verlet as _verlet
from pdamper.dem.result import DEMResult, ModalDEMResult

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.dem.drives import SampleGrid as _SampleGrid
    from pdamper.dem.simulation import DEMEngine

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


# ------------------------------------------------------------------ the bundles
@dataclass
class Run:
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
    #: Bed time the settling ran [s] and why it ended: ``"time"`` (``settle_time`` ran
    #: out), ``"at rest"`` (:class:`AtRest`), ``""`` (no settling).
    settle_simulated: float = 0.0
    settle_stop: str = ""

    @property
    def tangential(self) -> tuple | None:
        """What the Verlet kernels take for the friction law: None for the tanh law (its
        code compiled without the spring's), ``(0.0, vel, omg)`` for the spring law, whose
        tangential displacements the run carries (:mod:`pdamper.dem.kernels.forces`)."""
        return None if self.walls.xi.shape[0] == 0 else (0.0, self.vel, self.omg)


@dataclass
class Phase:
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
    state: Run = field(repr=False, compare=False)

    def moved(self, displacement) -> SettledBed:
        """This bed with every sphere moved by ``displacement`` [m] (an (n, 3) array), under
        the same key: another realisation of the settled state. A move made before the
        settling can be undone by it (the lattice's columns settle back to the same heights,
        to ~1e-17 m), one made after it cannot."""
        state = copy.deepcopy(self.state)
        d = np.asarray(displacement, dtype=float)
        if d.shape != state.pos.shape:
            raise ValueError(f"displacement must have shape {state.pos.shape}, got {d.shape}")
        state.pos += d
        return SettledBed(self.key, self.steps, self.seconds, state)

    @property
    def simulated(self) -> float:
        """Bed time the settling ran [s] (``settle_time``, or less where the bed came to
        rest first: :class:`AtRest`)."""
        return float(self.state.settle_simulated)

    @property
    def stop(self) -> str:
        """Why the settling ended: ``"time"`` or ``"at rest"``."""
        return str(self.state.settle_stop)

    @property
    def kinetic_energy(self) -> float:
        """Kinetic energy left in the bed, translational and rotational [J]: how far from
        rest the settling brought it."""
        st = self.state
        m = np.asarray(st.part.mass)
        r = np.asarray(st.part.rad)
        return float(0.5 * np.sum(m * np.sum(st.vel**2, axis=1))
                     + 0.2 * np.sum(m * r**2 * np.sum(st.omg**2, axis=1)))


# ------------------------------------------------------------------ the kernels
class VerletKernels:
    """The entry points of velocity Verlet (:mod:`pdamper.dem.kernels.verlet`)."""

    @staticmethod
    def start(run: Run, phase: Phase) -> None:
        _verlet.verlet_start(run.pos, run.vel, run.omg, run.world, run.law, run.part,
                             run.pair_types, run.nbrs, run.walls, phase.drive, phase.stepping,
                             run.work, phase.ledger, phase.state, phase.stats, phase.samples,
                             phase.snaps, run.tangential)

    @staticmethod
    def resume(run: Run, phase: Phase) -> None:
        _verlet.verlet_resume(run.pos, run.vel, run.omg, run.world, run.law, run.part,
                              run.pair_types, run.nbrs, run.walls, phase.drive, phase.stepping,
                              run.work, phase.ledger, phase.state, phase.stats, run.tangential)

    @staticmethod
    def advance(run: Run, phase: Phase, j_stop: int) -> None:
        _verlet.verlet_advance(run.pos, run.vel, run.omg, run.world, run.law, run.part,
                               run.pair_types, run.nbrs, run.walls, phase.drive, phase.stepping,
                               run.work, phase.ledger, phase.state, phase.stats, phase.samples,
                               phase.snaps, j_stop, run.tangential)


class GearKernels:
    """The entry points of variable-step Gear (:mod:`pdamper.dem.kernels.gear`)."""

    @staticmethod
    def start(run: Run, phase: Phase) -> None:
        _gear.gear_start(run.pos, run.vel, run.omg, run.world, run.law, run.part,
                         run.pair_types, run.nbrs, run.walls, phase.drive, phase.stepping,
                         run.work, run.nord, run.flights, phase.ledger, phase.state,
                         phase.stats, phase.samples, phase.snaps)

    @staticmethod
    def resume(run: Run, phase: Phase) -> None:
        # Gear's first step: Verlet's, from which its error control grows it
        _gear.gear_resume(run.pos, run.vel, run.omg, run.world, run.law, run.part,
                          run.pair_types, run.nbrs, run.walls, phase.drive, phase.stepping,
                          run.work, run.nord, run.flights, phase.ledger, phase.state,
                          phase.stats, float(phase.state[0]["dt"]))

    @staticmethod
    def advance(run: Run, phase: Phase, j_stop: int) -> None:
        _gear.gear_advance(run.pos, run.vel, run.omg, run.world, run.law, run.part,
                           run.pair_types, run.nbrs, run.walls, phase.drive, phase.stepping,
                           run.work, run.nord, run.flights, phase.ledger, phase.state,
                           phase.stats, phase.samples, phase.snaps, j_stop)


#: The kernels of each integrator, by :attr:`Phase.kernel`.
KERNELS: dict[str, type[VerletKernels | GearKernels]] = {"verlet": VerletKernels,
                                                         "gear": GearKernels}

#: Raises the phase's kernel error, if any (:meth:`DEMEngine._check`).
ErrorCheck = Callable[[Phase], None]


# ------------------------------------------------------------------ the loop
class Controller:
    """A feature that has a say between the chunks of :func:`advance` (no-op defaults)."""

    def limit(self, j: int, target: int) -> int:
        """The landing the next chunk (from landing ``j``) may reach at most."""
        return target

    def before(self) -> None:
        """Just before the kernel call."""

    def after(self, target: int, spent: float) -> None:
        """Just after the kernel call that reached ``target`` in ``spent`` [s] of wall time."""

    def landed(self, j: int) -> None:
        """The chunk ended at landing ``j`` (checked for kernel errors)."""

    def stop(self, j: int) -> bool:
        """True ends the phase at landing ``j``."""
        return False


class ChunkSizer:
    """Chunks of about ``seconds`` of wall time, sized from the measured rate (the first
    two landings long); ``math.inf``: one call for the whole phase; ``one_sample``: one
    sample per call (the step profile)."""

    def __init__(self, seconds: float, one_sample: bool = False) -> None:
        self.seconds = seconds
        self.whole = math.isinf(seconds) and not one_sample
        self.adapt = not math.isinf(seconds) and not one_sample
        self.size = 2

    def target(self, j: int, j_end: int) -> int:
        return j_end if self.whole else min(j_end, j + self.size)

    def measured(self, done: int, spent: float) -> None:
        """``done`` landings took ``spent`` seconds: the next chunk's size."""
        if self.adapt:
            rate = spent / done
            self.size = max(2, min(4 * done, int(self.seconds / rate) if rate > 0
                                   else 4 * done))


def advance(run: Run, phase: Phase, j_end: int, chunks: ChunkSizer,
            controllers: tuple[Controller, ...] = (), check: ErrorCheck | None = None) -> int:
    """Advance ``phase`` to landing ``j_end`` in chunks ending on samples (even landings),
    each as long as ``chunks`` and every controller allow; returns the last landing
    reached (before ``j_end`` when a controller stopped the phase)."""
    j = 0
    while j < j_end:
        target = chunks.target(j, j_end)
        for c in controllers:
            target = c.limit(j, target)
        target = min(target + target % 2, j_end)
        for c in controllers:
            c.before()
        t1 = time.perf_counter()
        KERNELS[phase.kernel].advance(run, phase, target)
        spent = time.perf_counter() - t1
        for c in controllers:
            c.after(target, spent)
        if check is not None:
            check(phase)
        done, j = target - j, target
        for c in controllers:
            c.landed(j)
        chunks.measured(done, spent)
        if any(c.stop(j) for c in controllers):
            break
    return j


# ------------------------------------------------------------------ the controllers
class StopRule(Controller):
    """Ask ``ask(j)`` after each chunk, only at the ends of whole cycles of ``cycle``
    landings (``cycle > 0``: the chunks end there); True ends the phase."""

    def __init__(self, ask: Callable[[int], bool], cycle: int, j_end: int) -> None:
        self.ask, self.cycle, self.j_end = ask, cycle, j_end

    def limit(self, j: int, target: int) -> int:
        if self.cycle > 0 and target < self.j_end:
            nxt = (j // self.cycle + 1) * self.cycle
            target = min(target, nxt) if nxt > j else target
        return target

    def stop(self, j: int) -> bool:
        return (j < self.j_end and (self.cycle <= 0 or j % self.cycle == 0)
                and bool(self.ask(j)))


class AtRest(Controller):
    """End the settling once the bed is at rest: at every ``every`` landings (one check),
    the bed's root-mean-square speed ``sqrt(2 E_kin / m_bed)`` (its translational kinetic
    energy as a speed) below ``speed`` [m/s], at ``checks`` checks in a row. The chunks
    end at every check, so the landing where the settling ends does not depend on the
    chunking.

    The bed's energy, not its fastest sphere: without rolling resistance a sphere rolls
    on at constant speed until something stops it, and in a large bed some caged sphere
    rattles (a random bed of 32 spheres of 5 mm: a sphere rolling at 3.3 mm/s, then one
    rolling down the heap at 8 cm/s, 0.5-0.9 s into the settling; 250 of 2.5 mm: the
    fastest at 3-10 mm/s from 0.8 s to the end of the default 1.16 s). Spin is left out: a
    sphere spinning about the vertical through its contact with the floor meets no
    friction there and keeps spinning in place.

    ``trace`` collects ``(landing, rms speed [m/s], fastest centre [m/s])`` at each check
    (measurements, tests)."""

    def __init__(self, run: Run, speed: float, checks: int, every: int = 2) -> None:
        self.run, self.speed, self.checks, self.every = run, float(speed), int(checks), every
        self.quiet = 0
        self.trace: list[tuple[int, float, float]] = []
        self.mass = np.asarray(run.part.mass)

    def speeds(self) -> tuple[float, float]:
        """The bed's rms speed and its fastest centre now [m/s]."""
        if not self.mass.size:
            return 0.0, 0.0
        v2 = np.sum(self.run.vel ** 2, axis=1)
        rms = math.sqrt(float(np.dot(self.mass, v2)) / float(np.sum(self.mass)))
        return rms, float(math.sqrt(np.max(v2)))

    def limit(self, j: int, target: int) -> int:
        return min(target, (j // self.every + 1) * self.every)

    def landed(self, j: int) -> None:
        if j % self.every:
            return
        rms, fastest = self.speeds()
        self.trace.append((j, rms, fastest))
        self.quiet = self.quiet + 1 if rms < self.speed else 0

    def stop(self, j: int) -> bool:
        return self.quiet >= self.checks


class TransientTolerance(Controller):
    """The Gear tolerance ``transient`` [-] up to landing ``end`` (the first cycles of the
    excitation), ``tolerance`` [-] from there on."""

    def __init__(self, phase: Phase, end: int, transient: float, tolerance: float) -> None:
        self.phase, self.end, self.tolerance = phase, end, float(tolerance)
        phase.stepping = phase.stepping._replace(tol=float(transient))

    def limit(self, j: int, target: int) -> int:
        return min(target, self.end) if j < self.end else target

    def landed(self, j: int) -> None:
        if j == self.end:
            self.phase.stepping = self.phase.stepping._replace(tol=self.tolerance)


class StepProfile(Controller):
    """Per sample interval (columns of :attr:`table`, 4 x samples): the accepted steps,
    the sphere-steps, the rejected steps and the kernel wall time [s] (run with
    ``ChunkSizer(..., one_sample=True)``)."""

    def __init__(self, phase: Phase, nsamp: int, count: int) -> None:
        self.stats, self.count = phase.stats, count
        self.table = np.zeros((4, nsamp))
        self._before = (0, 0, 0, 0)

    def before(self) -> None:
        st = self.stats[0]
        self._before = (int(st["steps"]), int(st["gear_steps"]), int(st["stepped"]),
                        int(st["rejects"]))

    def after(self, target: int, spent: float) -> None:
        st, b = self.stats[0], self._before
        steps = int(st["steps"]) - b[0]
        gear = int(st["gear_steps"]) - b[1]
        # Gear counts the spheres it stepped; velocity Verlet steps them all
        self.table[:, target // 2] = (steps, int(st["stepped"]) - b[2]
                                      + (steps - gear) * self.count,
                                      int(st["rejects"]) - b[3], spent)


class AutoSwitch(Controller):
    """``integrator="auto"``: at the end of each judgement window (:data:`AUTO_WINDOW`)
    of Gear, hand over to velocity Verlet when Gear's mean step over the window is below
    ``engine.auto_cost_ratio`` x the step Verlet would take; after a span of Verlet
    windows, probe Gear for one window (:data:`AUTO_FIRST_SPAN`, :data:`AUTO_MAX_SPAN`)."""

    def __init__(self, engine: DEMEngine, run: Run, phase: Phase, j_end: int,
                 check: ErrorCheck) -> None:
        self.engine, self.run, self.phase, self.j_end, self.check = (engine, run, phase,
                                                                     j_end, check)
        self.half = phase.stepping.half
        self.window = 2 * max(1, int(round(AUTO_WINDOW / (2.0 * self.half))))
        self.decide = self.window     # landing of the next decision
        self.span = AUTO_FIRST_SPAN   # windows of Verlet before the next probe of Gear
        self.last = (0, 0)            # landing and steps at the start of the Gear window

    def limit(self, j: int, target: int) -> int:
        return min(target, self.decide)

    def landed(self, j: int) -> None:
        if j != self.decide or j >= self.j_end:
            return
        phase = self.phase
        steps = int(phase.stats[0]["steps"])
        if phase.kernel == "gear":
            mean_step = (j - self.last[0]) * self.half / max(steps - self.last[1], 1)
            if mean_step < self.engine.auto_cost_ratio * self.verlet_step():
                self.switch("verlet", j)
                self.decide = j + self.span * self.window
                self.span = min(2 * self.span, AUTO_MAX_SPAN)
            else:
                self.span = AUTO_FIRST_SPAN
                self.decide = j + self.window
        else:  # probe: Gear for one window
            self.switch("gear", j)
            self.decide = j + self.window
        self.last = (j, int(phase.stats[0]["steps"]))

    def verlet_step(self) -> float:
        """The step velocity Verlet would take now: the design step, made shorter for the
        fastest impact so far as :func:`verlet_advance` does it."""
        eng, half = self.engine, self.phase.stepping.half
        vi = float(self.phase.stats[0]["max_impact"])
        v = 1.25 * vi if vi > eng.reference_velocity else eng.reference_velocity
        dt = eng.time_step * (eng.reference_velocity / v) ** 0.2
        return half / max(1, int(math.ceil(half / dt - 1e-9)))

    def switch(self, kernel: str, j: int) -> None:
        """Continue the phase with ``kernel`` from landing ``j``."""
        phase, old = self.phase, self.phase.stepping
        # (the tolerance of the moment: a transient one stays until its landing)
        phase.stepping = self.engine._stepping(old.t0, self.half, old.nsamp, old.snap_every,
                                               kernel)._replace(tol=old.tol)
        phase.kernel = kernel
        if kernel == "verlet" and math.isnan(phase.switch_time):
            phase.switch_time = float(phase.state[0]["t"])
        KERNELS[kernel].resume(self.run, phase)
        phase.switches += 1
        phase.kernel_landings[kernel] = phase.kernel_landings.get(kernel, 0) - j
        other = "gear" if kernel == "verlet" else "verlet"
        phase.kernel_landings[other] = phase.kernel_landings.get(other, 0) + j
        self.check(phase)


# ------------------------------------------------------------------ the result
def collect_result(engine: DEMEngine, run: Run, phase: Phase, grid: _SampleGrid, k: int, wall: float,
                   profile: np.ndarray | None = None) -> DEMResult:
    """The :class:`DEMResult` of samples ``0 .. k`` of the excitation ``phase`` on the
    sample ``grid`` (k < nsamp - 1: a run stopped early, whose last force window is closed
    as at the end of a run), after ``wall`` [s]; ``profile``: the :class:`StepProfile`
    table."""
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
    p = engine.particles
    extra: dict = {}
    cls: type[DEMResult] = DEMResult
    if phase.drive.nmodes > 0:  # a structure of N modes: its coordinates at the samples
        cls = ModalDEMResult
        n = phase.drive.nmodes
        rec = phase.drive.m_samples[:ns].T
        extra.update(modal_coordinates=rec[:n].copy(), modal_velocities=rec[n:2 * n].copy(),
                     modal_accelerations=rec[2 * n:].copy())
    return cls(
        **extra,
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
        radius=p.radius.copy(), masses=p.masses, integrator=engine.integrator,
        steps=int(st["steps"]), settle_steps=run.settle_steps,
        rebuilds=int(st["rebuilds"]), contact_onsets=int(st["onsets"]),
        rejected_steps=int(st["rejects"]), wall_seconds=wall,
        settle_seconds=run.settle_seconds, settle_reused=run.settle_reused,
        settle_simulated_time=run.settle_simulated, settle_stop=run.settle_stop,
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
        contact_time=engine.contact_time, max_overlap_ratio=float(st["max_overlap"]),
        max_impact_velocity=float(st["max_impact"]),
        frequency=grid.frequency, container_mass=engine.container.mass,
        requested_duration=grid.duration, stopped_early=not last, attrs=engine.describe(),
        **({} if profile is None else {
            "steps_per_sample": profile[0, :ns].astype(np.int64),
            "stepped_per_sample": profile[1, :ns].astype(np.int64),
            "rejected_per_sample": profile[2, :ns].astype(np.int64),
            "kernel_seconds_per_sample": profile[3, :ns].copy()}))


def failure_message(engine: DEMEngine, phase: Phase, name: str) -> str:
    """The one-line explanation of the kernel error recorded in ``phase`` (``stats.error``,
    the ``ERR_*`` codes of :mod:`pdamper.dem.kernels.state`) of the phase ``name``, with
    the setting to change."""
    st = phase.stats[0]
    err, t, val = int(st["error"]), float(st["t_error"]), float(st["error_value"])
    dt = phase.stepping.dt
    tc = engine.contact_time
    hint = (f"time step {dt:.3g} s too large for the contact time {tc:.3g} s; lower the "
            f"safety factor (now {engine.safety:g})" if phase.kernel == "verlet" else
            f"lower the Gear tolerance (now {engine.gear_tolerance:g}) or the safety factor "
            f"(now {engine.safety:g}, contact time {tc:.3g} s)")
    where = f"{name} at t = {t:.6g} s"
    if err == K.ERR_NAN:
        return f"unstable DEM run: non-finite state ({where}); {hint}"
    if err == K.ERR_OVERLAP:
        return (f"DEM run stopped: overlap {100 * val:.3g} % of the radius exceeds the "
                f"requested max_overlap {100 * engine.max_overlap:g} % ({where}); large "
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
