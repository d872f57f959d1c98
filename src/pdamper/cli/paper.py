"""``pdamper paper``: the reference paper's case study (the main job)."""

from __future__ import annotations

from typing import Annotated

import typer

from pdamper.cli._common import ForceOpt, JsonOpt, ScenarioOpt, check_output_directory, emit, load


def paper(
    out: Annotated[str, typer.Option(help="Directory for figures and tables (created if "
                                     "missing; its parent must exist).")] = "paper-results",
    dem: Annotated[bool, typer.Option("--dem/--no-dem",
                                      help="Include the DEM (model 1) Level III run.")] = True,
    force: ForceOpt = False,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Reproduce the paper's case study: Figs. 4, 5a, 5c, 7, 8, 9 and a table of every
    reported number next to ours. The scenario (default: the paper's case) sets the damper,
    structure, duration, Fig. 5 grid, optimisation and DEM options.

    The results appear together: a new directory only when complete; in an existing one
    the new files replace their namesakes (other files stay)."""
    import sys
    import time

    from rich.console import Console
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    from pdamper.files import atomic_directory
    from pdamper.reports import paper_case_study as study

    sc = load(scenario, runs=("case_study_dem" if dem else "case_study",), force=force)
    target = check_output_directory(out)
    t0 = time.perf_counter()
    console = Console(file=sys.stderr)
    # a progress display for a terminal only, gone when done: errors stay one line
    with Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(),
                  console=console, transient=True,
                  disable=not console.is_terminal) as prog:
        task = prog.add_task("case study", total=8)

        def step(msg: str) -> None:
            prog.update(task, description=msg, advance=1)

        cs = study.run_case_study(sc, step, dem)
        with atomic_directory(target) as stage:
            written = study.write_case_study(cs, stage, step)
        prog.update(task, description="done", completed=8)
    files = [target / p.relative_to(stage) for p in written]
    agree = sum(r.agrees is True for r in cs.rows)
    payload = {"out": str(target), "files": [str(p) for p in files],
               "agreeing": agree, "rows": len(cs.rows), "seconds": time.perf_counter() - t0}
    human = "\n".join(
        [f"{'ok ' if r.agrees else ('-- ' if r.agrees is None else 'NO ')} {r.quantity}: "
         f"paper {r.paper}, pdamper {r.ours}" for r in cs.rows]
        + [f"{agree} of {len(cs.rows)} reported numbers agree; files in {target}/"])
    emit(payload, as_json, human)
