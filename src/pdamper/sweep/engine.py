"""Run a point function over many points on dask.distributed, resumably.

:func:`run_sweep` evaluates ``function(params)`` for every ``params`` of ``points``: on a
local cluster of every core (default), on ``workers`` processes, on an existing cluster
(``scheduler``, or a ``client`` the caller holds), or in this process (``serial``). Each
finished point is written to the ``store`` directory as it completes
(:class:`~pdamper.sweep.store.PointStore`), so a sweep stopped at any moment and started
again computes only the points without a record and ends with the same values. A point
that raises is tried again (``retries`` times, where ``retry_if(exception)`` allows), then
recorded as failed with its error; a failed point never ends the sweep and is never
dropped. A worker process that dies is replaced by the cluster and its point rescheduled.
"""

from __future__ import annotations

import json
import logging
import math
import pickle
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pdamper.errors import InputError
from pdamper.sweep.store import PointStore, plain, point_key

logger = logging.getLogger(__name__)

#: Status codes of a point (stored in result files as ``status``).
OK = "ok"
FAILED = "failed"
STATUS_CODES = {OK: 0, FAILED: 1}


@dataclass(frozen=True)
class PointResult:
    """The outcome of one point.

    Attributes
    ----------
    index
        Position in the sweep's ``points``.
    params
        The point's parameters.
    key
        Its store key (:func:`~pdamper.sweep.store.point_key`).
    status
        ``"ok"`` or ``"failed"``.
    values
        What the point function returned (plain JSON values; empty when failed).
    error
        ``"ExceptionType: message"`` of the last attempt of a failed point, else ``""``.
    attempts
        How often the point was tried (in the run that computed it).
    seconds
        Wall time of the successful (or last) attempt [s].
    reused
        Loaded from the store instead of computed in this run.
    """

    index: int
    params: dict
    key: str
    status: str
    values: dict
    error: str = ""
    attempts: int = 1
    seconds: float = math.nan
    reused: bool = False

    @property
    def ok(self) -> bool:
        return self.status == OK


@dataclass
class SweepResult:
    """Every point of a sweep, in the order of its ``points``."""

    points: list[PointResult]
    seconds: float = math.nan
    workers: int = 0
    attrs: dict = field(default_factory=dict)

    @property
    def computed(self) -> int:
        """Points computed in this run."""
        return sum(not p.reused for p in self.points)

    @property
    def reused(self) -> int:
        """Points loaded from the store."""
        return sum(p.reused for p in self.points)

    @property
    def failed(self) -> int:
        return sum(not p.ok for p in self.points)

    def status_codes(self) -> np.ndarray:
        """0 (ok) / 1 (failed) per point."""
        return np.array([STATUS_CODES[p.status] for p in self.points], np.int8)

    def values(self, name: str, fill: Any = math.nan) -> np.ndarray:
        """The value ``name`` of every point (``fill`` where absent, e.g. failed)."""
        return np.array([p.values.get(name, fill) for p in self.points])

    def errors(self) -> list[str]:
        return [p.error for p in self.points]


def _attempt(function, params):
    """One call of the point function (runs on a worker): ``(True, values, seconds)``, or
    ``(False, exception, seconds)`` when it raised (returned, not raised: the worker logs
    no traceback for an expected failure, and the client decides about a retry)."""
    t0 = time.perf_counter()
    try:
        values = function(dict(params))
        if not isinstance(values, Mapping):
            raise TypeError(f"the point function must return a dict, got "
                            f"{type(values).__name__}")
        # one JSON round trip: a computed point equals the same point loaded from the store
        values = json.loads(json.dumps(plain(values), allow_nan=True))
    except Exception as exc:
        try:
            pickle.dumps(exc)
        except Exception:
            exc = RuntimeError(_error_text(exc))
        return False, exc, time.perf_counter() - t0
    return True, values, time.perf_counter() - t0


def _error_text(exc: BaseException) -> str:
    text = f"{type(exc).__name__}: {exc}".strip()
    return text.splitlines()[0][:2000] if text else type(exc).__name__


def _always(_exc: BaseException) -> bool:
    return True


class _Recorder:
    """Collects point results, writes each to the store at once, reports progress."""

    def __init__(self, n: int, store: PointStore | None, context: Mapping, progress):
        self.results: list[PointResult | None] = [None] * n
        self.store = store
        self.context = plain(dict(context))
        self.progress = progress
        self.done = 0
        self.total = n

    def record(self, pr: PointResult) -> None:
        if self.store is not None and not pr.reused:
            from pdamper import __version__

            self.store.save({"key": pr.key, "index": pr.index, "params": pr.params,
                             "status": pr.status, "values": pr.values, "error": pr.error,
                             "attempts": pr.attempts, "seconds": pr.seconds,
                             "pdamper_version": __version__})
        self.results[pr.index] = pr
        self.done += 1
        if self.progress is not None:
            self.progress(self.done, self.total, pr)


