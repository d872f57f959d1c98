"""``pdamper report``: one self-contained report.html of the user's own damper."""

from __future__ import annotations

from typing import Annotated, Literal

import typer

from pdamper.cli import _uncertainty
from pdamper.cli._common import ForceOpt, JsonOpt, ScenarioOpt, check_output_directory, emit, load


def report(
    out: Annotated[str, typer.Option(help="Directory for report.html and results.json "
                                     "(created if missing; its parent must exist).")]
    = "pdamper-report",
    dem: Annotated[bool, typer.Option("--dem/--no-dem", help="Include the DEM: its Level II "
                                      "map on [map] dem_frequency x dem_amplitude (cached in "
                                      "the output directory) and Level III model 1 (minutes)."
                                      )] = False,
    realisations: Annotated[str | None, typer.Option(
        "--realisations", help="With --dem: also run DEM model 1 from N random packings and "
        "show their band (default: none).")] = None,
    uncertainty: Annotated[int | None, typer.Option(
        "--uncertainty", parser=_uncertainty.points,
        help="Base points of the propagation of the inputs given as "
        "'value +- sd' (a power of two; default 32 when there are any).")] = None,
    uncertain: _uncertainty.UncertainOpt = None,
    uncertainty_seed: _uncertainty.UncertaintySeedOpt = 0,
    workers: Annotated[int | None, typer.Option(
        help="Worker processes of the DEM map (default: every core).")] = None,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Report of any scenario's damper: Level II map, free decay with the models compared,
    design landscape with the Pareto front, uncertainty of the answers, run times.

    Without --dem it runs the analytical and field models only (seconds to tens of
    seconds). The results appear together: a new directory only when complete."""
    import sys
    import time

    from rich.console import Console

    from pdamper.cli._quiet import quiet
    from pdamper.errors import InputError
    from pdamper.files import atomic_directory
    from pdamper.reports import damper_report
    from pdamper.runs.damper_report import run_damper_report

    sc = load(scenario, runs=("map", "simulation", "optimization"), model="analytic",
              force=force, **_uncertainty.merged({}, uncertain))
    n_real = _check_runs(sc, dem, realisations, uncertainty, force)
    target = check_output_directory(out)
    if workers is not None and workers < 1:
        raise InputError("workers", f"must be a whole number >= 1, got {workers}")
    options = {} if workers is None else {"workers": workers}
    t0 = time.perf_counter()
    console = Console(file=sys.stderr)
    with console.status("pdamper report", spinner="dots") if (
            console.is_terminal and not quiet()) else _Nothing() as status:
        def say(message: str) -> None:
            if status is not None:
                status.update(f"pdamper report: {message}")

        with atomic_directory(target) as stage:
            cache = target if target.is_dir() else stage
            rep = run_damper_report(
                sc, dem=dem, uncertainty=uncertainty, uncertainty_seed=uncertainty_seed,
                out=cache, progress=say, realisations=n_real, **options)
            written = damper_report.write_damper_report(rep, stage)
    files = [target / p.relative_to(stage) for p in written]
    if rep.figure_errors:  # the results are written; the missing figures end the command
        from pdamper.errors import OutputError

        name, why = next(iter(rep.figure_errors.items()))
        raise OutputError("out", f"the figure {name} could not be drawn ({why}); "
                          f"results.json and report.html without "
                          f"{', '.join(rep.figure_errors)} are in {target}")
    payload = {"out": str(target), "files": [str(p) for p in files],
               "figures": [f.name for f in rep.figures], "seconds": time.perf_counter() - t0,
               "version": rep.version, "seeds": rep.seeds}
    st = rep.study
    assert st is not None  # (run_damper_report makes the design study)
    lines = [f"report of {sc.title!r} in {target}/ ({payload['seconds']:.1f} s)",
             f"  best design: {damper_report._brief(st.best, [v.name for v in st.variables])}"
             + ("" if st.no_best is None else f" ({st.no_best})"),
             f"  lightest within {st.tolerance * 100:g} %: "
             f"{damper_report._brief(st.lightest_within, [v.name for v in st.variables])}"]
    for level, r in rep.uncertainty.items():
        lines.append(f"  uncertainty ({level}): driver {r.driver or 'none (no spread)'}")
    emit(payload, as_json, "\n".join(lines + _assumption_lines(rep)))


def _assumption_lines(rep) -> list[str]:
    """Where the report's answers rest on the analytical model outside its assumptions:
    the best design and the forced response's peak (the tables say more)."""
    out = []
    best = None if rep.study is None else rep.study.best
    if best is not None and best.extra.get("assumptions_hold") is False:
        out.append(f"  ! best design: {best.extra['assumptions']}")
    for m in rep.models():
        h = m.get("harmonicity")
        if h is not None and not h["near_harmonic"]:
            out.append(f"  ! free decay, {m['label']}: not near-harmonic (deviation "
                       f"{h['deviation']:.2f} > {h['threshold']:g}): its loss factor was "
                       "taken from a harmonic response the motion does not follow; use "
                       "--model plastic or dem there")
        if m.get("fields_from") == "analytic":
            out.append(f"  ! {m['label']}: {m['fields_note']}")
    summary = rep.forced_summary() or {"models": {}}
    for label, m in summary["models"].items():
        if m.get("peak_assumptions_hold") is False:
            out.append(f"  ! forced response, {label}: the peak is outside the analytic "
                       "model's assumptions; use fields from a DEM map, or dem there")
    return out


def _check_runs(sc, dem: bool, realisations: str | None, uncertainty: int | None,
                force: bool) -> int | None:
    """What the report will run, judged before any run: the DEM, its realisations (their
    count, or None) and the uncertainty propagation."""
    from pdamper.design.uncertainty import check_points
    from pdamper.errors import InputError
    from pdamper.runs.damper_report import DEFAULT_UNCERTAINTY_POINTS
    from pdamper.runs.resources import check_resources

    if dem:
        check_resources(sc, "simulation", "dem", force)
    n_real = None
    if realisations is not None:
        from pdamper.runs.realisations import check_level3_realisations, parse_count

        if not dem:
            raise InputError("realisations", "needs --dem (the realisations are those of the "
                             "DEM's random packings)")
        n_real = check_level3_realisations(parse_count(realisations), sc, "dem", force=force)
    if uncertainty is not None:
        _uncertainty.check(sc, "level3", uncertainty, force)
    elif sc.uncertain_inputs():
        check_points(DEFAULT_UNCERTAINTY_POINTS)
        from pdamper.runs.uncertainty import check_cost

        check_cost(sc, "level3", DEFAULT_UNCERTAINTY_POINTS, force)
    if sc.uncertain_inputs():  # the user's questions sampled too: the [frf] and [load] ones
        from pdamper.runs.damper_report import question_uncertainty
        from pdamper.runs.uncertainty import check_cost

        n = DEFAULT_UNCERTAINTY_POINTS if uncertainty is None else uncertainty
        for level, o in question_uncertainty(sc).items():
            if level == "frf":
                check_cost(sc, "frf", n, force, frequencies=len(o["frequency"]))
            else:
                check_cost(sc, "load", n, force, history=o["history"], tail=o["tail"])
    if sc.uncertain_inputs():  # its Level III answers (the time of the amplitude) judged
        from pdamper.runs.uncertainty import level3_answers

        level3_answers(sc, "analytic")
    return n_real


class _Nothing:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: object) -> Literal[False]:
        return False
