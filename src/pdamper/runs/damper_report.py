"""The runs of a report of the user's own damper (``pdamper report``): everything
:mod:`pdamper.reports.damper_report` shows, computed from one
:class:`~pdamper.io.scenario.Scenario`.

:func:`run_damper_report` computes:

- Level II: the analytical map (loss factor, effective mass, motion mode) over ``[map]``
  and, when asked (``dem=True``), the DEM map on ``[map] dem_frequency x dem_amplitude``
  (the sweep engine, cached in the output directory as ``pdamper paper`` does);
- Level III: the structure's free decay (``[structure]``, one DOF or N modes) with the
  models compared: the analytical formulas (model 3), the effective fields (model 2: the
  scenario's ``[fields] file``, else the analytical map, clamped at its edges) and, with
  ``dem=True``, the DEM (model 1);
- the forced response of the models with a harmonic balance (:func:`forced_response`);
- the design landscape of ``[optimization]`` (its ``vary``, or the particle-count study)
  with the analytical model, with the Pareto front of added mass against the objective, the
  best design and the lightest within the tolerance;
- the spread of the Level II and III answers under the inputs given as ``"value +- sd"``
  (:mod:`pdamper.runs.uncertainty`), when the scenario has any;
- the run time of each step, the version and the seeds.

The figures and the page are :mod:`pdamper.reports.damper_report`'s.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

    from pdamper.coupling.results import FreeVibrationResult
    from pdamper.damper import ParticleDamper
    from pdamper.design.study import DesignStudyResult
    from pdamper.io.scenario import Scenario

#: Base points of the report's uncertainty propagation (a power of two; N (d + 2) runs).
DEFAULT_UNCERTAINTY_POINTS = 32


@dataclass
class DamperReport:
    """What :func:`run_damper_report` computed."""

    title: str
    version: str
    inputs: dict
    damper: ParticleDamper | None = None
    structure: object = None
    level2_map: xr.Dataset | None = None  # analytical
    dem_map: xr.Dataset | None = None  # DEM, or None
    runs: dict = field(default_factory=dict)  # label -> FreeVibrationResult
    sources: dict = field(default_factory=dict)  # label -> what the model rests on
    empty: FreeVibrationResult | None = None  # run without particles
    study: DesignStudyResult | None = None
    study_model: str = "analytic"
    uncertainty: dict = field(default_factory=dict)  # "level2"/"level3" -> result
    timings: dict = field(default_factory=dict)
    seeds: dict = field(default_factory=dict)
    at: float = 0.0
    figures: list = field(default_factory=list)  # ReportFigure, made when it is written
    uncertain: tuple = ()  # the scenario's "value +- sd" inputs
    forced: dict = field(default_factory=dict)  # label -> FRFResult (harmonic balance)
    forced_load: Any = None  # the HarmonicLoad of the forced response
    forced_text: str = ""  # the load and where it acts, in words
    band: Any = None  # Level3Band of the DEM's realisations (with dem and realisations)
    figure_errors: dict = field(default_factory=dict)  # figure name -> why it is missing
    not_applicable: dict = field(default_factory=dict)  # result key -> why it is null
    # label -> whether the run's damper answers up to ``at`` hold the analytical model's
    # assumptions (pdamper.coupling.validity.decay_assumptions; models without the check
    # absent)
    assumptions: dict = field(default_factory=dict)
    # label -> the run's near-harmonic measure (pdamper.coupling.harmonicity.payload)
    harmonicity: dict = field(default_factory=dict)
    # label -> why the run's effective fields rest on the analytical model (no DEM map)
    analytic_fields: dict = field(default_factory=dict)
    used: dict = field(default_factory=dict)  # the inputs the report used
    not_used: dict = field(default_factory=dict)  # key -> why the report did not use it
    modal: dict = field(default_factory=dict)  # the structure's data (runs.report_inputs)
    mode_damping: list = field(default_factory=list)  # what each mode gains
    embedded: dict = field(default_factory=dict)  # "modes", "load" -> {name, text}
    design_drivers: dict = field(default_factory=dict)  # chosen_design_drivers

    def models(self) -> list[dict]:
        """One row per Level III run: label, model, source, amplitude at ``at``, final
        amplitude, wall time."""
        out = []
        for label, run in self.runs.items():
            reached = run.time[-1] >= self.at * (1.0 - 1e-9)
            out.append({"label": label, "model": run.model, "source": self.sources[label],
                        "amplitude_at": run.amplitude_at(self.at) if reached else None,
                        "final_amplitude": run.final_amplitude,
                        "seconds": self.timings.get(f"Level III: {label}"),
                        **({"assumptions": self.assumptions[label]}
                           if label in self.assumptions else {}),
                        **self.harmonicity.get(label, {}),
                        **analytic_field_marks(self.analytic_fields.get(label))})
        return out

    def forced_summary(self) -> dict | None:
        """The forced response in brief: the load and, per model, the largest steady
        amplitude of the output point and its frequency (harmonic balance, every stable
        branch), next to the structure's without particles."""
        if not self.forced:
            return None
        out: dict[str, Any] = {"load": self.forced_load.as_dict(), "models": {},
                               "load_text": self.forced_text}
        for label, r in self.forced.items():
            f = r.frequency
            hb = r.harmonic_balance
            # the largest stable solution per frequency (-inf where there is none)
            best = np.max(np.where(hb.steady & np.isfinite(hb.amplitude), hb.amplitude,
                                   -np.inf), axis=1)
            i = int(np.argmax(best))
            lin = np.abs(r.linear)
            j = int(np.argmax(lin))
            out["models"][label] = {
                "peak_amplitude": float(best[i]) if np.isfinite(best[i]) else None,
                "peak_frequency": float(f[i]) if np.isfinite(best[i]) else None,
                "several_solutions": bool((np.isin(hb.branch, ("stable", "unstable"))
                                           .sum(axis=1) > 1).any()),
                "frequency_range": [float(f[0]), float(f[-1])], "points": int(f.size)}
            out["no_particles"] = {"peak_amplitude": float(lin[j]),
                                   "peak_frequency": float(f[j])}
            out["models"][label]["modes"] = _per_mode(self.structure, f, best, lin)
            out["models"][label].update(_peak_assumptions(r, i))
            out["models"][label].update(analytic_field_marks(self.analytic_fields.get(label)))
            # harmonic balance solves for a harmonic motion: nothing to judge
            from pdamper.coupling.harmonicity import frf_summary

            near = frf_summary(r)
            out["models"][label]["near_harmonic"] = near["near_harmonic"]
            if "not_applicable" in near:
                out["models"][label]["not_applicable"] = near["not_applicable"]
        out["units"] = {"peak_amplitude": "m", "peak_frequency": "Hz"}
        return out

    def as_dict(self) -> dict:
        return {"title": self.title, "version": self.version, "seeds": self.seeds,
                "at": self.at, "models": self.models(), "timings": self.timings,
                "design_study": None if self.study is None else
                {**self.study.as_dict(), "model": self.study_model},
                "uncertainty": {k: v.as_dict() for k, v in self.uncertainty.items()},
                **({"design_drivers": {
                    **{k: v for k, v in self.design_drivers.items() if k != "result"},
                    "result": self.design_drivers["result"].as_dict()}}
                   if self.design_drivers else {}),
                "forced_response": self.forced_summary(),
                "realisations": None if self.band is None else self.band.as_dict(),
                **({"not_applicable": dict(self.not_applicable)} if self.not_applicable
                   else {}),
                "figures": [f.name for f in self.figures],
                "figure_errors": dict(self.figure_errors),
                "inputs": self.used or self.inputs, "inputs_not_used": self.not_used,
                "structure": self.modal, "mode_damping": self.mode_damping,
                "embedded_files": self.embedded,
                "units": {"mode_damping": {"frequency": "Hz", "damping_ratio": "1",
                                           "added": "1", "total": "1", "stroke": "m",
                                           "loss_factor": "1"}}}


