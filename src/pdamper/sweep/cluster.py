"""The dask.distributed engine a sweep runs on: a local cluster or an existing scheduler."""

from __future__ import annotations

import contextlib
import logging
import os
from collections.abc import Iterator

from pdamper.errors import InputError

logger = logging.getLogger(__name__)


def default_workers() -> int:
    """Every core of this machine (the cores this process may use, where known)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


@contextlib.contextmanager
def open_client(workers: int | None = None, scheduler: str | None = None) -> Iterator:
    """A ``distributed.Client``: to the scheduler at ``scheduler`` (an existing cluster;
    left running afterwards), else on a new local cluster of ``workers`` single-threaded
    worker processes (default: every core), bound to localhost (its status page too, on a
    free port); the local cluster is shut down on exit.
    """
    if workers is not None and (isinstance(workers, bool) or int(workers) != workers
                                or workers < 1):
        raise InputError("workers", f"must be a whole number >= 1, got {workers!r}")
    if workers is not None and scheduler is not None:
        raise InputError("workers", "give either the worker count of a local cluster or "
                         "--scheduler, not both")
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError) as exc:
            raise InputError("scheduler", f"cannot connect to {scheduler!r}: {exc}") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = default_workers() if workers is None else int(workers)
    logger.info("starting a local dask cluster of %d worker processes", n)
    with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR) as cluster, \
            Client(cluster) as client:
        yield client
