"""The page's design layer against the command line: the numbers ``pdamper explore`` shows
are ``pdamper frf``'s for the same design, and a saved scenario reproduces them."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest

from pdamper.errors import InputError

pytest.importorskip("tomli_w")

from pdamper.explore import design  # noqa: E402
from pdamper.explore.design import Inputs  # noqa: E402
from proc import command, env  # noqa: E402

GRID = "3Hz:9Hz:31"


def _frf_lines(*args: object) -> list[str]:
    out = subprocess.run(command("frf", "--frequency", GRID, "--sweep", "both", *args),
                         capture_output=True, text=True, env=env(), timeout=300)
    assert out.returncode == 0, out.stderr
    return [line for line in out.stdout.splitlines() if ": peak " in line]


def test_peak_lines_are_the_commands_for_a_changed_count():
    base = Inputs(frequency=GRID)
    more = base.with_value("particles.count", 40)
    shown = design.response(more).peak_lines
    assert shown == _frf_lines("--particles", 40)
    # more spheres, a lower peak (the direction the command gives too)
    peak = [float(line.split("peak ")[1].split(" mm")[0]) for line in shown]
    peak0 = [float(line.split("peak ")[1].split(" mm")[0])
             for line in design.response(base).peak_lines]
    assert all(a < b for a, b in zip(peak, peak0, strict=True))


def test_saved_scenario_reproduces_the_view(tmp_path):
    view = (Inputs(frequency=GRID).with_value("particles.count", 28)
            .with_value("particles.radius", 4.5).with_value("container.length", 110.0))
    path = design.save_scenario(view, tmp_path / "explored.toml")
    text = path.read_text()
    assert 'radius = "4.5 mm"' in text and "count = 28" in text
    assert design.response(view).peak_lines == _frf_lines("--scenario", path, "--force", "2N")


def test_bare_curve_is_the_closed_form_1dof():
    sc = design.scenario_of(Inputs(frequency=GRID))
    q = design.quick(Inputs(frequency=GRID))
    m = sc.structure_model()
    k, d = m.stiffness, m.damping
    w = 2 * np.pi * q.frequency
    closed = 2.0 / np.abs(k - m.mass * w**2 + 1j * d * w)  # 2 N at the damper's point
    np.testing.assert_allclose(q.bare, closed, rtol=1e-9)


def test_level2_map_is_the_models_response():
    inputs = Inputs(frequency=GRID)
    q = design.quick(inputs)
    sc = design.scenario_of(inputs)
    r = sc.model("analytic", sc.damper()).response(q.map_frequency[5], q.map_stroke[7])
    assert q.map_loss_factor[7, 5] == pytest.approx(float(np.ravel(r.loss_factor)[0]))
    assert q.map_mode[7, 5] == int(np.ravel(r.mode)[0])


def test_mass_against_a_limit():
    q = design.quick(Inputs(frequency=GRID).with_value("container.mass", 80.0))
    assert q.container_mass == pytest.approx(0.080)
    total = q.bed_mass + q.container_mass
    assert f"= {total * 1e3:.1f} g" in design.mass_text(q, 0.5)
    assert "exceeded by" in design.mass_text(q, 0.1)
    assert "met by" in design.mass_text(q, 0.5)


def test_bad_values_get_the_command_lines_message():
    with pytest.raises(InputError) as err:
        design.quick(Inputs(frequency=GRID).with_value("particles.count", 500))
    assert err.value.field == "particles.count" and "must be in [0, " in str(err.value)
    with pytest.raises(InputError) as err:
        design.quick(Inputs(frequency="3Hz:9Hz:0"))
    assert err.value.field == "frequency"


def test_a_scenario_that_would_not_load_is_not_written(tmp_path):
    view = Inputs(frequency=GRID).with_value("particles.radius", -1.0)
    with pytest.raises(InputError):
        design.save_scenario(view, tmp_path / "bad.toml")
    assert list(tmp_path.iterdir()) == []


def test_slider_spans_hold_the_scenarios_value_and_the_declared_range():
    for c in design.CONTROLS:
        decl = c.declaration()
        assert decl.unit in ("1", "m", "kg", "N/m", "kg/s"), c.key
        lo, hi = design.span(c, 1e9)
        assert hi >= 1e9
    lo, hi = design.span(design.CONTROL["structure.stiffness"], 1848.0)
    assert (lo, hi) == pytest.approx((184.8, 18480.0))


def test_machine_frame_unbalance_on_two_modes_is_the_commands(tmp_path):
    """A user's scenario (two modes, the load at the motor), the unbalance load: the page's
    peak lines are `pdamper frf --unbalance`'s."""
    from pathlib import Path

    import pdamper

    example = Path(pdamper.__file__).parents[2] / "examples" / "machine-frame" / "scenario.toml"
    view = Inputs(scenario=example, load_kind="unbalance", load_amplitude=1.76,
                  frequency="10Hz:14Hz:17", sweep="up")
    shown = design.response(view).peak_lines
    out = subprocess.run(command("frf", "--scenario", example, "--unbalance", "1.76kg*mm",
                                 "--frequency", "10Hz:14Hz:17", "--sweep", "up"),
                         capture_output=True, text=True, env=env(), timeout=300)
    assert out.returncode == 0, out.stderr
    assert shown == [line for line in out.stdout.splitlines() if ": peak " in line]
    assert view.command(Path("f.toml")).startswith("pdamper frf --scenario f.toml "
                                                   "--unbalance 1.76kg*mm")


