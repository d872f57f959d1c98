"""Scenario files: units at the edge, validation with one-line errors."""

import tomllib

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.io.scenario import EXAMPLE_SCENARIO, Scenario, load_scenario
from pdamper.runs.resources import check_resources
from pdamper.units import format_quantity, parse_quantity, parse_range


def test_example_scenario_is_valid_and_equals_the_defaults():
    assert Scenario.model_validate(tomllib.loads(EXAMPLE_SCENARIO)) == Scenario()


def test_quantities_with_units_become_si(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text('[container]\nlength = "12 cm"\n[particles]\nradius = "0.5 cm"\n'
                 'material = { name = "glass", youngs_modulus = "63 GPa", poisson_ratio = 0.2,'
                 ' density = "2.5 g/cm^3" }\n[excitation]\nfrequency = "600 1/min"\n')
    s = load_scenario(p)
    assert s.container.length == pytest.approx(0.12)
    assert s.particles.radius == pytest.approx(0.005)
    assert s.excitation.frequency == pytest.approx(10.0)
    d = s.damper()
    assert d.particle_material.density == pytest.approx(2500.0)
    assert d.particle_material.youngs_modulus == pytest.approx(63e9)


def test_units_round_trip():
    assert parse_quantity("32 mm", "m", "x") == pytest.approx(0.032)
    assert format_quantity(0.032, "mm") == "32 mm"
    assert parse_range("2Hz:20Hz:14", "Hz", "f") == (2.0, 20.0, 14)


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ('[container]\nlength = "-120 mm"', "container.length"),
        ('[particles]\nradius = "-5 mm"', "particles.radius"),
        ("[particles]\ncount = 200", "particles.count"),
        ('[excitation]\nfrequency = "0 Hz"', "excitation.frequency"),
        ('[excitation]\namplitude = "3 smoots2"', "excitation.amplitude"),
        ('[excitation]\namplitude = "3 s"', "excitation.amplitude"),
        ('[excitation]\nfrequency = "nan Hz"', "excitation.frequency"),
        ('[structure]\ninitial_displacement = "58 mm"', "structure.initial_displacement"),
        ("[particles]\ncolour = 'red'", "particles.colour"),
        ('[particles]\nmaterial = "unobtainium"', "particles.material"),
        ("[excitation\nfrequency = 1", "scenario"),
        ("[particles]\nradius = \"25 mm\"", "particles.radius"),
    ],
    ids=["negative-length", "negative-radius", "too-many-particles", "zero-frequency",
         "unknown-unit", "wrong-dimension", "nan", "positive-x0", "unknown-key",
         "unknown-material", "malformed-toml", "sphere-does-not-fit"],
)
def test_bad_scenarios_name_the_field(tmp_path, text, field):
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(InputError) as info:
        load_scenario(p).damper()
    assert str(info.value).startswith(field)
    assert "\n" not in str(info.value)


def test_missing_scenario_file():
    with pytest.raises(InputError, match="not found"):
        load_scenario("/nonexistent/scenario.toml")


@pytest.mark.parametrize(("text", "field"), [
    ('[particles]\nmaterial = { name = "g", youngs_modulus = "63 GPa", poisson_ratio = 0.5, '
     'density = "2500 kg/m^3" }', "particles.material.poisson_ratio"),
    ('[container]\nmaterial = { name = "g", youngs_modulus = "63 GPa", poisson_ratio = 0.2, '
     'density = "-2500 kg/m^3" }', "container.material.density"),
    ('[particles]\nmaterial = { name = "g", youngs_modulus = "63 GPa", poisson_ratio = 0.2, '
     'density = "2500 kg/m^3", colour = "red" }', "particles.material.colour"),
    ('[particles]\nmaterial = { name = "g", poisson_ratio = 0.2, density = "2500 kg/m^3" }',
     "particles.material.youngs_modulus"),
    ("[particles]\nmaterial = 5", "particles.material"),
], ids=["poisson", "density", "unknown-key", "missing-key", "not-a-table"])
def test_errors_inside_an_inline_material_name_the_sub_key(tmp_path, text, field):
    """Every such error once read "particles.material: Input should be a valid
    string"."""
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(InputError) as info:
        load_scenario(p)
    assert info.value.field == field, str(info.value)
    assert "valid string" not in info.value.message


@pytest.mark.parametrize(("text", "field"), [
    ('[map]\nfrequency = "2Hz::5"', "map.frequency"),
    ('[map]\namplitude = "1mm:200mm"', "map.amplitude"),
    ('[map]\nfrequency = "20Hz:2Hz:5"', "map.frequency"),
    ('[map]\nfrequency = "2Hz:1e300Hz:3"', "map.frequency"),
    ('[particles]\nradius = "1 um"', "particles.radius"),
    ('[excitation]\nfrequency = "Hz"', "excitation.frequency"),
    ('[structure]\ninitial_displacement = "-1e300 m"', "structure.initial_displacement"),
    ('[structure]\nstiffness = "1e20 N/m"', "structure.stiffness"),
], ids=["map-empty-stop", "map-no-count", "map-descending", "map-meaningless", "radius",
        "unit-only", "release", "stiffness"])
def test_every_section_is_validated_on_load(tmp_path, text, field):
    """Whichever command reads the scenario: a malformed or meaningless section is an error
    at load, not when (or if) a command uses it."""
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(InputError) as info:
        load_scenario(p)
    assert info.value.field == field, str(info.value)


