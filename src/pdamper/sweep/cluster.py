"""The dask.distributed engine a sweep runs on: a local cluster or an existing scheduler.

A scheduler's address is judged by :func:`check_scheduler` (the commands call it before
any computation; :func:`open_client` again, for callers of the library): a malformed one
is an :class:`~pdamper.errors.InputError` for ``scheduler``, as is one that cannot be
reached. An interrupted or failed sweep on a local cluster stops its worker processes at
once (:func:`_stop_workers`) instead of waiting the 4 s that dask grants a busy worker to
finish its task, so that Ctrl-C ends a DEM map within a second like every other command.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import os
from collections.abc import Iterator
from typing import Any

from pdamper.errors import InputError

logger = logging.getLogger(__name__)


#: Seconds a worker process of a local cluster is given to stop when the sweep was
#: interrupted or failed, before it is killed (its results are not wanted any more).
STOP_WAIT = 0.1
#: Seconds then allowed for the killed processes to be gone.
REAP_WAIT = 0.5
#: After an interrupt or a failure, child processes that appear later (a spawn already in
#: flight in one of dask's threads) are killed until none has appeared for LATE_QUIET s,
#: for at most LATE_WAIT s.
LATE_QUIET = 0.1
LATE_WAIT = 0.5

_EXAMPLE = "e.g. 'tcp://10.0.0.5:8786'"


def check_scheduler(address, field: str = "scheduler") -> str:
    """``address`` if it can be the address of a dask scheduler (``[scheme://]host:port``
    with a scheme dask knows and a port in 1-65535); an :class:`InputError` for ``field``
    otherwise. Whether a scheduler answers there is seen when connecting
    (:func:`open_client`).

    >>> check_scheduler("tcp://10.0.0.5:8786")
    'tcp://10.0.0.5:8786'
    >>> check_scheduler("notanaddress")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    pdamper.errors.InputError: scheduler: must be the address of a dask scheduler, ...
    """
    if not isinstance(address, str) or not address.strip():
        raise InputError(field, f"must be the address of a dask scheduler, {_EXAMPLE}, got "
                         f"{address!r}")
    from distributed.comm.addressing import get_address_host_port, parse_address
    from distributed.comm.registry import get_backend

    try:
        scheme, _ = parse_address(address)
        if scheme in ("tcp", "tls", "ws", "wss"):
            host, port = get_address_host_port(address)
            if not host or not 0 < int(port) < 65536:
                raise ValueError(f"no host or a port outside 1-65535 in {address!r}")
        else:  # inproc, ucx: a scheme that dask knows
            get_backend(scheme)
    except (ValueError, TypeError) as exc:
        raise InputError(field, f"must be the address of a dask scheduler, {_EXAMPLE}, got "
                         f"{address!r} ({exc})") from None
    return address


def _stop_workers(cluster) -> None:
    """Kill the worker processes of a local ``cluster`` at once, then close their nannies
    (within :data:`STOP_WAIT` s) and wait until the processes are gone (at most
    :data:`REAP_WAIT` s more; one still there at exit is reported by dask as a "stray
    process"). Killed before the nannies ask them to stop: dask's own close waits 4 s for a
    worker busy in a task (a DEM kernel), and a worker closed gracefully while its heartbeat
    is in flight logs the closed connection as an error on the terminal of whoever pressed
    Ctrl-C. Killed after each nanny is marked closing, or it would start a new worker."""
    import asyncio
    import signal

    async def stop():
        nannies = [w for w in list(cluster.workers.values()) if hasattr(w, "close")]
        # the worker processes (distributed's AsyncProcess), taken before close forgets them
        procs: list[Any] = [getattr(getattr(w, "process", None), "process", None)
                            for w in nannies]
        procs = [p for p in procs if p is not None and getattr(p, "pid", None)]
        # each close marks its nanny closing before its first wait: a nanny still running
        # when its worker dies starts a new one, whose queues' semaphores the exit
        # handlers of this process may miss (the resource tracker then reports them)
        closing = [asyncio.ensure_future(w.close(timeout=STOP_WAIT)) for w in nannies]
        await asyncio.sleep(0)
        for p in procs:
            with contextlib.suppress(Exception):
                if p.is_alive():
                    os.kill(p.pid, getattr(signal, "SIGKILL", signal.SIGTERM))
        await asyncio.gather(*closing, return_exceptions=True)
        await asyncio.gather(*(p.join(REAP_WAIT) for p in procs), return_exceptions=True)

    with contextlib.suppress(Exception):
        cluster.sync(stop)


def _kill(processes) -> None:
    """SIGKILL ``processes`` (``multiprocessing`` children) and reap them."""
    for p in processes:
        with contextlib.suppress(Exception):
            p.kill()
    for p in processes:
        with contextlib.suppress(Exception):
            p.join(REAP_WAIT)


def _child_pids() -> set[int]:
    """Process ids of this process's children (the operating system's record: a child
    whose spawn has not returned yet is not in multiprocessing's)."""
    import psutil  # a dependency of dask.distributed

    try:
        return {c.pid for c in psutil.Process().children()}
    except psutil.Error:  # pragma: no cover - this process is always readable
        return set()


def _kill_late(before: set[int]) -> None:
    """SIGKILL every child process of this one not in ``before`` (nor the resource
    tracker, which must outlive the workers to release their semaphores) as it appears,
    until none has appeared for :data:`LATE_QUIET` s (at most :data:`LATE_WAIT` s). A worker
    whose spawn was in flight in one of dask's threads when the sweep stopped would
    otherwise outlive this process and print the traceback of its lost start-up data."""
    import signal
    import time
    from multiprocessing import resource_tracker

    seen = set(before)
    tracker = getattr(getattr(resource_tracker, "_resource_tracker", None), "_pid", None)
    start = last = time.monotonic()
    while True:
        now = time.monotonic()
        if now - last >= LATE_QUIET or now - start >= LATE_WAIT:
            return
        tracker = getattr(getattr(resource_tracker, "_resource_tracker", None), "_pid",
                          None) or tracker
        for pid in _child_pids() - seen - {tracker}:
            seen.add(pid)
            last = time.monotonic()
            with contextlib.suppress(OSError):
                os.kill(pid, getattr(signal, "SIGKILL", signal.SIGTERM))
        time.sleep(0.005)


def _abandon(cluster, instances) -> None:
    """Let a cluster whose start was interrupted close in the background, without dask's
    exit handler waiting for it (it waits for every worker to finish starting, then for it
    to stop: 1-1.6 s, up to its 10 s limit). Its worker processes were killed before
    (:func:`open_client`)."""
    import threading

    with contextlib.suppress(Exception):
        instances.discard(cluster)
    quiet = _quiet_logs()
    quiet.__enter__()
    threading.Thread(target=_close_quietly, args=(cluster, quiet), daemon=True,
                     name="pdamper-abandoned-cluster").start()


def _close_quietly(cluster, quiet) -> None:
    try:
        with contextlib.suppress(BaseException):
            cluster.close(timeout=10)
    finally:
        quiet.__exit__(None, None, None)


@contextlib.contextmanager
def _quiet_logs() -> Iterator[None]:
    """dask's complaints while a cluster is torn down after an interrupt or an error
    ("Couldn't gather keys" of a scheduler whose workers were just killed) are no news to
    whoever stopped it: only critical ones are logged meanwhile."""
    log = logging.getLogger("distributed")
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        log.setLevel(level)


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
    free port); the local cluster is shut down on exit, at once when the block raised (an
    interrupt, an error).
    """
    if workers is not None and (isinstance(workers, bool) or int(workers) != workers
                                or workers < 1):
        raise InputError("workers", f"must be a whole number >= 1, got {workers!r}")
    if workers is not None and scheduler is not None:
        raise InputError("workers", "give either the worker count of a local cluster or "
                         "--scheduler, not both")
    from distributed import Client, LocalCluster

    if scheduler is not None:
        check_scheduler(scheduler)
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError, TypeError, OverflowError) as exc:
            raise InputError("scheduler", f"cannot connect to {scheduler!r}: {exc}") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = default_workers() if workers is None else int(workers)
    logger.info("starting a local dask cluster of %d worker processes", n)
    from distributed.deploy.spec import SpecCluster

    # the clusters of this process (dask's own record, which its exit handler closes, slowly)
    instances = getattr(SpecCluster, "_instances", ())
    before = set(instances)
    children = set(multiprocessing.active_children())
    pids = _child_pids()
    try:
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address="127.0.0.1:0",
                               silence_logs=logging.ERROR)
    except BaseException:
        # worker processes still reading their start-up data from this one would print
        # the traceback of its loss once this process has ended (its exit handlers unlink
        # the semaphores they unpickle): they are killed first, silently
        _kill(set(multiprocessing.active_children()) - children)
        for half in set(instances) - before:
            _abandon(half, instances)
        _kill_late(pids)
        raise
    quiet = contextlib.ExitStack()
    with quiet, cluster, Client(cluster) as client:
        try:
            yield client
        except BaseException:
            quiet.enter_context(_quiet_logs())  # until the cluster is closed
            _stop_workers(cluster)
            _kill(set(multiprocessing.active_children()) - children)  # any still starting
            _kill_late(pids)
            raise
