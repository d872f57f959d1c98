"""The Python API of DEM realisations (``pdamper.reports.realisations``)."""

from __future__ import annotations

import math

import pytest

from pdamper.errors import InputError
from pdamper.io.scenario import load_scenario
from pdamper.reports.realisations import check_realisations, run_realisations, with_seed

_SHORT = {"particles.count": 8, "dem.cycles": 2, "dem.skip_cycles": 1,
          "dem.packing": "random", "dem.seed": 3}


@pytest.mark.parametrize("bad", [0, -1, 2.5, True, "two", None, math.nan])
def test_bad_counts_name_realisations(bad):
    with pytest.raises(InputError) as exc:
        check_realisations(bad, load_scenario(None, _SHORT))
    assert exc.value.field == "realisations"


def test_whole_float_count_and_lattice():
    sc = load_scenario(None, _SHORT)
    assert check_realisations(3.0, sc) == 3
    lattice = load_scenario(None, {**_SHORT, "dem.packing": "lattice"})
    assert check_realisations(1, lattice) == 1  # the lattice is one realisation
    with pytest.raises(InputError, match="lattice"):
        check_realisations(2, lattice)


def test_run_realisations_serial_matches_single_models():
    """Realisation k is the DEM model of seed 3 + k run on its own."""
    sc = load_scenario(None, _SHORT)
    res = run_realisations(sc, 2, serial=True)
    assert res.seeds == [3, 4] and res.count == 2
    for seed, run in zip(res.seeds, res.runs, strict=True):
        s = with_seed(sc, seed)
        r = s.model("dem", s.damper()).response(s.excitation.frequency, s.excitation.amplitude)
        assert run["loss_factor"] == float(r.loss_factor)
        assert run["effective_mass_ratio"] == float(r.effective_mass_ratio)
    st = res.statistics("loss_factor")
    v = [r["loss_factor"] for r in res.runs]
    assert st["values"] == v and st["min"] == min(v) and st["max"] == max(v)
    assert math.isclose(st["std"], abs(v[0] - v[1]) / math.sqrt(2), rel_tol=1e-12)