def test_map_ranges_are_read_without_building_the_grid():
    s = load_scenario(None, {"map.frequency": "2Hz:20Hz:99999999999999999999"})
    (f0, f1, nf), _ = s.map_ranges()
    assert (f0, f1, nf) == (2.0, 20.0, 10**20 - 1)
    with pytest.raises(InputError, match="^map.frequency: .*memory"):
        check_resources(s, "map")


@pytest.mark.parametrize("kind", ["directory", "deep", "huge", "unreadable-bytes"])
def test_scenario_files_that_are_no_scenarios(tmp_path, kind):
    p = tmp_path / "s.toml"
    if kind == "directory":
        p.mkdir()
    elif kind == "deep":  # tomllib recurses: RecursionError
        p.write_text("a = " + "[" * 100_000 + "]" * 100_000)
    elif kind == "huge":
        p.write_text("# " + "x" * (2**20 + 10) + "\n")
    else:
        p.write_bytes(b"title = \"\xff\xfe\"\n")
    with pytest.raises(InputError) as info:
        load_scenario(p)
    assert info.value.field == "scenario" and "\n" not in str(info.value)
    assert len(str(info.value)) < 300


def test_level2_stationarity_and_map_keys(tmp_path):
    """[dem] cycles = "auto" (default) or a number, the steady-state options; [map] log
    grids, a particle-count axis, the case study's DEM grid and the maps' packing."""
    s = load_scenario(None)
    assert s.dem.cycles == "auto" and s.dem.max_cycles == 60
    assert s.map_particles() is None and s.map_model("dem").packing == "auto"
    assert s.model("dem").packing == "lattice"  # single runs and Level III: the lattice
    p = tmp_path / "s.toml"
    p.write_text('[dem]\ncycles = 8\nwindow_cycles = 2\n[map]\nparticles = "log:16:192:4"\n'
                 'amplitude = "log:1mm:100mm:3"\ndem_packing = "lattice"\n')
    s = load_scenario(p)
    assert s.model("dem").cycles == 8 and s.model("dem").steady.window_cycles == 2
    assert s.map_particles().tolist() == [16, 37, 84, 192]
    assert s.map_grid()[1] == pytest.approx([0.001, 0.01, 0.1])
    assert s.map_model("dem").packing == "lattice"
    f, x = s.dem_map_grid()
    assert f.tolist() == [4, 8, 12, 16, 20] and 0.032 in np.round(x, 4)


@pytest.mark.parametrize(("text", "field"), [
    ('[dem]\ncycles = "forever"', "dem.cycles"),
    ("[dem]\nmax_cycles = 5", "dem.max_cycles"),
    ("[dem]\nsteady_rtol = -1", "dem.steady_rtol"),
    ("[dem]\ntransient_tolerance = 0", "dem.transient_tolerance"),
    ('[dem]\ntransient_tolerance = "loose"', "dem.transient_tolerance"),
    ('[map]\nparticles = "16:90:6"', "map.particles"),
    ('[map]\nparticles = "100:300:3"', "map.particles"),
    ('[map]\ndem_packing = "hex"', "map.dem_packing"),
    ('[map]\ndem_amplitude = "log:-1mm:1mm:3"', "map.dem_amplitude"),
])
def test_bad_level2_keys_name_the_field(tmp_path, text, field):
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(InputError) as info:
        load_scenario(p)
    assert info.value.field == field


def test_gravity_is_a_quantity_of_the_excitation_and_reaches_the_models():
    """``[excitation] gravity``: default 9.81 m/s^2, with units, 0 allowed (orbit); the
    analytical and DEM models of the scenario get it."""
    from pdamper.analysis.analytical import ETA_MAX
    from pdamper.constants import STANDARD_GRAVITY
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER

    assert Scenario().excitation.gravity == STANDARD_GRAVITY
    default = Scenario().model("analytic").response(10.0, 0.032)
    paper = AnalyticalDamper(PAPER_DAMPER).response(10.0, 0.032)
    assert float(default.loss_factor) == float(paper.loss_factor)
    assert load_scenario(None, {"excitation.gravity": "1.62 m/s^2"}).excitation.gravity \
        == pytest.approx(1.62)
    assert load_scenario(None, {"excitation.gravity": "1 cm/s^2"}).excitation.gravity \
        == pytest.approx(0.01)
    s = load_scenario(None, {"excitation.gravity": "0 m/s^2"})
    assert s.excitation.gravity == 0.0
    assert s.model("dem").gravity == 0.0
    assert s.model("dem").settings.engine_settings().gravity == 0.0
    h = s.damper().clearance
    r = s.model("analytic").response(10.0, h / np.pi)
    assert float(r.loss_factor) == pytest.approx(ETA_MAX, rel=1e-9)
    check_resources(s, "excitation", "dem")  # the cost model copes without settling


@pytest.mark.parametrize("value", ["-1 m/s^2", "-0.001 m/s^2", float("inf"), float("nan"),
                                   "3 m", "fast"])
def test_gravity_outside_its_range_is_one_line_naming_the_field(value):
    with pytest.raises(InputError) as e:
        load_scenario(None, {"excitation.gravity": value})
    assert e.value.field == "excitation.gravity"
    assert "\n" not in str(e.value)
