"""The page's views drawn from the design layer, without a browser: the map's cells carry
their motion mode, the points where the analytical model's assumptions fail are marked on
the map and the forced response, and the fields fidelity is offered there."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("panel")
pytest.importorskip("tomli_w")

from pdamper.explore import app, design  # noqa: E402
from pdamper.explore.design import Inputs  # noqa: E402

GRID = "3Hz:9Hz:31"


def _page(tmp_path, inputs: Inputs) -> app.Page:
    page = app.Page(inputs, app.DEMChecks(), tmp_path)
    page.inputs = inputs
    page.quick = design.quick(inputs)
    page._draw_quick()
    return page


def test_map_cells_show_their_motion_mode(tmp_path):
    page = _page(tmp_path, Inputs(frequency=GRID))
    q = page.quick
    data = page.cell_src.data
    assert len(data["mode"]) == q.map_mode.size
    # the cell at (stroke 7, frequency 5): its mode's name and colour, its eta
    k = 7 * q.map_frequency.size + 5
    code = int(q.map_mode[7, 5])
    assert data["mode"][k] == app._MODE_NAMES[code]
    assert data["colour"][k] == app._MODE_COLOURS[code]
    assert data["eta"][k] == pytest.approx(q.map_loss_factor[7, 5])
    assert len(set(data["mode"])) >= 3  # solid-like, collect-and-collide, scattering


def test_failing_assumptions_are_marked_and_the_fields_fidelity_offered(tmp_path):
    page = _page(tmp_path, Inputs(frequency=GRID))
    q = page.quick
    # the scattering cells, and only the failing ones, are marked
    assert len(page.fail_src.data["f"]) == int(np.count_nonzero(~q.map_holds)) > 0
    assert page.offer.visible and "--fields map.nc" in page.offer.object
    res = design.response(page.inputs)
    page.response = res
    page._draw_response(res)
    assert len(page.frf_fail_src.data["f"]) == int(np.count_nonzero(~res.holds))


def test_nothing_offered_where_the_assumptions_hold(tmp_path):
    page = _page(tmp_path, Inputs(frequency="3Hz:4Hz:5", load_amplitude=0.5))
    q = page.quick
    page.response = design.response(page.inputs)
    page._draw_response(page.response)
    assert len(page.frf_fail_src.data["f"]) == 0
    if q.map_holds.all():
        assert not page.offer.visible
    else:  # the map reaches strokes the path does not: only those cells are counted
        assert "0 forced-response point(s)" in page.offer.object


def test_bed_mass_slider_sets_the_count(tmp_path):
    page = _page(tmp_path, Inputs(frequency=GRID))
    page.count_from.value = "bed mass"  # the watcher schedules the views (no document)
    page.bed_mass.value = 100.0
    page._on_bed_mass()
    assert page.inputs.bed_mass == 100.0
    assert page.widgets["particles.count"].disabled
    assert page.widgets["particles.count"].value == 24  # round(100 g / 4.14 g)
    page.count_from.value = "count"
    assert page.inputs.bed_mass is None and page.bed_mass.disabled
    assert not page.widgets["particles.count"].disabled
    assert dict(page.inputs.values)["particles.count"] == 24  # the count the mass gave


def test_time_view_draws_the_simulate_run(tmp_path):
    inputs = Inputs(frequency=GRID)
    page = _page(tmp_path, inputs)
    r = design.time_response(inputs)
    page._draw_time(r)
    assert np.array_equal(page.time_src.data["x"], r.displacement * 1e3)
    assert "free decay" in page.time_plot.title.text
    assert "final amplitude" in page.time_text.object


@pytest.mark.long
def test_report_button_reports_the_saved_design(tmp_path):
    """"Report" saves the view and runs `pdamper report` on it: the report appears beside
    the saved scenario and its inputs are the page's design (28 spheres of 4.5 mm)."""
    import asyncio
    import json

    inputs = (Inputs(frequency=GRID).with_value("particles.count", 28)
              .with_value("particles.radius", 4.5))
    page = _page(tmp_path, inputs)
    page.save_path.value = str(tmp_path / "mine.toml")
    asyncio.run(page._report())
    out = tmp_path / "mine-report"
    assert (out / "report.html").is_file(), page.saved.object
    assert "report written" in page.saved.object
    saved = (tmp_path / "mine.toml").read_text()
    assert "count = 28" in saved and 'radius = "4.5 mm"' in saved
    particles = json.loads((out / "results.json").read_text())["inputs"]["particles"]
    assert particles["count"] == 28 and particles["radius"] == pytest.approx(0.0045)
    assert "paper benchmark damper" in (out / "report.html").read_text()


