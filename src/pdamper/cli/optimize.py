"""``pdamper optimize``: design study; by default the paper's particle count (Sect. 4.2.2)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from pdamper.cli import _uncertainty
from pdamper.cli._common import (
    BaseAccelerationOpt,
    ForceOpt,
    JsonOpt,
    LoadOpt,
    ModelOpt,
    ModesOpt,
    ScenarioOpt,
    TailOpt,
    check_plot,
    emit,
    figure_last,
    key_help,
    load,
    metadata,
    plot_param,
)
from pdamper.errors import InputError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from pdamper.coupling.loads import LoadHistory
    from pdamper.design.study import DesignStudyResult, DesignVariable
    from pdamper.io.scenario import Scenario


#: The design variables and the objective, as the scenario's ``[optimization]`` keys.
VaryOpt = Annotated[list[str] | None, typer.Option("--vary", help=key_help(
    "optimization.vary", "Design variable, repeatable: 'particles=16:176:16' "
    "(start:stop:step), 'radius=3mm:6mm:4' (start:stop:count), "
    "'container-length=100mm:140mm:3', 'particle-material=S235,PVC'. Default: the particle "
    "count"))]
ObjectiveOpt = Annotated[str | None, typer.Option(help=key_help(
    "optimization.objective", "amplitude-at (min), settling-time (min) or mean-damping (max) "
    "of the free decay; peak or rms (min) of the response to --load / --base-acceleration; "
    "peak-frf or rms-frf (min) of the forced response to --frf-load"))]

#: The limits, as the scenario's ``[optimization]`` keys.
MaxMassOpt = Annotated[str | None, typer.Option("--max-mass", help=key_help(
    "optimization.max_mass", "Largest mass of bed plus container, e.g. '0.5kg'"))]
RequireOpt = Annotated[list[str] | None, typer.Option("--require", help=key_help(
    "optimization.require", "Response limit at the observation point, repeatable: "
    "'peak-acceleration<=10g', 'peak<=3mm', 'rms<=1mm', 'mean-damping>=2%' (the "
    "quantities the objective's runs compute)"))]


#: Options of the command (module level: the signature stays readable).
_BandOpt = Annotated[str | None, typer.Option(
    help=key_help("optimization.band",
                  "Frequencies of peak-frf and rms-frf, 'start:stop:count', e.g. '3Hz:9Hz:41' "
         "(default every mode of the structure, each resonance resolved for its damping)."))]
_FrfLoadOpt = Annotated[str | None, typer.Option(
    "--frf-load", help=key_help("optimization.frf_load",
                                "Harmonic load of peak-frf and rms-frf: a force ('2N', default), "
                       "an unbalance ('1.76kg*mm') or a base motion ('1mm', '0.3g')."))]
_WorkersOpt = Annotated[str | None, typer.Option(
    help=key_help("optimization.workers",
                  "Parallel dask workers; 0 = in-process; auto = 0 for cheap models, all cores "
         "for the DEM (when dask.distributed is installed)."))]
_ToleranceOpt = Annotated[str | None, typer.Option(
    help=key_help("optimization.tolerance",
                  "Relative tolerance on the objective: the lightest design within it of the best "
         "is reported with the Pareto front of added (bed) mass against the objective, "
         "e.g. '5%' or 0.05; in [0 %, 100 %) (default 5 %)."))]
_RealisationsOpt = Annotated[str | None, typer.Option(
    "--realisations", help="Evaluate every design from N random packings (DEM; seeds "
    "dem.seed ... dem.seed + N - 1) or the first N realisations of the fields' map: the "
    "objective is their mean, each candidate has "
    "objective_std, objective_min, objective_max and objective_values (default 1).")
]
_RobustQuantileOpt = Annotated[str | None, typer.Option(
    "--robust-quantile", help="With --uncertainty: rank the designs by this quantile of "
    "their objective over the samples (0.9 or 90%: the value 90 % of the samples meet; "
    "for a maximised objective the 10 % quantile) instead of the mean.")]
_MethodOpt = Annotated[str | None, typer.Option(
    help=key_help("optimization.method",
                  "auto, grid (brute force) or optimize (scipy differential evolution)."))]
_ThresholdOpt = Annotated[str | None, typer.Option(
    help=key_help("optimization.threshold",
                  "Settling threshold, e.g. '15mm' (default |x0| / 4)."))]


def optimize(
    model: ModelOpt = None,
    at: Annotated[str | None, typer.Option(help=key_help("optimization.at",
                                                         "Objective time T, e.g. '0.8s'."))] = None,
    step: Annotated[int | None, typer.Option(help=key_help(
        "optimization.step", "Particle-count increment (default: one layer)."))] = None,
    vary: VaryOpt = None,
    objective: ObjectiveOpt = None,
    band: _BandOpt = None,
    frf_load: _FrfLoadOpt = None,
    threshold: _ThresholdOpt = None,
    method: _MethodOpt = None,
    workers: _WorkersOpt = None,
    scheduler: Annotated[str | None, typer.Option(
        help=key_help("optimization.scheduler", "Address of an existing dask scheduler."))] = None,
    max_evaluations: Annotated[int | None, typer.Option(
        "--max-evaluations", help=key_help("optimization.max_evaluations",
                                           "Evaluation budget of the optimiser."))] = None,
    seed: Annotated[int | None, typer.Option(help=key_help("optimization.seed",
                                                           "Seed of the optimiser."))] = None,
    tolerance: _ToleranceOpt = None,
    max_mass: MaxMassOpt = None,
    require: RequireOpt = None,
    plot: Annotated[str | None, plot_param("the design landscape")] = None,
    modes: ModesOpt = None,
    load_file: LoadOpt = None,
    base_acceleration: BaseAccelerationOpt = None,
    tail: TailOpt = None,
    realisations: _RealisationsOpt = None,
    uncertainty: _uncertainty.UncertaintyOpt = None,
    uncertain: _uncertainty.UncertainOpt = None,
    uncertainty_seed: _uncertainty.UncertaintySeedOpt = 0,
    robust_quantile: _RobustQuantileOpt = None,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Design with the best objective; every candidate (the landscape) is listed."""
    sc = load(scenario, runs=("optimization",), force=force, **_uncertainty.merged(dict(
              simulation__model=model,
              optimization__at=at, optimization__step=step, optimization__vary=vary or None,
              optimization__objective=objective, optimization__threshold=threshold,
              optimization__method=method, optimization__workers=_workers(workers),
              optimization__scheduler=scheduler, optimization__max_evaluations=max_evaluations,
              optimization__seed=seed, optimization__tolerance=tolerance,
              optimization__band=band, optimization__frf_load=frf_load,
              optimization__max_mass=max_mass, optimization__require=require or None,
              structure__modes=None if modes is None else str(modes),
              load__force=None if load_file is None else str(load_file),
              load__base_acceleration=None if base_acceleration is None
              else str(base_acceleration), load__tail=tail), uncertain))
    spread = _spread_options(sc, uncertainty, uncertainty_seed, robust_quantile,
                             realisations, force)
    plot_path = check_plot(plot)
    history = _history(sc, tail, load_file is not None or base_acceleration is not None)
    damper = sc.damper()
    variables = _variables(sc.optimization, damper)
    proto = _prototype(sc, damper, history)
    n_workers = _worker_count(sc.optimization.workers, proto)
    res, seeds = _study(sc, damper, variables, history, n_workers,
                        _realisation_count(sc, realisations, force), spread)
    payload, lines = _report(sc, res, history, n_workers, seeds)
    if seeds is not None and sc.model(None, damper).fidelity == "fields":  # not packings
        payload["realisations"]["map_realisations"] = payload["realisations"].pop("seeds")
    if spread is not None:
        _spread_report(sc, res, spread, payload, lines)
    emit(payload, as_json, "\n".join(lines))  # the study first: a figure cannot lose it
    if plot_path is not None:
        _figure(res, plot_path)


