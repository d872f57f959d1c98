"""The page's views in headless Chromium (Playwright on Debian's chromium): what the browser
holds is what the design layer computes: the map's cells with their motion modes, the
points where the analytical assumptions fail marked and the fields fidelity offered (a
design-wide failure said once), the bed-mass slider setting the count and the forced
response, the time view with its release displacement, a large grid's first answer.

Long tests: they need the optional ``explore`` and ``browser`` dependencies, which
``.ci/run`` installs before ``pytest -m long``."""

from __future__ import annotations

import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("panel")
pytest.importorskip("tomli_w")
pytest.importorskip("playwright.sync_api")

from test_page import (  # noqa: E402
    GRID,
    _open,
    _peaks,
    _server,
    _set_frequency,
    _text,
    _wait_text,
)

from browser import chromium  # noqa: E402
from pdamper.explore import app, design  # noqa: E402
from pdamper.explore.design import Inputs  # noqa: E402
from proc import command, env  # noqa: E402

pytestmark = [pytest.mark.long,
              pytest.mark.skipif(chromium() is None, reason="chromium is not installed")]


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
        yield b
        b.close()

#: The data of the page's Bokeh source of a name, as the browser holds it.
SOURCE = """name => { for (const d of window.Bokeh.documents) {
  for (const m of d._all_models.values()) { if (m.name === name) {
    const out = {}; for (const [k, v] of Object.entries(m.data)) out[k] = Array.from(v);
    return out; } } } return null; }"""


def _source(page, name: str) -> dict:
    return page.evaluate(SOURCE, name)


def _wait(check, what: str, timeout: float = 60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = check()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"not seen in {timeout:.0f} s: {what}")


def _press(page, selector: str, key: str, times: int) -> None:
    handle = page.locator(f"{selector} .noUi-handle")
    handle.focus()
    for _ in range(times):
        page.keyboard.press(key)


def _frf_peaks(*args: object) -> list[str]:
    out = subprocess.run(command("frf", "--frequency", GRID, "--sweep", "both", *args),
                         capture_output=True, text=True, env=env(), timeout=300)
    assert out.returncode == 0, out.stderr
    return [line for line in out.stdout.splitlines() if ": peak " in line]


