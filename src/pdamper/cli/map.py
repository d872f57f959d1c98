"""``pdamper map``: an effective field over a (frequency x amplitude [x particles]) grid.

The analytical model is evaluated in one vectorised call; the DEM point by point on
dask.distributed (a local cluster of every core by default, ``--workers N``, or
``--scheduler ADDRESS``), with a progress bar, every finished point stored in
``<out>.partial/`` (a stopped map started again computes only the missing points) and
failed points recorded in the ``status`` and ``error`` variables.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, TextIO

import typer

from pdamper.cli import _uncertainty
from pdamper.cli._common import (
    ForceOpt,
    JsonOpt,
    ScenarioOpt,
    check_output,
    check_plot,
    emit,
    figure_last,
    key_help,
    load,
    plot_param,
)
from pdamper.cli._quiet import quiet
from pdamper.errors import InputError

if TYPE_CHECKING:
    from rich.progress import Progress, TaskID

    from pdamper.io.scenario import Scenario


#: The grid of the map, as the scenario's ``[map]`` keys.
FrequencyGridOpt = Annotated[str | None, typer.Option(help=key_help(
    "map.frequency", "Grid 'start:stop:count' (or 'log:start:stop:count'), e.g. "
    "'2Hz:20Hz:14'"))]
AmplitudeGridOpt = Annotated[str | None, typer.Option(help=key_help(
    "map.amplitude", "Grid 'start:stop:count' (or 'log:...'), e.g. '1mm:200mm:24'"))]
ParticlesAxisOpt = Annotated[str | None, typer.Option(help=key_help(
    "map.particles", "Number of spheres, or a particle-count axis '16:96:6' (or 'log:...')"))]


def map_(
    model: Annotated[str, typer.Option(
        help="Damper model (fidelity): analytic, fields or dem.")] = "analytic",
    frequency: FrequencyGridOpt = None,
    amplitude: AmplitudeGridOpt = None,
    particles: ParticlesAxisOpt = None,
    out: Annotated[str | None, typer.Option(help="NetCDF file to write.")] = None,
    uncertainty: _uncertainty.UncertaintyOpt = None,
    uncertain: _uncertainty.UncertainOpt = None,
    uncertainty_seed: _uncertainty.UncertaintySeedOpt = 0,
    force: ForceOpt = False,
    workers: Annotated[int | None, typer.Option(
        help="Worker processes of the local cluster (default: every core).")] = None,
    scheduler: Annotated[str | None, typer.Option(
        help="Address of an existing dask scheduler, e.g. 'tcp://10.0.0.5:8786'.")] = None,
    retries: Annotated[int, typer.Option(
        help="Further attempts of a point that failed for a non-deterministic reason.")] = 1,
    retry_failed: Annotated[bool, typer.Option(
        "--retry-failed", help="Compute points again that an earlier run recorded as failed.")
    ] = False,
    keep_partial: Annotated[bool, typer.Option(
        "--keep-partial", help="Keep <out>.partial/ (the per-point results) afterwards.")] = False,
    serial: Annotated[bool, typer.Option(
        "--serial", help="Run the points in this process, without dask.")] = False,
    realisations: Annotated[str | None, typer.Option(
        "--realisations", help="DEM: N independent random packings (seeds dem.seed ... "
        "dem.seed + N - 1); the map's values are their means, with the spread (std, min, max) "
        "of every cell and each realisation's values (dimension 'realisation').")] = None,
    plot: Annotated[str | None, plot_param(
        "the motion modes and the loss factor over the grid (the first particle count), "
        "points outside the analytical model's assumptions hatched")] = None,
    scenario: ScenarioOpt = None,
    as_json: JsonOpt = False,
) -> None:
    """Loss factor, effective mass, motion mode and stationarity over a grid (paper Fig. 5)."""
    import sys

    from pdamper.cli._common import metadata

    _check_run_options(workers, retries, scheduler)
    count, axis = _particle_count_or_axis(particles)
    sc = load(scenario, runs=("map",), model=model, force=force, **_uncertainty.merged(dict(
        map__frequency=frequency, map__amplitude=amplitude, particles__count=count,
        map__particles=axis), uncertain))
    _uncertainty.check(sc, "map", uncertainty, force)
    if uncertainty is not None:  # the sampled model refused before any run
        from pdamper.runs.uncertainty import map_answers

        map_answers(sc, model)
    out_path = check_output(out)
    plot_path = check_plot(plot)
    if out_path is not None and scheduler is None:
        _check_partial_store(out_path)
    options = _sweep_options(workers, scheduler, retries, retry_failed, serial)
    meta = metadata(sc, model=model, seed=sc.dem.seed)
    n_real = _realisation_count(sc, model, realisations, uncertainty, force)
    # with --uncertainty the file is written once, at the end, with its bands: a failed or
    # interrupted sampling leaves no map without them
    first_out = out_path if uncertainty is None else None
    with _progress(sys.stderr, as_json or quiet()) as progress:
        if n_real > 1:
            from pdamper.runs.realisations import run_map_realisations

            result = run_map_realisations(sc, model, n_real, out=first_out,
                                          keep_partial=keep_partial, progress=progress,
                                          force=force, **options)
        else:
            from pdamper.runs.maps import run_map

            result = run_map(sc, model, out=first_out, keep_partial=keep_partial,
                             progress=progress, **options)
    payload, human = _summary(sc, model, result, out_path, n_real, meta)
    if uncertainty is not None:  # the spread of every cell, added to the map and its file
        spread, payload["uncertainty"] = _uncertainty.map_spread(
            sc, model, uncertainty, uncertainty_seed, result.dataset, out_path)
        human += "\n" + "\n".join(_uncertainty.lines(spread, {}))
    emit(payload, as_json, human)
    if plot_path is not None:
        figure_last(lambda: _map_figure(result.dataset, model), plot_path, dpi=110)


def _map_figure(ds: Any, model: str) -> Any:
    """The motion modes and the loss factor over the grid (of the first particle count);
    cells outside the analytical model's assumptions hatched (plots.figures)."""
    from matplotlib.figure import Figure

    from pdamper.plots import plot_loss_factor_map, plot_mode_map

    what = f"{model} model"
    if "particles" in ds.dims:
        n = int(ds["particles"].values[0])
        ds, what = ds.isel(particles=0), f"{what}, {n} particles"
    fig = Figure(figsize=(13, 5), layout="constrained")
    axes = fig.subplots(1, 2)
    plot_mode_map(ds, ax=axes[0]).set_title(f"motion modes ({what})")
    plot_loss_factor_map(ds, ax=axes[1]).set_title(f"loss factor ({what})")
    return fig


