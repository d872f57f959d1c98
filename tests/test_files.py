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
