"""pdamper installed for real (issue 11): a wheel installed read-only and run by an
unprivileged user without a writable home runs the DEM (numba's cache falls back to a
per-user directory, :mod:`pdamper._numba_cache`)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from pdamper import _numba_cache
from proc import SRC, unprivileged_prefix


def test_cache_left_alone_when_the_user_chose_one(tmp_path):
    env = {"NUMBA_CACHE_DIR": "/somewhere", "HOME": str(tmp_path)}
    assert _numba_cache.configure(env, package=tmp_path / "missing") is None
    assert env["NUMBA_CACHE_DIR"] == "/somewhere"


def test_cache_left_alone_when_the_package_is_writable(tmp_path):
    env = {"HOME": str(tmp_path)}
    assert _numba_cache.configure(env, package=tmp_path) is None
    assert "NUMBA_CACHE_DIR" not in env


def test_read_only_package_caches_in_the_users_cache(tmp_path, monkeypatch):
    monkeypatch.setattr(_numba_cache, "_in_tree_writable", lambda package: False)
    env = {"HOME": str(tmp_path / "home")}
    got = _numba_cache.configure(env, package=tmp_path)
    assert got == tmp_path / "home" / ".cache" / "pdamper" / "numba"
    assert env["NUMBA_CACHE_DIR"] == str(got) and got.is_dir()
    env = {"HOME": str(tmp_path / "home"), "XDG_CACHE_HOME": str(tmp_path / "xdg")}
    assert _numba_cache.configure(env, package=tmp_path) == tmp_path / "xdg" / "pdamper" / "numba"


def test_no_home_falls_back_to_a_private_temporary_directory(tmp_path, monkeypatch):
    monkeypatch.setattr(_numba_cache, "_in_tree_writable", lambda package: False)
    monkeypatch.setattr(_numba_cache.tempfile, "gettempdir", lambda: str(tmp_path))
    blocked = tmp_path / "file"
    blocked.write_text("not a directory")
    env = {"HOME": str(blocked)}  # ~/.cache cannot be made
    got = _numba_cache.configure(env, package=tmp_path)
    assert got is not None and got.parent == tmp_path and got.name.startswith("pdamper-numba")
    assert (got.stat().st_mode & 0o777) == 0o700


def _run(cmd, **kw):
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=900, **kw)
    assert p.returncode == 0, f"{cmd}\n{p.stdout[-2000:]}\n{p.stderr[-4000:]}"
    return p


@pytest.mark.slow
def test_wheel_installed_read_only_runs_the_dem_as_an_unprivileged_user():
    """Non-editable install (a wheel, ``pip install --target``), every file read-only, run
    by an unprivileged user whose home is not writable: ``pdamper dem`` and ``simulate
    --model dem`` used to crash at import ("cannot cache function 'cor_at': no locator
    available"). Reduced: 4 spheres, one cycle, the Verlet kernel only."""
    root = SRC.parent
    if not (root / "pyproject.toml").is_file():
        pytest.skip("not run from a source tree")
    prefix = unprivileged_prefix()  # None: root, and no other user can run this Python
    # a directory other users can reach (pytest's are private to root); removed below
    base = Path(tempfile.mkdtemp(prefix="pdamper-install-"))
    base.chmod(0o755)
    try:
        _install_and_run(root, base, prefix, prefix is not None)
    finally:
        for path in [base, *base.rglob("*")]:
            if not path.is_symlink():
                path.chmod(0o755 if path.is_dir() else 0o644)
        shutil.rmtree(base, ignore_errors=True)


def _install_and_run(root: Path, base: Path, prefix, unprivileged: bool) -> None:
    wheels, site, work, source = (base / n for n in ("wheels", "site", "work", "source"))
    work.mkdir()
    work.chmod(0o777)  # the outputs and the numba cache of the other user
    # build from a copy: setuptools leaves build/ and *.egg-info beside the sources
    shutil.copytree(root / "src", source / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(root / name, source / name)
    build = [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(wheels)]
    offline = subprocess.run([*build, "--no-build-isolation", str(source)], capture_output=True)
    if offline.returncode != 0:  # no setuptools/wheel here: an isolated build fetches them
        _run([*build, str(source)])
    wheel = next(wheels.glob("pdamper-*.whl"))
    _run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(site),
          str(wheel)])
    for path in [site, *site.rglob("*")]:  # read-only, for everyone
        if not path.is_symlink():
            path.chmod(0o555 if path.is_dir() else 0o444)
    scenario = work / "verlet.toml"
    scenario.write_text('[dem]\nintegrator = "verlet"\n')
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "NUMBA_CACHE_DIR", "XDG_CACHE_HOME")}
    env.update(PYTHONPATH=str(site), HOME=str(site), TMPDIR=str(work), MPLBACKEND="Agg")
    prefix = prefix or []
    run = [*prefix, sys.executable, "-m", "pdamper"]
    try:
        dem = _run([*run, "dem", "--particles", "4", "--cycles", "1", "--skip-cycles", "0",
                    "--scenario", str(scenario), "--out", str(work / "dem.nc"), "--json"],
                   env=env, cwd=work)
        sim = _run([*run, "simulate", "--model", "dem", "--particles", "4", "--duration",
                    "0.05s", "--scenario", str(scenario), "--json"], env=env, cwd=work)
        where = _run([*prefix, sys.executable, "-c", "import pdamper, os; "
                      "print(pdamper.__file__); print(os.environ.get('NUMBA_CACHE_DIR'))"],
                     env=env, cwd=work).stdout.split()
    finally:
        for path in [site, *site.rglob("*")]:
            if not path.is_symlink():
                path.chmod(0o755 if path.is_dir() else 0o644)
    assert Path(where[0]).is_relative_to(site), "ran the installed wheel, not the sources"
    assert json.loads(dem.stdout)["steps"] > 0 and (work / "dem.nc").is_file()
    assert json.loads(sim.stdout)["peaks"]
    if not unprivileged:
        pytest.skip("ran the read-only install as root (no unprivileged user can run this "
                    "Python here): numba's fallback cache is not exercised")
    assert Path(where[1]).is_relative_to(work)  # HOME is read-only: a private temp dir
    assert list(Path(where[1]).rglob("*.nbi")), "nothing cached"
    assert not list(site.rglob("*.nbi")), "numba wrote into the installation"
