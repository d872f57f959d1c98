"""Parallel evaluation of design points on the sweep engine (:mod:`pdamper.sweep`).

:func:`evaluate_parallel` maps a function over design points in-process or on a
dask.distributed cluster (a LocalCluster of worker processes, or an existing scheduler)
through :func:`pdamper.sweep.run_sweep`, the engine of the effective-field maps, and returns
one :class:`Outcome` per item, in order, each either a value or the error that item raised.
A failing point never ends the study.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from pdamper.errors import InputError


@dataclass(frozen=True)
class Outcome:
    """Result of one evaluation: ``value``, or ``error`` (one line) if it raised."""

    value: Any = None
    error: str | None = None

    @property
    def ok(self) -> bool:
        return self.error is None


def _evaluate(fn: Callable[[Any], Any], params: dict) -> dict:
    """Point function of the sweep: the design's value under one key."""
    return {"value": fn(params)}


def evaluate_parallel(fn: Callable[[Any], Any], items: Sequence[dict], *,
                      workers: int | None = None, scheduler: str | None = None,
                      progress: Callable[[int, int], None] | None = None) -> list[Outcome]:
    """``[fn(item) for item in items]`` as :class:`Outcome` objects, possibly in parallel.

    Parameters
    ----------
    fn
        Function of one item; must be picklable by cloudpickle for a cluster (closures and
        lambdas are).
    items
        The designs to evaluate (JSON-able mappings).
    workers
        None or 0: evaluate in this process, one after another. N >= 1: a dask.distributed
        LocalCluster of N single-threaded worker processes (bound to localhost), closed
        afterwards.
    scheduler
        Address of an existing dask scheduler (``tcp://host:8786``); overrides ``workers``.
    progress
        Optional callback ``progress(done, total)``.

    Returns
    -------
    list of Outcome
        In the order of ``items``. A worker that dies records its points as failed.
    """
    if workers is not None and (isinstance(workers, bool) or int(workers) != workers
                                or workers < 0):
        raise InputError("optimization.workers", f"must be a whole number >= 0, got {workers!r}")
    from pdamper.sweep import run_sweep

    serial = scheduler is None and not workers
    result = run_sweep(functools.partial(_evaluate, fn), list(items), retries=0,
                       serial=serial, workers=None if serial else workers,
                       scheduler=scheduler,
                       progress=None if progress is None else
                       (lambda done, total, _point: progress(done, total)))
    return [Outcome(value=p.values.get("value")) if p.ok else Outcome(error=p.error)
            for p in result.points]