def _per_mode(structure: Any, f: np.ndarray, amplitude: np.ndarray,
              linear: np.ndarray) -> list[dict]:
    """Per mode of ``structure``: the largest ``amplitude`` [m] (and of ``linear``, the
    structure without particles) over the frequencies ``f`` [Hz] nearer its natural
    frequency than any other mode's (the geometric middle between neighbours)."""
    fn = np.atleast_1d(np.asarray(getattr(structure, "frequencies",
                                          [structure.natural_frequency]), float))
    edges = np.concatenate([[0.0], np.sqrt(fn[:-1] * fn[1:]), [np.inf]])
    out = []
    for k, f_k in enumerate(fn):
        sel = (f >= edges[k]) & (f < edges[k + 1])
        row: dict[str, Any] = {"mode": k + 1, "natural_frequency": float(f_k),
                               "peak_amplitude": None, "peak_frequency": None,
                               "no_particles_peak_amplitude": None}
        a = np.where(sel, amplitude, -np.inf)
        if np.any(sel) and np.isfinite(np.max(a)):
            i = int(np.argmax(a))
            row.update(peak_amplitude=float(a[i]), peak_frequency=float(f[i]))
        if np.any(sel):
            row["no_particles_peak_amplitude"] = float(np.max(linear[sel]))
        out.append(row)
    return out


