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
                                      help="Include the DEM (model 1) Level III run.")] = True,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Reproduce the paper's case study: Figs. 4, 5a, 5c, 7, 8, 9 and a table of every
    reported number next to ours. The scenario (default: the paper's case) sets the damper,
    structure, duration, Fig. 5 grid, optimisation and DEM options."""
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
    sc = load(scenario)
    t0 = time.perf_counter()
    console = Console(file=sys.stderr)
    with Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(),
                  console=console, transient=False) as prog:
        task = prog.add_task("case study", total=8)

        def step(msg: str) -> None:
            prog.update(task, description=msg, advance=1)

        cs = run_case_study(sc, step, dem)
        out.mkdir(exist_ok=True)
        files = write_case_study(cs, out, step)
        prog.update(task, description="done", completed=8)
    agree = sum(r.agrees is True for r in cs.rows)
    payload = {"out": str(out), "files": [str(p) for p in files],
               "agreeing": agree, "rows": len(cs.rows), "seconds": time.perf_counter() - t0}
    human = "\n".join(
        [f"{'ok ' if r.agrees else ('-- ' if r.agrees is None else 'NO ')} {r.quantity}: "
         f"paper {r.paper}, pdamper {r.ours}" for r in cs.rows]
        + [f"{agree} of {len(cs.rows)} reported numbers agree; files in {out}/"])
    emit(payload, as_json, human)