def test_inputs_the_fidelity_does_not_use_are_named_with_who_uses_them():
    q = design.quick(Inputs(frequency=GRID))
    assert "particles.friction" in q.unused and "dem" in q.unused["particles.friction"]


def test_a_saved_user_scenario_keeps_its_files(tmp_path):
    """The machine frame's modes and shock files are found from the saved copy elsewhere."""
    import tomllib
    from pathlib import Path

    import pdamper

    example = Path(pdamper.__file__).parents[2] / "examples" / "machine-frame" / "scenario.toml"
    path = design.save_scenario(Inputs(scenario=example).with_value("particles.count", 150),
                                tmp_path / "frame.toml")
    saved = tomllib.loads(path.read_text())
    assert Path(saved["structure"]["modes"]) == (example.parent / "modes.csv").resolve()
    assert Path(saved["load"]["force"]) == (example.parent / "shock.csv").resolve()
    assert saved["particles"]["count"] == 150


def test_the_page_starts_from_the_scenarios_frf_load():
    from pathlib import Path

    import pdamper

    example = Path(pdamper.__file__).parents[2] / "examples" / "machine-frame" / "scenario.toml"
    start = design.scenario_load(Inputs(scenario=example))
    assert (start.load_kind, start.load_text()) == ("unbalance", "1.76kg*mm")
    assert design.scenario_load(Inputs()).load_text() == "2N"  # the paper's: no [frf]


def test_map_cells_carry_the_models_assumptions():
    """Where the analytical model's assumptions fail (a bed of fewer spheres than a layer
    everywhere; a scattering bed), the map's cells say so with the model's reasons."""
    inputs = Inputs(frequency=GRID)
    q = design.quick(inputs)
    sc = design.scenario_of(inputs)
    F, X = np.meshgrid(q.map_frequency, q.map_stroke)
    d = sc.model("analytic", sc.damper()).response(F, X).diagnostics
    assert np.array_equal(q.map_holds, d["assumptions_hold"])
    assert np.array_equal(q.map_reasons, d["assumptions"])
    # scattering cells are among the failing ones, with the reason the model gives
    scattering = q.map_mode == 5
    assert scattering.any() and not q.map_holds[scattering].any()
    few = design.quick(inputs.with_value("particles.count", 3))
    assert not few.map_holds.any()
    assert all("not a collected bed" in r for r in few.map_reasons.ravel())


