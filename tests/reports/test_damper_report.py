"""``pdamper report``: one self-contained report.html of any scenario, checked by parsing
it and by rendering it in headless Chromium."""

from __future__ import annotations

import base64
import json
import math
from html.parser import HTMLParser

import numpy as np
import pytest

import browser
from pdamper import __version__


class _Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links, self.scripts, self.tables, self.rows = [], [], 0, [], {}
        self.headings, self._h2, self.text = [], False, []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a)
        if tag in ("link", "script", "iframe", "object", "embed") or "href" in a:
            self.links.append(tag)
        if tag == "table":
            self.tables.append(a.get("id"))
            self.rows[a.get("id")] = 0
        if tag == "tr":
            self.rows[self.tables[-1]] += 1
        self._h2 = tag == "h2"

    def handle_endtag(self, tag):
        if tag == "h2":
            self._h2 = False

    def handle_data(self, data):
        if self._h2:
            self.headings.append(data.strip())
        self.text.append(data)


#: A scenario of the user's own: an inline material, a modal structure from a CSV file, a
#: particle-count study, a friction coefficient and a container length with a standard
#: deviation.
_USER = """title = "my PMMA damper on a two-mode panel"
[container]
length = "90 mm +- 0.3 mm"
width = "40 mm"
depth = "40 mm"
material = { name = "my PMMA", youngs_modulus = "3.2 GPa", poisson_ratio = 0.35, \
density = "1190 kg/m^3", yield_strength = "70 MPa" }
[particles]
count = 24
radius = "4 mm"
material = { name = "my steel", youngs_modulus = "200 GPa", poisson_ratio = 0.29, \
density = "7850 kg/m^3" }
friction = "0.1 +- 0.03"
[structure]
modes = "modes.csv"
initial_displacement = "-40 mm"  # double CaC first: the clearance matters
[simulation]
duration = "1.2 s"
[optimization]
at = "0.6 s"
vary = ["particles=0:60:12"]
[map]
frequency = "2Hz:20Hz:8"
amplitude = "log:1mm:100mm:10"
"""
_MODES = ("frequency [Hz], damping ratio [1], damper [kg^-0.5]\n"
          "6.0, 0.005, 0.9\n17.5, 0.008, 0.5\n")


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """The example scenario (as `pdamper example-scenario` prints it) and the user's."""
    from pdamper.cli import main

    tmp = tmp_path_factory.mktemp("report")
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["example-scenario"]) == 0
    (tmp / "example.toml").write_text(buf.getvalue())
    (tmp / "user.toml").write_text(_USER)
    (tmp / "modes.csv").write_text(_MODES)
    out = {}
    for name, extra in (("example", []), ("user", ["--uncertainty", "8"])):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            code = main(["report", "--scenario", str(tmp / f"{name}.toml"), "--out",
                         str(tmp / name), "--json", *extra])
        assert code == 0
        out[name] = (tmp / name, json.loads(buf.getvalue()))
    return out


def _page(path):
    page = _Page()
    page.feed((path / "report.html").read_text(encoding="utf-8"))
    return page


@pytest.mark.parametrize("name", ["example", "user"])
def test_every_figure_and_table_is_in_the_page(reports, name):
    out, payload = reports[name]
    page = _page(out)
    figures = payload["figures"]
    expected = ["level2_map", "free_decay", "design_landscape"] + (
        ["uncertainty"] if name == "user" else []) + ["forced_response"]
    assert figures == expected
    assert len(page.images) == len(figures)
    for img in page.images:
        data = base64.b64decode(img["src"].split(",", 1)[1], validate=True)
        assert img["src"].startswith("data:image/png;base64,") and data[:8] == b"\x89PNG\r\n\x1a\n"
    assert page.links == [] and page.scripts == 0  # self-contained
    tables = ["inputs", "models", "landscape", "timings", "forced_response"] + (
        ["uncertain_inputs", "uncertainty", "sobol_indices"] if name == "user" else [])
    assert sorted(page.tables) == sorted(tables)
    assert page.rows["models"] == 1 + 2  # models 3 and 2
    for h in ("Inputs", "Level II: the damper under harmonic excitation",
              "Level III: free decay, the models compared", "Design landscape", "Uncertainty",
              "Forced response", "Run times", "All inputs"):
        assert h in page.headings
    text = " ".join(page.text)
    assert f"pdamper {__version__}" in text and "dem.seed = 0" in text


