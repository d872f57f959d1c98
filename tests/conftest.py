"""Shared fixtures of the test suite.

DEM inputs of the benchmark damper are plain functions in ``dem_inputs.py`` (this
directory is on ``sys.path``), so that module-level helpers can use them too.
"""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")


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
