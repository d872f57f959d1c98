"""Outputs into a directory that is a mount point (a device of its own, the usual container
set-up): a rename across devices fails (EXDEV), so the staging files are made where they
are renamed to. Simulated: every rename between the "mounted" directory and the outside
fails as the kernel's does."""

from __future__ import annotations

import errno
import json
import os
from pathlib import Path

import pytest

from pdamper.files import atomic_directory, atomic_write_text


@pytest.fixture
def mounted(tmp_path, monkeypatch):
    """``tmp_path / "mnt"``, an existing directory that renames treat as another device."""
    mnt = (tmp_path / "mnt").absolute()
    mnt.mkdir()

    def inside(p) -> bool:
        p = Path(p).absolute()
        return p == mnt or mnt in p.parents

    for name in ("rename", "replace"):
        real = getattr(os, name)

        def cross(src, dst, *args, _real=real, **kwargs):
            if inside(src) != inside(dst):
                raise OSError(errno.EXDEV, "Invalid cross-device link")
            return _real(src, dst, *args, **kwargs)

        monkeypatch.setattr(os, name, cross)
    return mnt


def test_the_simulated_mount_refuses_a_rename_across(mounted, tmp_path):
    (tmp_path / "a").write_text("x")
    with pytest.raises(OSError) as info:
        os.replace(tmp_path / "a", mounted / "a")
    assert info.value.errno == errno.EXDEV


def test_atomic_directory_into_a_mount_point(mounted):
    (mounted / "keep.txt").write_text("an earlier file")
    with atomic_directory(mounted) as stage:
        atomic_write_text(stage / "report.html", "<html></html>")
    assert sorted(p.name for p in mounted.iterdir()) == ["keep.txt", "report.html"]
    assert (mounted / "report.html").read_text() == "<html></html>"


def test_atomic_directory_new_directory_on_a_mount_point(mounted):
    with atomic_directory(mounted / "results") as stage:
        atomic_write_text(stage / "table.md", "| a |")
    assert (mounted / "results" / "table.md").read_text() == "| a |"
    assert [p.name for p in mounted.iterdir()] == ["results"]


def test_report_into_a_mount_point(cli, mounted):
    code, out, err = cli("report", "--out", mounted, "--json")
    assert code == 0, err
    assert sorted(p.name for p in mounted.iterdir()) == ["report.html", "results.json"]
    assert json.loads((mounted / "results.json").read_text())["design_study"]["best"]


def test_map_uncertainty_writes_the_file_once_with_its_bands(cli, tmp_path, monkeypatch):
    """A failed sampling leaves no map without its bands: the file is written once, at
    the end."""
    import pdamper.runs.uncertainty as uncertain

    out = tmp_path / "map.nc"

    def fails(*_a, **_k):
        raise RuntimeError("the sampling died")

    monkeypatch.setattr(uncertain, "propagate_scenario", fails)
    with pytest.raises(RuntimeError):
        cli("map", "--frequency", "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2", "--uncertain",
            "particles.friction=0.1+-0.03", "--uncertainty", "4", "--out", out)
    assert not out.exists()
    monkeypatch.undo()
    code, _, err = cli("map", "--frequency", "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2",
                       "--uncertain", "particles.friction=0.1+-0.03", "--uncertainty", "4",
                       "--out", out, "--json")
    assert code == 0, err
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert "loss_factor_mean" in ds and "loss_factor_p95" in ds
