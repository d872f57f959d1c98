"""The DEM damper's settings (pdamper.models.settings): one declaration per setting, the
damper takes them as one object or by name, lists them and is cloned with changes; every
fidelity states its own cost."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import pytest

import pdamper
from pdamper.dem import EngineSettings
from pdamper.errors import InputError
from pdamper.models import AnalyticalDamper, DamperModel, DEMDamper, get_damper_model
from pdamper.models.settings import (
    CONCERNS,
    DAMPER_DEFAULTS,
    ENGINE_SET_BY_RUN,
    FIELD,
    DEMSettings,
    RunPlan,
    SteadyState,
)
from pdamper.parameters import PAPER_DAMPER

ROOT = Path(pdamper.__file__).parent


def test_every_damper_setting_is_declared_in_exactly_one_concern():
    owners: dict[str, list[str]] = {}
    for concern in CONCERNS:
        for name in concern.model_fields:
            if concern is EngineSettings and name in ENGINE_SET_BY_RUN:
                continue
            # by the flat name (SteadyState's windows, rtol, atol are steady_windows, ...)
            flat = getattr(concern, "flat_names", {}).get(name, name)
            owners.setdefault(flat, []).append(concern.__name__)
    assert {n: o for n, o in owners.items() if len(o) > 1} == {}
    assert set(DEMSettings.flat_fields()) == set(owners)
    for name, info in DEMSettings.flat_fields().items():
        concern = next(c for c in CONCERNS if owners[name] == [c.__name__])
        own = concern.model_fields[FIELD[name]]
        assert info.description == own.description
        assert info.json_schema_extra == own.json_schema_extra
        assert info.default == DAMPER_DEFAULTS.get(name, own.default), name


def test_the_damper_takes_one_settings_object_or_the_settings_by_name():
    by_name = DEMDamper(PAPER_DAMPER, integrator="verlet", cycles=3, skip_cycles=1)
    by_object = DEMDamper(PAPER_DAMPER, DEMSettings(integrator="verlet", cycles=3,
                                                    skip_cycles=1))
    assert by_name.settings == by_object.settings
    assert by_name.cycles == 3 and by_name.integrator == "verlet"
    assert DEMDamper(PAPER_DAMPER).integrator == "gear"  # the damper's default, not Verlet
    # the signature lists every setting (help(), inspection), no catch-all
    params = inspect.signature(DEMDamper).parameters
    assert list(params)[:2] == ["damper", "settings"]
    assert set(list(params)[2:]) == set(DEMSettings.flat_fields()) | {"plan", "steady", "contact", "engine"}
    with pytest.raises(TypeError, match="unexpected keyword argument 'gear_tolerence'"):
        DEMDamper(PAPER_DAMPER, gear_tolerence=1e-4)
    with pytest.raises(InputError, match="dem.settings|settings: must be a DEMSettings"):
        DEMDamper(PAPER_DAMPER, {"cycles": 3})


def test_get_params_and_clone_as_scikit_learn():
    m = DEMDamper(PAPER_DAMPER, cycles=8, packing="random", seed=4)
    p = m.get_params()
    assert p["damper"] is PAPER_DAMPER and p["plan"].cycles == 8 and p["plan"].seed == 4
    assert set(p) == {"damper", *DEMDamper(PAPER_DAMPER).settings.get_params()}
    assert DEMDamper(**p).settings == m.settings
    c = m.clone(seed=5, damper=PAPER_DAMPER.with_count(16))
    assert (c.seed, c.cycles, c.damper.count, m.seed) == (5, 8, 16, 4)
    with pytest.raises(InputError, match="dem.skip_cycles"):
        m.clone(skip_cycles=8)  # the cross checks run again
    a = AnalyticalDamper(PAPER_DAMPER, gravity=1.62)
    assert a.get_params() == {"damper": PAPER_DAMPER, "gravity": 1.62}
    assert a.clone(gravity=0.0).gravity == 0.0 and a.gravity == 1.62


@pytest.mark.parametrize(("changes", "field"), [
    ({"cycles": 0}, "dem.cycles"), ({"cycles": "many"}, "dem.cycles"),
    ({"steady_windows": 1}, "dem.steady_windows"), ({"safety": 1.5}, "dem.safety"),
    ({"packing": "hexagonal"}, "dem.packing"), ({"accuracy": 0.0}, "dem.accuracy"),
    ({"max_cycles": 5}, "dem.max_cycles"), ({"damping_model": "x"}, "dem.damping_model"),
])
def test_bad_settings_name_the_scenario_field(changes, field):
    with pytest.raises(InputError) as exc:
        DEMDamper(PAPER_DAMPER, **changes)
    assert exc.value.field == field


def test_the_concerns_project_the_flat_settings():
    s = DEMSettings(window_cycles=5, steady_windows=4, skip_cycles=3, integrator="auto")
    c = s.concern(SteadyState).criterion(s.skip_cycles)
    assert (c.window_cycles, c.windows, c.skip_cycles) == (5, 4, 3)
    assert s.concern(RunPlan).skip_cycles == 3
    e = s.engine_settings(seed=9)
    assert (e.integrator, e.seed, e.transient_cycles) == ("auto", 9, 0)


def test_each_fidelity_states_its_cost():
    analytic, dem = get_damper_model("analytic"), get_damper_model("dem")
    assert analytic.excitation_cost(PAPER_DAMPER, 10.0, 0.032) is None
    one = dem.excitation_cost(PAPER_DAMPER, 10.0, 0.032, DEMSettings(cycles=8))
    longer = dem.excitation_cost(PAPER_DAMPER, 10.0, 0.032, DEMSettings(cycles=16))
    assert one.seconds > 0 and longer.seconds > one.seconds
    assert one.drivers[0] == ("dem.cycles", 8 / 60)
    grid = ((2.0, 20.0, 4), (0.01, 0.03, 3))
    assert dem.map_cost(PAPER_DAMPER, *grid, 12.0).runs == 12
    assert analytic.map_cost(PAPER_DAMPER, *grid, 12.0).what == "the analytical map"
    free = dem.free_vibration_cost(PAPER_DAMPER, 1.0, 200.0, 10.0, x0=0.01)
    assert free.seconds > analytic.free_vibration_cost(PAPER_DAMPER, 1.0, 200.0, 10.0).seconds
    assert DamperModel.excitation_cost.__doc__


def test_the_scenario_and_the_resources_branch_on_no_fidelity_name():
    names = {"dem", "analytic", "fields"}
    for rel in ("io/scenario.py", "resources.py", "runs/resources.py"):
        for node in ast.walk(ast.parse((ROOT / rel).read_text())):
            if isinstance(node, ast.Compare):
                consts = [c.value for c in (node.left, *node.comparators)
                          if isinstance(c, ast.Constant)]
                assert not names & set(consts), f"{rel}:{node.lineno} compares with a name"
    text = (ROOT / "runs" / "realisations.py").read_text()
    assert "._dem_level2_cost" not in text
