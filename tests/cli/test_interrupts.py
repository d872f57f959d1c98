"""Ctrl-C and SIGTERM: every command ends within a second with one line,
``interrupted``, status 130 (SIGINT) or 143 (SIGTERM), no traceback, no temporary file, an
earlier complete result intact and no empty output directory."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import time

import pytest

from proc import command, env

#: Seconds after the start at which the signal is sent (start-up is ~1.5 s here).
AFTER = 3.0
#: Seconds from the signal to the exit that the test allows (the promise is "a second";
#: the margin is for a loaded 2-core CI machine).
PROMPT = 1.5

_BIG_MAP = ["map", "--frequency", "2Hz:20Hz:100", "--amplitude", "1mm:200mm:100"]


def interrupt(args, sig=signal.SIGINT, after=AFTER, cwd=None, ready=None):
    """Start ``pdamper ARGS``, send ``sig`` after ``after`` s, or as soon as ``ready()`` is
    true (a state of the run, whatever the machine's speed); (status, stderr, seconds)."""
    p = subprocess.Popen(command(*args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=env(), text=True, cwd=cwd)
    try:
        if ready is None:
            time.sleep(after)
        else:
            deadline = time.monotonic() + 60
            while not ready() and time.monotonic() < deadline:
                assert p.poll() is None, f"finished before it was ready: {p.communicate()}"
                time.sleep(0.01)
            assert ready(), "never ready"
        assert p.poll() is None, f"finished before the signal: {p.communicate()}"
        t0 = time.monotonic()
        p.send_signal(sig)
        try:
            _, err = p.communicate(timeout=4 * PROMPT)
        except subprocess.TimeoutExpired:
            pytest.fail(f"still running {4 * PROMPT:g} s after the signal")
        return p.returncode, err, time.monotonic() - t0
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()


def assert_interrupted(status, err, seconds, sig=signal.SIGINT):
    assert err == "interrupted\n", err
    assert status == 128 + sig, status
    assert seconds < PROMPT, f"took {seconds:.2f} s to stop"


def no_temporaries(directory):
    """Hidden files beside the results: the writers' temporaries (a write-permission probe
    of the output check lives for microseconds and is not one of them)."""
    return [p.name for p in directory.rglob("*")
            if p.name.startswith(".") and not p.name.startswith(".pdamper-probe-")]


def _interrupt_map_in_process(cli, monkeypatch, args, sig):
    """Run ``pdamper map ARGS`` in this process and send ``sig`` to it as soon as the field
    is being computed (deterministic, unlike a timed signal); (status, stderr, seconds)."""
    import os
    import threading

    import pdamper.analysis.fields as fields

    started, finished = threading.Event(), threading.Event()
    compute = fields.effective_field

    def effective_field(*a, **kw):
        started.set()
        try:
            return compute(*a, **kw)
        finally:
            finished.set()

    monkeypatch.setattr(fields, "effective_field", effective_field)
    sent: list[float] = []

    def send():
        if not started.wait(20):
            return
        time.sleep(0.05)  # inside the computation (~0.5 s)
        if not finished.is_set():  # never at this process when the handler is gone
            sent.append(time.monotonic())
            os.kill(os.getpid(), sig)

    sender = threading.Thread(target=send, daemon=True)
    sender.start()
    code, _, err = cli(*args)
    done = time.monotonic()
    sender.join(30)
    assert sent, f"the field was not being computed: {code} {err!r}"
    return code, err, done - sent[0]


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_map(tmp_path, cli, monkeypatch, sig):
    assert_interrupted(*_interrupt_map_in_process(
        cli, monkeypatch, [*_BIG_MAP, "--out", tmp_path / "m.nc"], sig), sig)
    assert list(tmp_path.iterdir()) == []


def test_map_keeps_the_earlier_result(tmp_path, cli, monkeypatch):
    out = tmp_path / "m.nc"
    assert cli("map", "--frequency", "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2", "--out",
               out)[0] == 0
    before = out.read_bytes()
    assert_interrupted(*_interrupt_map_in_process(cli, monkeypatch,
                                                  [*_BIG_MAP, "--out", out], signal.SIGINT))
    assert out.read_bytes() == before
    assert no_temporaries(tmp_path) == []


def test_simulate(tmp_path):
    # an undamped structure without particles never comes to rest: every cycle is computed
    # (6000 s of it take about 28 s: the signal at AFTER lands well inside the run)
    scenario = tmp_path.parent / f"{tmp_path.name}-undamped.toml"
    scenario.write_text('[structure]\ndamping = "0 kg/s"\n[particles]\ncount = 0\n')
    assert_interrupted(*interrupt(["simulate", "--scenario", scenario, "--duration", "6000s",
                                   "--out", tmp_path / "s.nc"]))
    assert list(tmp_path.iterdir()) == []


def test_optimize_sigterm():
    sig = signal.SIGTERM
    assert_interrupted(*interrupt(["optimize", "--at", "300s"], sig), sig)


def test_paper_leaves_no_directory(tmp_path):
    """``paper`` used to leave an empty directory behind. The signal comes while the
    results are being made in their temporary directory (``paper --no-dem`` takes ~3.5 s
    on a fast machine: a fixed delay could come after the end)."""
    assert_interrupted(*interrupt(["paper", "--no-dem", "--out", tmp_path / "results"],
                                  ready=lambda: any(tmp_path.glob(".results*"))))
    assert list(tmp_path.iterdir()) == []


#: Seconds the patched writer takes after its file is complete.
_WRITE = 1.0
_SLOW_WRITE = textwrap.dedent(f"""
    import sys, time
    import xarray as xr
    from pdamper.cli import main
    write = xr.Dataset.to_netcdf
    def slow(self, path, **kw):
        write(self, path, **kw)
        open(sys.argv[1], "w").close()  # HDF5 is at work: the test may send its signal
        time.sleep({_WRITE})  # the signal arrives during the write, here or before
    xr.Dataset.to_netcdf = slow
    sys.exit(main(sys.argv[2:]))
""")


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_signal_during_the_write_leaves_no_temporary(tmp_path, sig):
    """A kill during the write used to leave ``.m.nc.tmp``; a signal raised inside the HDF5
    library was sometimes swallowed there (the command went on). The writer holds the
    signal until HDF5 has made the file (in memory), then stops: no temporary, the earlier
    file intact."""
    out = tmp_path / "m.nc"
    out.write_text("earlier")
    mark = tmp_path.parent / f"{tmp_path.name}-writing"
    p = subprocess.Popen([sys.executable, "-c", _SLOW_WRITE, str(mark), "map", "--frequency",
                          "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2", "--out", str(out)],
                         stderr=subprocess.PIPE, stdout=subprocess.PIPE, env=env(), text=True)
    try:
        deadline = time.monotonic() + 60
        while not mark.exists() and time.monotonic() < deadline:
            assert p.poll() is None, p.communicate()
            time.sleep(0.01)
        assert mark.exists(), "the writer never started"
        t0 = time.monotonic()
        p.send_signal(sig)
        try:
            _, err = p.communicate(timeout=_WRITE + 4 * PROMPT)
        except subprocess.TimeoutExpired:
            pytest.fail(f"still running {_WRITE + 4 * PROMPT:g} s after the signal")
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    seconds = time.monotonic() - t0
    assert_interrupted(p.returncode, err, max(0.0, seconds - _WRITE), sig)
    assert sorted(q.name for q in tmp_path.iterdir()) == ["m.nc"]
    assert out.read_text() == "earlier"


def test_dem(tmp_path):
    """The DEM kernel returns to Python often enough for the signal to be noticed (a
    192-sphere, 60-cycle run used to go on for 294 s)."""
    # 8 s: past the start-up and the numba cache load, inside a kernel call
    assert_interrupted(*interrupt(["dem", "--particles", 192, "--cycles", 60, "--out",
                                   tmp_path / "d.nc"], after=8.0))
    assert list(tmp_path.iterdir()) == []


_IN_A_FINALIZER = textwrap.dedent("""
    import os, signal
    from pdamper.cli._signals import raising_interrupts
    from pdamper.errors import Interrupted

    class Finalized:
        def __del__(self):  # the signal lands here, where Python prints and goes on
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(1000):
                pass

    try:
        with raising_interrupts():
            Finalized()
            for _ in range(10**8):
                pass
        print("not interrupted")
    except Interrupted as exc:
        print("interrupted", exc.signum)
""")


def test_a_signal_in_a_finalizer_is_delivered_again():
    """A signal whose exception is raised in a finalizer (a generator closed by the
    garbage collector, a ``__del__``) would be printed as "Exception ignored" and lost."""
    p = subprocess.run([sys.executable, "-c", _IN_A_FINALIZER], capture_output=True,
                       text=True, env=env(), timeout=120)
    assert (p.stdout, p.stderr) == ("interrupted 2\n", "")


#: ``pdamper ARGS`` with an import hook: when ``TARGET`` is first imported, the process
#: sends itself SIGINT and the module's initialisation turns what the signal raised into
#: ``ImportError: initialization failed``, as matplotlib's extension modules (pybind11) do
#: with any error of their initialisation.
_IMPORT_TURNS_THE_SIGNAL_INTO_AN_ERROR = textwrap.dedent("""
    import importlib.abc, importlib.util, os, signal, sys

    TARGET = sys.argv[1]

    class Loader(importlib.abc.Loader):
        def create_module(self, spec):
            return None

        def exec_module(self, module):
            try:
                os.kill(os.getpid(), signal.SIGINT)
                for _ in range(10**6):  # the handler runs here
                    pass
            except BaseException as exc:
                raise ImportError("initialization failed") from exc

    class Finder(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name != TARGET:
                return None
            sys.meta_path.remove(self)
            return importlib.util.spec_from_loader(name, Loader())

    sys.meta_path.insert(0, Finder())
    from pdamper.cli import main
    sys.exit(main(sys.argv[2:]))
""")


@pytest.mark.parametrize(("target", "args"), [
    ("matplotlib.figure", ["cor", "--velocity", "0.5m/s:1m/s:2", "--plot", "{tmp}/c.png"]),
    ("typer", ["analytic"]),
], ids=["cor-plot-matplotlib", "start-up-typer"])
def test_a_signal_during_an_import(tmp_path, target, args):
    """A Ctrl-C landing in ``import matplotlib`` (``cor --plot``) ended with
    ``ImportError: initialization failed`` and status 1: the signal is recorded before its
    exception is raised, so that whatever a library makes of it the command is
    interrupted. The command line's own imports (typer) come after its handlers."""
    p = subprocess.run([sys.executable, "-c", _IMPORT_TURNS_THE_SIGNAL_INTO_AN_ERROR, target,
                        *[a.replace("{tmp}", str(tmp_path)) for a in args]],
                       capture_output=True, text=True, env=env(), timeout=300)
    assert (p.returncode, p.stderr) == (130, "interrupted\n")
    assert list(tmp_path.iterdir()) == []


#: A DEM map on a local cluster of two worker processes whose points take seconds each.
_DEM_MAP = ["map", "--model", "dem", "--workers", 2, "--particles", 16, "--frequency",
            "4Hz:6Hz:2", "--amplitude", "2mm:4mm:3"]


@pytest.mark.parametrize("when", ["starting", "computing"])
def test_dem_map_on_a_local_cluster(tmp_path, when):
    """Ctrl-C into a DEM map on a local cluster took 4.1 s: dask gives a worker busy in a
    task 4 s to finish before it kills it, its exit handler waits for a cluster that is
    still starting, and a signal delivered to one of dask's threads was heard only when
    the main thread's wait ended. The workers are stopped at once and none is left
    behind. ("starting": the worker processes have existed for 0.5 s, past the first
    instants of their start-up, in which a worker whose parent ends prints the traceback
    of its lost start-up data.)"""
    import psutil  # a dependency of dask.distributed

    out = tmp_path / "m.nc"
    partial = tmp_path / "m.nc.partial"
    p = subprocess.Popen(command(*_DEM_MAP, "--out", out), stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, env=env(), text=True)
    try:
        me = psutil.Process(p.pid)
        deadline = time.monotonic() + 120
        born = None
        while time.monotonic() < deadline:
            assert p.poll() is None, f"finished before it was ready: {p.communicate()}"
            workers = me.children(recursive=True)
            points = list(partial.glob("*.json"))
            born = born or (time.monotonic() if workers else None)
            if when == "starting" and born and time.monotonic() - born > 0.5 and not points:
                break  # worker processes are starting; nothing computed yet
            if when == "computing" and points:
                break  # the first point is in: the others are being computed
            time.sleep(0.01)
        else:
            pytest.fail("never ready")
        workers = me.children(recursive=True)
        t0 = time.monotonic()
        p.send_signal(signal.SIGINT)
        try:
            _, err = p.communicate(timeout=4 * PROMPT)
        except subprocess.TimeoutExpired:
            pytest.fail(f"still running {4 * PROMPT:g} s after the signal")
        seconds = time.monotonic() - t0
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    # warnings of the DEM runs may come first; the end is one line
    assert p.returncode == 130 and err.endswith("interrupted\n"), err
    assert "Traceback" not in err and "distributed." not in err, err
    assert seconds < PROMPT, f"took {seconds:.2f} s to stop"
    assert not out.exists()
    _, alive = psutil.wait_procs(workers, timeout=10)
    assert not alive, f"worker processes left behind: {alive}"