def test_the_user_scenario_is_what_the_report_shows(reports):
    out, _ = reports["user"]
    text = " ".join(_page(out).text)
    d = json.loads((out / "results.json").read_text())
    assert "my steel" in text and "my PMMA" in text
    assert "particles.friction = 0.1 +- 0.03" in text  # the inputs table keeps the sd
    assert "2 mode(s) at 6, 17.5 Hz" in text
    st = d["design_study"]
    assert [c["particles"] for c in st["candidates"]] == [0, 12, 24, 36, 48, 60]
    assert st["front"] and st["best"] and st["lightest_within"]
    assert _page(out).rows["landscape"] == 1 + 6
    u = d["uncertainty"]["level3"]
    assert u["points"] == 8 and u["seed"] == 0
    assert {i["field"] for i in u["inputs"]} == {"container.length", "particles.friction"}
    amp = u["answers"]["amplitude_at"]
    assert amp["driver"] == "container.length"  # friction does not enter the analytic model
    assert amp["total_order"]["particles.friction"] == 0.0
    assert d["at"] == 0.6 and d["version"] == __version__
    band = u["bands"]["envelope"]  # the band of the free decay's envelope
    assert len(band["time"]) == len(band["p5"]) == len(band["p95"]) > 10
    assert band["time"][-1] == pytest.approx(1.2)
    assert all(lo <= m <= hi for lo, m, hi in zip(band["p5"], band["p50"], band["p95"],
                                                  strict=True))
    assert band["nominal"][0] == pytest.approx(0.04)  # released from -40 mm
    assert max(h - lo for lo, h in zip(band["p5"], band["p95"], strict=True)) > 0


def test_example_report_has_the_papers_landscape(reports):
    out, payload = reports["example"]
    d = json.loads((out / "results.json").read_text())
    st = d["design_study"]
    assert st["best"]["particles"] == 112
    assert st["lightest_within"]["particles"] <= st["best"]["particles"]
    assert "No input of this scenario carries an uncertainty" in " ".join(_page(out).text)
    assert "DEM (model 1)" not in " ".join(_page(out).text)  # by default: no DEM run


_CHECK = """<script>
window.addEventListener("load", function () {
  var imgs = Array.prototype.slice.call(document.images);
  var loaded = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; });
  var tables = Array.prototype.slice.call(document.querySelectorAll("table"));
  document.body.setAttribute("data-check", JSON.stringify({images: imgs.length,
    loaded: loaded.length, widths: loaded.map(function (i) { return i.naturalWidth; }),
    tables: tables.length, heights: tables.map(function (t) {
      return t.getBoundingClientRect().height; })}));
});
</script>"""


@pytest.mark.skipif(browser.chromium() is None, reason="headless Chromium not installed "
                    "(Debian package 'chromium')")
@pytest.mark.parametrize("name", ["example", "user"])
def test_report_renders_in_headless_chromium(reports, name, tmp_path):
    out, payload = reports[name]
    check = browser.probe(out / "report.html", _CHECK, tmp_path)
    assert check["images"] == check["loaded"] == len(payload["figures"])
    assert all(w > 300 for w in check["widths"])
    assert check["tables"] == len(_page(out).tables)
    assert all(h > 20 for h in check["heights"])  # every table laid out with rows
    img = browser.screenshot(out / "report.html", tmp_path, 5000)
    assert img.shape[:2] == (5000, 1280)
    grey = img.mean(axis=2)
    assert np.mean(grey < 0.5) > 0.002  # text and lines
    assert np.mean((img.max(axis=2) - img.min(axis=2)) > 0.25) > 0.002  # the figures' colours
    assert grey.std() > 0.05  # not a blank page