def _timed(rep: DamperReport, key: str, fn: Callable[..., Any]) -> Any:
    t0 = time.perf_counter()
    out = fn()
    rep.timings[key] = time.perf_counter() - t0
    return out


def run_damper_report(scenario: Scenario, *, dem: bool = False, uncertainty: int | None = None,
                      uncertainty_seed: int = 0, out: Path | None = None,
                      realisations: int | None = None,
                      progress: Callable[[str], None] | None = None,
                      **sweep_options: Any) -> DamperReport:
    """Compute the report of ``scenario`` (module docstring).

    Parameters
    ----------
    scenario
        The :class:`~pdamper.io.scenario.Scenario` (its resources judged by the caller).
    dem
        Add the DEM: its Level II map and Level III model 1.
    uncertainty
        Base points of the propagation of the ``"value +- sd"`` inputs (default
        :data:`DEFAULT_UNCERTAINTY_POINTS` when the scenario has any; none without).
    uncertainty_seed
        Seed of its Sobol' sequence.
    realisations
        With ``dem``: also run DEM model 1 from this many random packings (seeds
        ``dem.seed + k``) and show their band (:class:`~pdamper.runs.realisations.
        Level3Band`).
    out
        Directory of the DEM map's cache.
    sweep_options
        ``workers``, ``scheduler`` of the DEM map.
    """
    from pdamper import __version__
    from pdamper.coupling import Simulation
    from pdamper.models import AnalyticalDamper
    from pdamper.runs.maps import run_map

    sc = scenario
    say = progress or (lambda _m: None)
    damper, structure = sc.damper(), sc.structure_model()
    x0, duration = sc.structure.initial_displacement, sc.simulation.duration
    rep = DamperReport(sc.title, __version__, sc.model_dump(mode="json"), damper, structure,
                       at=min(sc.optimization.at, duration))
    rep.seeds = {"dem.seed": sc.dem.seed, "optimization.seed": sc.optimization.seed}
    rep.uncertain = sc.uncertain_inputs()

    say("Level II: analytical map")
    rep.level2_map = _timed(rep, "Level II: analytical map",
                            lambda: run_map(sc, "analytic").dataset)
    if dem:
        _dem_map(rep, sc, damper.count, out, say, sweep_options)

    gravity = sc.excitation.gravity
    models = level3_models(sc, damper, dem)
    _level3_runs(rep, sc, damper, structure, models, say)
    rep.empty = _timed(rep, "Level III: no particles", lambda: Simulation(
        structure, AnalyticalDamper(damper.with_count(0), gravity=gravity), x0).run(
        duration, sc.simulation.sample_rate))

    say("forced response (harmonic balance)")
    _timed(rep, "forced response", lambda: forced_response(rep, models, structure, x0,
                                                           frf=sc.frf))
    if dem and realisations is not None and realisations > 1:
        from pdamper.runs.realisations import run_level3_realisations

        say(f"Level III: DEM model 1, {realisations} realisations")
        rep.band = _timed(rep, "Level III: DEM realisations", lambda: run_level3_realisations(
            sc, realisations, "dem", **sweep_options))
        rep.seeds["realisation_seeds"] = rep.band.seeds

    say("design landscape")
    rep.study = _timed(rep, "design study", lambda: design_study(sc, damper, structure))
    _record_inputs(rep, sc, damper, structure, dem)

    if sc.uncertain_inputs():
        _propagate_uncertainty(rep, sc, uncertainty, uncertainty_seed, say)
    return rep


