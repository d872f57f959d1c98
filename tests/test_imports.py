"""Start-up: ``import pdamper``, the CLI and a command import only what they use.

Heavy libraries are imported where used: dask for sweeps, xarray and h5netcdf where files
are written, matplotlib for plots, numba for the DEM. Checked in child processes (this
process has imported everything by now); the timings are benchmarks/bench_startup.py's.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from proc import env

HEAVY = ("dask", "distributed", "xarray", "h5netcdf", "h5py", "matplotlib", "numba")


def _imported_after(code: str) -> list[str]:
    probe = (f"import sys\n{code}\n"
             f"print(__import__('json').dumps(sorted(m for m in {HEAVY!r} if m in sys.modules)))")
    p = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env(),
                       timeout=300)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.splitlines()[-1])


@pytest.mark.parametrize("module", ["pdamper", "pdamper.cli"])
def test_import_pulls_in_no_heavy_library(module):
    assert _imported_after(f"import {module}") == []


def _after_command(*args: str) -> list[str]:
    code = ("import contextlib, io\nfrom pdamper.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            f"    assert main({list(args)!r}) == 0")
    return _imported_after(code)


def test_analytic_imports_neither_dask_nor_xarray_nor_matplotlib():
    assert _after_command("analytic") == []
    assert _after_command("analytic", "--frequency", "6 Hz", "--amplitude", "15 mm",
                          "--json") == []


def test_dem_without_files_loads_numba_only():
    """A DEM run that writes no file: numba, not the libraries of files, plots or sweeps."""
    assert _after_command("dem", "--frequency", "10Hz", "--amplitude", "32mm", "--cycles",
                          "1", "--skip-cycles", "0") == ["numba"]


def test_version_and_help_import_nothing_heavy():
    assert _after_command("--version") == []
    assert _after_command("dem", "--help") == []