def test_a_design_wide_failure_is_said_once_not_marked_everywhere(tmp_path):
    page = _page(tmp_path, Inputs(frequency=GRID).with_value("particles.count", 3))
    q = page.quick
    # not a collected bed: everywhere, said once; marked only the cells failing on their
    # own too (scattering)
    own = [r for r in q.map_reasons.ravel() if "scattering" in r]
    assert len(page.fail_src.data["f"]) == len(own) < q.map_reasons.size
    assert page.offer.visible and "for this design everywhere" in page.offer.object


def test_the_page_uses_panels_current_api(tmp_path):
    """Building the page and its layout warns of nothing Panel deprecates (a widget's
    ``label``, a button's ``color``)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", PendingDeprecationWarning)
        warnings.simplefilter("error", DeprecationWarning)
        page = app.Page(Inputs(frequency=GRID), app.DEMChecks(), tmp_path)
        page.layout()
        page.load_kind.value = "base"  # relabels the load slider
    assert page.load.label == "load amplitude [mm]"
    assert page.save_button.label == "Save scenario"


def _done(value) -> app.Future:
    fut = app.Future()
    fut.set_result(value)
    return fut


def test_release_displacement_widget_sets_and_saves_the_release(tmp_path):
    page = _page(tmp_path, Inputs(frequency=GRID))
    w = page.widgets["structure.initial_displacement"]
    assert w.label.endswith("[mm]") and w.value == pytest.approx(-58.0)
    assert w.start < w.end < 0  # the declared range: < 0
    page._on_value("structure.initial_displacement")(type("E", (), {"new": -25.0})())
    assert dict(page.inputs.values)["structure.initial_displacement"] == -25.0
    page.save_path.value = str(tmp_path / "mine.toml")
    saved = page._save()
    assert saved is not None and 'initial_displacement = "-25 mm"' in saved.read_text()
    # a structure from a modes file keeps the release control (its other sliders go)
    modes = tmp_path / "modes.csv"
    modes.write_text("frequency [Hz], damping ratio [%], damper [kg^-0.5], "
                     "observation [kg^-0.5]\n5.5, 0.8, 0.2582, 0.2582\n")
    scen = tmp_path / "modal.toml"
    scen.write_text(f'[structure]\nmodes = "{modes}"\n')
    modal = app.Page(Inputs(scenario=scen, frequency=GRID), app.DEMChecks(), tmp_path)
    assert "structure.initial_displacement" in modal.widgets
    assert "structure.stiffness" not in modal.widgets


def test_a_preview_is_drawn_first_and_the_full_answer_replaces_it(tmp_path):
    inputs = Inputs(frequency="3Hz:9Hz:121")
    page = _page(tmp_path, inputs)
    page.generation = gen = 5
    first = design.preview(inputs)
    page._previewed(gen, _done(first), 0.0)
    assert len(page.frf_src["up"].data["f"]) == 21
    assert "first answer at 21 of the 121 frequencies" in page.status.object
    assert "pdamper frf --frequency 3Hz:9Hz:21" in page.status.object
    assert ": peak" not in page.peaks.object  # the peak lines shown: the full answer's
    full = design.response(inputs)
    page._solved(gen, _done(full), 0.0)
    assert len(page.frf_src["up"].data["f"]) == 121
    assert page.peaks.object.count("peak") == len(full.peak_lines)
    page._previewed(gen, _done(first), 0.0)  # late: the full answer stays
    assert len(page.frf_src["up"].data["f"]) == 121
    page._previewed(gen - 1, _done(first), 0.0)  # an older design's: not drawn
    assert len(page.frf_src["up"].data["f"]) == 121
    # the release moved: the drawn forced response is the design's; no preview, only the
    # (cached) full answer and the time view are asked for
    page._on_value("structure.initial_displacement")(type("E", (), {"new": -30.0})())
    assert [f.cancel() or f for f in page._queued] and len(page._queued) == 2
    app._SOLVER.submit(lambda: None).result()


def test_warm_up_builds_a_page_and_the_quick_views_not_the_solve(tmp_path):
    """Before the server says it is ready: a page built and the base design's quick views
    cached; no forced response solved (a page asks for it)."""
    base = Inputs(frequency="3Hz:9Hz:17", load_amplitude=1.5)
    app._SOLVER.submit(lambda: None).result()  # what earlier tests queued has run
    solved = design.response.cache_info().currsize
    app.warm(base, app.DEMChecks(), tmp_path)
    app._SOLVER.submit(lambda: None).result()  # whatever was queued has run
    assert design.response.cache_info().currsize == solved
    hits = design.quick.cache_info().hits
    design.quick(base)
    assert design.quick.cache_info().hits == hits + 1
