"""Every corner of the paper's map runs to the end with the defaults (issue: "runs
everywhere"): the fast corner (impacts at ~46 m/s, overlaps of ~15 % of the radius, which
stopped the run before), the slow corner and the full container. The energy ledger closes
to 1 % and the diagnostics are reported."""

from __future__ import annotations

import pytest

from pdamper.dem import HarmonicMotion
from pdamper.dem.model import LargeOverlapWarning
from pdamper.models import DEMDamper
from pdamper.parameters import PAPER_DAMPER


def _run(f, x, n, cycles, **kw):
    eng = DEMDamper(PAPER_DAMPER.with_count(n), settle_time=0.05, **kw).build_engine(
        HarmonicMotion(x, f))
    return eng.run(cycles / f, sample_rate=4000.0)


@pytest.mark.parametrize("integrator", ["gear", "verlet"])
def test_fast_corner_runs_to_the_end(integrator):
    """20 Hz / 200 mm: overlaps beyond 5 % warn, the run goes on."""
    with pytest.warns(LargeOverlapWarning):
        res = _run(20.0, 0.2, 32, 1.0 if integrator == "gear" else 0.3, integrator=integrator)
    assert not res.stopped_early
    assert res.max_overlap_ratio > 0.05 and res.max_impact_velocity > 20.0
    assert res.energy_balance_error() < 0.01


def test_slow_corner_runs_to_the_end():
    res = _run(2.0, 0.2, 32, 0.5)
    assert res.energy_balance_error() < 0.01 and res.max_impact_velocity > 1.0


@pytest.mark.filterwarnings("ignore::pdamper.dem.model.LargeOverlapWarning")
def test_full_container_at_the_fast_corner_runs_to_the_end():
    """192 spheres fill the box (no clearance): the container drives the whole lattice."""
    res = _run(20.0, 0.2, 192, 0.25)
    assert res.energy_balance_error() < 0.01 and res.max_impact_velocity > 1.0