def _workers(workers: str | None) -> int | str | None:
    """``--workers`` as a count, ``'auto'`` or None (not given)."""
    if workers is None or workers == "auto":
        return workers
    try:
        return int(workers)
    except ValueError:
        raise InputError("optimization.workers", f"must be a whole number >= 0 or 'auto', "
                         f"got {workers!r}") from None


def _history(sc: Scenario, tail: str | None, history_given: bool) -> LoadHistory | None:
    """The load history of the peak and rms objectives (None: an objective on the free
    decay, which refuses ``--tail`` and a given history)."""
    o = sc.optimization
    history = sc.load.history() if o.objective in ("peak", "rms") else None
    if history is None and tail is not None and not sc.load.given:
        raise InputError("load.tail", "is the free vibration after a load history: give "
                         "--load or --base-acceleration")
    if history is None and history_given:
        raise InputError("optimization.objective", f"a load history is given but the "
                         f"objective {o.objective!r} is on the free decay: use peak or rms")
    return history


def _variables(o: Any, damper: Any) -> list[DesignVariable]:
    """The design variables of ``--vary``; by default the paper's study: whole layers
    0, step, ... below n_max."""
    from pdamper.design.study import DesignVariable

    variables = o.variables()
    if not variables:  # the paper's study: whole layers 0, step, ... below n_max
        step_ = damper.per_layer if o.step is None else o.step
        counts = tuple(range(0, damper.max_count, step_))
        variables = [DesignVariable("particles", counts,
                                    spec=f"particles={counts[0]}:{counts[-1]}:{step_}")]
    return variables


