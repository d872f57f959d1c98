"""The forced response's cost (pdamper.runs.resources.frf_cost / check_frf), judged before
the work, per fidelity."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.coupling.frf import HarmonicLoad
from pdamper.errors import InputError
from pdamper.io.scenario import load_scenario
from pdamper.runs.resources import check_frf, check_resources, frf_cost

LOAD = HarmonicLoad("force", 2.0)


def test_default_response_is_within_the_limits():
    check_resources(load_scenario(None, {}), "frf")


def test_frequency_count_is_refused_naming_allow_cost():
    with pytest.raises(InputError) as exc:
        check_frf(load_scenario(None, {}), None, np.linspace(4.0, 7.0, 20000), LOAD)
    assert exc.value.field == "frequency"
    assert "--allow-cost" in exc.value.message and "--force" not in exc.value.message


def test_allow_cost_lifts_the_usual_limit():
    check_frf(load_scenario(None, {}), None, np.linspace(4.0, 7.0, 20000), LOAD, force=True)


def test_cost_grows_with_the_cube_of_the_state():
    """A cycle on N modes costs ~(2N)^3: 50 modes cost far more per step than one."""
    sc = load_scenario(None, {})
    one = frf_cost(sc, None, [5.0], LOAD)
    # the same counts on 50 modes, through the cost model directly
    from pdamper import resources

    fifty = resources.stepped_sine_cost(1, 2000, 2, 50, 800)
    assert fifty.seconds > 20 * one.seconds  # 4 ms a cycle against 0.1 ms (measured)


def test_dem_at_a_low_frequency_costs_its_periods():
    sc = load_scenario(None, {})
    low, high = (frf_cost(sc, "dem", [f], LOAD) for f in (0.5, 5.0))
    assert low.seconds > 5 * high.seconds
    with pytest.raises(InputError) as exc:
        check_frf(sc, "dem", [0.001], LOAD)
    assert exc.value.field == "frequency"


def test_check_frf_judges_the_load_against_the_physics_limits_before_any_frequency():
    """The forced response's cost check also judges its load (``check_harmonic_load``, the
    check the design study's forced-response objectives use): 1 MN on the paper's 1-DOF is
    refused by the check itself, before any frequency is solved; 2 N passes."""
    sc = load_scenario(None, {})
    with pytest.raises(InputError) as e:
        check_frf(sc, None, [5.0, 5.5, 6.0], HarmonicLoad("force", 1e6))
    assert e.value.field == "force" and "the stroke must be within" in e.value.message
    check_frf(sc, None, [5.0, 5.5, 6.0], LOAD)  # a usual load passes
