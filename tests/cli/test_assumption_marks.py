"""The analytical model knows its limits in every output: maps (JSON, NetCDF, plots), the
forced response (JSON per row and summary, text, NetCDF, plot), and zero gravity."""

from __future__ import annotations

import json

import numpy as np
import pytest


def test_map_flags_a_scattering_cell_in_json_netcdf_and_plot(tmp_path, cli):
    import matplotlib

    matplotlib.use("Agg")
    import xarray as xr

    from pdamper.plots import plot_loss_factor_map, plot_mode_map

    path, fig = tmp_path / "map.nc", tmp_path / "map.png"
    # 25 Hz / 10 mm: the paper's damper scatters there (docs/analytical.md); 10 Hz / 32 mm
    # is a double collect-and-collide whose assumptions hold
    code, out, _ = cli("map", "--model", "analytic", "--frequency", "10Hz:25Hz:2",
                       "--amplitude", "10mm:32mm:2", "--out", path, "--plot", fig, "--json")
    assert code == 0 and fig.stat().st_size > 0
    d = json.loads(out)
    assert d["assumptions"]["points"] == 4 and d["assumptions"]["flagged"] >= 1
    assert d["assumptions"]["reasons"]["scattering"] >= 1
    assert "dem" in d["assumptions"]["use"] and "fields" in d["assumptions"]["use"]
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    hold = ds["assumptions_hold"]
    assert ds["assumptions_hold"].attrs["flag_meanings"] == "outside_assumptions assumptions_hold"
    assert int(hold.sel(frequency=25.0, amplitude=0.010)) == 0
    assert "scattering" in str(ds["assumptions"].sel(frequency=25.0, amplitude=0.010).values)
    assert int(hold.sel(frequency=10.0, amplitude=0.032)) == 1
    assert str(ds["assumptions"].sel(frequency=10.0, amplitude=0.032).values) == ""
    flagged = int((hold.values == 0).sum())
    assert flagged == d["assumptions"]["flagged"]
    for draw in (plot_loss_factor_map, plot_mode_map):
        ax = draw(ds)
        marks = [c for c in ax.collections if c.get_hatch()]
        assert len(marks) == 1 and len(marks[0].get_paths()) == flagged
        legend = [t.get_text() for t in ax.get_legend().get_texts()]
        assert any("scattering" in t and "fields from a DEM map, or dem" in t for t in legend)


def test_map_text_names_the_flagged_points(cli):
    code, out, _ = cli("map", "--model", "analytic", "--frequency", "25Hz",
                       "--amplitude", "10mm")
    assert code == 0
    assert ("analytic assumptions fail at 1 of 1 points (scattering 1): use fields from a "
            "DEM map (--model fields) or dem there") in out


def test_a_map_whose_assumptions_hold_everywhere_has_no_marks():
    import matplotlib

    matplotlib.use("Agg")
    from pdamper.analysis.fields import effective_field
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER
    from pdamper.plots import plot_loss_factor_map

    ds = effective_field(AnalyticalDamper(PAPER_DAMPER), [10.0], [0.032, 0.05])
    assert ds["assumptions_hold"].values.tolist() == [[1, 1]]
    assert not [c for c in plot_loss_factor_map(ds).collections if c.get_hatch()]