def _prototype(sc: Scenario, damper: Any, history: LoadHistory | None) -> Any:
    """The scenario's model of ``damper``, which must have a load-history form when there
    is a history (checked before any design)."""
    proto = sc.model(None, damper)
    if history is not None:  # the model must have a load-history form, before any design
        from pdamper.coupling.loads import load_strategy
        from pdamper.coupling.registry import has_load_cost

        if has_load_cost(load_strategy(proto)):  # its cost per candidate is not judged yet
            raise InputError("simulation.model", f"a design study under a load history "
                             f"runs pseudo-force models (analytic, fields), not "
                             f"{type(proto).__name__}; simulate it with --model")
    return proto


def _worker_count(workers: int | str, proto: Any) -> int:
    """The dask workers: ``'auto'`` is parallel where it pays (an expensive model) and
    dask.distributed is installed."""
    if workers != "auto":
        return int(workers)
    import importlib.util
    import os

    parallel = proto.expensive and importlib.util.find_spec("distributed") is not None
    return (os.cpu_count() or 1) if parallel else 0


def _realisation_count(sc: Scenario, realisations: str | None, force: bool) -> int:
    """``--realisations`` as a count checked against the study's cost (1: one packing)."""
    if realisations is None:
        return 1
    from pdamper.runs.realisations import check_design_realisations, parse_count

    return check_design_realisations(parse_count(realisations), sc, force=force)


def _spread_options(sc: Scenario, n: int | None, seed: int, quantile: str | None,
                    realisations: str | None, force: bool) -> tuple[int, int, float | None] | None:
    """``(N, seed, quantile)`` of ``--uncertainty`` and ``--robust-quantile`` checked, with
    the cost of every design's ``2 N + 1`` runs, before any run (None: no uncertainty)."""
    if n is None:
        if quantile is not None:
            raise InputError("robust_quantile", "is a quantile over the samples of the "
                             "uncertain inputs: give --uncertainty N")
        return None
    from pdamper.design.uncertainty import check_points
    from pdamper.runs.uncertainty import check_design_cost, parse_quantile

    check_points(n)
    q = None if quantile is None else parse_quantile(quantile)
    if realisations is not None and realisations.strip() != "1":
        raise InputError("realisations", "must be 1 with --uncertainty (a spread over the "
                         "inputs or over the packings, one at a time)")
    if not sc.uncertain_inputs():
        raise InputError("uncertainty", "no input carries an uncertainty: give one as "
                         "'value +- sd' in the scenario or with --uncertain FIELD=VALUE+-SD")
    check_design_cost(sc, n, force)
    return n, seed, q


