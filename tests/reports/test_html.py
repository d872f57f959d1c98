"""``report.html`` of ``pdamper paper``: one self-contained page (figures as base64 PNG,
the table of the paper's numbers with the agree column, models, run times, inputs,
version), checked by parsing it and by rendering it in headless Chromium."""

from __future__ import annotations

import base64
import json
from html.parser import HTMLParser

import numpy as np
import pytest

import browser
from pdamper import __version__
from pdamper.io.scenario import load_scenario
from pdamper.reports.paper_case_study import write_case_study
from pdamper.runs.paper_case_study import run_case_study


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    sc = load_scenario(None, {"map.frequency": "2Hz:20Hz:7", "map.amplitude": "2mm:200mm:9"})
    cs = run_case_study(sc, dem=False)
    out = tmp_path_factory.mktemp("paper")
    files = write_case_study(cs, out)
    return cs, out, files


class _Page(HTMLParser):
    """The parts of the page the test checks."""

    def __init__(self):
        super().__init__()
        self.images, self.links, self.scripts = [], [], 0
        self.tables, self.headers, self.rows = {}, {}, {}
        self._table = None
        self._in_th = False
        self.text = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a)
        if tag in ("link", "script", "iframe", "object", "embed") or "href" in a:
            self.links.append((tag, a))
        if tag == "script":
            self.scripts += 1
        if tag == "table":
            self._table = a.get("id")
            self.tables[self._table] = True
            self.headers[self._table], self.rows[self._table] = [], 0
        if tag == "tr" and self._table:
            self.rows[self._table] += 1
        self._in_th = tag == "th"

    def handle_endtag(self, tag):
        if tag == "table":
            self._table = None
        if tag == "th":
            self._in_th = False

    def handle_data(self, data):
        if self._in_th and self._table:
            self.headers[self._table].append(data.strip())
        self.text.append(data)


def test_report_is_written_with_the_other_files(report):
    cs, out, files = report
    assert out / "report.html" in files
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # atomic writes


def test_report_structure_is_self_contained_and_complete(report):
    """Parsed with the standard HTML parser: one embedded PNG per figure file (decodable),
    nothing fetched from anywhere (no link, script, href), the comparison table with the
    agree column and one row per reported number, the models and timing tables, the
    inputs and the version."""
    cs, out, files = report
    page = _Page()
    page.feed((out / "report.html").read_text(encoding="utf-8"))
    pngs = sorted(p.name for p in files if p.suffix == ".png")
    assert len(page.images) == len(pngs) >= 6
    for img in page.images:
        src = img["src"]
        assert src.startswith("data:image/png;base64,")
        data = base64.b64decode(src.split(",", 1)[1], validate=True)
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        assert img.get("alt")
    assert page.links == [] and page.scripts == 0
    assert page.headers["comparison"] == ["quantity", "paper", "pdamper", "agrees", "source",
                                          "note"]
    assert page.rows["comparison"] == len(cs.rows) + 1
    assert page.rows["models"] == 1 + 3  # models 3 and 2, no particles (no DEM here)
    assert page.rows["timings"] >= 1 + 5
    text = " ".join(page.text)
    assert f"pdamper {__version__}" in text
    assert "effective fields (model 2)" in text and "analytical Fig. 5 map" in text
    assert '"particles"' in text  # the inputs
    assert "http://" not in (out / "report.html").read_text()
    assert "https://" not in (out / "report.html").read_text()


def test_results_json_records_models_and_timings(report):
    _, out, _ = report
    d = json.loads((out / "results.json").read_text())
    assert {m["model"] for m in d["models"]} == {"analytic", "fields"}
    assert {"model 3", "model 2", "optimisation"} <= set(d["timings"])
    assert "fields" in d["level3_runs"]


_CHECK = """<script>
window.addEventListener("load", function () {
  var imgs = Array.prototype.slice.call(document.images);
  var loaded = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; });
  var rows = document.querySelectorAll("#comparison tbody tr").length;
  var cells = document.querySelectorAll("#comparison td.yes, #comparison td.no").length;
  var r = document.getElementById("comparison").getBoundingClientRect();
  document.body.setAttribute("data-check", JSON.stringify({images: imgs.length,
    loaded: loaded.length, widths: loaded.map(function (i) { return i.naturalWidth; }),
    rows: rows, verdicts: cells, table_height: r.height}));
});
</script>"""


@pytest.mark.skipif(browser.chromium() is None, reason="headless Chromium not installed "
                    "(Debian package 'chromium')")
def test_report_renders_in_headless_chromium(report, tmp_path):
    """Chromium (no network: everything is inside the file) decodes every image, lays out
    the comparison table, and the screenshot is not blank: it has the page's dark text
    and the figures' colours."""
    cs, out, files = report
    # 1. a copy with a probe script: what the browser made of the page
    check = browser.probe(out / "report.html", _CHECK, tmp_path)
    n_png = sum(p.suffix == ".png" for p in files)
    assert check["images"] == check["loaded"] == n_png
    assert all(w > 300 for w in check["widths"])
    assert check["rows"] == len(cs.rows)
    assert check["verdicts"] == sum(r.agrees is not None for r in cs.rows)
    assert check["table_height"] > 20 * len(cs.rows)
    # 2. a screenshot of the report itself
    img = browser.screenshot(out / "report.html", tmp_path, 6000)
    assert img.shape[0] == 6000 and img.shape[1] == 1280
    grey = img.mean(axis=2)
    assert np.mean(grey < 0.5) > 0.002           # text and lines
    colourful = (img.max(axis=2) - img.min(axis=2)) > 0.25
    assert np.mean(colourful) > 0.002            # the figures' coloured lines and maps
    assert grey.std() > 0.05                     # not a blank page