def _sweep_options(workers: int | None, scheduler: str | None, retries: int,
                   retry_failed: bool, serial: bool) -> dict[str, Any]:
    """The options of the sweep engine (those given; the engine's defaults for the rest)."""
    options: dict[str, Any] = {"retries": retries, "retry_failed": retry_failed,
                               "serial": serial}
    if workers is not None:
        options["workers"] = workers
    if scheduler is not None:
        options["scheduler"] = scheduler
    return options


def _check_run_options(workers: int | None, retries: int, scheduler: str | None) -> None:
    """``--workers`` at least 1, ``--retries`` at least 0 and ``--scheduler`` an address."""
    if workers is not None and workers < 1:
        raise InputError("workers", f"must be a whole number >= 1, got {workers}")
    if retries < 0:
        raise InputError("retries", f"must be a whole number >= 0, got {retries}")
    if scheduler is not None:
        from pdamper.sweep.cluster import check_scheduler

        check_scheduler(scheduler)


def _particle_count_or_axis(particles: str | None) -> tuple[int | None, str | None]:
    """``--particles`` as a count or as a particle-count axis ('start:stop:count')."""
    if particles is None:
        return None, None
    if ":" in particles:
        return None, particles
    try:
        return int(particles), None
    except ValueError:
        raise InputError("particles", f"expected a whole number or 'start:stop:count', "
                         f"got {particles!r}") from None


def _check_partial_store(out: Path) -> None:
    """The per-point store beside ``out`` must be a directory if it exists."""
    from pdamper.runs.maps import partial_store

    part = partial_store(out)
    if part.exists() and not part.is_dir():
        raise InputError("out", f"{part} exists and is not a directory")


def _realisation_count(sc: Scenario, model: str, realisations: str | None,
                       uncertainty: int | None, force: bool) -> int:
    """``--realisations`` as a count checked against the map's cost (1: one packing),
    refused above 1 with ``--uncertainty``."""
    if realisations is None:
        return 1
    from pdamper.runs.realisations import check_map_realisations, parse_count

    n_real = check_map_realisations(parse_count(realisations), sc, model, force=force)
    if n_real > 1 and uncertainty is not None:
        raise InputError("realisations", f"must be 1 with --uncertainty (the sampled "
                         f"inputs are the map's spread there), got {n_real}")
    return n_real


