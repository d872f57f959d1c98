"""The DEM damper model at Level II: the complex power method on DEM runs (Eqs. 1-4)."""

import pytest

from pdamper.analysis.modes import MotionMode
from pdamper.errors import InputError
from pdamper.models import DEMDamper
from pdamper.parameters import PAPER_DAMPER


def test_response_complex_power_agrees_with_the_energy_ledger():
    """Eq. (2) against the ledger: work of the container walls per cycle = E~. The run
    travels in the response's details (no side channel)."""
    model = DEMDamper(PAPER_DAMPER, cycles=5, skip_cycles=2)
    r = model.response(10.0, 0.032)
    run = r.details.item()
    ledger = run.ledger_per_cycle(2)
    assert float(r.dissipated_energy_per_cycle) == pytest.approx(ledger["container_work"],
                                                                 rel=0.05)
    assert 0.3 < float(r.loss_factor) < 1.6
    assert int(r.mode) in {int(m) for m in MotionMode}  # classified from the run
    st = r.diagnostics["stationarity"].item()
    assert (st.first_cycle, st.last_cycle) == (3, 5)  # the paper's window: after 2 cycles
    assert r.stationary.item() == st.stationary
    assert not hasattr(model, "last_results")


def test_dem_model_input_errors():
    with pytest.raises(InputError, match="dem.packing"):
        DEMDamper(PAPER_DAMPER, packing="hexagonal")
    with pytest.raises(InputError, match="dem.skip_cycles"):
        DEMDamper(PAPER_DAMPER, cycles=3, skip_cycles=3)
    with pytest.raises(InputError, match="dem.damping_model"):
        DEMDamper(PAPER_DAMPER, damping_model="magic")
    with pytest.raises(InputError, match="dem.safety"):
        DEMDamper(PAPER_DAMPER, safety=0.0)
    with pytest.raises(InputError, match="particles.count"):
        DEMDamper(PAPER_DAMPER.with_count(0)).response(10.0, 0.01)
    with pytest.raises(InputError, match="damper: must be a ParticleDamper"):
        DEMDamper(None)
