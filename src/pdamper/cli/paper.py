"""``pdamper paper``: the reference paper's case study (the main job)."""

from __future__ import annotations

from typing import Annotated

import typer

from pdamper.cli._common import ForceOpt, JsonOpt, ScenarioOpt, check_output_directory, emit, load
from pdamper.cli._quiet import quiet


def paper(
    out: Annotated[str, typer.Option(help="Directory for figures and tables (created if "
                                     "missing; its parent must exist).")] = "paper-results",
    dem: Annotated[bool, typer.Option("--dem/--no-dem",
                                      help="Include the DEM: the Fig. 5b/5d map (cached in "
                                           "the output directory), Fig. 3 and the Level III "
                                           "model 1 runs.")] = True,
    workers: Annotated[int | None, typer.Option(
        help="Worker processes of the DEM map (default: every core).")] = None,
    scheduler: Annotated[str | None, typer.Option(
        help="Address of an existing dask scheduler for the DEM map.")] = None,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Reproduce the paper's case study: Figs. 3, 4, 5 a-d, 7, 8, 9 and a table of every
    reported number next to ours. The scenario (default: the paper's case) sets the damper,
    structure, duration, Fig. 5 grids, optimisation and DEM options.

    The results appear together: a new directory only when complete; in an existing one
    the new files replace their namesakes (other files stay). The DEM map is cached in an
    existing output directory, so that a rerun (or a rerun after an interrupt) does not
    recompute its finished points."""
    import sys
    import time

    from rich.console import Console
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    from pdamper.errors import InputError
    from pdamper.files import atomic_directory
    from pdamper.reports import paper_case_study as study

    sc = load(scenario, runs=("case_study_dem" if dem else "case_study",), force=force)
    target = check_output_directory(out)
    if workers is not None and workers < 1:
        raise InputError("workers", f"must be a whole number >= 1, got {workers}")
    if scheduler is not None:
        from pdamper.sweep.cluster import check_scheduler

        check_scheduler(scheduler)
    options = {k: v for k, v in (("workers", workers), ("scheduler", scheduler)) if v is not None}
    t0 = time.perf_counter()
    console = Console(file=sys.stderr)
    # a progress display for a terminal only, gone when done: errors stay one line
    with Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(),
                  console=console, transient=True,
                  disable=not console.is_terminal or quiet()) as prog:
        steps = 10 if dem else 8
        task = prog.add_task("case study", total=steps)
        points = None

        def step(msg: str) -> None:
            prog.update(task, description=msg, advance=1)

        def map_points(done: int, total: int, _point) -> None:
            nonlocal points
            if points is None:
                points = prog.add_task("DEM map points", total=total)
            prog.update(points, completed=done)

        with atomic_directory(target) as stage:
            cache = target if target.is_dir() else stage
            cs = study.run_case_study(sc, step, dem, out=cache, map_progress=map_points,
                                      **options)
            written = study.write_case_study(cs, stage, step)
        prog.update(task, description="done", completed=steps)
    files = [target / p.relative_to(stage) for p in written]
    agree = sum(r.agrees is True for r in cs.rows)
    payload = {"out": str(target), "files": [str(p) for p in files],
               "agreeing": agree, "rows": len(cs.rows), "seconds": time.perf_counter() - t0}
    human = "\n".join(
        [f"{'ok ' if r.agrees else ('-- ' if r.agrees is None else 'NO ')} {r.quantity}: "
         f"paper {r.paper}, pdamper {r.ours}" for r in cs.rows]
        + [f"{agree} of {len(cs.rows)} reported numbers agree; files in {target}/"])
    emit(payload, as_json, human)