def _spread_report(sc: Scenario, res: DesignStudyResult, spread: tuple, payload: dict,
                   lines: list[str]) -> None:
    """The uncertainty of the study: JSON key ``uncertainty`` and its text lines."""
    from pdamper.models import get_damper_model
    from pdamper.models.registry import not_used

    n, seed, q = spread
    inputs = sc.uncertain_inputs()
    unused = not_used(get_damper_model(sc.simulation.model, "simulation.model"),
                      [u.field for u in inputs])
    stat = "mean" if q is None else f"quantile {q:g}"
    payload["statistic"] = stat
    payload["uncertainty"] = {
        "points": n, "samples": 2 * n, "seed": seed,
        **({} if q is None else {"robust_quantile": q}),
        "method": "every design at the 2 N quasi-Monte Carlo samples (scrambled Sobol') of "
                  "the uncertain inputs",
        "objective": ("the mean over the samples" if q is None else
                      f"the {q:g} quantile over the samples (minimised objective; for a "
                      f"maximised one the {1 - q:g} quantile)"),
        "inputs": [u.as_dict() for u in inputs], "not_used": unused,
        "keys": ["objective_nominal", "objective_mean", "objective_std", "objective_p5",
                 "objective_p25", "objective_p50", "objective_p75", "objective_p95",
                 *(["objective_quantile"] if q is not None else [])]}
    lines.append(f"uncertainty: every design at {2 * n} samples of "
                 + ", ".join(f"{u.field} = {u.value:.4g} +- {u.sd:.3g}" for u in inputs)
                 + f" (seed {seed}); objective: the {stat} over them (+- its std)")
    for field, why in unused.items():
        lines.append(f"  {field}: not used by the {why['fidelity']} fidelity (used by: "
                     f"{', '.join(why['used_by']) or 'none'}): {why['reason']}")
    best = res.best
    if best is not None and "objective_mean" in best.extra:
        k = _SHOWN[res.objective.name][0]
        e = best.extra
        lines.append(f"{'robust choice' if q is not None else 'best'}: "
                     f"{', '.join(f'{v.name} {best.design[v.name]}' for v in res.variables)}"
                     f": nominal "
                     f"{e['objective_nominal'] * k:.4g}, mean {e['objective_mean'] * k:.4g} +- "
                     f"{e['objective_std'] * k:.2g}, 5-95 % [{e['objective_p5'] * k:.4g}, "
                     f"{e['objective_p95'] * k:.4g}]")


def _study(sc: Scenario, damper: Any, variables: list[DesignVariable],
           history: LoadHistory | None, n_workers: int,
           n_real: int, spread: tuple | None = None
           ) -> tuple[DesignStudyResult, list[int] | None]:
    """The design study, each design from ``n_real`` packings when above 1, or at the
    samples of the uncertain inputs (``spread``: ``(N, seed, quantile)``); with the seeds
    of the packings (None: one), and a progress display of the designs evaluated
    (stderr, a terminal only; none with --quiet)."""
    from pdamper.cli._progress import Bar

    with Bar("designs evaluated") as progress:
        return _run_study(sc, damper, variables, history, n_workers, n_real, progress, spread)


