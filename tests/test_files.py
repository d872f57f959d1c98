"""The one atomic writer (:mod:`pdamper.files`)."""

from __future__ import annotations

import os
import stat

import pytest

from pdamper.files import atomic_write, atomic_write_text


def test_writes_and_replaces_with_normal_permissions(tmp_path):
    p = tmp_path / "out.txt"
    atomic_write_text(p, "one")
    atomic_write_text(p, "two")
    assert p.read_text() == "two"
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(p.stat().st_mode) == 0o666 & ~mask
    assert [q.name for q in tmp_path.iterdir()] == ["out.txt"]


def test_failed_writer_leaves_the_old_file_and_no_temporary(tmp_path):
    p = tmp_path / "out.nc"
    atomic_write_text(p, "complete")

    def broken(path):
        path.write_text("half")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        atomic_write(p, broken)
    assert p.read_text() == "complete"
    assert [q.name for q in tmp_path.iterdir()] == ["out.nc"]


def test_a_signal_during_the_writer_is_raised_after_it_and_removes_the_temporary(tmp_path):
    """A signal handler raising inside the HDF5 library was sometimes swallowed there (the
    command went on); the writer holds it until it returns, then the interrupt raises, the
    temporary goes and the earlier file stays."""
    import signal

    from pdamper.cli._signals import raising_interrupts
    from pdamper.errors import Interrupted

    p = tmp_path / "out.nc"
    atomic_write_text(p, "complete")
    seen = []

    def writer(path):
        path.write_text("new")
        os.kill(os.getpid(), signal.SIGTERM)
        seen.append("the writer ran to its end")

    with pytest.raises(Interrupted) as info, raising_interrupts():
        atomic_write(p, writer)
    assert info.value.signum == signal.SIGTERM
    assert seen == ["the writer ran to its end"]
    assert p.read_text() == "complete"
    assert [q.name for q in tmp_path.iterdir()] == ["out.nc"]


def test_signals_deferred_restores_the_handlers_and_leaves_default_ones_alone():
    import signal

    from pdamper.files import signals_deferred

    before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        def mine(_signum, _frame):
            pass

        signal.signal(signal.SIGINT, mine)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        with signals_deferred():
            assert signal.getsignal(signal.SIGINT) is not mine  # held
            assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL  # left alone
        assert signal.getsignal(signal.SIGINT) is mine
        assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
    finally:
        for s, h in before.items():
            signal.signal(s, h)


def test_a_full_device_is_one_output_error_and_leaves_the_old_file(tmp_path, monkeypatch):
    """The bytes of every file are written by ``os.write`` calls whose counts are checked
    (a NetCDF file is made by HDF5 in memory first): a full device is an OutputError of one
    line naming the option and the size, the old file stays and no temporary is left.
    (Where a tmpfs can be mounted, tests/cli/test_outputs.py fills a real one.)"""
    import errno

    import xarray as xr

    from pdamper import files
    from pdamper.errors import OutputError

    p = tmp_path / "map.nc"
    atomic_write_text(p, "complete")
    real = os.write

    def fills_up(fd, view):
        if fd <= 2:
            return real(fd, view)
        n = real(fd, bytes(view[:1000]))  # a short write, then nothing fits
        monkeypatch.setattr(files.os, "write", full)
        return n

    def full(fd, view):
        if fd <= 2:
            return real(fd, view)
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(files.os, "write", fills_up)
    ds = xr.Dataset({"loss_factor": (("frequency",), [0.1, 0.2])},
                    attrs={"note": "two\nlines"})
    with pytest.raises(OutputError) as info:
        files.atomic_write_netcdf(p, ds, "out")
    message = str(info.value)
    assert message.startswith(f"out: cannot write {p}: No space left on device (writing ")
    assert "\n" not in message
    assert p.read_text() == "complete"
    assert [q.name for q in tmp_path.iterdir()] == ["map.nc"]


def test_netcdf_made_in_memory_reads_back(tmp_path):
    import numpy as np
    import xarray as xr

    from pdamper.files import atomic_write_netcdf

    ds = xr.Dataset({"x": (("i", "j"), np.arange(6.0).reshape(2, 3))},
                    coords={"i": [1.0, 2.0]}, attrs={"inputs": '{"a": 1}'})
    p = atomic_write_netcdf(tmp_path / "a.nc", ds)
    back = xr.load_dataset(p, engine="h5netcdf")
    xr.testing.assert_identical(back, ds)


def test_an_interrupt_just_after_the_staging_directory_is_made_leaves_nothing(tmp_path,
                                                                              monkeypatch):
    """``atomic_directory``: a signal that arrives once the staging directory exists but
    before the block runs (``pdamper paper`` interrupted at its start on a loaded machine)
    used to leave the empty ``.results.*.tmp`` behind."""
    import signal
    import tempfile

    from pdamper import files

    made = tempfile.mkdtemp

    def mkdtemp_then_signal(*args, **kw):
        path = made(*args, **kw)
        os.kill(os.getpid(), signal.SIGINT)  # the handler runs before mkdtemp returns
        return path

    monkeypatch.setattr(files.tempfile, "mkdtemp", mkdtemp_then_signal)
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            with files.atomic_directory(tmp_path / "results"):
                pytest.fail("the block ran despite the interrupt")
    finally:
        signal.signal(signal.SIGINT, old)
    assert list(tmp_path.iterdir()) == []
