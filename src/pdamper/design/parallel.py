"""Parallel evaluation of design points on dask.distributed, with per-point error capture.

:func:`evaluate_parallel` is the one place where the design study meets a parallel engine:
it maps a function over items in-process or on a dask.distributed cluster (a LocalCluster
of worker processes, or an existing scheduler) and returns one :class:`Outcome` per item,
in order, each either a value or the error that item raised. A failing point never ends the
study. A generic sweep engine can replace this function without touching its callers.
"""

from __future__ import annotations

import logging
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from pdamper.errors import InputError

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class Outcome:
    """Result of one evaluation: ``value``, or ``error`` (one line) if it raised."""

    value: Any = None
    error: str | None = None

    @property
    def ok(self) -> bool:
        return self.error is None


class _Captured:
    """``fn`` wrapped so that an exception becomes an :class:`Outcome` (runs on workers)."""

    def __init__(self, fn: Callable[[Any], Any]):
        self.fn = fn

    def __call__(self, item) -> Outcome:
        try:
            return Outcome(value=self.fn(item))
        except Exception as exc:  # a failed point is recorded, never fatal
            logger.debug("evaluation failed: %s", traceback.format_exc())
            return Outcome(error=f"{type(exc).__name__}: {exc}".splitlines()[0])


def evaluate_parallel(fn: Callable[[Any], Any], items: Sequence[Any], *,
                      workers: int | None = None, scheduler: str | None = None,
                      progress: Callable[[int, int], None] | None = None) -> list[Outcome]:
    """``[fn(item) for item in items]`` as :class:`Outcome` objects, possibly in parallel.

    Parameters
    ----------
    fn
        Function of one item; must be picklable by cloudpickle for a cluster (closures and
        lambdas are).
    items
        The points to evaluate.
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
    items = list(items)
    wrapped = _Captured(fn)
    total = len(items)
    if workers is not None and (isinstance(workers, bool) or int(workers) != workers
                                or workers < 0):
        raise InputError("optimization.workers", f"must be a whole number >= 0, got {workers!r}")
    if scheduler is None and not workers:
        out = []
        for k, item in enumerate(items):
            out.append(wrapped(item))
            if progress:
                progress(k + 1, total)
        return out
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError("optimization.workers", "parallel evaluation needs dask.distributed: "
                         "pip install 'pdamper[distributed]' (or use --workers 0)") from None
    if scheduler is not None:
        cluster = None
        client = Client(scheduler)
    else:
        # localhost only; the scheduler's HTTP server on a free port, no dashboard
        cluster = LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address="127.0.0.1:0",
                               scheduler_kwargs={"dashboard": False})
        client = Client(cluster)
    try:
        futures = client.map(wrapped, items, pure=False)
        index = {f.key: k for k, f in enumerate(futures)}
        out: list[Outcome | None] = [None] * total
        done = 0
        for fut in as_completed(futures):
            k = index[fut.key]
            try:
                out[k] = fut.result()
            except Exception as exc:  # the worker died, or the task could not run
                out[k] = Outcome(error=f"{type(exc).__name__}: {exc}".splitlines()[0])
            done += 1
            if progress:
                progress(done, total)
        return [o for o in out if o is not None]
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