def _run_study(sc: Scenario, damper: Any, variables: list[DesignVariable],
               history: LoadHistory | None, n_workers: int, n_real: int,
               progress: Any, spread: tuple | None = None
               ) -> tuple[DesignStudyResult, list[int] | None]:
    """:func:`_study`, reporting each design evaluated to ``progress(done, total)``."""
    import functools

    from pdamper.design.study import optimize_design

    o = sc.optimization
    if spread is not None:
        from pdamper.design.study import make_objective, run_design_study
        from pdamper.runs.uncertainty import design_evaluator as uncertain_evaluator

        obj = make_objective(o.objective, o.at, sc.structure.initial_displacement,
                             sc.structure_model(), o.threshold, load=history,
                             tail=sc.load.tail, band=o.frf_band(), frf_load=o.frf_load)
        res = run_design_study(uncertain_evaluator(sc, spread[0], spread[1], obj, spread[2]),
                               damper, variables, obj, method=o.method, max_grid=o.max_grid,
                               max_evaluations=o.max_evaluations, seed=o.seed,
                               workers=n_workers, scheduler=o.scheduler,
                               tolerance=o.tolerance, limits=o.require,
                               max_mass=o.max_mass, progress=progress)
        return res, None
    if n_real > 1:
        from pdamper.design.study import make_objective, run_design_study
        from pdamper.runs.realisations import design_evaluator

        obj = make_objective(o.objective, o.at, sc.structure.initial_displacement,
                             sc.structure_model(), o.threshold, load=history,
                             tail=sc.load.tail, band=o.frf_band(),
                             frf_load=o.frf_load)
        evaluate = design_evaluator(sc, n_real, obj)
        res = run_design_study(evaluate, damper, variables, obj, method=o.method,
                               max_grid=o.max_grid, max_evaluations=o.max_evaluations,
                               seed=o.seed, workers=n_workers, scheduler=o.scheduler,
                               tolerance=o.tolerance, limits=o.require,
                               max_mass=o.max_mass, progress=progress)
        return res, evaluate.seeds
    res = optimize_design(sc.structure_model(), damper, sc.structure.initial_displacement,
                          variables, o.objective, o.at,
                          model=functools.partial(sc.model, None),
                          threshold=o.threshold, method=o.method, max_grid=o.max_grid,
                          max_evaluations=o.max_evaluations, seed=o.seed,
                          workers=n_workers, scheduler=o.scheduler,
                          tolerance=o.tolerance, load=history, tail=sc.load.tail,
                          band=o.frf_band(), frf_load=o.frf_load, limits=o.require,
                          max_mass=o.max_mass, progress=progress)
    return res, None


def _figure(res: DesignStudyResult, path: Path) -> None:
    """The design landscape to ``--plot``."""
    def draw() -> Figure:
        from matplotlib.figure import Figure

        from pdamper.plots import plot_design_landscape
        from pdamper.plots.level3 import has_spread

        if not res.limits and not has_spread(res):  # limits or a spread: the front too
            fig = Figure(figsize=(7, 5), layout="constrained")
            plot_design_landscape(res, ax=fig.subplots())
            return fig
        from pdamper.plots import plot_design_front

        fig = Figure(figsize=(13, 5), layout="constrained")
        left, right = fig.subplots(1, 2)
        plot_design_landscape(res, ax=left)
        plot_design_front(res, ax=right)
        return fig

    figure_last(draw, path, dpi=120)


#: Scale and column head of each objective in the text.
_SHOWN = {"amplitude-at": (1e3, "amplitude [mm]"), "settling-time": (1.0, "settling [s]"),
          "mean-damping": (1.0, "mean zeta [-]"), "peak": (1e3, "peak [mm]"),
          "rms": (1e3, "RMS [mm]"), "peak-frf": (1e3, "peak [mm]"),
          "rms-frf": (1e3, "RMS [mm]")}


