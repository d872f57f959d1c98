"""The near-harmonic flag (pdamper.coupling.harmonicity) and the analytic-fields mark on
every surface: ``frf`` (JSON per row and text), ``optimize`` (per design) and ``report``
(text, results.json, report.html)."""

import json
from pathlib import Path

import pytest

FRAME = Path(__file__).resolve().parents[2] / "examples" / "machine-frame" / "scenario.toml"


def test_frf_rows_carry_the_flag_and_a_cut_off_step_is_not_near_harmonic(cli):
    args = ("frf", "--frequency", "5.3Hz:5.7Hz:3", "--force", "2N", "--sweep", "up")
    # run to steady: every step's last cycle is the harmonic its loss factor was taken at
    code, out, err = cli(*args, "--json")
    assert code == 0, err
    res = json.loads(out)
    rows = [p["up"] for p in res["points"]]
    assert all(r["steady"] and r["near_harmonic"] for r in rows)
    assert all(0 <= r["harmonic_deviation"] < 0.01 for r in rows)
    assert res["near_harmonic"]["all"] is True
    # two cycles a step: the transient is still there, the 5.3 Hz step far from harmonic
    code, out, err = cli(*args, "--max-cycles", "2", "--json")
    assert code == 0, err
    res = json.loads(out)
    first = res["points"][0]["up"]
    assert not first["steady"] and not first["near_harmonic"]
    assert first["harmonic_deviation"] > 0.25
    s = res["near_harmonic"]["by_sweep"]["up"]
    assert s["not_near_harmonic"] >= 1 and 5.3 in s["frequencies"]
    assert res["near_harmonic"]["all"] is False
    code, out, _ = cli(*args, "--max-cycles", "2")
    assert code == 0
    assert "! not near-harmonic: up at" in out and "use --model plastic" in out


def test_frf_netcdf_carries_the_deviation(tmp_path):
    import numpy as np

    from pdamper.coupling.frf import HarmonicLoad, frequency_response
    from pdamper.models import AnalyticalDamper, PlasticBedDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

    f = [5.3, 5.5]
    for model, key in ((AnalyticalDamper, "sweep_harmonic_deviation"),
                       (PlasticBedDamper, "sweep_distortion")):
        r = frequency_response(model(PAPER_DAMPER), PAPER_STRUCTURE,
                               HarmonicLoad("force", 2.0), f, sweep="up", max_cycles=2)
        ds = r.to_dataset()
        assert ds[key].attrs["units"] == "1"
        np.testing.assert_array_equal(ds[key].values[0], r.sweeps["up"].diagnostics[
            key.removeprefix("sweep_")])


def test_frf_of_the_plastic_block_says_why_the_flag_does_not_apply(cli):
    code, out, err = cli("frf", "--model", "plastic", "--frequency", "5.5Hz", "--force", "2N",
                         "--sweep", "up", "--json")
    assert code == 0, err
    res = json.loads(out)
    assert res["near_harmonic"] is None
    assert "follows the motion itself" in res["not_applicable"]["near_harmonic"]
    row = res["points"][0]["up"]
    assert "near_harmonic" not in row and 0 <= row["distortion"] < 1


def test_optimize_marks_each_design(cli):
    # the machine frame's two modes released from -3 mm beat: each design with particles
    # rests on a motion that is not near-harmonic (0.29); without particles: no answer
    code, out, err = cli("optimize", "--scenario", FRAME, "--vary", "particles=0:190:95",
                         "--json")
    assert code == 0, err
    c = {d["particles"]: d for d in json.loads(out)["candidates"]}
    assert "near_harmonic" not in c[0]
    for n in (95, 190):
        assert c[n]["near_harmonic"] is False and c[n]["harmonic_deviation"] > 0.25
    code, out, _ = cli("optimize", "--scenario", FRAME, "--vary", "particles=0:190:95")
    assert code == 0
    assert "~ 2 of 3 evaluated designs rest on a motion that is not near-harmonic" in out
    # the paper's one-mode decay is near-harmonic (0.15)
    code, out, err = cli("optimize", "--vary", "particles=16:32:16", "--json")
    assert code == 0, err
    for d in json.loads(out)["candidates"]:
        assert d["near_harmonic"] is True and d["harmonic_deviation"] < 0.25


