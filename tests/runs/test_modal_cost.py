"""The modal free vibration's cost (:func:`pdamper.runs.resources.modal_free_vibration_cost`)
against what the coupling holds, and its refusal naming what the limits allow."""

from __future__ import annotations

import re
import tracemalloc

import numpy as np
import pytest

from hostile_corpus import _modes_file
from pdamper import resources
from pdamper.errors import InputError
from pdamper.io.scenario import load_scenario
from pdamper.runs.resources import modal_free_vibration_cost


def _structure(tmp_path, n: int):
    path = tmp_path / f"modes_{n}.csv"
    path.write_text(_modes_file(n))
    return load_scenario(None, {"structure.modes": str(path)}).structure_model()


def test_the_memory_estimate_covers_one_update_without_overstating_it(tmp_path):
    """One damper update of 150 modes (the state's eigen-decomposition and the scan for the
    next minimum), its arrays traced: the estimate is their peak to within 25 % below and a
    factor of four above (measured: about equal)."""
    from pdamper.coupling import modal

    s = _structure(tmp_path, 150)
    z0 = np.concatenate([s.release_state(-0.058), np.zeros(s.modes)])
    tracemalloc.start()
    try:
        seg = modal._Segment(s, 0.1, 1.0, z0)
        assert seg.next_minimum(0.058) is not None
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    est = modal_free_vibration_cost(s, 0.0, 1.0).memory  # no trajectory: one update's arrays
    assert peak / 1.25 <= est <= 4 * peak


def test_the_refusal_names_the_most_modes_that_fit(tmp_path):
    s = _structure(tmp_path, 1500)
    with pytest.raises(InputError) as err:
        resources.require(modal_free_vibration_cost(s, 2.0, 2000.0))
    assert err.value.field == "structure.modes"
    k = int(re.search(r"at most (\d+) modes", err.value.message).group(1))
    assert 1 < k < 1500
    fewer = _structure(tmp_path, k)  # the first k modes of the same file
    resources.require(modal_free_vibration_cost(fewer, 2.0, 2000.0))
    with pytest.raises(InputError):
        resources.require(modal_free_vibration_cost(_structure(tmp_path, k + 1), 2.0, 2000.0))