def _report(sc: Scenario, res: DesignStudyResult, history: LoadHistory | None, n_workers: int,
            seeds: list[int] | None) -> tuple[dict, list[str]]:
    """The JSON payload and the text: every candidate, the Pareto front and the lightest
    design within the tolerance (``seeds``: of the realisations, None: one run)."""
    unit = {"m": "m", "s": "s", "1": "1"}[res.objective.unit]
    payload = {**res.as_dict(), "workers": n_workers,
               "units": {"mass": "kg", "container_mass": "kg", "total_mass": "kg",
                         "bed_mass": "kg", "fill": "1", "objective": unit, "at": "s",
                         "radius": "m",
                         "container_length": "m", "container_width": "m",
                         "container_depth": "m", "threshold": "m"},
               **metadata(sc)}
    if why := {**res.not_applicable(), **res.unset_reasons()}:
        payload["not_applicable"] = why
    if seeds is not None:
        payload["statistic"] = "mean"
        payload["realisations"] = {"count": len(seeds), "seeds": seeds, "std_ddof": 1,
                                   "keys": ["objective_std", "objective_min",
                                            "objective_max", "objective_values"]}
    if history is not None:
        payload["load"] = {"file": history.source, "kind": history.kind,
                           "record_duration": history.duration, "tail": sc.load.tail}
    lines = [f"{_head(res, history)}, {sc.simulation.model} model, {res.method}: "
             f"{len(res.candidates)} designs)"] + _candidate_lines(res)
    return payload, lines


def _head(res: DesignStudyResult, history: LoadHistory | None) -> str:
    """The objective and what it is of, the text's first line."""
    obj = res.objective
    if obj.frf_load is not None:
        b, ld = obj.band, obj.frf_load
        assert b is not None  # a forced-response objective always has its band
        return (f"{obj.name} ({b[0]:g}-{b[-1]:g} Hz in {len(b)}, {ld.kind} "
                f"{ld.amplitude:g} {ld.unit}")
    if history is not None:
        return f"{obj.name} (response to {history.source}"
    if obj.name != "settling-time":
        return f"{obj.name} (t = {res.at:g} s"
    assert obj.threshold is not None  # settling-time always has its threshold
    return f"settling-time (to {obj.threshold * 1e3:g} mm"


def _candidate_lines(res: DesignStudyResult) -> list[str]:
    """The landscape table (best and lightest marked), the Pareto front and the lightest
    design within the tolerance."""
    from pdamper.design.study import DESIGN_VARIABLES, describe_design, show_value

    names = [v.name for v in res.variables]
    shown = _SHOWN[res.objective.name]
    boxed = any(c.container_mass for c in res.candidates)  # the total differs from the bed
    lines = ["  " + "  ".join(f"{n:>17s}" for n in names) + "  mass [g]"
             + ("  total [g]" if boxed else "") + f"  {shown[1]}"]
    light = res.lightest_within
    for c in res.candidates:
        cells = []
        for n in names:
            v = c.design[n]
            if isinstance(v, float) and DESIGN_VARIABLES[n].unit == "m":
                cells.append(f"{v * 1e3:15.3f}mm")  # the column as it always was
            else:
                cells.append(f"{show_value(n, v):>17s}")
        value = (f"{c.objective * shown[0]:12.4g}" if c.objective is not None
                 else f"{c.status:>12s}")
        if c.objective is not None and "objective_std" in c.extra:
            value += f" +- {c.extra['objective_std'] * shown[0]:.2g}"
        mass = f"{c.mass * 1e3:8.1f}" if c.mass is not None else "       -"
        if boxed:
            mass += (f"  {c.total_mass * 1e3:9.1f}" if c.total_mass is not None
                     else "          -")
        mark = ("" if c is not res.best else "  <- best" if not res.failures
                else f"  <- best of the {sum(d.status == 'ok' for d in res.candidates)} "
                     "evaluated")
        if c is light and c is not res.best:
            mark = f"  <- lightest within {res.tolerance * 100:g} %"
        if c.violations:
            mark = "  outside the limits: " + "; ".join(c.violations)
        outside = " !" if c.extra.get("assumptions_hold") is False else ""
        outside += " ~" if c.extra.get("near_harmonic") is False else ""
        lines.append("  " + "  ".join(cells) + f"  {mass}  {value}{outside}{mark}")

    def brief(c: Any) -> str:
        design = ", ".join(f"{n} {show_value(n, c.design[n])}" for n in names)
        total = (f", {c.total_mass * 1e3:.1f} g with the container"
                 if c.container_mass else "")
        return f"{design} ({c.mass * 1e3:.1f} g{total}, {c.objective * shown[0]:.4g})"

    for c in res.failures:  # every failure with its reason
        lines.append(f"failed: {describe_design(c, names)}: {c.reason}")
    front = res.front
    lines.append(f"Pareto front of added mass vs {shown[1]} ({len(front)}, lightest first): "
                 + ("; ".join(brief(c) for c in front) if front else "none"))
    if res.no_best is not None:
        lines.append(f"best: none: {res.no_best}")
    else:
        lines.append(f"lightest within {res.tolerance * 100:g} % of the best: "
                     + (brief(light) if light is not None else "none"))
    if res.limits:
        lines.append(f"limits: {'; '.join(lim.describe() for lim in res.limits)} "
                     f"({len(res.feasible)} of "
                     f"{sum(c.status == 'ok' for c in res.candidates)} evaluated designs "
                     "within them)")
        chosen = [("best", res.best), (f"lightest within {res.tolerance * 100:g} %", light),
                  ("lightest within the limits", res.lightest_feasible),
                  ("closest to the limits", res.closest)]
        shown_: list[Any] = []
        for label, pick in chosen:
            if pick is not None and pick.limits and not any(pick is d for d in shown_):
                shown_.append(pick)
                lines.append(f"  {label}: {describe_design(pick, names)}: " + margins(pick))
    return lines + _assumption_lines(res) + _harmonic_lines(res)


