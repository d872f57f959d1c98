"""Stopping a local cluster at once (an interrupted or failed sweep)."""

import logging
import multiprocessing

import pytest

pytest.importorskip("distributed")


class _Said(logging.Handler):
    def __init__(self):
        super().__init__(logging.DEBUG)
        self.said: list[str] = []

    def emit(self, record):
        self.said.append(record.getMessage())


def test_stopped_workers_are_not_restarted():
    """A nanny still running when its worker process dies starts a new one (with new
    queues, whose semaphores the resource tracker reports as leaked if this process ends
    before they are released): each nanny is marked closing before its worker is killed,
    and no worker process is left or started."""
    from distributed import LocalCluster

    from pdamper.sweep.cluster import _stop_workers

    said = _Said()
    log = logging.getLogger("distributed.nanny")
    level = log.level
    log.setLevel(logging.INFO)
    log.addHandler(said)
    before = set(multiprocessing.active_children())
    try:
        with LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                          host="127.0.0.1", dashboard_address=None) as cluster:
            started = set(multiprocessing.active_children()) - before
            assert len(started) == 1
            _stop_workers(cluster)
            left = set(multiprocessing.active_children()) - before
            assert not [m for m in said.said if "Restarting worker" in m], said.said
            assert not left, left
    finally:
        log.removeHandler(said)
        log.setLevel(level)


def test_a_child_process_that_appears_after_the_stop_is_killed():
    """A worker whose spawn was in flight in one of dask's threads when a sweep stopped
    appears after the kill: it is killed as it appears (else it outlives pdamper and
    prints the traceback of its lost start-up data); the children there before are left."""
    import signal
    import subprocess
    import sys
    import threading
    import time

    from pdamper.sweep.cluster import _child_pids, _kill_late

    sleep = [sys.executable, "-c", "import time; time.sleep(30)"]
    old = subprocess.Popen(sleep)
    try:
        before = _child_pids()
        late: list[subprocess.Popen] = []

        def spawn_later():
            time.sleep(0.03)
            late.append(subprocess.Popen(sleep))

        t = threading.Thread(target=spawn_later)
        t.start()
        _kill_late(before)
        t.join()
        assert late and late[0].wait(timeout=5) == -signal.SIGKILL
        assert old.poll() is None
    finally:
        old.kill()
        old.wait()
