"""``pdamper paper``: the reference paper's case study (the main job)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from pdamper.cli._common import JsonOpt, ScenarioOpt, emit, load


def paper(
    out: Annotated[Path, typer.Option(help="Directory for figures and tables.")] = Path(
        "paper-results"),
    dem: Annotated[bool, typer.Option("--dem/--no-dem",
                                      help="Include the DEM: the Fig. 5b/5d map (cached in "
                                           "the output directory), Fig. 3 and the Level III "
                                           "model 1 run.")] = True,
    workers: Annotated[int | None, typer.Option(
        help="Worker processes of the DEM map (default: every core).")] = None,
    scheduler: Annotated[str | None, typer.Option(
        help="Address of an existing dask scheduler for the DEM map.")] = None,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Reproduce the paper's case study: Figs. 3, 4, 5 a-d, 7, 8, 9 and a table of every
    reported number next to ours. The scenario (default: the paper's case) sets the damper,
    structure, duration, Fig. 5 grids, optimisation and DEM options."""
    import sys
    import time

    from rich.console import Console
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    from pdamper.errors import InputError
    from pdamper.reports.paper_case_study import run_case_study, write_case_study

    if out.exists() and not out.is_dir():
        raise InputError("out", f"must be a directory, {out} is a file")
    if not out.parent.is_dir():
        raise InputError("out", f"directory does not exist: {out.parent}")
    if workers is not None and workers < 1:
        raise InputError("workers", f"must be a whole number >= 1, got {workers}")
    sc = load(scenario)
    options = {k: v for k, v in (("workers", workers), ("scheduler", scheduler)) if v is not None}
    out.mkdir(exist_ok=True)
    t0 = time.perf_counter()
    console = Console(file=sys.stderr)
    with Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(),
                  console=console, transient=False) as prog:
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

        cs = run_case_study(sc, step, dem, out=out, map_progress=map_points, **options)
        files = write_case_study(cs, out, step)
        prog.update(task, description="done", completed=steps)
    agree = sum(r.agrees is True for r in cs.rows)
    payload = {"out": str(out), "files": [str(p) for p in files],
               "agreeing": agree, "rows": len(cs.rows), "seconds": time.perf_counter() - t0}
    human = "\n".join(
        [f"{'ok ' if r.agrees else ('-- ' if r.agrees is None else 'NO ')} {r.quantity}: "
         f"paper {r.paper}, pdamper {r.ours}" for r in cs.rows]
        + [f"{agree} of {len(cs.rows)} reported numbers agree; files in {out}/"])
    emit(payload, as_json, human)
