"""Resume on dask.distributed: a sweep killed half-way (the whole process, and separately
one worker) computes only the missing points when started again and ends identical to an
uninterrupted one."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
from functools import partial
from pathlib import Path

import pytest
from sweep_points import calls, point, points

from pdamper.sweep import PointStore, run_sweep

HERE = Path(__file__).parent
N = 24


def _same(a, b) -> bool:
    return a.keys() == b.keys() and all(
        (isinstance(a[k], float) and math.isnan(a[k]) and math.isnan(b[k])) or a[k] == b[k]
        for k in a)


@pytest.fixture(scope="module")
def reference():
    """The uninterrupted sweep (in this process: the values do not depend on where)."""
    return run_sweep(point, points(N), context={"test": "resume"}, serial=True)


def test_killed_sweep_process_resumes_with_only_the_missing_points(tmp_path, reference):
    store, log = tmp_path / "store", tmp_path / "calls"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(HERE), *os.environ.get("PYTHONPATH", "").split(os.pathsep)])}
    proc = subprocess.Popen([sys.executable, str(HERE / "sweep_points.py"), str(store), str(N),
                             str(log)], env=env, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while len(PointStore(store)) < N // 3 and proc.poll() is None:
            assert time.monotonic() < deadline, "the sweep made no progress"
            time.sleep(0.05)
    finally:  # the sweep, its scheduler and its workers: the process group we started
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    done = len(PointStore(store))
    assert N // 3 <= done < N, "killed half-way"
    before = len(calls(log))
    r = run_sweep(partial(point, log=str(log)), points(N), store=store,
                  context={"test": "resume"}, workers=2)
    assert r.reused == done and r.computed == N - done
    assert len(calls(log)) - before == N - done  # only the missing points ran
    stored = {p.index for p in r.points if p.reused}
    assert not stored & set(calls(log)[before:])
    for a, b in zip(r.points, reference.points, strict=True):
        assert a.status == b.status == "ok" and _same(a.values, b.values)


def test_killed_worker_loses_no_point(tmp_path, reference):
    """A worker process dies in the middle of point 5: the cluster replaces it, the point
    runs again, and the sweep ends with every point, equal to the uninterrupted one."""
    log, marker = tmp_path / "calls", tmp_path / "killed"
    r = run_sweep(partial(point, log=str(log), sleep=0.05, kill_marker=str(marker), kill_at=5),
                  points(N), store=tmp_path / "store", context={"test": "resume"}, workers=2)
    assert marker.exists()  # the worker was killed
    seen = calls(log)
    assert seen.count(5) == 2 and sorted(set(seen)) == list(range(N))
    assert r.failed == 0 and r.computed == N and len(PointStore(tmp_path / "store")) == N
    for a, b in zip(r.points, reference.points, strict=True):
        assert _same(a.values, b.values)


def test_existing_cluster_by_scheduler_address(tmp_path, reference):
    """--scheduler ADDRESS: the sweep runs on a cluster it did not start and leaves it up."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, protocol="tcp",
                      host="127.0.0.1",
                      dashboard_address="127.0.0.1:0") as cluster:
        r = run_sweep(point, points(6), context={"test": "resume"},
                      scheduler=cluster.scheduler_address)
        with Client(cluster.scheduler_address) as c:  # still running
            assert len(c.scheduler_info()["workers"]) == 1
    assert r.computed == 6 and r.workers == 1
    for a, b in zip(r.points, reference.points[:6], strict=True):
        assert _same(a.values, b.values)