def _level3_runs(rep: DamperReport, sc: Scenario, damper: Any, structure: Any,
                 models: dict, say: Callable[[str], None]) -> None:
    """Level III: the decay of ``structure`` from the scenario's initial displacement
    under each of ``models`` (label -> (model, source)), with the checks of each run's
    assumptions and its harmonicity, into ``rep``."""
    from pdamper.coupling import Simulation
    from pdamper.coupling.harmonicity import payload as harmonicity_payload
    from pdamper.coupling.validity import decay_assumptions

    x0, duration = sc.structure.initial_displacement, sc.simulation.duration
    for label, (model, source) in models.items():
        say(f"Level III: {label}")
        rep.runs[label] = _timed(rep, f"Level III: {label}", lambda m=model: Simulation(
            structure, m, x0).run(duration, sc.simulation.sample_rate))
        rep.sources[label] = source
        marks = decay_assumptions(model, rep.runs[label], rep.at)
        made_by = getattr(model, "map_attrs", {}).get("model")
        if label in ANALYTIC_FIELDS_LABELS and (sc.fields.file is None
                                                or made_by in ANALYTIC_MAP_MODELS):
            # the fields are the analytical model's: its checks at the run's updates
            rep.analytic_fields[label] = ANALYTIC_FIELDS_REASON + (
                "" if sc.fields.file is None else
                f" (the map {sc.fields.file} was made by the {made_by} model)")
            marks = decay_assumptions(sc.model("analytic", damper), rep.runs[label], rep.at)
        if marks is not None:
            rep.assumptions[label] = marks
        rep.harmonicity[label] = harmonicity_payload(rep.runs[label])


def _propagate_uncertainty(rep: DamperReport, sc: Scenario, uncertainty: int | None,
                           uncertainty_seed: int, say: Callable[[str], None]) -> None:
    """The propagation of the scenario's uncertain inputs (``uncertainty`` base points,
    default :data:`DEFAULT_UNCERTAINTY_POINTS`; Sobol' seed ``uncertainty_seed``) to
    Level II, Level III, the questions' quantities and the chosen design, into ``rep``."""
    from pdamper.runs.uncertainty import propagate_scenario

    n = DEFAULT_UNCERTAINTY_POINTS if uncertainty is None else uncertainty
    rep.seeds["uncertainty_seed"] = uncertainty_seed
    for level in ("level2", "level3"):
        say(f"uncertainty: {level}")
        rep.uncertainty[level] = _timed(
            rep, f"uncertainty ({level})", lambda lv=level: propagate_scenario(
                sc, lv, n, uncertainty_seed, model="analytic"))
    for level, options in question_uncertainty(sc, rep).items():
        say(f"uncertainty: {level}")
        rep.uncertainty[level] = _timed(
            rep, f"uncertainty ({level})", lambda lv=level, o=options: propagate_scenario(
                sc, lv, n, uncertainty_seed, model="analytic", **o))
    study = rep.study
    if study is not None and study.best is not None:
        say("uncertainty: the chosen design's drivers")
        rep.design_drivers = _timed(rep, "uncertainty (chosen design)", lambda: (
            chosen_design_drivers(sc, study, n, uncertainty_seed)))


