"""The scenario's [dem] section is derived from the settings' declarations: flat keys as
before, or a table per concern; an old flat-key file loads to the same settings and the
same result."""

from __future__ import annotations

import pytest

from pdamper.errors import InputError
from pdamper.io.scenario import (
    DEM_SCENARIO_ONLY,
    DEM_SET_ELSEWHERE,
    DEM_TABLES,
    DEMSpec,
    load_scenario,
    scenario_from_dict,
)
from pdamper.models.settings import DEMSettings

#: A scenario with every flat [dem] key of the releases before the settings were declared
#: once, each away from its default.
OLD_FLAT = """
[particles]
count = 6

[excitation]
frequency = "12 Hz"
amplitude = "20 mm"

[dem]
integrator = "verlet"
cycles = 4
skip_cycles = 1
max_cycles = 30
window_cycles = 3
steady_windows = 2
steady_rtol = 0.2
steady_atol = 0.05
quiet_window_cycles = 1
quiet_scatter = 0.3
quiet_windows = 3
quiet_skip_cycles = 1
restitution_pp = 0.7
restitution_pw = 0.8
damping_model = "gonthier"
min_impact_velocity = "2 cm/s"
packing = "random"
seed = 3
safety = 0.03
sample_rate = "3 kHz"
error_estimate = false
gear_free_flight = false
accuracy = 0.02
max_refinements = 1
transient_tolerance = 1e-4
"""

#: The same, the settings in a table per concern.
NESTED = """
[particles]
count = 6

[excitation]
frequency = "12 Hz"
amplitude = "20 mm"

[dem]
restitution_pp = 0.7
restitution_pw = 0.8

[dem.plan]
cycles = 4
skip_cycles = 1
max_cycles = 30
packing = "random"
seed = 3
sample_rate = "3 kHz"
transient_tolerance = 1e-4

[dem.steady_state]
window_cycles = 3
steady_windows = 2
steady_rtol = 0.2
steady_atol = 0.05
quiet_window_cycles = 1
quiet_scatter = 0.3
quiet_windows = 3
quiet_skip_cycles = 1

[dem.accuracy_target]
error_estimate = false
accuracy = 0.02
max_refinements = 1

[dem.contact]
damping_model = "gonthier"
min_impact_velocity = "2 cm/s"

[dem.engine]
integrator = "verlet"
safety = 0.03
gear_free_flight = false
"""

#: What the scenario loaded with the code before the settings were declared once: loss
#: factor, effective mass ratio, steps (that release's run of OLD_FLAT, 4 cycles).
BEFORE = (0.6343833805154818, 2.7780407288630267, 532584)


def test_the_dem_section_is_derived_from_the_declarations():
    expected = (set(DEMSettings.flat_fields()) - set(DEM_SET_ELSEWHERE)) | set(DEM_SCENARIO_ONLY)
    assert set(DEMSpec.flat_fields()) == expected
    for name in set(DEMSpec.flat_fields()) - set(DEM_SCENARIO_ONLY):
        spec, decl = DEMSpec.flat_fields()[name], DEMSettings.flat_fields()[name]
        assert (spec.default, spec.description, spec.json_schema_extra) == \
            (decl.default, decl.description, decl.json_schema_extra), name
    tables = {getattr(concern, "flat_names", {}).get(n, n)  # by flat name
              for concern in DEM_TABLES.values() for n in concern.model_fields}
    assert set(DEMSpec.flat_fields()) - set(DEM_SCENARIO_ONLY) <= tables


def test_old_flat_scenario_loads_to_the_same_settings_and_result(tmp_path):
    flat, nested = tmp_path / "flat.toml", tmp_path / "nested.toml"
    flat.write_text(OLD_FLAT)
    nested.write_text(NESTED)
    a, b = load_scenario(flat), load_scenario(nested)
    assert a.dem == b.dem
    m = a.model("dem")
    assert m.settings == DEMSettings(
        integrator="verlet", cycles=4, skip_cycles=1, max_cycles=30, window_cycles=3,
        steady_windows=2, steady_rtol=0.2, steady_atol=0.05, quiet_window_cycles=1,
        quiet_scatter=0.3, quiet_windows=3, quiet_skip_cycles=1, damping_model="gonthier",
        min_impact_velocity=0.02, packing="random", seed=3, safety=0.03, sample_rate=3000.0,
        error_estimate=False, gear_free_flight=False, accuracy=0.02, max_refinements=1,
        transient_tolerance=1e-4)
    assert b.model("dem").settings == m.settings
    r = m.response(a.excitation.frequency, a.excitation.amplitude)
    # the same steps; the values to 1e-8 relative: the strict arithmetic the kernels'
    # helpers now use (a run the same on a cold and a warm numba cache, docs/performance.md)
    # moved their last bits (5e-10 relative here)
    assert r.details.item().steps == BEFORE[2]
    assert (float(r.loss_factor), float(r.effective_mass_ratio)) == pytest.approx(
        BEFORE[:2], rel=1e-8)


@pytest.mark.parametrize(("dem", "field"), [
    ({"safety": 2.0}, "dem.safety"),
    ({"engine": {"safety": 2.0}}, "dem.safety"),
    ({"sample_rate": "3 m"}, "dem.sample_rate"),
    ({"cycles": 0}, "dem.cycles"),
    ({"gear_tolerance": 0.0}, "dem.gear_tolerance"),
    ({"engine": {"cycles": 4}}, "dem"),           # cycles belongs to [dem.plan]
    ({"cycles": 4, "plan": {"cycles": 5}}, "dem"),  # given twice
    ({"gravity": 1.0}, "dem.gravity"),            # g is [excitation] gravity
    ({"gear_tolerence": 1e-4}, "dem.gear_tolerence"),
])
def test_bad_dem_keys_name_the_field(dem, field):
    with pytest.raises(InputError) as exc:
        scenario_from_dict({"dem": dem})
    assert exc.value.field == field


def test_engine_settings_are_scenario_keys_too():
    sc = scenario_from_dict({"dem": {"gear_tolerance": 1e-4, "settle_time": "0.5 s",
                                     "max_step": "50 us"}})
    e = sc.model("dem").settings.engine_settings()
    assert (e.gear_tolerance, e.settle_time, e.max_step) == (1e-4, 0.5, pytest.approx(5e-5))
    assert scenario_from_dict({"excitation": {"gravity": "0 m/s^2"}}).model("dem").gravity == 0
