"""Resumable parameter sweeps on dask.distributed (effective-field maps, design studies).

Generic: a picklable point function, a list of points, a store directory::

    from pdamper.sweep import run_sweep

    def point(params):                       # module level: it travels to the workers
        return {"y": params["x"] ** 2}

    result = run_sweep(point, [{"x": x} for x in range(100)], store="squares.partial",
                       context={"version": 1}, workers=4)
    result.values("y"), result.status_codes(), result.computed, result.reused

Each finished point is written to the store at once (atomically); run the same sweep again
and only the points without a record are computed. Failed points are retried
(``retries``), then recorded with their error. See :func:`run_sweep` and docs/fields.md.
dask.distributed is imported only when a sweep runs on it.
"""

from pdamper.sweep.engine import (
    FAILED,
    OK,
    STATUS_CODES,
    PointResult,
    SweepResult,
    run_sweep,
)
from pdamper.sweep.store import PointStore, point_key

__all__ = ["FAILED", "OK", "STATUS_CODES", "PointResult", "PointStore", "SweepResult",
           "point_key", "run_sweep"]