#: The most frequencies of the report's forced response sampled under the uncertain
#: inputs: each sample solves the harmonic balance at every one (about 0.05 s each with the
#: analytical model), so the band is drawn on a subset that keeps every resonance.
FRF_SAMPLED_POINTS = 25


def sampled_frequencies(f: Any, peaks: Any = ()) -> np.ndarray:
    """About :data:`FRF_SAMPLED_POINTS` of the frequencies ``f`` [Hz] (all of them when
    fewer): each of ``peaks`` (a mode's resonance, None skipped) with its two neighbours on
    either side, the rest evenly spread over ``f`` from its first to its last."""
    f = np.asarray(f, float)
    if f.size <= FRF_SAMPLED_POINTS:
        return f
    keep: set[int] = set()
    for p in peaks:
        if p is not None:
            i = int(np.argmin(np.abs(f - p)))
            keep.update(range(max(0, i - 2), min(f.size, i + 3)))
    rest = max(FRF_SAMPLED_POINTS - len(keep), 2)
    keep.update(np.round(np.linspace(0, f.size - 1, rest)).astype(int).tolist())
    return f[sorted(keep)]


def question_uncertainty(sc: Scenario, rep: DamperReport | None = None) -> dict[str, dict]:
    """The user's own questions that the report's uncertainty propagation answers besides
    the Level II and III ones: ``"frf"`` (the forced response at the frequencies of the
    report's, with its load) when the scenario has an ``[frf]`` section, ``"load"`` (the
    response to the record and its tail) when it has a ``[load]``; each level's options of
    :func:`pdamper.runs.uncertainty.propagate_scenario` (``rep``: the report's forced
    response, whose frequencies and load are sampled; without it they are built as
    :func:`forced_response` builds them, for the cost check before any run)."""
    out: dict[str, dict] = {}
    if "frf" in sc.model_fields_set:
        from pdamper.coupling.frf import check_damped
        from pdamper.errors import InputError

        if rep is not None and rep.forced:
            first = next(iter(rep.forced.values()))
            summary: dict[str, Any] = rep.forced_summary() or {}
            per_model: list[dict] = list(summary.get("models", {}).values())
            peaks = [m["peak_frequency"] for m in (per_model[0].get("modes", [])
                                                   if per_model else [])]
            out["frf"] = {"load": rep.forced_load,
                          "frequency": sampled_frequencies(first.frequency, peaks)}
        elif rep is None:
            from pdamper.coupling.loads import acting_at

            structure = sc.structure_model()
            try:
                check_damped(structure)
                damped = True
            except InputError:  # no forced response: nothing to sample
                damped = False
            if damped:
                at = acting_at(structure, sc.frf.at, "frf.at")
                load = sc.frf.load() or forced_load(at, sc.structure.initial_displacement)
                f = np.atleast_1d(sc.frf.frequencies(at, sc.damper().bed_mass))
                out["frf"] = {"load": load, "frequency": f[:FRF_SAMPLED_POINTS]}  # its count
    if sc.load.given:
        out["load"] = {"history": sc.load.history(), "tail": sc.load.tail}
    return out


#: The answer of the propagation at the chosen design per objective: the level sampled and
#: the answer its Sobol' indices are read from.
DESIGN_QUESTION = {"peak-frf": ("frf", "peak"), "rms-frf": ("frf", "rms"),
                   "peak": ("load", "peak"), "rms": ("load", "rms")}


#: The scenario field of each design variable set by :func:`design_scenario` (a bed mass
#: or fill sets the count the candidate records).
_DESIGN_FIELDS = {"radius": "particles.radius", "container_length": "container.length",
                  "container_width": "container.width", "container_depth": "container.depth",
                  "particle_material": "particles.material"}


def design_scenario(sc: Scenario, design: dict, varied: Any = None) -> Scenario:
    """``sc`` with the damper of a study's ``design``: its particle count and the values
    of the variables named in ``varied`` (default all that the candidate records), as the
    candidate records them (SI; a material by its library name)."""
    from pdamper.io.uncertain import with_values

    values: dict[str, Any] = {"particles.count": int(design["particles"])}
    for key, field_ in _DESIGN_FIELDS.items():
        if (varied is None or key in varied) and design.get(key) is not None:
            values[field_] = design[key]
    return with_values(sc, values)