def test_frf_on_the_papers_case_flags_the_scattering_solution(tmp_path, cli):
    """At 5.5 Hz under 2 N the paper's damper has three harmonic-balance solutions, the
    largest stroke a scattering bed (Eq. 8's eta = 1e-3): that one is flagged, per row
    and in the summary, the text says so in one line and the NetCDF carries it."""
    import xarray as xr

    nc = tmp_path / "frf.nc"
    code, out, _ = cli("frf", "--model", "analytic", "--frequency", "5.5Hz", "--out", nc,
                       "--json")
    assert code == 0
    d = json.loads(out)
    hb = d["points"][0]["harmonic_balance"]
    assert [r["assumptions_hold"] for r in hb] == [r["mode"] != "scattering" for r in hb]
    assert [r["mode"] for r in hb].count("scattering") == 1
    bad = next(r for r in hb if r["mode"] == "scattering")
    assert "scattering" in bad["assumptions"] and "dem" in bad["assumptions"]
    assert all(d["points"][0][s]["assumptions_hold"] for s in ("up", "down"))
    a = d["assumptions"]
    assert (a["points"], a["flagged"], a["reasons"]) == (5, 1, {"scattering": 1})
    assert a["by_source"]["harmonic_balance"] == {"points": 3, "flagged": 1}
    assert a["frequencies"] == [5.5] and "fields" in a["use"]
    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        assert int((ds["hb_assumptions_hold"].values == 0).sum()) == 1
        assert int((ds["sweep_assumptions_hold"].values == 0).sum()) == 0
        assert ds["hb_assumptions"].values.ravel().tolist().count("") == \
            ds["hb_assumptions"].size - 1
    code, out, _ = cli("frf", "--model", "analytic", "--frequency", "5.5Hz")
    lines = [ln for ln in out.splitlines() if "assumptions fail" in ln]
    assert lines == ["analytic assumptions fail at 1 of 5 answers (scattering 1): use fields "
                     "from a DEM map (--model fields) or dem there (5.5-5.5 Hz; o in the "
                     "figure, JSON assumptions_hold per row)"]


def test_frf_without_flagged_points_prints_no_line_and_keeps_its_keys(cli):
    code, out, _ = cli("frf", "--model", "analytic", "--frequency", "4Hz:4.5Hz:2", "--json")
    d = json.loads(out)
    assert d["assumptions"]["flagged"] == 0 and d["assumptions"]["reasons"] == {}
    assert all(p["up"]["assumptions_hold"] and p["up"]["assumptions"] == ""
               for p in d["points"])
    code, out, _ = cli("frf", "--model", "analytic", "--frequency", "4Hz:4.5Hz:2")
    assert code == 0 and "assumptions fail" not in out


def test_frf_plot_rings_the_flagged_answers():
    import matplotlib

    matplotlib.use("Agg")
    from pdamper.coupling.frf import HarmonicLoad, frequency_response
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
    from pdamper.plots.frf import plot_frf

    res = frequency_response(AnalyticalDamper(PAPER_DAMPER, gravity=0.0), PAPER_STRUCTURE,
                             HarmonicLoad("force", 2.0), [4.0, 6.5], sweep="up")
    # without gravity, strokes below h / pi (26.5 mm here) scatter (docs/analytical.md)
    up = res.sweeps["up"]
    assert not up.diagnostics["assumptions_hold"].any() and (up.mode == 5).all()
    axes = plot_frf(res)
    ring = [ln for ln in axes[0].get_lines() if "assumptions" in str(ln.get_label())]
    assert len(ring) == 1
    assert "fields from a DEM map, or dem" in ring[0].get_label()
    n_hb = int(np.count_nonzero(~res.harmonic_balance.diagnostics["assumptions_hold"]
                                & np.isfinite(res.harmonic_balance.amplitude)))
    assert len(ring[0].get_xdata()) == 2 + n_hb


def test_a_single_ball_is_flagged_at_every_frequency():
    import dataclasses

    from pdamper.coupling.frf import HarmonicLoad, assumption_record, frequency_response
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

    ball = dataclasses.replace(PAPER_DAMPER, length=0.041, width=0.041, depth=0.041,
                               particle_radius=0.02, count=1)
    res = frequency_response(AnalyticalDamper(ball), PAPER_STRUCTURE,
                             HarmonicLoad("force", 2.0), [5.0, 5.5, 6.0], sweep="up")
    rec = assumption_record(res)
    assert rec["flagged"] == rec["points"] and rec["reasons"]["collected_bed"] == rec["points"]
    assert rec["frequencies"] == [5.0, 5.5, 6.0]


