"""The case study (:mod:`pdamper.runs.paper_case_study`, written out by
:mod:`pdamper.reports.paper_case_study`): rows from the parameter set,
files written atomically, figures without pyplot state."""

from __future__ import annotations

import json

import pytest

from pdamper.io.scenario import load_scenario
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.reports.paper_case_study import write_case_study
from pdamper.runs.paper_case_study import run_case_study


@pytest.fixture(scope="module")
def small_study():
    sc = load_scenario(None, {"map.frequency": "2Hz:20Hz:7", "map.amplitude": "2mm:200mm:9"})
    return run_case_study(sc, dem=False)


def test_rows_come_from_the_parameter_set(small_study):
    """Every row is one of the paper's reported numbers, in the parameter set's order, with
    the paper's text and source; without the DEM its three rows are absent."""
    expected = [r for r in paper.PAPER_REPORTED if not r.key.startswith("dem_")]
    assert len(small_study.rows) == len(expected) == 24
    for row, rep in zip(small_study.rows, expected, strict=True):
        assert row.paper == rep.paper and row.source == rep.source
    assert small_study.rows[11].quantity == "maximum eta on the 7 x 9 grid"
    assert all(r.agrees for r in small_study.rows[:6])  # Fig. 4 modes


def test_write_is_atomic_and_leaves_no_pyplot_state(small_study, tmp_path):
    import matplotlib
    import matplotlib.pyplot as plt

    backend = matplotlib.get_backend()
    files = write_case_study(small_study, tmp_path)
    assert {p.name for p in files} == {p.name for p in tmp_path.iterdir()}
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]
    assert plt.get_fignums() == [] and matplotlib.get_backend() == backend
    data = json.loads((tmp_path / "results.json").read_text())
    assert [r["quantity"] for r in data["rows"]] == [r.quantity for r in small_study.rows]
    assert data["map_shape"] == [7, 9]
    for f in files:
        if f.suffix == ".png":
            assert f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_short_runs_give_no_verdict_instead_of_a_wrong_one():
    """A duration shorter than the paper's 0.75 s comparison: n/a, not a number."""
    sc = load_scenario(None, {"simulation.duration": "0.5 s", "map.frequency": "5Hz:10Hz:2",
                              "map.amplitude": "10mm:50mm:2"})
    cs = run_case_study(sc, dem=False)
    row = next(r for r in cs.rows if r.quantity == "amplitude at 0.75 s, 32 spheres")
    assert row.agrees is None and row.ours.startswith("n/a")


@pytest.mark.long
def test_dem_rows_fig2_and_both_cor_runs(tmp_path):
    """With the DEM (reduced: 0.8 s, small grids, a one-point DEM map of 4 cycles in this
    process): the Fig. 2 single-impact check within 0.01, DEM model 1 with the scenario's
    constant COR and, next to it, with the paper's curves (two different runs), Fig. 2
    written, the COR models recorded in results.json."""
    sc = load_scenario(None, {"simulation.duration": "0.8 s", "map.frequency": "5Hz:10Hz:2",
                              "map.amplitude": "10mm:50mm:2", "map.dem_frequency": "10Hz",
                              "map.dem_amplitude": "32mm", "dem.cycles": 4,
                              "dem.skip_cycles": 1})
    said, points = [], []
    cs = run_case_study(sc, said.append, dem=True, serial=True,
                        map_progress=lambda done, total, _p: points.append((done, total)))
    assert cs.dem_map["loss_factor"].shape == (1, 1)
    # what the progress display shows: the kernels compiled before the map, its points
    first = next(i for i, m in enumerate(said) if m.startswith("Fig. 5b/5d: DEM map 1 x 1"))
    assert said[first - 1].startswith("compiling the DEM kernels (gear")
    assert points[-1] == (1, 1) and cs.timings["DEM kernels"] > 0
    rows = {r.quantity: r for r in cs.rows}
    cal = rows["Fig. 2 COR curves in single DEM impacts, 0.01-2 m/s (max |e_DEM - e|)"]
    assert cal.agrees and all(c.max_deviation < 0.01 for c in cs.cor_checks)
    const = rows["amplitude at 0.75 s, 32 spheres, DEM model 1, constant COR 0.6 / 0.85"]
    curves = rows["amplitude at 0.75 s, 32 spheres, DEM model 1, the paper's COR curves (Fig. 2)"]
    assert const.ours.endswith("mm)") and curves.ours.endswith("mm)")
    keys = [r.key for r in paper.PAPER_REPORTED]
    assert keys.index("dem_curves_amplitude_32_0p75s") == keys.index("dem_amplitude_32_0p75s") + 1
    assert cs.run_dem is not cs.run_dem_curves
    assert cs.run_dem.inputs["steps"] != cs.run_dem_curves.inputs["steps"]
    files = write_case_study(cs, tmp_path, said.append)
    assert (tmp_path / "fig2_materials_cor.png") in files
    assert {f"writing {p.name}" for p in files if p.suffix == ".png"} <= set(said)
    data = json.loads((tmp_path / "results.json").read_text())
    assert data["restitution"]["scenario"]["particle_wall"] == "constant 0.85"
    assert "dem_paper_cor_curves" in data["level3_runs"]
    assert len(data["restitution"]["dem_single_impacts"]) == 2
