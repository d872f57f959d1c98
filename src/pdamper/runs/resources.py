"""What the runs of a scenario imply (memory, time steps, grid points), judged before they
start.

:func:`check_resources` refuses a run of a :class:`~pdamper.io.scenario.Scenario` whose
implied memory or time is above the limits of :mod:`pdamper.resources` (with ``force``: up
to the hard limits), naming the input that drives the cost; :func:`check_runs` judges the
runs a command is about to make. The costs themselves are the models' own
(:meth:`pdamper.models.DamperModel.excitation_cost`, ``map_cost``,
``free_vibration_cost``); this module says which runs a scenario asks for and what each
input drives relative to the defaults (the paper's case).

What has no physical meaning in any model is refused when the scenario is read
(:meth:`pdamper.io.scenario.Scenario.check_physics`), whichever command reads it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from pdamper import resources
from pdamper.errors import InputError
from pdamper.io.scenario import Scenario
from pdamper.parameters import vertical_dampers_paper as paper

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.coupling.frf import HarmonicLoad
    from pdamper.damper import ParticleDamper
    from pdamper.models.base import DamperModel

#: Runs whose cost :func:`check_resources` judges.
RUNS = ("excitation", "map", "simulation", "optimization", "case_study", "case_study_dem",
        "frf")
#: The option that lifts the cost limits of ``pdamper frf`` (its ``--force`` is the load).
FRF_OVERRIDE = "--allow-cost"
#: Usual frequency count, load cycles per step of a pseudo-force and of a DEM stepped sine,
#: and the DEM's samples per load cycle (``pdamper frf``'s defaults).
USUAL_FRF = {"frequencies": 121, "pseudo_force_cycles": 2000, "co_simulation_cycles": 60,
             "samples_per_cycle": 64}
#: Usual (f [Hz], X [m]) of a Level II run: the paper's benchmark point; of the two, the
#: one further above its usual value is named when a motion is too fast.
USUAL_EXCITATION = paper.BENCHMARK_EXCITATION

#: A judge of one cost, ``require(cost, force)`` (:func:`pdamper.resources.require`).
Require = Callable[..., Any]


def check_runs(scenario: Scenario, runs: Iterable[str], model: str | None = None,
               force: bool = False) -> Scenario:
    """:func:`check_resources` of each of ``runs`` with ``model`` and ``force``; returns
    ``scenario`` (a command's ``load_scenario(...)`` followed by the judgement of the runs
    it is about to make)."""
    for run in runs:
        check_resources(scenario, run, model, force)
    return scenario


def check_resources(scenario: Scenario, run: str, model: str | None = None,
                    force: bool = False, require: Require | None = None) -> None:
    """Refuse a run whose implied memory or time is above the limits of
    :mod:`pdamper.resources` (``force``: up to the hard limits), or for which its model's
    physics does not hold (the DEM's contact law).

    Parameters
    ----------
    scenario
        The :class:`~pdamper.io.scenario.Scenario`.
    run
        ``"excitation"`` (Level II at ``[excitation]``), ``"map"`` (Level II over
        ``[map]``), ``"simulation"`` (Level III, ``[simulation]``), ``"optimization"``
        (``[optimization]``), ``"case_study"`` or ``"case_study_dem"`` (the paper's,
        without or with the DEM model 1 run), ``"frf"`` (the forced response of
        ``pdamper frf`` at its default load and frequencies; :func:`check_frf` judges
        others).
    model
        Damper fidelity of ``excitation``, ``map`` and ``simulation`` (default
        ``"analytic"``; for ``simulation`` and ``optimization`` the ``[simulation]``
        model).
    force
        Allow more than the limits, up to what this machine can hold.
    require
        The judge of each cost, ``require(cost, force)`` (default
        :func:`pdamper.resources.require`; e.g. one that counts N realisations of a run).

    Raises
    ------
    InputError
        The input that drives a cost above the limits (its message names ``--force``
        where forcing would allow it), or ``run`` for an unknown run.

    Examples
    --------
    >>> from pdamper.io.scenario import load_scenario
    >>> s = load_scenario(None, {"map.frequency": "2Hz:20Hz:10000"})
    >>> try:
    ...     check_resources(s, "map")
    ... except InputError as exc:
    ...     print(exc.field, "--force" in exc.message)
    map.frequency True
    """
    from pdamper.models import get_damper_model

    if run not in RUNS:
        raise InputError("run", f"must be one of {', '.join(RUNS)}, got {run!r}")
    req = resources.require if require is None else require
    damper = scenario.damper()
    default = Scenario()
    field = "model" if model else "simulation.model"
    sim = scenario.simulation
    if run == "excitation":
        cost = excitation_cost(scenario, model or "analytic", damper)
        if cost is not None:
            req(cost, force)
    elif run == "map":
        _check_map(scenario, damper, get_damper_model(model or "analytic", "model"), default,
                   force, req)
    elif run == "simulation":
        cls = get_damper_model(model or sim.model, field)
        _check_simulation(scenario, damper, cls, sim.duration, sim.sample_rate, default,
                          force, req)
    elif run == "optimization":
        cls = get_damper_model(model or sim.model, field)
        _check_optimization(scenario, damper, cls, default, force, req)
    elif run == "frf":
        from pdamper.coupling.frf import HarmonicLoad

        check_frf(scenario, model, np.linspace(3.0, 9.0, USUAL_FRF["frequencies"]),
                  HarmonicLoad("force", 2.0), force=force, require=req)
    else:  # the paper's case study (pdamper.runs.paper_case_study)
        analytic = get_damper_model("analytic")
        _check_map(scenario, damper, analytic, default, force, req)
        for duration in (sim.duration, max(sim.duration, paper.PAPER_DURATION)):
            _check_simulation(scenario, damper, analytic, duration, sim.sample_rate, default,
                              force, req)
        _check_optimization(scenario, damper, analytic, default, force, req)
        if run == "case_study_dem":
            _check_simulation(scenario, damper, get_damper_model("dem"), sim.duration,
                              sim.sample_rate, default, force, req)


def excitation_cost(scenario: Scenario, model: str = "analytic",
                    damper: ParticleDamper | None = None) -> resources.Cost | None:
    """What one Level II response of fidelity ``model`` at ``[excitation]`` costs
    (:meth:`pdamper.models.DamperModel.excitation_cost`; None: not worth judging), for
    ``damper`` (default the scenario's)."""
    from pdamper.models import get_damper_model

    cls = get_damper_model(model, "model")
    d = scenario.damper() if damper is None else damper
    x = scenario.excitation
    return cls.excitation_cost(d, x.frequency, x.amplitude, scenario.settings_of(cls),
                               gravity=x.gravity, usual=USUAL_EXCITATION,
                               damper_drivers=_damper_drivers(d, Scenario()))


def _damper_drivers(damper: ParticleDamper, default: Scenario) -> list[tuple]:
    """The damper's inputs that drive a run's cost, relative to the default damper: the
    particle count (time ~ n_p) and the radius (the contact time ~ r: time ~ 1 / r)."""
    dm = default.damper()
    return [("particles.count", damper.count / dm.count),
            ("particles.radius", dm.particle_radius / damper.particle_radius, True)]


def _check_map(sc: Scenario, damper: ParticleDamper, cls: type[DamperModel],
               default: Scenario, force: bool, req: Require) -> None:
    """Cost of the Level II map of ``[map]``: its grid and result arrays, and the model's
    runs at every point."""
    (f0, f1, nf), (x0, x1, nx) = sc.map_ranges()
    (_, _, nf0), (_, _, nx0) = default.map_ranges()
    counts = sc.map_particles()
    axes = (("map.frequency", nf / nf0), ("map.amplitude", nx / nx0),
            ("map.particles", 1.0 if counts is None else float(counts.size)))
    points = float(nf) * float(nx) * (1.0 if counts is None else float(counts.size))
    # the grid and the four result arrays [8 bytes each], whichever the model
    req(resources.Cost("the map", 0.0, points * 40.0, f"{points:.3g} points", axes), force)
    req(cls.map_cost(damper, (f0, f1, nf), (x0, x1, nx), points, sc.settings_of(cls),
                     gravity=sc.excitation.gravity, usual=USUAL_EXCITATION, axes=axes,
                     damper_drivers=_damper_drivers(damper, default)), force)


def _check_simulation(sc: Scenario, damper: ParticleDamper, cls: type[DamperModel],
                      duration: float, sample_rate: float, default: Scenario, force: bool,
                      req: Require) -> None:
    """Cost of one Level III free vibration of ``duration`` [s] sampled at
    ``sample_rate`` [Hz]."""
    structure = sc.structure_model()
    ds = default.simulation
    drivers = [("simulation.duration", duration / ds.duration),
               ("simulation.sample_rate", sample_rate / ds.sample_rate),
               ("structure.stiffness", structure.natural_frequency
                / default.structure_model().natural_frequency)]
    req(cls.free_vibration_cost(
        damper, duration, sample_rate, structure.natural_frequency, sc.settings_of(cls),
        x0=sc.structure.initial_displacement, drivers=drivers,
        damper_drivers=_damper_drivers(damper, default)), force)
    modes = int(getattr(structure, "modes", 1))
    # the DEM's cost above holds on N modes too (the modes' integration costs nothing
    # against the particles'); a damper force's modal march is costed here
    if modes > 1 and not _integrates_particles(cls):
        req(modal_free_vibration_cost(structure, duration, sample_rate, drivers), force)


def _integrates_particles(cls: type[DamperModel]) -> bool:
    """Whether the coupling of model class ``cls`` integrates the particles with the
    structure (the DEM's cost), from the coupling table."""
    from pdamper.coupling.registry import coupling_of

    return coupling_of(cls).integrates_particles


#: Pseudo-force coupling on N modes (:mod:`pdamper.coupling.modal`), per damper update:
#: one-core seconds per entry of the 2N x 2N state matrix cubed (its eigen-decomposition,
#: condition number and solve) and per entry of the state matrix squared and scan sample
#: (the closed-form state at each sample scanned for the next minimum, about two first-mode
#: periods of them). Measured (one core, 2-core machine under load, one update per run,
#: modes from 5 Hz up at 1 % damping): 1.5-1.9 s per update at N = 400 (2 400 samples per
#: scanned period), 8.9 s at 700 (4 200), 26.5 s at 1 000 (6 000) and 57 s at 1 000 with
#: modes up to 5.6 kHz (12 000); the eigen-decomposition alone 0.49 s and one scan 0.58 s
#: at N = 400. These constants give 2.0 / 10.7 / 31 / 50 s: within 20 %, mostly above.
MODAL_SECONDS_PER_STATE_CUBED = 1.5e-9
MODAL_SECONDS_PER_STATE_SQUARED_SAMPLE = 8e-10
#: Bytes per state entry and scan sample (the complex exponentials and their product with
#: the eigenvectors, held at once: three complex arrays, more where a segment's slowest
#: oscillation is slower than the first mode's and its scan longer) and per entry of the
#: 2N x 2N state matrix (it and its eigenvectors, held through the scan). Measured peak
#: resident memory above the process's 0.1 GB: one update 0.28 GB at N = 700, 0.51 GB at
#: 1 000, 0.89 GB at 1 000 up to 5.6 kHz; the whole 2 s run of 1 000 modes (10 updates)
#: 1.4 GB, in 974 s wall on the loaded 2-core machine. These constants give 0.77 / 1.47 /
#: 2.8 GB: the whole run is covered, and 1 000 modes up to 5.6 kHz is refused (2 GiB).
MODAL_BYTES_PER_STATE_SAMPLE = 16 * 7
MODAL_BYTES_PER_STATE_ENTRY = 16 * 2
#: Scan samples per first-mode period and per period of the fastest mode
#: (:mod:`pdamper.coupling.modal`'s scan step).
MODAL_SCAN_PER_PERIOD, MODAL_SCAN_PER_FAST_PERIOD = 400, 12


def modal_free_vibration_cost(structure: Any, duration: float, sample_rate: float,
                              drivers: Sequence[tuple] = (), *,
                              what: str = "the modal free vibration",
                              runs: float = 1.0) -> resources.Cost:
    """What the pseudo-force free vibration of an N-mode ``structure`` (a
    :class:`~pdamper.structure.modal.ModalStructure`) of ``duration`` [s] sampled at
    ``sample_rate`` [Hz] costs, judged from the mode count and the modes' frequencies
    before any matrix is built: per damper update (one per first-mode period, ``duration
    f_1 + 1`` of them) an eigen-decomposition of the 2N x 2N state matrix, ~(2N)^3, and a
    scan of ``max(400, 12 f_N / f_1)`` samples per period of the state, ~(2N)^2 each and
    held at once; the stored trajectory, N x the samples. ``runs`` such runs one after
    another (a design study's candidates) cost ``runs`` times the time. The mode count is
    named when it is too high, with the most modes that fit the limits.
    """
    n = int(structure.modes)
    freqs = np.sort(np.asarray(structure.frequencies, float))
    cost = _modal_cost(freqs, duration, sample_rate, runs)
    seconds, memory, updates, scan = cost
    state = 2 * n
    detail = (f"{n} modes ({freqs[0]:.3g}-{freqs[-1]:.3g} Hz), {updates:.3g} damper updates "
              f"of a {state} x {state} state scanned at {scan:.3g} samples per period")
    if runs != 1:
        detail = f"{runs:.3g} runs, each {detail}"
    return resources.Cost(
        what, seconds, memory, detail, (("structure.modes", float(n)), *drivers),
        runs=int(min(max(runs, 1.0), 2**62)), longest=seconds / max(runs, 1.0),
        remedy=_modes_allowed(freqs, duration, sample_rate, runs))


def _modal_cost(freqs: np.ndarray, duration: float, sample_rate: float,
                runs: float = 1.0) -> tuple[float, float, float, float]:
    """(seconds, bytes, damper updates, scan samples per period) of
    :func:`modal_free_vibration_cost` for the ascending mode frequencies ``freqs`` [Hz]."""
    n = freqs.size
    f1, fmax = float(freqs[0]), float(freqs[-1])
    state = 2.0 * n
    scan = max(MODAL_SCAN_PER_PERIOD, MODAL_SCAN_PER_FAST_PERIOD * fmax / f1)
    updates = duration * f1 + 1.0
    per_update = (MODAL_SECONDS_PER_STATE_CUBED * state**3
                  + MODAL_SECONDS_PER_STATE_SQUARED_SAMPLE * state**2 * scan)
    samples = duration * sample_rate + 1.0
    memory = (MODAL_BYTES_PER_STATE_SAMPLE * state * scan
              + MODAL_BYTES_PER_STATE_ENTRY * state**2 + 8.0 * (n + 3) * samples)
    return runs * updates * per_update, memory, updates, scan


def _modes_allowed(freqs: np.ndarray, duration: float, sample_rate: float,
                   runs: float) -> str:
    """What the limits allow: the most of the first modes whose run stays within the
    usual limits of :func:`pdamper.resources.require`."""
    def fits(k: int) -> bool:
        seconds, memory, _, _ = _modal_cost(freqs[:k], duration, sample_rate, runs)
        longest = seconds / max(runs, 1.0)
        return (memory <= resources.MEMORY_LIMIT and longest <= resources.TIME_LIMIT
                and (runs <= 1 or seconds <= resources.SWEEP_TIME_LIMIT))

    if not fits(1):
        return "shorten the run"  # not even one mode fits: the duration drives it
    lo, hi = 1, int(freqs.size)
    while lo < hi:  # the cost grows with the first k modes
        mid = (lo + hi + 1) // 2
        lo, hi = (mid, hi) if fits(mid) else (lo, mid - 1)
    return (f"give structure.modes at most {lo} modes (the first {lo} fit the limits; the "
            "first few carry a damper's response) or shorten the run")


def _check_optimization(sc: Scenario, damper: ParticleDamper, cls: type[DamperModel],
                        default: Scenario, force: bool, req: Require) -> None:
    """Cost of the design study (:func:`pdamper.design.optimize_design`): one free
    vibration of ``at`` plus two periods, sampled at 200 Hz, per candidate (the
    particle counts of the paper's study, the grid of ``vary``, or the optimiser's
    budget), and the values of each varied variable, judged from their numbers before
    they are built."""
    from pdamper.design.study import USUAL_VALUES, values_cost, variable_field

    structure = sc.structure_model()
    o = sc.optimization
    at = o.at
    duration = at + 2.0 / structure.natural_frequency
    d0 = default.damper()
    step = o.step or damper.per_layer
    counts = range(0, damper.max_count, step)
    drivers: tuple = (("optimization.at", at / default.optimization.at),)
    if o.vary:
        sizes = o.sizes()
        for name, size in sizes:
            req(values_cost(name, size), force)
        grid = math.prod(size for _, size in sizes)
        method = o.method
        if method == "auto":
            method = "grid" if grid <= o.max_grid else "optimize"
        if method == "grid" and math.isfinite(grid):
            candidates = grid
            drivers += tuple((variable_field(name), size / USUAL_VALUES)
                             for name, size in sizes)
        else:
            candidates = o.max_evaluations
            drivers += (("optimization.max_evaluations",
                         candidates / default.optimization.max_evaluations),)
    else:
        candidates = len(counts)
        drivers += (("optimization.step", (d0.per_layer / step)
                     * (damper.max_count / d0.max_count), True),)
    if o.objective in ("peak-frf", "rms-frf"):
        _check_frf_objective(sc, damper, cls, candidates, force, req)
    history = sc.load.history() if o.objective in ("peak", "rms") else None
    if history is not None:  # the load objectives' history, as simulate judges it
        from pdamper.coupling.loads import acting_at

        check_load_history(sc, acting_at(structure, sc.load.at), history)
    # one candidate; where the time grows with the count, the mean count stands for all
    one = cls.free_vibration_cost(damper, duration, 200.0, structure.natural_frequency,
                                  sc.settings_of(cls), x0=sc.structure.initial_displacement,
                                  count=max(1, round(counts[-1] / 2)) if counts else 1)
    if int(getattr(structure, "modes", 1)) > 1 and not _integrates_particles(cls):
        # every candidate's free vibration on the N modes (the modal march of a damper force)
        req(modal_free_vibration_cost(structure, duration, 200.0, drivers,
                                      what="the optimisation", runs=candidates), force)
    req(resources.Cost(
        "the optimisation", one.seconds * candidates,
        one.memory + candidates * resources.BYTES_PER_CANDIDATE,
        f"{candidates:.3g} candidates, each {one.detail}", drivers,
        runs=int(min(candidates, 2**62)), longest=one.seconds), force)


def _check_frf_objective(sc: Scenario, damper: ParticleDamper, cls: type[DamperModel],
                         candidates: float, force: bool, req: Require) -> None:
    """The forced-response objectives: the band's count judged before it is built, one
    forced response per candidate (:func:`frf_cost`), and the load against the physics
    limits at the largest steady stroke it drives the bare structure to over the band."""
    from pdamper.coupling.frf import HarmonicLoad, check_damped
    from pdamper.design.study import FRF_BAND, FRF_LOAD
    from pdamper.io.scenario import parse_axis

    o = sc.optimization
    structure = sc.structure_model()
    check_damped(structure)  # an undamped structure's response is unbounded: said first
    if o.band is not None and ":" in o.band:
        count = parse_axis(o.band, "Hz", "optimization.band")[2]  # before the grid exists
        req(resources.count_cost(count, "the band", "frequencies",
                                 bytes_each=resources.FRF_BYTES_PER_STROKE * 800,
                                 field="optimization.band", usual=FRF_BAND[2]), force)
    band = o.frf_band()
    if band is None:  # every mode of the structure (as make_objective)
        from pdamper.coupling.frf import default_frequencies

        band = default_frequencies(structure)
    band = np.atleast_1d(np.asarray(band, float))
    load = HarmonicLoad.parse(o.frf_load or FRF_LOAD, field="optimization.frf_load")
    one = frf_cost(sc, cls.fidelity, band, load)
    req(resources.Cost("the optimisation's forced responses", one.seconds * candidates,
                       one.memory, f"{candidates:.3g} candidates, each {one.detail}",
                       (("optimization.band", band.size / FRF_BAND[2]),),
                       runs=int(min(candidates, 2**62)), longest=one.seconds), force)
    check_harmonic_load(damper, structure, load, band,
                        fields=("optimization.band", "optimization.frf_load"),
                        gravity=sc.excitation.gravity)


def check_harmonic_load(damper: ParticleDamper, structure: Any, load: HarmonicLoad,
                        frequencies: Any, *, fields: tuple[str, str], gravity: float) -> None:
    """Judge a harmonic load by :func:`check_load` before any frequency is solved: the
    bare structure's steady stroke at the damper's point, the largest over
    ``frequencies`` [Hz] (any structure: the force at the damper that moves it as the load
    does). A load the structure cannot take (base motion of N modes) is refused under the
    load's field (``fields``: the frequencies' and the load's names)."""
    from pdamper.coupling.frf import _modal, check_damped, damper_force, receptance

    check_damped(structure)  # an undamped structure's response is unbounded: said first
    s = _modal(structure)
    band = np.atleast_1d(np.asarray(frequencies, float))
    try:
        x = np.array([abs(complex(receptance(s, f))) * abs(damper_force(s, load, f))
                      for f in band])
    except InputError as exc:  # a load this structure cannot take (base motion, N modes)
        raise InputError(fields[1], exc.message) from None
    k = int(np.argmax(x))
    check_load(damper, float(band[k]), float(x[k]), fields=fields, gravity=gravity)


def check_load(damper: ParticleDamper, frequency: float, stroke: float, *,
               fields: tuple[str, str], gravity: float) -> None:
    """The one judge of a load against the physics limits: refuse a load that drives the
    bare structure's damper point through ``stroke`` [m] at ``frequency`` [Hz] where a
    damper's motion there would have no physical meaning
    (:func:`pdamper.resources.check_motion`: the stroke, the impact speed against the bar
    wave speed, the contact frequency). ``fields``: the frequency's and the load's names
    (the load's is named when the speed is too high)."""
    try:
        resources.check_motion(damper, frequency, stroke, fields=fields,
                               usual=(math.inf, 0.0), gravity=gravity)
    except InputError as exc:
        raise InputError(exc.field, f"the load drives the bare structure to {stroke:.3g} m "
                         f"at {frequency:.3g} Hz: {exc.message}") from None


def check_load_history(scenario: Scenario, structure: Any, history: Any) -> None:
    """Judge a load history (:class:`~pdamper.coupling.loads.LoadHistory`: a force at the
    structure's load point, or a base acceleration of a one-mode structure) by
    :func:`check_load`, before any run: the bare structure's linear response of the damper
    point to each line of the record's spectrum (the record resampled on its finest step,
    at most 2^16 samples), its largest line taken as a steady motion, as the
    forced-response objectives judge a harmonic load. A base acceleration of an N-mode
    structure is not judged here (its modal forces need the coupling's participation
    factors)."""
    from pdamper.coupling.frf import HarmonicLoad, _modal, load_force, receptance

    field = "load" if history.kind == "force" else "base_acceleration"
    t = np.asarray(history.time, float)
    v = np.asarray(history.values, float)
    span = float(t[-1] - t[0])
    if span <= 0 or not np.any(v):
        return
    n = int(min(2**16, max(16, span / max(float(np.min(np.diff(t))), span / 2**16) + 1)))
    grid = np.linspace(t[0], t[-1], n)
    line = 2.0 * np.abs(np.fft.rfft(np.interp(grid, t, v))) / n
    f = np.fft.rfftfreq(n, span / (n - 1))
    keep = f > 0
    f, line = f[keep], line[keep]
    s = _modal(structure)
    if history.kind == "force":
        x = np.abs(receptance(s, f, "damper", "load")) * line
    elif s.modes == 1 and np.array_equal(s.damper_shape, s.output_shape):
        # the absolute motion of a 1-DOF's damper point under the base's
        x = np.array([abs(complex(receptance(s, fk))
                          * load_force(s, HarmonicLoad("base", 1.0, acceleration=True), fk))
                      for fk in f]) * line
    else:  # N modes: the coupling's participation factors carry it (not judged here)
        return
    k = int(np.argmax(x))
    check_load(scenario.damper(), float(f[k]), float(x[k]), fields=(field, field),
               gravity=scenario.excitation.gravity)


def check_frf(scenario: Scenario, model: str | None, frequencies: Sequence[float] | np.ndarray,
              load: HarmonicLoad, *, max_cycles: int | None = None, sweep: str = "both",
              force: bool = False, require: Require | None = None) -> resources.Cost:
    """Refuse a forced response (``pdamper frf``) whose implied memory or time is above the
    limits (``force``: up to the hard limits; the message names :data:`FRF_OVERRIDE`), or
    whose load is beyond the physics limits (:func:`check_harmonic_load`), before any
    frequency is solved; returns its :func:`frf_cost`."""
    from pdamper.coupling.loads import acting_at

    cost = frf_cost(scenario, model, frequencies, load, max_cycles=max_cycles, sweep=sweep)
    cost = (require(cost, force) if require is not None
            else resources.require(cost, force, override=FRF_OVERRIDE))
    check_harmonic_load(scenario.damper(), acting_at(scenario.structure_model(),
                                                     scenario.frf.at, "frf.at"),
                        load, frequencies, fields=("frequency", load.kind),
                        gravity=scenario.excitation.gravity)
    return cost


def frf_cost(scenario: Scenario, model: str | None, frequencies: Sequence[float] | np.ndarray,
             load: HarmonicLoad, *, max_cycles: int | None = None,
             sweep: str = "both") -> resources.Cost:
    """What the forced response of :func:`pdamper.coupling.frf.frequency_response` costs with
    fidelity ``model`` (default ``[simulation] model``) on the scenario's structure, under
    ``load`` at ``frequencies`` [Hz], judged from the counts before any work: the
    fidelity's coupling decides the per-cycle cost.

    - pseudo-force models (analytic, fields): frequencies x sweeps x ``max_cycles`` load
      cycles per step x the cost of a cycle on N modes, ~(2N)^3, plus a describing-function
      table per frequency (:func:`pdamper.resources.stepped_sine_cost`);
    - the DEM (co-simulation): a DEM run of ``max_cycles`` load periods per frequency and
      sweep (:func:`pdamper.resources.dem_cost`), its impacts at the fastest speed the
      load's steady amplitude on the bare structure implies (``max_cycles / f`` simulated
      seconds: a low frequency costs most).
    """
    from pdamper.coupling.frf import DEFAULT_MAX_CYCLES, DEFAULT_STROKES, _modal, receptance
    from pdamper.coupling.frf import load_force as harmonic_force
    from pdamper.models import get_damper_model

    cls = get_damper_model(model or scenario.simulation.model,
                           "model" if model else "simulation.model")
    f = np.unique(np.asarray(frequencies, float).ravel())
    nf = int(f.size)
    sweeps = {"both": 2, "none": 0}.get(sweep, 1)
    s = _modal(scenario.structure_model())
    n = int(s.modes)
    drivers: list[tuple] = [("frequency", nf / USUAL_FRF["frequencies"]),
                            ("structure.modes", float(n))]
    if _integrates_particles(cls):
        cycles = 60 if max_cycles is None else int(max_cycles)
        damper = scenario.damper()
        settings = scenario.settings_of(cls)
        safety = getattr(settings, "safety", 0.1)
        gravity = scenario.excitation.gravity
        drivers += [("max_cycles", cycles / USUAL_FRF["co_simulation_cycles"]),
                    ("frequency", 1.0 / float(f[0]), True),
                    *_damper_drivers(damper, Scenario())]
        # the lowest frequencies cost most (max_cycles / f simulated seconds): judge a sample
        sample = f if nf <= 16 else f[np.unique(np.linspace(0, nf - 1, 16).astype(int))]
        costs = []
        for fk in sample:
            fk = float(fk)
            if s.modes == 1 and s.coincident:
                x = abs(complex(receptance(s, fk))) * abs(harmonic_force(s, load, fk))
            else:
                x = 0.0  # refused by the coupling before any run (one DOF only)
            speed = resources.impact_speed(x, fk, damper.length, gravity)
            costs.append(resources.dem_cost(
                damper, cycles / fk, speed, sample_rate=USUAL_FRF["samples_per_cycle"] * fk,
                safety=safety, frequency=fk, gravity=gravity, drivers=drivers,
                what="the DEM forced response"))
        worst = max(costs, key=lambda c: c.seconds)
        total = float(np.mean([c.seconds for c in costs])) * nf * sweeps
        return resources.Cost(
            "the DEM forced response", total, max(c.memory for c in costs),
            f"{nf} frequencies x {sweeps} sweeps, the longest step {worst.detail}",
            tuple(drivers), runs=max(1, nf * sweeps), longest=worst.seconds,
            remedy="raise the lowest frequency, give frequency fewer values or lower "
                   "max_cycles")
    from pdamper.coupling.registry import coupling_of

    own = coupling_of(cls).sweep_cost(s, f, sweeps, max_cycles, drivers)
    if own is not None:  # a coupling that judges its own stepped sine (the plastic block)
        return own
    cycles = DEFAULT_MAX_CYCLES if max_cycles is None else int(max_cycles)
    drivers.append(("max_cycles", cycles / USUAL_FRF["pseudo_force_cycles"]))
    cost = resources.stepped_sine_cost(nf, cycles, sweeps, n, DEFAULT_STROKES, drivers)
    return dataclasses.replace(cost, remedy="give frequency fewer values, lower max_cycles "
                               "or give structure.modes fewer modes")


def frf_sample_cost(scenario: Scenario, frequencies: int) -> resources.Cost:
    """What one sample of an uncertain forced response costs (``pdamper frf
    --uncertainty``, :func:`pdamper.runs.uncertainty.frf_answers`): harmonic balance at
    ``frequencies`` frequencies on the scenario's structure (a describing-function table
    per frequency, no stepped sine), as :func:`frf_cost` judges it."""
    from pdamper.coupling.frf import DEFAULT_STROKES, _modal

    n = int(_modal(scenario.structure_model()).modes)
    return resources.stepped_sine_cost(int(frequencies), 0, 0, n, DEFAULT_STROKES,
                                       [("frequency", frequencies / USUAL_FRF["frequencies"]),
                                        ("structure.modes", float(n))])


__all__ = ["FRF_OVERRIDE", "RUNS", "USUAL_EXCITATION", "check_frf", "check_load",
           "check_load_history", "check_resources",
           "check_runs", "excitation_cost", "frf_cost", "frf_sample_cost",
           "modal_free_vibration_cost"]