def test_frf_at_zero_gravity_answers_within_seconds(cli):
    """frf at g = 0 answers where analytic answers, in seconds, and flags the scattering
    answers below h / pi (it used to run 100 s and refuse with advice about gravity)."""
    import time

    t0 = time.perf_counter()
    code, out, err = cli("frf", "--model", "analytic", "--gravity", "0 m/s^2",
                         "--frequency", "5Hz:6Hz:5", "--json")
    assert code == 0, err
    assert time.perf_counter() - t0 < 30
    d = json.loads(out)
    assert d["inputs"]["excitation"]["gravity"] == 0.0
    rows = [p["up"] for p in d["points"]]
    assert all(np.isfinite(r["amplitude"]) for r in rows)
    assert all(r["assumptions_hold"] == (r["mode"] != "scattering") for r in rows)
    assert d["assumptions"]["reasons"]["scattering"] >= 1
    code, out, _ = cli("analytic", "--gravity", "0 m/s^2", "--frequency", "5.5Hz",
                       "--amplitude", f"{rows[2]['stroke'] * 1e3:.6g}mm", "--json")
    assert code == 0 and json.loads(out)["mode"] == rows[2]["mode"]


BALL = """[container]
length = "41mm"
width = "41mm"
depth = "41mm"
[particles]
radius = "20mm"
count = 1
"""


def test_optimize_marks_a_design_resting_on_flagged_answers(tmp_path, cli):
    """One 40 mm ball in a 41 mm box: the analytical model's clearance is 0 (n_max = 1)
    and one ball rebounds rather than collects; the design that has it is marked, the
    empty container rests on no damper answer."""
    sc = tmp_path / "ball.toml"
    sc.write_text(BALL)
    args = ("optimize", "--scenario", sc, "--model", "analytic", "--at", "0.8s",
            "--vary", "particles=0:1:1")
    code, out, _ = cli(*args, "--json")
    assert code == 0
    rows = {c["particles"]: c for c in json.loads(out)["candidates"]}
    assert "assumptions_hold" not in rows[0]  # no particles: no damper answer
    assert rows[1]["assumptions_hold"] is False
    assert "collected bed" in rows[1]["assumptions"] and "clearance" in rows[1]["assumptions"]
    assert "fields from a DEM map" in rows[1]["assumptions"]
    code, out, _ = cli(*args)
    assert code == 0
    table = [ln for ln in out.splitlines() if ln.strip().startswith("1 ")]
    assert table and table[0].rstrip().endswith("!")
    assert ("! 1 of 2 evaluated designs rest on answers outside the analytic model's "
            "assumptions: check them with fields from a DEM map, or dem") in out


def test_peak_frf_study_marks_its_designs():
    from pdamper.coupling.frf import HarmonicLoad
    from pdamper.design.study import DesignEvaluator, make_objective
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

    o = make_objective("peak-frf", 0.8, -0.058, PAPER_STRUCTURE,
                       frf_load=HarmonicLoad("force", 2.0), band=(5.0, 5.5, 6.0))
    ev = DesignEvaluator(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, o,
                         lambda d: AnalyticalDamper(d, gravity=0.0))
    _, extra = ev({"particles": 32})
    assert extra["assumptions_hold"] is False and "scattering" in extra["assumptions"]