def test_forced_response_of_the_example_damper(reports):
    """The load drives the bare 1-DOF to the release amplitude at resonance: |F| = D w_n |x0|
    (|H(w_n)| = 1 / (D w_n) of Eq. 23); the bare peak is then |x0| (the grid holds f_n;
    the damped peak lies a hair below it, at most 1 + zeta^2 higher); the damper lowers it."""
    _, payload = reports["example"]
    out, _ = reports["example"]
    fr = json.loads((out / "results.json").read_text())["forced_response"]
    from pdamper.parameters import vertical_dampers_paper as paper

    s = paper.PAPER_STRUCTURE
    w_n = math.sqrt(s.stiffness / s.mass)
    x0 = 0.058
    assert fr["load"]["amplitude"] == pytest.approx(s.damping * w_n * x0, rel=1e-9)
    assert fr["no_particles"]["peak_amplitude"] == pytest.approx(x0, rel=1e-3)
    assert fr["no_particles"]["peak_frequency"] == pytest.approx(w_n / (2 * math.pi), rel=0.01)
    f_n = w_n / (2 * math.pi)
    for label in ("analytical formulas (model 3)", "effective fields (model 2)"):
        m = fr["models"][label]
        # every mode of the structure, its resonance resolved for its damping
        # (default_frequencies): from half the first to 1.5 times the last mode
        assert m["frequency_range"] == pytest.approx([0.5 * f_n, 1.5 * f_n], rel=1e-9)
        assert m["points"] > 81
        assert 0.1 * x0 < m["peak_amplitude"] < 0.5 * x0  # 32 spheres damp the resonance


@pytest.mark.long
def test_dem_realisations_band_in_the_report(tmp_path, cli):
    """--dem --realisations 2: model 1 from two random packings, its band in the page and
    in results.json (each realisation equals that seed's run alone: the Level III
    realisation tests; here the band reaches the report)."""
    (tmp_path / "s.toml").write_text(
        '[particles]\ncount = 16\n[simulation]\nduration = "0.6 s"\n[optimization]\n'
        'at = "0.3 s"\n[map]\ndem_frequency = "5Hz:6Hz:2"\ndem_amplitude = "20mm:40mm:2"\n'
        '[dem]\npacking = "random"\ncycles = 4\n')
    code, out, err = cli("report", "--scenario", tmp_path / "s.toml", "--out", tmp_path / "r",
                         "--dem", "--realisations", "2", "--workers", "1", "--json")
    assert code == 0, err
    payload = json.loads(out)
    assert "realisations" in payload["figures"]
    res = json.loads((tmp_path / "r" / "results.json").read_text())["realisations"]
    assert res["count"] == 2 and res["seeds"] == [0, 1]
    a = res["amplitude_at"]
    assert a["min"] <= a["mean"] <= a["max"] and len(a["values"]) == 2
    assert "realisations" in _page(tmp_path / "r").tables


def test_realisations_need_the_dem(tmp_path, cli):
    code, _, err = cli("report", "--out", tmp_path / "r", "--realisations", "3")
    assert code == 2 and err.startswith("error: realisations:")
    assert not (tmp_path / "r").exists()


def test_merge_sections_joins_the_page(reports):
    from pdamper.reports.damper_report import merge_sections

    assert merge_sections() == []
    assert merge_sections("<h2>Forced response</h2>", None) == ["<h2>Forced response</h2>"]


def test_bad_uncertainty_is_refused_before_any_output(tmp_path, cli):
    code, _, err = cli("report", "--out", tmp_path / "r", "--uncertain",
                       "particles.friction=0.1+-0.03", "--uncertainty", "12")
    assert code == 2 and err.startswith("error: uncertainty:")
    assert not (tmp_path / "r").exists()


def test_uncertainty_tables_read_in_mm_and_g(reports):
    """The uncertainty tables show lengths in mm and masses in g (JSON keeps SI): the
    user's container length of 90 mm +- 0.3 mm is a row "90 | 0.3 | mm"."""
    import re

    out, payload = reports["user"]
    html = (out / "report.html").read_text(encoding="utf-8")
    table = re.search(r'<table id="uncertain_inputs">(.*?)</table>', html, re.S).group(1)
    row = re.search(r"<tr><td>container\.length</td>(.*?)</tr>", table).group(1)
    cells = re.findall(r"<td[^>]*>(.*?)</td>", row)
    assert cells[:3] == ["90", "0.3", "mm"], cells
    answers = re.search(r'<table id="uncertainty">(.*?)</table>', html, re.S).group(1)
    units = set(re.findall(r"<tr><td>[^<]*</td><td>[^<]*</td><td>([^<]*)</td>", answers))
    assert "m" not in units and "kg" not in units and "J" not in units, units