def chosen_design_drivers(sc: Scenario, study: DesignStudyResult, n: int, seed: int) -> dict:
    """The sensitivity of the study's chosen design (its best) to the uncertain inputs: the
    propagation (:func:`pdamper.runs.uncertainty.propagate_scenario`, analytical model) of
    the objective's question at that design (:data:`DESIGN_QUESTION`; the free decay for
    the free-decay objectives), with its Sobol' indices. ``{"design", "level", "answer",
    "result"}``."""
    from pdamper.runs.uncertainty import propagate_scenario

    assert study.best is not None
    design = study.best.as_dict()
    at = design_scenario(sc, design, [v.name for v in study.variables])
    level, answer = DESIGN_QUESTION.get(study.objective.name, ("level3", "amplitude_at"))
    obj = study.objective
    options: dict = ({"load": obj.frf_load, "frequency": obj.band} if level == "frf" else
                     {"history": obj.load, "tail": obj.tail} if level == "load" else {})
    result = propagate_scenario(at, level, n, seed, model="analytic", **options)
    if answer not in result.answers:  # the free decay's answers: its amplitude at t
        answer = next(iter(result.answers))
    return {"design": design, "level": level, "answer": answer, "result": result}


def _dem_map(rep: DamperReport, sc: Scenario, count: int, out: Path | None,
             say: Callable[[str], None], sweep_options: dict) -> None:
    """The report's DEM map (Level II) into ``rep.dem_map``, its kernels compiled first."""
    from pdamper.dem import warmup
    from pdamper.runs.maps import run_map

    say("compiling the DEM kernels (first run only, then cached)")
    _timed(rep, "DEM kernels", lambda: warmup((sc.dem.integrator,)))
    f, x = sc.dem_map_grid()
    say(f"Level II: DEM map {len(f)} x {len(x)}")
    target = None if out is None else Path(out) / "dem_map.nc"
    rep.dem_map = _timed(rep, "Level II: DEM map", lambda: run_map(
        sc, "dem", frequency=f, amplitude=x, particles=np.array([count]),
        out=target, cache=True, **sweep_options).dataset)


def _record_inputs(rep: DamperReport, sc: Scenario, damper: ParticleDamper, structure: Any,
                   dem: bool) -> None:
    """What the report rests on (:mod:`pdamper.runs.report_inputs`): the inputs it used and
    why the others were not, the structure's data and the files it read embedded, the
    damping each mode gains."""
    from pdamper.design.study import LOAD_OBJECTIVES
    from pdamper.runs.report_inputs import embedded_file, modal_data, mode_damping, used_inputs

    load_used = sc.optimization.objective in LOAD_OBJECTIVES and sc.load.given
    rep.used, rep.not_used = used_inputs(rep.inputs, dem=dem, load_used=load_used)
    from pdamper.io.structure import given_structure, includes_container_mass

    rep.modal = modal_data(given_structure(sc))  # the user's data as given
    if not includes_container_mass(sc) and sc.container.mass > 0:
        # the runs' structure: the container's mass added at the damper's point
        rep.modal["with_container"] = {"container_mass": sc.container.mass,
                                       **modal_data(structure)}
    rep.mode_damping = mode_damping(structure, damper, sc.excitation.gravity)
    for key, path in (("modes", sc.structure.modes),
                      ("load", (sc.load.force or sc.load.base_acceleration)
                       if load_used else None)):
        if (text := embedded_file(path)) is not None:
            rep.embedded[key] = text


#: The span of the paper's report of old, (1 -+ FORCED_SPAN) x the first natural frequency
#: in FORCED_POINTS (kept for the record: the report's forced response now spans every mode,
#: :func:`pdamper.coupling.frf.default_frequencies`, or the scenario's [frf] frequency).
FORCED_POINTS = 81
FORCED_SPAN = 0.4