def test_map_marks_time_view_release_and_bed_mass_in_the_browser(tmp_path, browser):
    base = Inputs(frequency=GRID)
    q = design.quick(base)
    with _server(tmp_path) as (_, url, _ready):
        page = _open(browser, url)
        _set_frequency(page, GRID)
        _wait_text(page, ".peaks", "up: peak")
        # the map's cells: every cell with its motion mode's name and colour
        cells = _wait(lambda: (s := _source(page, "map-cells")) and
                      len(s["mode"]) == q.map_mode.size and s, "the map's cells")
        names = [app._mode_name(c) for c in q.map_mode.ravel()]
        assert cells["mode"] == names and len(set(names)) >= 3
        assert cells["colour"] == [app._MODE_COLOURS.get(int(c), "#bbbbbb")
                                   for c in q.map_mode.ravel()]
        # the cells and the forced response's points failing the assumptions, marked;
        # the fields fidelity offered with the commands that give it
        res = design.response(base)
        common = design.design_wide(q.map_reasons, res.reasons)
        assert len(_source(page, "map-fails")["f"]) == \
            int(np.count_nonzero(design.marked(q.map_reasons, common))) > 0
        _wait(lambda: len(_source(page, "frf-fails")["f"]) ==
              int(np.count_nonzero(design.marked(res.reasons, common))), "the FRF's marks")
        offer = _text(page, ".offer")
        cells_n = int(np.count_nonzero(design.marked(q.map_reasons, common)))
        points_n = int(np.count_nonzero(design.marked(res.reasons, common)))
        assert f"fail at {cells_n} map cell(s) and {points_n} forced-response point(s)" \
            in offer
        assert "--fields map.nc" in offer and "fidelity: fields" in offer
        # the mass against no limit, and the inputs the fidelity does not use
        assert design.mass_text(q, None) in _text(page, ".mass")
        notes = _text(page, ".notes")
        assert all(f"{k}: not used by the analytic fidelity" in notes for k in q.unused)
        # the time view, on its tab: pdamper simulate's decay table of the design
        page.locator(".bk-tab", has_text="in time").click()
        lines = design.time_response(base).lines
        _wait_text(page, ".time-lines", lines[-1])
        shown = [line.strip() for line in _text(page, ".time-lines").strip().splitlines()]
        assert shown == [line.strip() for line in lines]
        assert len(_source(page, "time")["x"]) == design.time_response(base).time.size
        # the release displacement: one step (0.5 mm) nearer to rest; the decay follows
        _press(page, ".ctl-structure-initial_displacement", "ArrowRight", 1)
        moved = design.time_response(base.with_value("structure.initial_displacement",
                                                     -57.5))
        _wait_text(page, ".time-lines", moved.lines[0])
        x0 = _wait(lambda: (x := _source(page, "time")["x"]) and x[0] > -57.9 and x,
                   "the release at -57.5 mm")
        assert x0[0] == pytest.approx(-57.5, abs=1e-6)
        # the bed given by its mass: 133 g -> 100 g sets 24 spheres, and the forced
        # response is `pdamper frf --particles 24`'s
        page.locator(".count-from button", has_text="bed mass").click()
        handle = page.locator(".ctl-bed-mass .noUi-handle")
        for _ in range(80):  # one gram a press, until the slider shows 100 g
            if float(handle.get_attribute("aria-valuenow")) <= 100.0:
                break
            handle.focus()
            page.keyboard.press("ArrowLeft")
            time.sleep(0.05)
        assert float(handle.get_attribute("aria-valuenow")) == 100.0
        _wait_text(page, ".ctl-particles-count", "24")
        expected = _frf_peaks("--particles", 24)
        _wait(lambda: _peaks(page) == expected, "the peak lines of 24 spheres")
        # Save scenario: the bed mass and the release written
        page.locator(".save button").click()
        saved = _wait_text(page, ".saved", "saved").split("saved ")[1].split(";")[0]
        text = Path(saved.strip().strip("`")).read_text(encoding="utf-8")
        assert "count = 24" in text and 'initial_displacement = "-57.5 mm"' in text


def test_a_design_wide_failure_said_once_and_a_first_answer(tmp_path, browser):
    """Three spheres (not a collected bed): the offer says the design-wide reason once
    and the map marks only the cells failing on their own; a 121-frequency grid shows
    its 21-frequency answer first, then the full grid's peak lines."""
    scen = tmp_path / "three.toml"
    scen.write_text("[particles]\ncount = 3\n")
    base = Inputs(scenario=scen, frequency=GRID)
    q = design.quick(base)
    with _server(tmp_path, "--scenario", scen) as (_, url, _ready):
        page = _open(browser, url)
        _set_frequency(page, GRID)
        _wait_text(page, ".peaks", "up: peak")
        offer = _wait_text(page, ".offer", "for this design everywhere")
        assert offer.count("for this design everywhere") == 1
        own = [r for r in q.map_reasons.ravel() if "scattering" in r]
        assert len(_source(page, "map-fails")["f"]) == len(own) < q.map_reasons.size
        fine = Inputs(scenario=scen, frequency="3Hz:9Hz:121")
        _set_frequency(page, "3Hz:9Hz:121")
        first = _wait_text(page, ".status", "first answer at 21 of the 121 frequencies")
        assert "pdamper frf --frequency 3Hz:9Hz:21" in first
        _wait_text(page, ".status", "forced response solved", timeout=120)
        assert len(_source(page, "frf-up")["f"]) == 121
        assert _peaks(page) == design.response(fine).peak_lines