def test_failing_points_offer_the_fields_fidelity():
    # three spheres: not a collected bed anywhere, said once for the design, no point marked
    few = Inputs(frequency=GRID).with_value("particles.count", 3)
    res = design.response(few)
    assert res.holds is not None and not res.holds.any()  # every point of the path
    q = design.quick(few)
    common = design.design_wide(q.map_reasons, res.reasons)
    assert len(common) == 1 and common[0].startswith("not a collected bed")
    assert not design.marked(res.reasons, common).any()
    line = design.fields_offer(q, res, "analytic")
    assert line.startswith("the analytic fidelity's assumptions fail for this design "
                           "everywhere: not a collected bed (3 sphere(s)")
    assert "--fields map.nc" in line
    # the paper's damper: its scattering cells fail on their own, counted and marked
    paper = Inputs(frequency=GRID)
    qp, rp = design.quick(paper), design.response(paper)
    assert design.design_wide(qp.map_reasons, rp.reasons) == []
    cells = int(np.count_nonzero(~qp.map_holds))
    points = int(np.count_nonzero(~rp.holds))
    assert cells > 0
    assert (f"the analytic fidelity's assumptions fail at {cells} map cell(s) and {points} "
            "forced-response point(s) (marked x): scattering") in \
        design.fields_offer(qp, rp, "analytic")
    # a low load: the path stays where the model holds
    calm = Inputs(frequency="3Hz:4Hz:5", load_amplitude=0.5)
    r = design.response(calm)
    assert r.holds is not None and r.holds.all()


def test_bed_mass_derives_the_count_as_optimize_does(tmp_path):
    """A bed mass instead of a count: the nearest whole number of spheres of the radius and
    material set (the count of `pdamper optimize`'s bed-mass variable), kept as the radius
    changes, refused naming the bed mass where it needs more spheres than fit."""
    import math

    steel = design.scenario_of(Inputs()).damper()
    sphere = steel.particle_mass  # 4/3 pi r^3 rho of the paper's spheres
    view = Inputs(frequency=GRID, bed_mass=100.0)
    d = design.scenario_of(view).damper()
    assert d.count == round(0.100 / sphere) == 24
    small = design.scenario_of(view.with_value("particles.radius", 3.0)).damper()
    assert small.count == round(0.100 / (sphere * (3.0 / (steel.particle_radius * 1e3)) ** 3))
    assert abs(small.bed_mass - 0.100) < small.particle_mass  # the mass kept, not the count
    assert math.isclose(design.quick(view).bed_mass, d.bed_mass)
    with pytest.raises(InputError) as err:
        design.scenario_of(Inputs(bed_mass=5000.0))
    assert err.value.field == "bed_mass" and "must be at most" in str(err.value)
    saved = design.save_scenario(view, tmp_path / "by_mass.toml").read_text()
    assert "count = 24" in saved