def forced_load(structure: Any, x0: float) -> Any:
    """The harmonic force of the report's forced response: the amplitude [N] that drives
    the structure without particles, at its first natural frequency, to the release
    amplitude ``|x0|`` (so that the damper works in the range of strokes of the free
    decay)."""
    from pdamper.coupling.frf import HarmonicLoad, linear_frf

    f_n = float(structure.natural_frequency)
    unit = abs(complex(linear_frf(structure, HarmonicLoad("force", 1.0), [f_n])[0]))
    return HarmonicLoad("force", abs(x0) / unit)


def forced_response(rep: DamperReport, models: dict, structure: Any, x0: float,
                    frf: Any = None) -> None:
    """Harmonic balance of every report model that has one (the pseudo-force coupling:
    the analytical formulas and the effective fields) under the scenario's load (``frf``,
    its ``[frf]`` section: load, frequencies and where the load acts), else under
    :func:`forced_load`, over the section's frequencies, else over every mode of the
    structure (:func:`pdamper.coupling.frf.default_frequencies`); into ``rep.forced``,
    ``rep.forced_load`` and ``rep.forced_text``."""
    from pdamper.coupling.frf import (
        HARMONIC_BALANCE,
        check_damped,
        frequency_response,
        load_point_text,
    )
    from pdamper.coupling.loads import acting_at
    from pdamper.errors import InputError

    try:
        check_damped(structure)
    except InputError as exc:  # an undamped structure: no bounded forced response
        rep.not_applicable["forced_response"] = (
            f"the structure has an undamped mode ({exc.field}: {exc.message})")
        return
    given = None if frf is None else frf.load()
    if frf is not None:
        structure = acting_at(structure, frf.at, "frf.at")
    load = given or forced_load(structure, x0)
    bed = max((m.bed_mass for m, _ in models.values()), default=0.0)
    if frf is not None:
        f = frf.frequencies(structure, bed)
    else:
        from pdamper.coupling.frf import default_frequencies

        f = default_frequencies(structure, bed)
    rep.forced_load = load
    where = load_point_text(structure) if load.at_load_point else "the base"
    rep.forced_text = (f"{load.describe()} at {where}, the scenario's [frf] load"
                       if given is not None else
                       f"harmonic force of {load.amplitude:.4g} N at {where} (the amplitude "
                       "that drives the structure without particles to the release "
                       "amplitude at its first natural frequency; give [frf] a load for "
                       "your own)")
    for label, (model, _source) in models.items():
        if model.coupling in HARMONIC_BALANCE:
            rep.forced[label] = frequency_response(model, structure, load, f, sweep="none")


def _peak_assumptions(r: Any, i: int) -> dict:
    """``assumptions`` (:func:`~pdamper.coupling.frf.assumption_record`) of the forced
    response ``r`` and whether they hold at its peak, the largest stable solution at
    frequency index ``i`` (``peak_assumptions_hold``, ``peak_assumptions``: the reason
    and the fidelity to use); {} where the model reports no such check."""
    from pdamper.coupling.frf import assumption_record

    marks = assumption_record(r)
    hb = r.harmonic_balance
    if marks is None or "assumptions_hold" not in hb.diagnostics:
        return {}
    amp = np.where(hb.steady[i] & np.isfinite(hb.amplitude[i]), hb.amplitude[i], -np.inf)
    j = int(np.argmax(amp))
    holds = bool(hb.diagnostics["assumptions_hold"][i, j]) or not np.isfinite(amp[j])
    return {"assumptions": marks, "peak_assumptions_hold": holds,
            "peak_assumptions": "" if holds else str(hb.diagnostics["assumptions"][i, j])}


#: The report's model whose effective fields come from the analytical map without a
#: ``[fields] file`` (:func:`level3_models`).
ANALYTIC_FIELDS_LABELS = ("effective fields (model 2)",)
#: Fidelities of a map file whose fields are the analytical bed's (the map's ``model``).
ANALYTIC_MAP_MODELS = ("analytic", "plastic")
#: Why such a model's answers carry the analytical model's limits.
ANALYTIC_FIELDS_REASON = (
    "the effective fields were computed from the analytical model (Eqs. 5-22), not from a "
    "DEM map: they carry its limits and its assumption checks; give [fields] file a DEM map "
    "(pdamper map --model dem) for model 2 proper")