def run_sweep(function: Callable[[dict], Mapping], points: Sequence[Mapping], *,
              store: str | Path | PointStore | None = None, context: Mapping | None = None,
              retries: int = 1, retry_if: Callable[[BaseException], bool] | None = None,
              retry_failed: bool = False, client=None, workers: int | None = None,
              scheduler: str | None = None, serial: bool = False,
              progress: Callable[[int, int, PointResult], None] | None = None) -> SweepResult:
    """Evaluate ``function(params)`` at every point, storing each result as it finishes.

    Parameters
    ----------
    function
        Picklable callable ``params -> dict`` of numbers / strings / lists (a module-level
        function or a ``functools.partial`` of one, e.g. with a damper model bound).
    points
        The points' parameters, JSON-able mappings (e.g. ``{"frequency": 10.0, ...}``).
    store
        Directory for per-point results (None: nothing stored, no resume).
    context
        JSON-able inputs shared by every point (model inputs, version, seeds): part of each
        point's key, so a changed input never reuses a stored result.
    retries
        Further attempts of a point that raised, where ``retry_if(exception)`` (default:
        always) allows.
    retry_failed
        Compute points again that an earlier run recorded as failed (default: keep them).
    client
        A ``distributed.Client`` to run on (kept open); else ``scheduler`` (address of an
        existing cluster), else a local cluster of ``workers`` processes (default: every
        core), else with ``serial`` in this process.
    progress
        Called as ``progress(done, total, point_result)`` after every point (stored points
        first).

    Returns
    -------
    SweepResult

    Examples
    --------
    >>> import math, functools
    >>> r = run_sweep(functools.partial(dict, kind="demo"), [{"x": 1.0}, {"x": 2.0}], serial=True)
    >>> [p.values for p in r.points], r.computed
    ([{'x': 1.0, 'kind': 'demo'}, {'x': 2.0, 'kind': 'demo'}], 2)
    """
    if isinstance(retries, bool) or int(retries) != retries or retries < 0:
        raise InputError("retries", f"must be a whole number >= 0, got {retries!r}")
    retry_if = retry_if or _always
    params = [plain(dict(p)) for p in points]
    context = dict(context or {})
    keys = [point_key(function, context, p) for p in params]
    st = None if store is None else (store if isinstance(store, PointStore) else PointStore(store))
    rec = _Recorder(len(params), st, context, progress)
    t0 = time.perf_counter()
    stored = st.load_all() if st is not None else {}
    todo = []
    for i, (p, k) in enumerate(zip(params, keys, strict=True)):
        old = stored.get(k)
        if old is not None and (old.get("status") == OK or not retry_failed):
            rec.record(PointResult(i, p, k, old.get("status", FAILED), old.get("values") or {},
                                   old.get("error", ""), int(old.get("attempts", 1)),
                                   float(old.get("seconds", math.nan)), reused=True))
        else:
            todo.append(i)
    logger.info("sweep: %d points, %d from the store, %d to compute", len(params),
                len(params) - len(todo), len(todo))
    nworkers = 1
    if todo:
        if serial and client is None:
            _run_serial(function, params, keys, todo, retries, retry_if, rec)
        elif client is not None:
            nworkers = _run_dask(client, function, params, keys, todo, retries, retry_if, rec)
        else:
            from pdamper.sweep.cluster import open_client

            with open_client(workers, scheduler) as c:
                nworkers = _run_dask(c, function, params, keys, todo, retries, retry_if, rec)
    results = [r for r in rec.results if r is not None]
    if len(results) != len(params):  # pragma: no cover - every path records every point
        raise RuntimeError("sweep ended with unrecorded points")
    return SweepResult(results, time.perf_counter() - t0, nworkers,
                       {"retries": retries, "store": None if st is None else str(st.directory)})


def _run_serial(function, params, keys, todo, retries, retry_if, rec: _Recorder) -> None:
    for i in todo:
        attempt = 0
        while True:
            attempt += 1
            ok, out, secs = _attempt(function, params[i])
            if ok:
                rec.record(PointResult(i, params[i], keys[i], OK, out, "", attempt, secs))
                break
            if attempt <= retries and retry_if(out):
                logger.info("point %d failed (%s); retrying", i, _error_text(out))
                continue
            # a failed point is recorded, never ends the sweep
            rec.record(PointResult(i, params[i], keys[i], FAILED, {}, _error_text(out),
                                   attempt, secs))
            break


def _run_dask(client, function, params, keys, todo, retries, retry_if, rec: _Recorder) -> int:
    from distributed import as_completed

    def submit(i: int, attempt: int):
        fut = client.submit(_attempt, function, params[i], pure=False,
                            key=f"pdamper-point-{keys[i]}-{i}-{attempt}")
        meta[fut.key] = (i, attempt)
        return fut

    meta: dict[str, tuple[int, int]] = {}
    nworkers = len(client.scheduler_info().get("workers", {})) or 1
    started = {}
    pending = as_completed([submit(i, 1) for i in todo])
    for i in todo:
        started[i] = time.perf_counter()
    for fut in pending:
        i, attempt = meta.pop(fut.key)
        if fut.status == "finished":
            ok, out, secs = fut.result()
        else:  # the task itself failed: e.g. its worker died too often (KilledWorker)
            try:
                out = fut.exception()
            except Exception as err:  # pragma: no cover - cancelled or lost futures
                out = err
            ok, secs = False, time.perf_counter() - started[i]
        fut.release()
        if ok:
            rec.record(PointResult(i, params[i], keys[i], OK, out, "", attempt, secs))
        elif attempt <= retries and retry_if(out):
            logger.info("point %d failed (%s); retrying", i, _error_text(out))
            pending.add(submit(i, attempt + 1))
        else:
            rec.record(PointResult(i, params[i], keys[i], FAILED, {}, _error_text(out),
                                   attempt, secs))
    return nworkers