def _summary(sc: Scenario, model: str, result: Any, out: Path | None, n_real: int,
             meta: dict) -> tuple[dict, str]:
    """The JSON payload and the text of a finished map: its shape, the counts of points
    and the largest loss factor with where it is."""
    import math

    import numpy as np

    ds = result.dataset
    eta = np.asarray(ds["loss_factor"].values, float)
    finite = np.isfinite(eta)
    best = {}
    if finite.any():
        idx = np.unravel_index(np.nanargmax(np.where(finite, eta, -math.inf)), eta.shape)
        best = {d: float(ds[d].values[i]) for d, i in zip(ds["loss_factor"].dims, idx,
                                                           strict=True)}
    steady = int((ds["stationary"].values == 1).sum())
    payload = {
        "out": str(out) if out else None, "shape": list(eta.shape),
        "dims": list(ds["loss_factor"].dims), "seconds": result.seconds,
        "points": int(eta.size), "computed": result.computed, "reused": result.reused,
        "failed": result.failed, "steady": steady, "workers": result.workers,
        "max_loss_factor": float(np.nanmax(eta)) if finite.any() else None, "max_at": best,
        **meta,
    }
    marks = assumption_record(ds)
    if marks is not None:
        payload["assumptions"] = marks
    why = {k: reason for k, reason in (
        ("out", "--out not given: the map is not written"),
        ("max_loss_factor", "no point of the map has a finite loss factor"))
        if payload[k] is None}
    if why:
        payload["not_applicable"] = why
    if n_real > 1:
        from pdamper.runs.realisations import map_spread_record

        payload["statistic"] = "mean"
        payload["realisations"] = map_spread_record(ds)
    where = ", ".join(f"{k} = {v:.4g}" for k, v in best.items())
    human = (f"{model} field {' x '.join(map(str, eta.shape))} in {result.seconds:.3g} s "
             f"({result.computed} computed, {result.reused} reused, {result.failed} failed, "
             f"{steady} steady)"
             + (f"; max loss factor {np.nanmax(eta):.3f} at {where}" if finite.any() else "")
             + (f"; mean of {n_real} realisations (seeds {sc.dem.seed}..."
                f"{sc.dem.seed + n_real - 1}), spread per cell in the file"
                if n_real > 1 else "")
             + (f"; written to {out}" if out else ""))
    from pdamper.analysis.analytical import assumption_line

    line = None if marks is None else assumption_line(marks, "points")
    return payload, human + (f"\n{line}" if line else "")


def assumption_record(ds: Any) -> dict | None:
    """The map's ``assumptions_hold`` summed up (:func:`~pdamper.analysis.analytical.
    assumption_summary` over the points with a result; None: the model reports none)."""
    import numpy as np

    from pdamper.analysis.analytical import assumption_summary

    if "assumptions_hold" not in ds:
        return None
    ok = (ds["status"].values == 0) if "status" in ds else np.ones(
        ds["assumptions_hold"].shape, bool)
    return assumption_summary(ds["assumptions_hold"].values[ok] == 1,
                              ds["assumptions"].values[ok])


class _progress:
    """A rich progress bar on stderr (none with --json or --quiet), as a sweep ``progress``
    callback."""

    def __init__(self, stream: TextIO, quiet: bool):
        self.stream, self.quiet = stream, quiet
        self.bar: Progress | None = None
        self.task: TaskID | None = None
        self.failed = 0

    def __enter__(self) -> _progress | None:
        if self.quiet:
            return None
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                            TimeElapsedColumn(), TimeRemainingColumn(),
                            console=Console(file=self.stream), transient=False,
                            disable=not Console(file=self.stream).is_terminal)
        self.bar.__enter__()
        self.task = self.bar.add_task("map points", total=None)
        return self

    def __call__(self, done: int, total: int, point: Any) -> None:
        self.failed += not point.ok
        desc = f"map points ({self.failed} failed)" if self.failed else "map points"
        assert self.bar is not None and self.task is not None  # called only when entered
        self.bar.update(self.task, completed=done, total=total, description=desc)

    def __exit__(self, *exc: Any) -> Literal[False]:
        if self.bar is not None:
            if self.task is not None and self.bar.tasks[0].total is None:  # vectorised: no points
                self.bar.remove_task(self.task)
            self.bar.__exit__(*exc)
        return False