def analytic_field_marks(reason: str | None) -> dict:
    """A report row's marks where its effective fields rest on the analytical model:
    ``fields_from`` (``"analytic"``) and ``fields_note`` (why it matters); {} otherwise."""
    if reason is None:
        return {}
    return {"fields_from": "analytic", "fields_note": reason}


def level3_models(sc: Scenario, damper: ParticleDamper, dem: bool) -> dict[str, tuple]:
    """The report's Level III models, ``label -> (model, what its data rest on)``: the
    analytical formulas, the effective fields (the scenario's map file, else the analytical
    map of ``[map]``, clamped) and, with ``dem``, the DEM co-simulation."""
    from pdamper.models import EffectiveFieldDamper

    models = {"analytical formulas (model 3)": (sc.model("analytic", damper), "Eqs. 5-22")}
    if sc.fields.file is not None:
        models["effective fields (model 2)"] = (sc.model("fields", damper),
                                                f"map {sc.fields.file}")
    else:
        f, x = sc.map_grid()
        fmap = effective_field_map(damper, f, x, sc.excitation.gravity)
        opts = {**sc.fields.options(), "file": None, "extrapolation": "clamp"}
        models["effective fields (model 2)"] = (
            EffectiveFieldDamper(damper, field=fmap, **opts),
            "analytical map of [map], clamped at its edges")
    if dem:
        models["DEM (model 1)"] = (sc.model("dem", damper), "DEM co-simulation")
    return models


def effective_field_map(damper: ParticleDamper, frequency: np.ndarray, amplitude: np.ndarray,
                        gravity: float) -> xr.Dataset:
    """The analytical map of ``damper`` on a grid: model 2's fields without a map file."""
    from pdamper.analysis.fields import effective_field
    from pdamper.models import AnalyticalDamper

    return effective_field(AnalyticalDamper(damper, gravity=gravity), frequency, amplitude)


def design_study(sc: Scenario, damper: ParticleDamper, structure: Any) -> DesignStudyResult:
    """The design study of ``[optimization]`` (its ``vary``, or the particle count in
    whole layers) with the analytical model, in-process; every objective, those on the
    response to ``[load]`` and the forced-response ones over ``[optimization] band``
    included."""
    from pdamper.design.study import LOAD_OBJECTIVES, DesignVariable, optimize_design

    o = sc.optimization
    variables = o.variables()
    if not variables:
        step = damper.per_layer if o.step is None else o.step
        counts = tuple(range(0, damper.max_count, step))
        variables = [DesignVariable("particles", counts,
                                    spec=f"particles={counts[0]}:{counts[-1]}:{step}")]
    return optimize_design(structure, damper, sc.structure.initial_displacement, variables,
                           o.objective, o.at, model=functools.partial(sc.model, "analytic"),
                           threshold=o.threshold, method=o.method, max_grid=o.max_grid,
                           max_evaluations=o.max_evaluations, seed=o.seed, workers=0,
                           tolerance=o.tolerance,
                           load=sc.load.history() if o.objective in LOAD_OBJECTIVES else None,
                           tail=sc.load.tail, band=o.frf_band(), frf_load=o.frf_load,
                           limits=o.require, max_mass=o.max_mass)


__all__ = ["ANALYTIC_FIELDS_LABELS", "ANALYTIC_FIELDS_REASON", "analytic_field_marks",
           "DEFAULT_UNCERTAINTY_POINTS", "FORCED_POINTS", "FORCED_SPAN", "DamperReport",
           "DESIGN_QUESTION", "chosen_design_drivers", "design_scenario", "design_study",
           "FRF_SAMPLED_POINTS", "effective_field_map", "question_uncertainty",
           "sampled_frequencies", "forced_load", "forced_response",
           "level3_models", "run_damper_report"]