def _harmonic_lines(res: DesignStudyResult) -> list[str]:
    """The designs whose describing-function answer rests on a motion that is not
    near-harmonic (~ in the table; JSON per candidate: ``near_harmonic``,
    ``harmonic_deviation``, :mod:`pdamper.coupling.harmonicity`)."""
    from pdamper.coupling.harmonicity import FOLLOWING_FIDELITY, NEAR_HARMONIC_DEVIATION

    flagged = [c for c in res.candidates if c.extra.get("near_harmonic") is False]
    if not flagged:
        return []
    ok = sum(c.status == "ok" for c in res.candidates)
    out = [f"~ {len(flagged)} of {ok} evaluated designs rest on a motion that is not "
           f"near-harmonic (deviation above {NEAR_HARMONIC_DEVIATION:g} from the harmonic "
           f"their loss factor was taken at): check them with --model {FOLLOWING_FIDELITY}"
           " or dem"]
    if res.best is not None and res.best.extra.get("near_harmonic") is False:
        out.append(f"~ the best design: deviation {res.best.extra['harmonic_deviation']:.2f}")
    return out


def _assumption_lines(res: DesignStudyResult) -> list[str]:
    """The designs whose answer rests on the analytical model outside its assumptions
    (! in the table), with the best design's reason (JSON per candidate:
    ``assumptions_hold``, ``assumptions``)."""
    flagged = [c for c in res.candidates if c.extra.get("assumptions_hold") is False]
    if not flagged:
        return []
    ok = sum(c.status == "ok" for c in res.candidates)
    out = [f"! {len(flagged)} of {ok} evaluated designs rest on answers outside the analytic "
           "model's assumptions: check them with fields from a DEM map, or dem"]
    if res.best is not None and res.best.extra.get("assumptions_hold") is False:
        out.append(f"! the best design: {res.best.extra['assumptions']}")
    return out


def margins(c: Any) -> str:
    """Each limit of design ``c`` with its value and margin, in display units:
    ``"mass 412 g (margin 88 g, 17.6 %)"``."""
    from pdamper.design.study import show_quantity

    return "; ".join(
        f"{r['quantity']} {show_quantity(r['value'], r['unit'])} "
        f"{r['op'] if r['met'] else {'<=': '>', '>=': '<'}[r['op']]} "
        f"{show_quantity(r['limit'], r['unit'])} ({'margin' if r['met'] else 'misses by'} "
        f"{show_quantity(abs(r['margin']), r['unit'])}, "
        f"{abs(r['relative_margin']) * 100:.3g} %)" for r in c.limits)
