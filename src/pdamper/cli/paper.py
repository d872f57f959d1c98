"""``pdamper paper``: the reference paper's case study (the main job)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any

import typer

from pdamper.cli._common import ForceOpt, JsonOpt, ScenarioOpt, check_output_directory, emit, load
from pdamper.cli._quiet import quiet

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import Console
    from rich.progress import Task, TaskID


class _Progress:
    """What ``pdamper paper`` is doing, live on a terminal (stderr), gone when done: the
    step (compiling the DEM kernels, each figure, ...), the DEM map's points done of
    total, the time elapsed. Nothing at all where stderr is no terminal (a pipe, a file, a
    test's capture): the output and error lines stay as they are."""

    def __init__(self, console: Console) -> None:
        from rich.progress import (
            BarColumn,
            Progress,
            ProgressColumn,
            SpinnerColumn,
            TextColumn,
            TimeElapsedColumn,
        )
        from rich.text import Text

        class Count(ProgressColumn):
            """``done/total`` where there is a total (the map's points), else nothing."""

            def render(self, task: Task) -> Text:
                return Text("" if task.total is None else
                            f"{int(task.completed)}/{int(task.total)}")

        self._progress = Progress(SpinnerColumn(), TextColumn("{task.description}"),
                                  BarColumn(bar_width=20), Count(), TimeElapsedColumn(),
                                  console=console, transient=True,
                                  disable=not console.is_terminal or quiet())
        self._points: TaskID | None = None
        self._task: TaskID | None = None

    def __enter__(self) -> _Progress:
        self._progress.__enter__()
        # no total: the steps depend on the scenario; the bar of this line only pulses
        self._task = self._progress.add_task("pdamper paper: the case study", total=None)
        return self

    def __exit__(self, *exc: Any) -> None:
        self._progress.__exit__(*exc)

    def step(self, message: str) -> None:
        """A new step of the case study, drawn at once (not at the next refresh: a step
        shorter than a refresh is shown too)."""
        assert self._task is not None  # (added on entering the context)
        self._progress.update(self._task, description=message, refresh=True)

    def map_points(self, done: int, total: int, _point: Any = None) -> None:
        """The DEM map's points: ``done`` of ``total`` (finished or reused)."""
        if self._points is None:
            self._points = self._progress.add_task("DEM map points", total=total)
        self._progress.update(self._points, completed=done, total=total, refresh=True)


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
    realisations: Annotated[str | None, typer.Option(
        "--realisations", help="With the DEM: model 1 also from N random packings (seeds "
        "dem.seed ... dem.seed + N - 1), drawn as a band (mean, min-max shaded) in Figs. 7/8 "
        "and its spread in results.json under 'dem_realisations'; 1: none (default 5, none "
        "where the bed is too dense for a random packing).")] = None,
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

    from pdamper.errors import InputError
    from pdamper.files import atomic_directory
    from pdamper.reports.paper_case_study import write_case_study
    from pdamper.runs import paper_case_study as study

    sc = load(scenario, runs=("case_study_dem" if dem else "case_study",), force=force)
    target = check_output_directory(out)
    if workers is not None and workers < 1:
        raise InputError("workers", f"must be a whole number >= 1, got {workers}")
    if scheduler is not None:
        from pdamper.sweep.cluster import check_scheduler

        check_scheduler(scheduler)
    options = {k: v for k, v in (("workers", workers), ("scheduler", scheduler)) if v is not None}
    from pdamper.runs.realisations import parse_count

    n_real = study.PAPER_REALISATIONS if realisations is None else parse_count(realisations)
    if dem and n_real > 1:  # judged before any run: N random packings of the Level III DEM
        from pdamper.runs.realisations import check_level3_realisations

        try:
            check_level3_realisations(n_real, study.band_scenario(sc), "dem", force=force)
        except InputError as exc:
            # by default, a bed too dense to be packed at random has no band (the lattice
            # is its one realisation); asked for, the reason is the answer
            if realisations is not None or exc.field != "particles.count":
                raise
            n_real = 1
    t0 = time.perf_counter()
    with _Progress(Console(file=sys.stderr)) as prog:
        with atomic_directory(target) as stage:
            cache = target if target.is_dir() else stage
            cs = study.run_case_study(sc, prog.step, dem, out=cache,
                                      map_progress=prog.map_points,
                                      realisations=n_real if dem else 1, **options)
            written = write_case_study(cs, stage, prog.step)
    files = [target / p.relative_to(stage) for p in written]
    agree = sum(r.agrees is True for r in cs.rows)
    payload = {"out": str(target), "files": [str(p) for p in files],
               "realisations": n_real if dem else 0,
               "agreeing": agree, "rows": len(cs.rows), "seconds": time.perf_counter() - t0}
    human = "\n".join(
        [f"{'ok ' if r.agrees else ('-- ' if r.agrees is None else 'NO ')} {r.quantity}: "
         f"paper {r.paper}, pdamper {r.ours}" for r in cs.rows]
        + [f"{agree} of {len(cs.rows)} reported numbers agree; files in {target}/"])
    emit(payload, as_json, human)
