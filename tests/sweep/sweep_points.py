"""Cheap point functions for the sweep tests (importable by the dask worker processes).

Side channels (a log of the calls, a worker to kill) are bound with ``functools.partial``
and are not part of a point's key: the same points keep the same keys in every run.
"""

from __future__ import annotations

import math
import os
import signal
import sys
import time
from functools import partial
from pathlib import Path


def value_of(params: dict) -> dict:
    """A deterministic, non-trivial result of a point."""
    x = params["x"]
    return {"y": math.sin(x) * math.exp(-0.1 * x), "x2": x * x, "label": f"p{x:g}",
            "nan": math.nan if x == 3 else 0.0}


def point(params: dict, log: str | None = None, sleep: float = 0.0, fail_at=(),
          kill_marker: str | None = None, kill_at: int = -1) -> dict:
    """Log the call, sleep, maybe fail or kill this worker once, return :func:`value_of`."""
    if log:
        with open(log, "a") as fh:  # O_APPEND: one short line per call, atomic
            fh.write(f"{params['i']}\n")
    if kill_marker and params["i"] == kill_at and not os.path.exists(kill_marker):
        Path(kill_marker).write_text("killed")
        os.kill(os.getpid(), signal.SIGKILL)  # this worker process dies mid-point
    time.sleep(sleep)
    if params["i"] in fail_at:
        raise ValueError(f"point {params['i']} cannot be computed")
    return value_of(params)


def points(n: int) -> list[dict]:
    return [{"i": i, "x": 0.5 * i} for i in range(n)]


def calls(log: str) -> list[int]:
    p = Path(log)
    return [int(line) for line in p.read_text().split()] if p.exists() else []


if __name__ == "__main__":  # the sweep a test kills: python sweep_points.py STORE N LOG
    import sweep_points as this  # by its module name: the same function name (key) as the tests'

    from pdamper.sweep import run_sweep

    store, n, log = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    run_sweep(partial(this.point, log=log, sleep=0.25), this.points(n), store=store,
              context={"test": "resume"}, workers=2)
