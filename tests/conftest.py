"""Shared fixtures of the test suite.

DEM inputs of the benchmark damper are plain functions in ``dem_inputs.py`` (this
directory is on ``sys.path``), so that module-level helpers can use them too.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
# One BLAS thread per process, set before numpy loads its BLAS (here, in the xdist workers
# and in every child, which inherit it): the suite runs one process per core already, and
# its BLAS calls are on matrices of a few rows (an 8 x 8 matrix exponential per cycle of a
# load history), where OpenBLAS's threads only wait for a core: with them such a call took
# 0.16 ms on a quiet machine and 3-10 ms beside another worker, 0.01 ms without them.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
# Bytecode caches written (``__pycache__``, ignored by git) even where the environment says
# PYTHONDONTWRITEBYTECODE, here, in the xdist workers and in every child: without them each
# of the suite's ~150 ``python -m pdamper`` children compiles the package's modules from
# source again (0.1-0.3 s each: ``pdamper analytic`` starts in 0.49 s, 0.40 s with them),
# and pytest rewrites the test modules' asserts in both workers on every run (5.8 s each).
sys.dont_write_bytecode = False
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)

#: ``--cpu-durations``: each test's CPU seconds (tests/cpu_durations.py).
pytest_plugins = ["cpu_durations"]

#: The DEM kernels warmed before pytest-xdist's workers start, one group per process, the
#: groups at once: "gear" and "verlet" compile apart; "auto" adds its hand-over to them.
WARMUP_GROUPS = (("gear", "auto"), ("verlet",))


def _kernels_cached() -> bool:
    """numba's cache holds the integrators' kernels, newer than every kernel source (a
    cheap look at the files; numba itself checks each source's stamp when it loads)."""
    import pdamper  # drops kernels cached from older sources (pdamper._numba_cache)
    from pdamper import _numba_cache

    package = Path(pdamper.__file__).resolve().parent
    root = _numba_cache._cache_root(package, os.environ)
    cache = root / "dem" / "kernels"
    if root == package:
        cache = cache / "__pycache__"
    sources = package / "dem" / "kernels"
    try:
        newest = max(p.stat().st_mtime for p in sources.glob("*.py"))
        for kernel in ("gear.gear_advance", "gear.gear_resume", "verlet.verlet_advance",
                       "verlet.verlet_resume"):
            index = list(cache.glob(f"{kernel}-*.nbi"))
            if not index or max(p.stat().st_mtime for p in index) < newest:
                return False
    except (OSError, ValueError):
        return False
    return True


def pytest_sessionstart(session):
    """With pytest-xdist's workers (``-n``): compile the DEM kernels into numba's cache
    before the workers start, in parallel processes (one per group of
    :data:`WARMUP_GROUPS`), so that the workers load them instead of each compiling all
    of them at once (about 50 s of CPU per process on a fresh clone). Nothing to do in a
    worker, without workers (the first test compiles what it needs) or when they are
    cached already."""
    config = session.config
    if hasattr(config, "workerinput") or not config.pluginmanager.hasplugin("dsession"):
        return
    if _kernels_cached():
        return
    from proc import env

    # the spring friction law's Verlet kernels too (its tests): in the Verlet group,
    # which finishes well before Gear's
    code = ("import sys; from pdamper.dem import warmup; "
            "warmup(tuple(sys.argv[1:]), friction_models=('regularised', 'spring'))")
    procs = [subprocess.Popen([sys.executable, "-c", code, *group], env=env(),
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
             for group in WARMUP_GROUPS]
    for group, p in zip(WARMUP_GROUPS, procs, strict=True):
        _, err = p.communicate()
        if p.returncode != 0:  # the tests that need the kernels will say why
            print(f"warning: warming the DEM kernels {group} failed:\n{err[-2000:]}",
                  file=sys.stderr)


#: Tests of several seconds each that use no module-scoped fixture, run first (in this
#: order): pytest-xdist's work stealing balances the short tests behind them, so that no
#: worker ends the run alone on one of them (measured CPU seconds, one process: the type
#: check 10-14 s on a fresh clone, the rest 4-8 s, of which the DEM run interrupted after
#: 8 s, the DEM maps and uncertainty runs on local clusters of two worker processes, the
#: dense growths a refused random bed of 192 spheres tries; ``--cpu-durations`` lists them).
FIRST = (
    "tests/test_code_shape.py::test_the_type_check_passes",
    "tests/cli/test_interrupts.py::test_dem",
    "tests/models/test_dem_damper.py::test_auto_packing_is_random_where_every_sphere_can_be_placed_at_random",
    "tests/cli/test_corpus.py::test_corpus_case[ok-report-gravity-zero]",
    "tests/coupling/test_loads_dem.py::test_base_acceleration_on_a_featherweight_bed_is_the_transmissibility",
    "tests/cli/test_map.py::test_dem_map_with_a_cor_table_in_the_scenario",
    "tests/cli/test_dem_uncertainty.py::test_dem_uncertainty_on_the_sweep_engine_as_in_this_process",
    "tests/cli/test_map.py::test_dem_map_on_a_local_cluster",
    "tests/cli/test_interrupts.py::test_dem_map_on_a_local_cluster[computing]",
    "tests/cli/test_cli_realisations.py::test_simulate_fields_band_from_a_map_with_realisations",
    "tests/dem/test_cli_dem.py::test_dem_realisations_on_workers_equal_serial",
    "tests/dem/test_packing.py::test_random_packing_refuses_more_than_fill_limit",
    "tests/design/test_limits.py::test_bracket_no_design_within_80_g_meets_10_g_and_the_study_says_by_how_much",
)


def pytest_collection_modifyitems(config, items):
    """In an xdist worker, move the tests of :data:`FIRST` to the front, the others in
    their order (the same in every worker: their collections must agree). Not without
    workers: there the kernels are compiled by the first test that needs them, not before,
    and a signal sent 8 s into a compilation is heard only after it."""
    if not hasattr(config, "workerinput"):
        return
    rank = {nodeid: i for i, nodeid in enumerate(FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid, len(rank)))


@pytest.fixture
def cli(capsys):
    """Run ``pdamper ARGS...``; returns ``(exit status, stdout, stderr)``."""
    from pdamper.cli import main

    def run(*args):
        code = main([str(a) for a in args])
        out = capsys.readouterr()
        return code, out.out, out.err

    return run


@pytest.fixture(scope="session")
def paper_run32():
    """Model 3 on the paper's structure: 32 spheres released from -58 mm, 2 s (Fig. 7)."""
    from pdamper.coupling import Simulation
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_INITIAL_DISPLACEMENT, PAPER_STRUCTURE

    return Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER),
                      PAPER_INITIAL_DISPLACEMENT).run(2.0)


@pytest.fixture(scope="session")
def paper_model1_ensemble():
    """Model 1 (the DEM coupled to the paper's structure, Sect. 4.1): 32 spheres from
    -58 mm, 0.95 s, from ten random packings (seeds 0-9; about 0.6 s of CPU each).

    One run of model 1 is one realisation of a chaotic transient (from the paper's lattice,
    1e-9 m moves of the spheres or last-bit changes of the code moved the amplitude at
    0.75 s between 23.5 and 27.7 mm): tests compare the ensemble, not one run. Its
    amplitudes at 0.75 s scatter by 0.5-0.7 mm (standard deviation), so the mean of three
    moved by 0.8 mm with a last-bit change of the free flights (21.49 -> 20.74 mm) while
    the mean of ten moved by 0.2 mm (21.58 -> 21.35), within its standard error.
    """
    from pdamper.coupling import Simulation
    from pdamper.models import DEMDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_INITIAL_DISPLACEMENT, PAPER_STRUCTURE

    return [Simulation(PAPER_STRUCTURE, DEMDamper(PAPER_DAMPER, packing="random", seed=s),
                       PAPER_INITIAL_DISPLACEMENT).run(0.95) for s in range(10)]
