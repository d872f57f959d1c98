"""The Python API of DEM realisations (``pdamper.runs.realisations``)."""

from __future__ import annotations

import math

import pytest

from pdamper.errors import InputError
from pdamper.io.scenario import load_scenario
from pdamper.runs.realisations import check_realisations, run_realisations, with_seed

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


@pytest.mark.long
def test_case_study_draws_dem_model1_as_a_band(tmp_path):
    """The case study with 3 realisations of DEM model 1 (reduced: 0.8 s, a one-point DEM
    map): the band's amplitude at 0.75 s in results.json, realisation k the random packing
    of seed k alone, Figs. 7/8 written."""
    import json

    from pdamper.coupling import Simulation
    from pdamper.reports.paper_case_study import write_case_study
    from pdamper.runs.paper_case_study import run_case_study

    sc = load_scenario(None, {"simulation.duration": "0.8 s", "map.frequency": "5Hz:10Hz:2",
                              "map.amplitude": "10mm:50mm:2", "map.dem_frequency": "10Hz",
                              "map.dem_amplitude": "32mm", "dem.cycles": 4,
                              "dem.skip_cycles": 1})
    cs = run_case_study(sc, dem=True, serial=True, realisations=3)
    band = cs.dem_band
    assert band.count == 3 and band.seeds == [0, 1, 2] and band.at == 0.75
    s1 = with_seed(load_scenario(None, {"dem.packing": "random"}), 1)
    alone = Simulation(sc.structure_model(), s1.model("dem", sc.damper()),
                       sc.structure.initial_displacement).run(0.8, sc.simulation.sample_rate)
    assert band.runs[1].amplitude_at(0.75) == alone.amplitude_at(0.75)
    write_case_study(cs, tmp_path)
    data = json.loads((tmp_path / "results.json").read_text())["dem_realisations"]
    a = data["amplitude_at"]
    assert data["count"] == 3 and data["at"] == 0.75 and len(set(a["values"])) == 3
    assert a["min"] < a["mean"] < a["max"]
    assert (tmp_path / "fig7_trajectory.png").stat().st_size > 10_000
    row = next(m for m in cs.models() if "random packings" in m["label"])  # the report's table
    assert row["amplitude_0p75"] == a["mean"] and row["amplitude_0p75_band"]["min"] == a["min"]
    page = (tmp_path / "report.html").read_text()
    assert "mean of 3 random packings" in page and f"{a['max'] * 1e3:.2f} mm" in page
