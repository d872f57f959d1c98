"""``pdamper report`` on the machine frame (a user's modes file, a mass limit): the modal
data embedded, only the inputs it used, human units, the damping each mode gains, every
limit with its margin; rendered in headless Chromium."""

from __future__ import annotations

import json
import re

import pytest

import browser
from pdamper.parameters import vertical_dampers_paper as paper

#: The machine frame's modes (the user case machine-frame/modes.csv) with the shapes at the
#: damper and the sensor (both the tip); the motor's column is the unbalance's point, which
#: no run of this report loads.
MODES = ("frequency [Hz], damping ratio [%], damper [kg^-0.5], observation [kg^-0.5]\n"
         "12.0, 1.0, 0.2582, 0.2582\n31.0, 0.8, -0.3162, -0.3162\n")
#: The aluminium box: 60 mm cube inside, 1.5 mm walls (problem.md), by hand [kg].
BOX = 2700.0 * (0.063**3 - 0.060**3)


@pytest.fixture(scope="module")
def frame_report(tmp_path_factory):
    from pdamper.cli import main

    tmp = tmp_path_factory.mktemp("frame")
    (tmp / "modes.csv").write_text(MODES)
    (tmp / "frame.toml").write_text(f"""title = "machine frame"
[container]
length = "60 mm"
width = "60 mm"
depth = "60 mm"
material = "aluminium"
mass = "{BOX} kg"
[particles]
material = "100Cr6"
radius = "4 mm"
count = 50
[structure]
modes = "modes.csv"
initial_displacement = "-5 mm"
[simulation]
duration = "1 s"
[optimization]
objective = "peak-frf"
frf_load = "10 N"
band = "10 Hz:14 Hz:5"
max_mass = "0.5 kg"
vary = ["radius=3mm,6mm", "bed-mass=0.2kg:0.45kg:2"]
[map]
frequency = "4Hz:36Hz:5"
amplitude = "log:1mm:50mm:5"
""")
    out = tmp / "report"
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["report", "--scenario", str(tmp / "frame.toml"), "--out", str(out),
                     "--json"]) == 0
    html = (out / "report.html").read_text(encoding="utf-8")
    return out, json.loads((out / "results.json").read_text()), html, tmp


def _text(html: str) -> str:
    return re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))


def test_the_report_holds_no_input_it_did_not_use(frame_report):
    _, results, html, _ = frame_report
    structure = results["inputs"]["structure"]
    assert not {"mass", "stiffness", "damping"} & set(structure)
    for key in ("structure.stiffness", "structure.damping", "particles.friction", "dem",
                "restitution", "load"):
        assert key in results["inputs_not_used"]
    assert "dem" not in results["inputs"] and "restitution" not in results["inputs"]
    assert "friction" not in results["inputs"]["particles"]
    # the paper's structure is nowhere on the page: not its stiffness, nor its damping
    assert f"{paper.PAPER_STIFFNESS:g}" not in html
    assert f'"damping": {paper.PAPER_DAMPING}' not in html
    assert "restitution_pp" not in html


def test_the_modal_data_are_embedded_not_a_path(frame_report):
    _, results, html, tmp = frame_report
    text = (tmp / "modes.csv").read_text()
    assert results["embedded_files"]["modes"] == {"name": "modes.csv", "text": text}
    for row in text.splitlines():
        assert row in html
    modes = results["structure"]["modes"]
    assert [m["frequency"] for m in modes] == [12.0, 31.0]
    assert [m["damping_ratio"] for m in modes] == pytest.approx([0.010, 0.008])
    assert modes[0]["mass_at_damper"] == pytest.approx(15.0, rel=1e-4)  # problem.md
    page = _text(html)
    assert "f = 12 Hz, damping ratio 1 %" in page and "f = 31 Hz, damping ratio 0.8 %" in page


def test_the_damping_each_mode_gains_is_the_hand_estimate(frame_report):
    _, results, html, _ = frame_report
    from pdamper.materials import get_material

    rho = get_material("100Cr6").density
    bed = 50 * rho * 4 / 3 * 3.141592653589793 * 0.004**3  # 50 spheres of 100Cr6, 4 mm
    gains = results["mode_damping"]
    assert [g["mode"] for g in gains] == [1, 2]
    # problem.md: zeta_add = eta m_bed / (2 M), M = 15 kg (mode 1), 10 kg (mode 2), with the
    # box's mass added at the damper's point (a modes file does not include it): the mass
    # referred to the tip grows by about the box's (the modes barely change shape)
    box = results["structure"]["with_container"]["container_mass"]
    used = results["structure"]["with_container"]["modes"]
    for g, m, u in zip(gains, (15.0, 10.0), used, strict=True):
        assert u["mass_at_damper"] == pytest.approx(m + box, rel=0.02)
        assert g["added"] == pytest.approx(g["loss_factor"] * bed / (2 * u["mass_at_damper"]),
                                           rel=2e-3)
        assert g["total"] == pytest.approx(g["damping_ratio"] + g["added"])
    assert 0.003 < gains[0]["added"] < 0.006  # about 0.4 % for 105 g at eta about 1.2
    assert "damping the damper adds to mode 1" in _text(html)


def test_every_limit_with_its_margin_in_human_units(frame_report):
    _, results, html, _ = frame_report
    st = results["design_study"]
    assert st["limits"][0]["quantity"] == "mass"
    best = st["best"]
    assert best["total_mass"] <= 0.5
    assert best["container_mass"] == pytest.approx(BOX)
    page = _text(html)
    assert "Limits: mass &lt;= 500 g" in page or "Limits: mass <= 500 g" in page
    margin = 0.5 - best["total_mass"]
    assert f"{margin * 1e3:.4g} g" in page  # the best's margin, in grams
    assert "radius [mm]" in page and "bed_mass [g]" in page
    assert not re.search(r"radius = 0\.0\d", page)  # no metres beside grams
    assert 'id="limits"' in html


@pytest.mark.skipif(browser.chromium() is None, reason="headless Chromium not installed")
def test_the_machine_frame_report_renders_in_chromium(frame_report, tmp_path):
    out, results, html, _ = frame_report
    check = browser.probe(out / "report.html", """<script>
window.addEventListener("load", function () {
  var imgs = Array.prototype.slice.call(document.images);
  var tables = Array.prototype.slice.call(document.querySelectorAll("table"));
  document.body.setAttribute("data-check", JSON.stringify({images: imgs.length,
    loaded: imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length,
    tables: tables.length, heights: tables.map(function (t) {
      return t.getBoundingClientRect().height; })}));
});
</script>""", tmp_path)
    assert check["images"] == check["loaded"] == len(results["figures"])
    assert "design_landscape" in results["figures"]
    assert check["tables"] == html.count("<table")
    assert all(h > 20 for h in check["heights"])
