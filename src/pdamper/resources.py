"""The resource and physics model: what a run implies, judged before it starts.

Every input is checked where it is read (the scenario reader and the command line share
these checks through :func:`pdamper.runs.resources.check_resources`), and so is what it
implies. Two kinds of limit, each answered by one line that names the field, the
implied cost or the reason, and how to get below the limit:

**Physical meaning** (no override: such a run would describe no damper).

- :data:`MIN_PARTICLE_RADIUS`: below a tenth of a millimetre adhesion (van der Waals
  forces) outweighs the weight of a sphere and a granular bed becomes a cohesive powder;
  neither the collect-and-collide model nor the contact law without adhesion describes it
  (and the lattice of the paper's box would hold 10^13 spheres).
- :data:`MAX_STROKE`: a container stroke or a release deflection above 10 m belongs to no
  vibrating structure a damper is mounted on (the paper's: 1-200 mm).
- :data:`MAX_SPEED_FRACTION`: the fastest impact the motion implies (free fall over the
  container height plus twice the container's peak speed) must stay below a tenth of the
  slowest bar wave speed ``sqrt(E/rho)`` of the materials: impacts are then quasi-static, as
  Hertz's law and the rigid-body collect-and-collide model assume (146 m/s for PVC walls;
  the paper's fastest corner, 20 Hz x 200 mm, implies 52 m/s).
- The **contact frequency**: an excitation period must be longer than the longest Hertz
  contact between the spheres and the walls at that impact speed (impacts are short events
  in every model; 10 MHz is no vibration a damper can follow).
- :data:`MAX_CONTACT_RADIUS_RATIO` (models that use the contact law: the DEM): at the
  fastest implied impact the Hertz contact radius ``a = sqrt(R* delta_max)`` must stay
  below half the sphere radius; Hertz's theory assumes ``a << R`` (the paper's fastest
  corner gives a/R = 0.47; 200 Hz x 32 mm gives 0.57).

**Cost** (``--force`` overrides, ``--allow-cost`` in ``pdamper frf``, whose ``--force`` is its
load; estimates are orders of magnitude, meant to catch inputs that are off by orders of
magnitude, not to tune runs).

- :data:`MAX_SCENARIO_BYTES`: a scenario file of at most 1 MiB (no override: a scenario
  describes one damper in a few hundred bytes).

- :data:`MEMORY_LIMIT`: 2 GiB of arrays a run holds (stored time series, snapshots,
  neighbour lists, the working arrays of a map). Never above the machine's physical memory,
  even with ``--force``: such a run cannot succeed.
- :data:`TIME_LIMIT`: one hour of estimated run time on one core for one run (a DEM run,
  a free vibration, an analytical map); :data:`SWEEP_TIME_LIMIT`, a day, for a sweep of
  runs the user listed one by one (the points of a DEM map, the candidates of an
  optimisation, which run in parallel), each of them within :data:`TIME_LIMIT`.
  Never above :data:`FORCE_TIME_LIMIT` (30 days), even with ``--force``.

**Where.** The edges (scenario, command line) judge what their inputs imply, naming their
fields, with ``--force``. Underneath, every run is judged where it is made, so that every
command and the API inherit the limits: :class:`pdamper.dem.DEMEngine` (every DEM run)
by :func:`check_impacts` at its reference speed and by the hard cost limits at ``run``;
the damper models (sphere radius, the analytical model's excitation) and
:class:`pdamper.coupling.Simulation` (the release). A count (a grid's axes, a range's
values, a list of runs) is judged from its parameters (:func:`count_cost`) before the
list exists.

The per-unit costs below are the figures of docs/performance.md (2-core machine, one core), rounded up.
The DEM step count is that of a fixed step of ``safety`` x the shortest Hertz contact time
at the fastest implied impact (the variable-step Gear integrator mostly needs fewer).
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

from pdamper.constants import STANDARD_GRAVITY
from pdamper.contact.elastic import (
    bar_wave_speed,
    contact_duration,
    effective_modulus,
    effective_radius,
    hertz_stiffness,
    max_overlap,
)
from pdamper.damper import ParticleDamper
from pdamper.errors import InputError
from pdamper.materials import Material

# ---------------------------------------------------------------- physical meaning
#: Smallest sphere radius [m] (adhesion outweighs gravity below).
MIN_PARTICLE_RADIUS = 1e-4
#: Largest container stroke X or release deflection |x0| [m].
MAX_STROKE = 10.0
#: Largest implied impact speed as a fraction of the slowest bar wave speed [-].
MAX_SPEED_FRACTION = 0.1
#: Largest Hertz contact radius over the sphere radius at the fastest impact (DEM) [-].
MAX_CONTACT_RADIUS_RATIO = 0.5

# ---------------------------------------------------------------- cost limits
#: Largest scenario file [bytes] (one damper takes a few hundred; a larger file is not a
#: scenario, and parsing it would take the time and memory of its size).
MAX_SCENARIO_BYTES = 2**20
#: Memory a run may hold without ``--force`` [bytes].
MEMORY_LIMIT = 2 * 2**30
#: Estimated one-core time of one run allowed without ``--force`` [s].
TIME_LIMIT = 3600.0
#: Estimated one-core time of a sweep of runs allowed without ``--force`` [s].
SWEEP_TIME_LIMIT = 86400.0
#: Estimated run time that not even ``--force`` allows [s].
FORCE_TIME_LIMIT = 30 * 86400.0
#: Design study (:mod:`pdamper.design.study`): most grid points of a brute-force study
#: before ``method="auto"`` turns to the optimiser, and the optimiser's evaluation budget
#: (here, not in the study, so that the scenario reader does not import Level III).
DEFAULT_MAX_GRID = 400
DEFAULT_MAX_EVALUATIONS = 200
#: Relative tolerance on the objective of the lightest design reported as nearly as good
#: as the best (:func:`pdamper.design.study.lightest_within`).
DEFAULT_TOLERANCE = 0.05

# ---------------------------------------------------------------- per-unit costs
#: DEM: seconds per particle and time step (docs/performance.md: 29-34 ns, Verlet).
DEM_SECONDS_PER_PARTICLE_STEP = 5e-8
#: DEM: bytes per stored sample (17 series, held by the kernel, the result and a dataset).
DEM_BYTES_PER_SAMPLE = 17 * 8 * 3
#: DEM: bytes per particle and snapshot (positions, velocities, angular velocities, twice).
DEM_BYTES_PER_SNAPSHOT_PARTICLE = 9 * 8 * 2
#: DEM: bytes per particle of state and neighbour lists (~33 candidates, both lists).
DEM_BYTES_PER_PARTICLE = 4096
#: Analytical model: seconds and working bytes per (f, X) point of a map (measured:
#: 0.3-0.5 ms and 11 KB per point, the phase scan holds 256 samples per point).
ANALYTIC_SECONDS_PER_POINT = 5e-4
ANALYTIC_BYTES_PER_POINT = 12 * 1024
#: Pseudo-force coupling: seconds per cycle update (four damper evaluations; measured
#: 2 ms with the analytical model) and bytes per trajectory sample (time, displacement,
#: the dataset's copy).
PSEUDO_FORCE_SECONDS_PER_CYCLE = 3e-3
PSEUDO_FORCE_BYTES_PER_SAMPLE = 16 * 3
#: A value of a list built from a range (a design variable's values, the impact speeds of
#: ``pdamper cor``): a Python object, its slot in a tuple, its text in the JSON record.
BYTES_PER_VALUE = 64
#: A candidate of a design study: its design, result record and JSON text.
BYTES_PER_CANDIDATE = 2048
#: Forced response (:mod:`pdamper.coupling.frf`) of a pseudo-force model: seconds and bytes
#: per stroke of a frequency's describing-function table (measured with the analytical
#: model: 12-15 ms and 35 KB for the 800 strokes of a frequency), and seconds per load cycle
#: of a stepped-sine step: a fixed part plus the cycle's matrix exponential and solves of the
#: 2N x 2N modal state matrix, ~(2N)^3 (measured: 0.05 ms for one mode, 4 ms for 50).
FRF_SECONDS_PER_STROKE = 2e-5
FRF_BYTES_PER_STROKE = 48
FRF_SECONDS_PER_CYCLE = 1e-4
FRF_SECONDS_PER_STATE_CUBED = 4e-9
#: Bytes per entry of the 2N x 2N state matrices a stepped-sine cycle holds (about ten
#: complex matrices: the state matrix, its exponential, the solves' work arrays).
FRF_BYTES_PER_STATE_ENTRY = 160
#: One simulated single impact of ``pdamper cor`` (an engine built and run; measured over
#: 0.01-2 m/s: 0.7 ms with Gear, 9 ms with Verlet).
SECONDS_PER_IMPACT = 0.01


def _gib(b: float) -> str:
    if b >= 2**40:
        return f"{b / 2**40:.3g} TiB"
    if b >= 2**30:
        return f"{b / 2**30:.3g} GiB"
    return f"{b / 2**20:.3g} MiB"


def _duration(s: float) -> str:
    if s >= 86400 * 365:
        return f"{s / (86400 * 365):.3g} years"
    if s >= 86400:
        return f"{s / 86400:.3g} day" + ("" if round(s / 86400, 2) == 1 else "s")
    if s >= 3600:
        return f"{s / 3600:.3g} h"
    if s >= 60:
        return f"{s / 60:.3g} min"
    return f"{s:.3g} s"


def physical_memory() -> float | None:
    """Physical memory of this machine [bytes], or None where the system does not say."""
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


# ================================================================ physics
def impact_speed(amplitude: float, frequency: float, height: float,
                 gravity: float = STANDARD_GRAVITY) -> float:
    """Fastest relative speed of a sphere and a wall that a harmonic container motion
    ``X sin(2 pi f t)`` implies [m/s]: free fall over the container height plus twice the
    container's peak speed (the DEM engine's reference speed for its step).

    >>> round(impact_speed(0.032, 10.0, 0.12), 2)
    5.56
    """
    return math.sqrt(2.0 * gravity * height) + 2.0 * amplitude * 2.0 * math.pi * frequency


@dataclass(frozen=True)
class Impact:
    """Hertz contacts of a damper's spheres at one impact speed (elastic closed forms).

    Attributes
    ----------
    speed
        Impact speed [m/s].
    shortest_contact, longest_contact
        Shortest and longest contact duration over sphere-sphere and sphere-wall [s].
    contact_radius_ratio
        Largest Hertz contact radius ``sqrt(R* delta_max)`` over the sphere radius [-].
    """

    speed: float
    shortest_contact: float
    longest_contact: float
    contact_radius_ratio: float


def hertz_impacts(spheres: Iterable[tuple[float, Material]], wall: Material | None,
                  speed: float, *, between_spheres: bool = True) -> Impact:
    """Contact times and contact radii of spheres ``(radius [m], material)`` hitting each
    other (unless ``between_spheres`` is False) and a ``wall`` (unless None) at ``speed``
    [m/s]: every pair of the distinct kinds (paper Sect. 3; elastic Hertz closed forms).
    The contact radius is relative to the smaller sphere of a pair."""
    kinds = list({(float(r), m.name): (float(r), m) for r, m in spheres}.values())
    v = max(float(speed), 1e-6)
    pairs = []  # (m*, R*, E*, smaller radius)
    for i, (ri, mi) in enumerate(kinds):
        massi = 4.0 / 3.0 * math.pi * ri**3 * mi.density
        for rj, mj in kinds[i:] if between_spheres else ():
            massj = 4.0 / 3.0 * math.pi * rj**3 * mj.density
            pairs.append((massi * massj / (massi + massj), effective_radius(ri, rj),
                          effective_modulus(mi, mj), min(ri, rj)))
        if wall is not None:
            pairs.append((massi, effective_radius(ri), effective_modulus(mi, wall), ri))
    if not pairs:
        raise ValueError("hertz_impacts needs a wall or contacts between spheres")
    times, ratios = [], []
    for m_star, r_star, e_star, r in pairs:
        k = hertz_stiffness(e_star, r_star)
        times.append(contact_duration(m_star, k, v))
        ratios.append(math.sqrt(r_star * max_overlap(m_star, k, v)) / r)
    return Impact(v, min(times), max(times), max(ratios))


def hertz_impact(damper: ParticleDamper, speed: float) -> Impact:
    """Contact times and contact radius of ``damper``'s spheres hitting each other and the
    walls at ``speed`` [m/s] (:func:`hertz_impacts`).

    >>> from pdamper.parameters import PAPER_DAMPER
    >>> imp = hertz_impact(PAPER_DAMPER, 5.55)
    >>> round(imp.longest_contact * 1e6), round(imp.contact_radius_ratio, 2)
    (100, 0.19)
    """
    return hertz_impacts([(damper.particle_radius, damper.particle_material)],
                         damper.wall_material, speed)


def check_impacts(spheres: Sequence[tuple[float, Material]], wall: Material | None,
                  speed: float, *, speed_field: str, frequency: float | None = None,
                  frequency_field: str = "frequency", radius_field: str = "particles.radius",
                  contact_law: bool = True, between_spheres: bool = True,
                  remedy: str = "lower the impact speed", cause: str = "") -> Impact:
    """Refuse impacts that have no physical meaning: spheres ``(radius [m], material)``
    hitting each other and ``wall`` at up to ``speed`` [m/s] (the fastest impact a run
    implies), under an excitation of ``frequency`` [Hz] (None: none). The limits of the
    module's documentation (the sphere radius, the speed, the contact frequency and, for
    the contact law, the contact radius), in terms of the impacts themselves: every DEM run
    is judged by them when its engine is built (:class:`pdamper.dem.DEMEngine`), and the
    single impacts of ``pdamper cor`` before the first runs, and every harmonic motion
    (:func:`check_motion`); ``cause`` says where the speed comes from in the messages."""
    spheres = list(spheres)
    r_min = min(float(r) for r, _ in spheres)
    if r_min < MIN_PARTICLE_RADIUS:
        raise InputError(radius_field, _small_sphere(r_min))
    materials = [m for _, m in spheres] + ([] if wall is None else [wall])
    slowest = min(materials, key=bar_wave_speed)
    v_max = MAX_SPEED_FRACTION * bar_wave_speed(slowest)
    if not speed <= v_max:
        raise InputError(speed_field, f"impacts at up to {speed:.3g} m/s{cause} are above "
                         f"{MAX_SPEED_FRACTION:g} of the bar wave speed of {slowest.name} "
                         f"({v_max:.3g} m/s): not a quasi-static impact (Hertz's law and "
                         f"the rigid-body model do not hold); {remedy}")
    imp = hertz_impacts(spheres, wall, speed, between_spheres=between_spheres)
    if frequency is not None and frequency * imp.longest_contact > 1.0:
        raise InputError(frequency_field, f"{frequency:.3g} Hz is above the contact frequency "
                         f"{1.0 / imp.longest_contact:.3g} Hz of these spheres at the implied "
                         f"impact speed {speed:.3g} m/s: impacts would last longer than a period")
    if contact_law and imp.contact_radius_ratio > MAX_CONTACT_RADIUS_RATIO:
        raise InputError(speed_field, f"impacts at up to {speed:.3g} m/s{cause} give a Hertz contact "
                         f"radius of {imp.contact_radius_ratio:.2f} of the sphere radius "
                         f"(Hertz's law holds below {MAX_CONTACT_RADIUS_RATIO:g}); {remedy}")
    return imp


def _ratio(value: float, usual: float) -> float:
    return value / usual if usual > 0 else math.inf


class Driver(NamedTuple):
    """An input a cost grows with: ``factor`` is how many times the usual cost its value
    makes (e.g. ``cycles / 8``, or ``10 Hz / frequency`` for an input whose decrease costs,
    ``raising`` then True)."""

    field: str
    factor: float
    raising: bool = False


def _blame(drivers: Sequence[tuple]) -> str:
    """The field that inflates a cost most (its factor over the usual value)."""
    return max(drivers, key=lambda d: d[1] if math.isfinite(d[1]) else math.inf)[0]


def _remedy(drivers: Sequence[tuple], blamed: str) -> str:
    """``lower a, b or raise c``: the inputs above their usual cost, the worst first."""
    big = sorted((Driver(*d) for d in drivers if d[0] == blamed or not d[1] <= 1.0),
                 key=lambda d: -d.factor if math.isfinite(d.factor) else -math.inf)
    verbs = [("lower", [d.field for d in big if not d.raising]),
             ("raise", [d.field for d in big if d.raising])]
    return " or ".join(f"{verb} {', '.join(dict.fromkeys(fields))}"
                       for verb, fields in verbs if fields) or "lower the inputs"


def check_particles(damper: ParticleDamper, field: str = "particles.radius") -> None:
    """Refuse spheres smaller than :data:`MIN_PARTICLE_RADIUS`."""
    r = damper.particle_radius
    if not r >= MIN_PARTICLE_RADIUS:
        raise InputError(field, _small_sphere(r))


def _small_sphere(r: float) -> str:
    return (f"must be >= {MIN_PARTICLE_RADIUS * 1e3:g} mm, got {r * 1e3:.3g} mm: below, "
            f"adhesion outweighs the weight of a sphere (a cohesive powder, not a particle "
            f"damper) and the contact law does not apply")


def check_stroke(value: float, field: str, what: str = "the stroke") -> None:
    """Refuse strokes (or release deflections) above :data:`MAX_STROKE`."""
    if abs(value) > MAX_STROKE:
        raise InputError(field, f"{what} must be within {MAX_STROKE:g} m, got {value:.3g} m: no "
                         f"vibrating structure a damper is mounted on moves that far")


def check_motion(damper: ParticleDamper, frequency: float, amplitude: float, *,
                 fields: tuple[str, str] = ("excitation.frequency", "excitation.amplitude"),
                 usual: tuple[float, float] = (10.0, 0.032), contact_law: bool = False,
                 gravity: float = STANDARD_GRAVITY) -> Impact:
    """Refuse a harmonic motion ``X sin(2 pi f t)`` of ``damper`` that has no physical
    meaning (see the module's documentation); returns the :class:`Impact` it implies.

    Parameters
    ----------
    fields
        Names of the frequency and the amplitude in error messages.
    usual
        Usual frequency [Hz] and amplitude [m]: the one further above is named when the
        speed is too high.
    contact_law
        Also check the Hertz contact radius (models that use the contact law).
    """
    f_field, x_field = fields
    check_stroke(amplitude, x_field)
    materials = (damper.particle_material, damper.wall_material)
    slowest = min(materials, key=bar_wave_speed)
    v_max = MAX_SPEED_FRACTION * bar_wave_speed(slowest)
    # the fastest contact frequency any admissible speed gives: above it, f alone is wrong
    f_contact_max = 1.0 / hertz_impact(damper, v_max).longest_contact
    if frequency > f_contact_max:
        raise InputError(f_field, f"{frequency:.3g} Hz is above the contact frequency of these "
                         f"spheres (at most {f_contact_max:.3g} Hz, one Hertz contact per "
                         f"period at the fastest admissible impact, {v_max:.3g} m/s): impacts "
                         f"would last longer than a period")
    v = impact_speed(amplitude, frequency, damper.length, gravity)
    blame = _blame([(f_field, _ratio(frequency, usual[0])), (x_field, _ratio(amplitude, usual[1]))])
    return check_impacts([(damper.particle_radius, damper.particle_material)],
                         damper.wall_material, v, speed_field=blame, frequency=frequency,
                         frequency_field=f_field, contact_law=contact_law,
                         cause=f" (implied by f = {frequency:.3g} Hz, X = {amplitude:.3g} m)",
                         remedy="lower the frequency or the amplitude")


def check_grid(damper: ParticleDamper, frequency: tuple[float, float],
               amplitude: tuple[float, float], *,
               fields: tuple[str, str] = ("map.frequency", "map.amplitude"),
               usual: tuple[float, float] = (10.0, 0.032), contact_law: bool = False,
               gravity: float = STANDARD_GRAVITY) -> None:
    """:func:`check_motion` over a (frequency x amplitude) grid given by its ranges: the
    impact speed grows with both, the contact frequency with the speed, so the corners
    (f_max, X_max) and (f_max, X_min) decide."""
    for x in (amplitude[1], amplitude[0]):
        check_motion(damper, frequency[1], x, fields=fields, usual=usual,
                     contact_law=contact_law, gravity=gravity)


def check_release(damper: ParticleDamper, natural_frequency: float, x0: float, *,
                  field: str = "structure.initial_displacement",
                  frequency_field: str = "structure.stiffness", contact_law: bool = False,
                  gravity: float = STANDARD_GRAVITY) -> Impact:
    """Refuse a free vibration released from ``x0`` [m] at the structure's natural
    frequency [Hz] that has no physical meaning (see the module's documentation)."""
    check_stroke(x0, field, "the release deflection")
    try:
        return check_motion(damper, natural_frequency, abs(x0),
                            fields=(frequency_field, field), usual=(math.inf, 0.0),
                            contact_law=contact_law, gravity=gravity)
    except InputError as exc:
        if exc.field == frequency_field:  # say which frequency
            raise InputError(frequency_field, "the natural frequency of the structure: "
                             + exc.message) from None
        raise


# ================================================================ cost
@dataclass(frozen=True)
class Cost:
    """What a run implies.

    Attributes
    ----------
    what
        The run, e.g. ``"the DEM run"``.
    seconds
        Estimated run time on one core [s].
    memory
        Bytes of arrays the run holds at once.
    detail
        The implied quantities, e.g. ``"8e+09 s simulated, 4.1e+15 time steps"``.
    drivers
        :class:`Driver` ``(field, factor[, raising])``: each input the cost grows with and
        how many times the usual cost its value makes; the largest is named in an error.
    runs
        For a sweep: the number of runs and the estimated time of the longest
        (``seconds`` is the total).
    remedy
        How to get below a limit (default: lower the drivers above their usual value).
    """

    what: str
    seconds: float
    memory: float
    detail: str
    drivers: tuple[tuple[str, float], ...]
    runs: int = 1
    longest: float | None = None
    remedy: str | None = None


def require(cost: Cost, force: bool = False, override: str = "--force") -> Cost:
    """Refuse ``cost`` above the limits (see the module's documentation); returns it.
    ``override`` is the option that lifts the usual limits, named in the messages
    (``--force``; ``pdamper frf``, whose ``--force`` is its load: ``--allow-cost``).

    Raises
    ------
    InputError
        Naming the input that inflates the cost most, with the implied cost, the limit and
        how to get below it.
    """
    field = _blame(cost.drivers) if cost.drivers else "run"
    lower = cost.remedy or _remedy(cost.drivers, field)
    seconds = cost.seconds if math.isfinite(cost.seconds) else math.inf
    memory = cost.memory if math.isfinite(cost.memory) else math.inf
    ram = physical_memory()
    if ram is not None and memory > ram:
        raise InputError(field, f"{cost.what} would need {_gib(memory)} of memory "
                         f"({cost.detail}), more than this machine has ({_gib(ram)}); "
                         f"{lower}")
    if seconds > FORCE_TIME_LIMIT:
        raise InputError(field, f"{cost.what} would take about {_duration(seconds)} on one "
                         f"core ({cost.detail}), beyond any run ({_duration(FORCE_TIME_LIMIT)} "
                         f"even with {override}); {lower}")
    if force:
        return cost
    if memory > MEMORY_LIMIT:
        raise InputError(field, f"{cost.what} would need {_gib(memory)} of memory "
                         f"({cost.detail}), above the limit of {_gib(MEMORY_LIMIT)}; "
                         f"{lower}, or pass {override}")
    longest = seconds if cost.longest is None else cost.longest
    if longest > TIME_LIMIT:
        each = "" if cost.runs == 1 else " per run"
        raise InputError(field, f"{cost.what} would take about {_duration(longest)}{each} on "
                         f"one core ({cost.detail}), above the limit of "
                         f"{_duration(TIME_LIMIT)}; {lower}, or pass {override}")
    if cost.runs > 1 and seconds > SWEEP_TIME_LIMIT:
        raise InputError(field, f"{cost.what} would take about {_duration(seconds)} on one "
                         f"core in all ({cost.detail}), above the limit of "
                         f"{_duration(SWEEP_TIME_LIMIT)} for a sweep; {lower}, or pass "
                         f"{override}")
    return cost


def dem_cost(damper: ParticleDamper, duration: float, speed: float, *, sample_rate: float,
             safety: float, snapshot_rate: float | None = None,
             frequency: float | None = None, drivers: Iterable[tuple[str, float]] = (),
             what: str = "the DEM run", gravity: float = STANDARD_GRAVITY) -> Cost:
    """Cost of one DEM run of ``duration`` [s] (after settling) with impacts up to
    ``speed`` [m/s]; with a harmonic ``frequency`` the samples per cycle are whole, as the
    engine makes them."""
    dt = safety * hertz_impact(damper, speed).shortest_contact
    # no settling without gravity (the DEM's free_fall_settling)
    settle = math.sqrt(2.0 * damper.length / gravity) + 0.05 if gravity > 0 else 0.0
    if frequency is not None and frequency > 0:
        per_cycle = max(4.0, round(sample_rate / frequency))
        samples = duration * frequency * per_cycle + 1
    else:
        samples = duration * sample_rate + 1
    snapshots = 2.0 if snapshot_rate is None else duration * snapshot_rate + 1
    return dem_run_cost(damper.count, duration, duration + settle, dt, samples, snapshots,
                        drivers, what)


def dem_run_cost(count: int, duration: float, simulated: float, time_step: float,
                 samples: float, snapshots: float, drivers: Iterable[tuple[str, float]] = (),
                 what: str = "the DEM run") -> Cost:
    """Cost of a DEM run of ``count`` spheres that simulates ``simulated`` [s] (``duration``
    of them recorded: settling included) in steps of ``time_step`` [s] (a fixed step; the
    Gear integrator mostly needs fewer), holding ``samples`` samples and ``snapshots``
    particle snapshots; judged from these numbers alone, before any array exists
    (:class:`pdamper.dem.DEMEngine` judges every run by it)."""
    n = max(int(count), 1)
    steps = simulated / time_step
    memory = (samples * DEM_BYTES_PER_SAMPLE + snapshots * n * DEM_BYTES_PER_SNAPSHOT_PARTICLE
              + n * DEM_BYTES_PER_PARTICLE)
    seconds = steps * n * DEM_SECONDS_PER_PARTICLE_STEP
    detail = (f"{duration:.3g} s simulated, ~{steps:.2g} time steps of {time_step:.2g} s for "
              f"{n} spheres, {samples:.3g} samples")
    return Cost(what, seconds, memory, detail, tuple(drivers))


def count_cost(count: float, what: str, items: str, *, bytes_each: float,
               seconds_each: float = 0.0, field: str, usual: float,
               extra: Iterable[tuple[str, float]] = ()) -> Cost:
    """Cost of ``count`` ``items`` (the values of a range, the runs of a list) judged from
    the count alone, before the list is built: ``bytes_each`` of memory and
    ``seconds_each`` of one core per item (each a run of its own when not 0); ``field`` is
    the input that sets the count (``usual``: its usual count).

    >>> c = count_cost(1e9, "the COR check", "single impacts", bytes_each=64,
    ...                seconds_each=0.02, field="velocity", usual=40)
    >>> try:
    ...     require(c, force=True)
    ... except InputError as exc:
    ...     print(exc.field)
    velocity
    """
    n = float(count)
    return Cost(what, n * seconds_each, n * bytes_each, f"{n:.3g} {items}",
                ((field, _ratio(n, usual)), *extra),
                runs=max(1, int(min(n, 2**62))) if seconds_each else 1,
                longest=seconds_each if seconds_each else None,
                remedy=f"give {field} fewer values")


def analytic_map_cost(points: float, drivers: Iterable[tuple[str, float]] = ()) -> Cost:
    """Cost of the analytical model over ``points`` (f, X) points."""
    return Cost("the analytical map", points * ANALYTIC_SECONDS_PER_POINT,
                points * ANALYTIC_BYTES_PER_POINT, f"{points:.3g} grid points", tuple(drivers))


def pseudo_force_cost(duration: float, sample_rate: float, natural_frequency: float,
                      drivers: Iterable[tuple[str, float]] = (),
                      what: str = "the free vibration") -> Cost:
    """Cost of a pseudo-force free vibration of ``duration`` [s]: one damper update per
    cycle (at most ``natural_frequency`` cycles per second), the trajectory sampled at
    ``sample_rate`` [Hz]."""
    samples = duration * sample_rate + 1
    cycles = duration * natural_frequency + 1
    return Cost(what, cycles * PSEUDO_FORCE_SECONDS_PER_CYCLE,
                samples * PSEUDO_FORCE_BYTES_PER_SAMPLE,
                f"{samples:.3g} samples, {cycles:.3g} damper updates", tuple(drivers))


def stepped_sine_cost(frequencies: float, cycles: float, sweeps: int, modes: int,
                      strokes: int, drivers: Iterable[tuple] = (),
                      what: str = "the forced response") -> Cost:
    """Cost of a pseudo-force forced response (:func:`pdamper.coupling.frf.frequency_response`)
    at ``frequencies`` frequencies: a describing-function table of ``strokes`` strokes per
    frequency (shared by harmonic balance and the sweeps, all held at once) and ``sweeps``
    stepped sines of at most ``cycles`` load cycles per step on ``modes`` modes, each cycle
    ~(2N)^3 (the modal state's matrix exponential).

    >>> c = stepped_sine_cost(121, 2000, 2, 1, 800)
    >>> round(c.seconds)
    50
    """
    nf, n = float(frequencies), float(max(int(modes), 1))
    per_cycle = FRF_SECONDS_PER_CYCLE + FRF_SECONDS_PER_STATE_CUBED * (2.0 * n) ** 3
    steps = nf * max(int(sweeps), 0)
    seconds = nf * strokes * FRF_SECONDS_PER_STROKE + steps * float(cycles) * per_cycle
    memory = nf * strokes * FRF_BYTES_PER_STROKE + FRF_BYTES_PER_STATE_ENTRY * (2.0 * n) ** 2
    return Cost(what, seconds, memory,
                f"{nf:.3g} frequencies x {int(sweeps)} sweeps x up to {float(cycles):.3g} "
                f"cycles per step on {int(n)} modes", tuple(drivers))
