"""pdamper installed for real: a wheel installed read-only and run by an
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


def _kernel_package(root: Path) -> Path:
    """A package with a numba kernel, a helper it inlines from another file, and a cache
    beside them."""
    pkg = root / "pkg"
    (pkg / "sub" / "__pycache__").mkdir(parents=True)
    (pkg / "__pycache__").mkdir()
    (pkg / "sub" / "kernel.py").write_text("from numba import njit\n@njit(cache=True)\n"
                                           "def f(x):\n    return helper(x)\n")
    (pkg / "sub" / "helper.py").write_text("from numba import njit\n@njit(inline='always')\n"
                                           "def helper(x):\n    return x + 1\n")
    (pkg / "plain.py").write_text("X = 1\n")
    return pkg


def _cached(pkg: Path) -> list[Path]:
    for name in ("kernel.f-3.py311.nbi", "kernel.f-3.py311.1.nbc"):
        (pkg / "sub" / "__pycache__" / name).write_bytes(b"compiled")
    return sorted(pkg.rglob("*.nb[ic]"))


def test_cached_kernels_dropped_when_an_inlined_helper_changes(tmp_path):
    """numba checks a cached kernel against its own file only: a change of the helper it
    inlines from another file must drop the cache (pdamper._numba_cache.refresh), a change
    of a module without kernels, or none, must not."""
    pkg = _kernel_package(tmp_path)
    env = {"HOME": str(tmp_path)}
    _cached(pkg)
    assert _numba_cache.refresh(env, package=pkg) == 2  # no fingerprint yet: dropped
    files = _cached(pkg)
    assert _numba_cache.refresh(env, package=pkg) == 0  # same sources: kept
    (pkg / "plain.py").write_text("X = 2\n")
    assert _numba_cache.refresh(env, package=pkg) == 0
    assert sorted(pkg.rglob("*.nb[ic]")) == files
    (pkg / "sub" / "helper.py").write_text("from numba import njit\n@njit(inline='always')\n"
                                           "def helper(x):\n    return x + 2\n")
    assert _numba_cache.refresh(env, package=pkg) == 2
    assert not list(pkg.rglob("*.nb[ic]"))


def test_cache_refresh_under_a_user_cache_directory(tmp_path):
    """With NUMBA_CACHE_DIR numba mirrors the package path inside it; the fingerprint and
    the files dropped are there, the package itself is not touched."""
    pkg = _kernel_package(tmp_path)
    cache = tmp_path / "cache"
    mirror = cache / pkg.resolve().as_posix().lstrip("/") / "sub" / "__pycache__"
    mirror.mkdir(parents=True)
    (mirror / "kernel.f-3.py311.nbi").write_bytes(b"compiled")
    env = {"NUMBA_CACHE_DIR": str(cache)}
    assert _numba_cache.refresh(env, package=pkg) == 1
    assert (cache / pkg.resolve().as_posix().lstrip("/") / _numba_cache.STAMP).is_file()
    assert not (pkg / "__pycache__" / _numba_cache.STAMP).exists()
    (mirror / "kernel.f-3.py311.nbi").write_bytes(b"compiled")
    assert _numba_cache.refresh(env, package=pkg) == 0


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


@pytest.mark.long
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