def _simulate(*args: object) -> list[str]:
    out = subprocess.run(command("simulate", *args), capture_output=True, text=True, env=env(),
                         timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout.splitlines()


def test_free_decay_is_the_simulate_commands(tmp_path):
    """The time view of a changed design is `pdamper simulate`'s release of the saved
    scenario: the same decay table, digit for digit, and the trajectory it is read from."""
    view = Inputs(frequency=GRID).with_value("particles.count", 40)
    shown = design.time_response(view)
    assert shown.kind == "release"
    path = design.save_scenario(view, tmp_path / "decay.toml")
    printed = _simulate("--scenario", path)
    assert shown.lines == printed[2:]  # after the structure's line and the model's
    assert "AnalyticalDamper(count=40)" in printed[1]
    first = [float(v) for v in printed[3].split()[:2]]
    assert first == [0.0, pytest.approx(abs(shown.displacement[0]) * 1e3, abs=0.005)]


def test_load_response_is_the_simulate_commands():
    """The machine frame's [load] (its shock): the page's line is `pdamper simulate`'s."""
    from pathlib import Path

    import pdamper

    example = Path(pdamper.__file__).parents[2] / "examples" / "machine-frame" / "scenario.toml"
    shown = design.time_response(Inputs(scenario=example).with_value("particles.count", 150))
    assert shown.kind == "load"
    printed = _simulate("--scenario", example, "--particles", 150)
    model_line = [line for line in printed if line.startswith("AnalyticalDamper(count=150)")]
    assert model_line and model_line[0].split("): ", 1)[1].startswith(shown.lines[0])
    assert shown.time[-1] == pytest.approx(1.05, abs=1e-3)  # the 50 ms record + 1 s tail


def test_release_displacement_is_set_saved_and_released_from(tmp_path):
    """The free decay's release point is a control in mm within the declared range
    (< 0): the saved scenario carries it, `pdamper simulate` of that file prints the
    page's decay table, and the decay starts there; the forced response and the map are
    the design's, not solved again."""
    from pdamper.io.scenario import load_scenario

    c = design.CONTROL["structure.initial_displacement"]
    assert c.unit == "mm" and c.declaration().allowed == "< 0" and c.high < 0
    view = Inputs(frequency=GRID).with_value("structure.initial_displacement", -30.0)
    path = design.save_scenario(view, tmp_path / "release.toml")
    assert 'initial_displacement = "-30 mm"' in path.read_text()
    assert load_scenario(path).structure.initial_displacement == pytest.approx(-0.030)
    shown = design.time_response(view)
    assert shown.displacement[0] == pytest.approx(-0.030, rel=1e-9)
    assert shown.lines == _simulate("--scenario", path)[2:]
    base = Inputs(frequency=GRID)
    assert design.response(view) is design.response(base)
    assert design.quick(view) is design.quick(base)
    with pytest.raises(InputError) as err:  # the command line's message, naming the key
        design.quick(base.with_value("structure.initial_displacement", 5.0))
    assert err.value.field == "structure.initial_displacement"


def test_preview_is_the_command_on_a_coarser_grid_of_the_same_band():
    """A large grid's first answer is `pdamper frf --frequency` on every k-th of its
    frequencies (121 -> 21, the same ends): its peak lines are the command's for that grid;
    a grid of fewer than twice the preview's points has none."""
    view = Inputs(frequency="3Hz:9Hz:121").with_value("particles.count", 40)
    first = design.preview(view)
    assert first is not None and first.grid == "3Hz:9Hz:21" and first.of == 121
    assert first.frf.frequency.size == 21
    cli = subprocess.run(command("frf", "--frequency", "3Hz:9Hz:21", "--sweep", "both",
                                 "--particles", 40), capture_output=True, text=True,
                         env=env(), timeout=300)
    assert first.peak_lines == [line for line in cli.stdout.splitlines() if ": peak " in line]
    assert design.preview(Inputs(frequency=GRID)) is None  # 31 points: answered at once
    assert design.preview_inputs(Inputs(frequency="8Hz:40Hz:161")).frequency == "8Hz:40Hz:21"
    # no coarser start:stop:count of the same points (41 is prime): 21 over the band
    assert design.preview_inputs(Inputs(frequency="3Hz:9Hz:42")).frequency == "3Hz:9Hz:21"
    assert list(design.preview_grid(42)) == [*range(0, 40, 3), 41]
    # the command's default grid (dense at the mode): 21 evenly over its band
    default = design.preview(Inputs())
    grid = design.quick(Inputs()).frequency
    assert default.of == grid.size and default.grid == \
        f"{grid[0]:.6g}Hz:{grid[-1]:.6g}Hz:21" == "2.78Hz:8.34Hz:21"
    assert default.frf.frequency.size == 21