def test_a_free_decay_at_zero_gravity_rests_on_scattering_updates():
    """The paper's decay from -58 mm: at 9.81 m/s^2 every update up to 0.8 s holds the
    assumptions; without gravity the bed scatters below h / pi (26.5 mm), so 3 of the 5
    updates before 0.8 s are flagged, and the report's models table says so."""
    from pdamper.coupling import Simulation
    from pdamper.coupling.validity import decay_assumptions
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
    from pdamper.reports.damper_report import _decay_cell

    marks = {}
    for g in (9.81, 0.0):
        m = AnalyticalDamper(PAPER_DAMPER, gravity=g)
        marks[g] = decay_assumptions(m, Simulation(PAPER_STRUCTURE, m, -0.058).run(1.0), 0.8)
    assert (marks[9.81]["points"], marks[9.81]["flagged"]) == (5, 0)
    assert (marks[0.0]["points"], marks[0.0]["flagged"]) == (5, 3)
    assert _decay_cell(marks[9.81]) == "hold at every update (5)"
    assert _decay_cell(marks[0.0]) == ("fail at 3 of 5 updates (scattering): use fields "
                                       "from a DEM map, or dem")


def test_report_tables_say_where_the_analytic_answers_rest_on_failed_assumptions():
    """Without gravity the paper's damper scatters at its forced peak (stroke < h / pi):
    the report's forced-response row says so with the reason and the fidelity to use."""
    from pdamper.coupling.frf import HarmonicLoad, frequency_response
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
    from pdamper.reports.damper_report import _assumptions_cell
    from pdamper.runs.damper_report import _peak_assumptions

    r = frequency_response(AnalyticalDamper(PAPER_DAMPER, gravity=0.0), PAPER_STRUCTURE,
                           HarmonicLoad("force", 2.0), [5.0, 5.5, 6.0], sweep="none")
    i = int(np.nanargmax(np.where(r.harmonic_balance.steady, r.harmonic_balance.amplitude,
                                  np.nan)) // r.harmonic_balance.amplitude.shape[1])
    m = _peak_assumptions(r, i)
    assert m["peak_assumptions_hold"] is False and "scattering" in m["peak_assumptions"]
    cell = _assumptions_cell(m)
    assert cell.startswith("fail at the peak: scattering")
    assert cell.endswith("use fields from a DEM map, or dem")
    ok = frequency_response(AnalyticalDamper(PAPER_DAMPER), PAPER_STRUCTURE,
                            HarmonicLoad("force", 2.0), [4.0, 4.5], sweep="none")
    assert _assumptions_cell(_peak_assumptions(ok, 1)) == "hold at the peak; hold at every answer"


def test_analytic_says_whether_its_assumptions_hold(cli):
    code, out, _ = cli("analytic", "--frequency", "25Hz", "--amplitude", "10mm", "--json")
    d = json.loads(out)
    assert d["mode"] == "scattering" and d["assumptions_hold"] is False
    assert "scattering" in d["assumptions"] and "use dem" in d["assumptions"]
    code, out, _ = cli("analytic", "--frequency", "25Hz", "--amplitude", "10mm")
    assert "outside the model's assumptions: scattering" in out
    code, out, _ = cli("analytic", "--frequency", "10Hz", "--amplitude", "32mm", "--json")
    assert json.loads(out)["assumptions_hold"] is True


@pytest.mark.long  # the whole report: 50-100 s on two busy cores
def test_report_at_zero_gravity_answers_and_marks_the_scattering_peak(tmp_path, cli):
    sc = tmp_path / "zg.toml"
    sc.write_text('[excitation]\ngravity = "0 m/s^2"\n')
    code, out, err = cli("report", "--scenario", sc, "--out", tmp_path / "rep")
    assert code == 0, err
    assert "! forced response, analytical formulas (model 3): the peak is outside" in out
    res = json.loads((tmp_path / "rep" / "results.json").read_text())
    m = res["forced_response"]["models"]["analytical formulas (model 3)"]
    assert m["peak_assumptions_hold"] is False and m["assumptions"]["flagged"] > 0
    html = (tmp_path / "rep" / "report.html").read_text()
    assert "fail at the peak: scattering" in html
    row = next(r for r in res["models"] if r["label"] == "analytical formulas (model 3)")
    assert row["assumptions"]["reasons"]["scattering"] >= 1
    assert "updates (scattering): use fields from a DEM map, or dem" in html