@pytest.fixture(scope="module")
def frame_report(tmp_path_factory):
    import contextlib
    import io

    from pdamper.cli import main

    out = tmp_path_factory.mktemp("frame") / "report"
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = main(["report", "--scenario", str(FRAME), "--out", str(out)])
    assert code == 0
    return out, buf.getvalue()


def test_report_carries_the_flag_in_text_json_and_page(frame_report):
    out, text = frame_report
    res = json.loads((out / "results.json").read_text())
    rows = {m["label"]: m for m in res["models"]}
    for label in ("analytical formulas (model 3)", "effective fields (model 2)"):
        assert rows[label]["near_harmonic"] is False
        assert rows[label]["harmonicity"]["deviation"] > 0.25
        assert f"! free decay, {label}: not near-harmonic" in text
    # the forced response is harmonic balance: nothing to judge, and it says why
    for m in res["forced_response"]["models"].values():
        assert m["near_harmonic"] is None and "harmonic balance" in \
            m["not_applicable"]["near_harmonic"]
    page = (out / "report.html").read_text()
    assert "near-harmonic" in page and "! no: deviation" in page


def test_report_marks_fields_made_from_the_analytical_model(frame_report):
    out, text = frame_report
    res = json.loads((out / "results.json").read_text())
    rows = {m["label"]: m for m in res["models"]}
    fields = rows["effective fields (model 2)"]
    assert fields["fields_from"] == "analytic" and "not from a DEM map" in fields["fields_note"]
    # its answers carry the analytical model's checks at its own updates
    assert fields["assumptions"]["points"] > 0
    assert "fields_from" not in rows["analytical formulas (model 3)"]
    forced = res["forced_response"]["models"]
    assert forced["effective fields (model 2)"]["fields_from"] == "analytic"
    assert "fields_from" not in forced["analytical formulas (model 3)"]
    assert "! effective fields (model 2): the effective fields were computed from the " \
        "analytical model" in text
    page = (out / "report.html").read_text()
    assert "(! the effective fields were computed from the analytical model" in page
    assert "(! fields from the analytical model)" in page


def test_report_marks_a_fields_file_made_by_the_analytical_model(cli, tmp_path):
    code, _, err = cli("map", "--model", "analytic", "--frequency", "2Hz:20Hz:6",
                       "--amplitude", "log:1mm:100mm:6", "--out", tmp_path / "m.nc")
    assert code == 0, err
    (tmp_path / "s.toml").write_text(
        'title = "fields from an analytical map file"\n'
        '[simulation]\nduration = "1 s"\n'
        '[optimization]\nat = "0.5 s"\nvary = ["particles=0:32:16"]\n'
        '[map]\nfrequency = "2Hz:20Hz:3"\namplitude = "log:1mm:100mm:3"\n'
        '[fields]\nfile = "m.nc"\nextrapolation = "analytic"\n')
    code, out, err = cli("report", "--scenario", tmp_path / "s.toml", "--out",
                         tmp_path / "out")
    assert code == 0, err
    res = json.loads((tmp_path / "out" / "results.json").read_text())
    rows = {m["label"]: m for m in res["models"]}
    fields = rows["effective fields (model 2)"]
    assert fields["fields_from"] == "analytic"
    assert "was made by the analytic model" in fields["fields_note"]
    assert fields["assumptions"]["points"] > 0
    assert "! effective fields (model 2)" in out
    # the same fields labelled as a DEM map's: no mark
    import xarray as xr

    with xr.open_dataset(tmp_path / "m.nc") as ds:
        dem = ds.load()
    dem.attrs["model"] = "dem"
    dem.to_netcdf(tmp_path / "m.nc")
    code, out, err = cli("report", "--scenario", tmp_path / "s.toml", "--out",
                         tmp_path / "out2")
    assert code == 0, err
    res = json.loads((tmp_path / "out2" / "results.json").read_text())
    rows = {m["label"]: m for m in res["models"]}
    assert "fields_from" not in rows["effective fields (model 2)"]
    assert "! effective fields (model 2)" not in out
