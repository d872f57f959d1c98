"""Engine settings declared once (pdamper.dem.settings): the declarations are complete, the
engine takes them as one object and reads nothing else, and no other module restates a
constraint of a setting."""

from __future__ import annotations

import ast
import inspect
import math
from pathlib import Path

import pytest

import pdamper
from dem_inputs import contact, container, lattice
from pdamper.dem import DEMEngine, EngineSettings
from pdamper.dem.settings import KINDS, Settings, declaration
from pdamper.errors import InputError
from pdamper.models.settings import CONCERNS

ROOT = Path(pdamper.__file__).parent


@pytest.mark.parametrize("cls", CONCERNS, ids=lambda c: c.__name__)
def test_every_setting_has_its_declaration(cls):
    for name, info in cls.model_fields.items():
        decl = declaration(cls, name)
        assert decl["kind"] in KINDS, name
        assert info.description and len(info.description) > 10, name
        if info.default is None:
            assert decl["none"], f"{name}: what None means is declared"
        if decl["kind"] == "choice":
            assert info.default in decl["choices"], name
        assert type(cls()).model_fields[name].default == info.default


def test_engine_takes_at_most_six_parameters_and_one_settings_object():
    params = [p for p in inspect.signature(DEMEngine.__init__).parameters if p != "self"]
    assert len(params) <= 6
    assert params == ["particles", "container", "contact", "motion", "settings"]


def test_the_engine_reads_its_settings_and_resolves_the_open_defaults():
    s = EngineSettings(integrator="gear", gear_tolerance=1e-4, seed=7, settle_time=0.0)
    e = DEMEngine(lattice(4), container(), contact(), None, s)
    assert e.settings is s
    assert (e.integrator, e.gear_tolerance, e.seed, e.settle_time) == ("gear", 1e-4, 7, 0.0)
    assert e.gear_transient_tolerance == 1e-4  # None: the Gear tolerance
    assert e.max_overlap == math.inf
    assert e.skin == pytest.approx(0.2 * float(lattice(4).radius.min()))
    assert DEMEngine(lattice(4), container(), contact()).settings == EngineSettings()
    with pytest.raises(AttributeError):
        e.no_such_setting  # noqa: B018
    with pytest.raises(InputError, match="settings: must be an EngineSettings"):
        DEMEngine(lattice(4), container(), contact(), None, {"integrator": "gear"})


@pytest.mark.parametrize(("changes", "field", "text"), [
    ({"safety": 0.0}, "safety", "(0, 1]"),
    ({"safety": True}, "safety", "must be a number"),
    ({"integrator": "euler"}, "integrator", "gear, verlet, auto"),
    ({"transient_cycles": 1.5}, "transient_cycles", "whole number >= 0"),
    ({"gear_free_flight": 1}, "gear_free_flight", "true or false"),
    ({"max_step": math.nan}, "max_step", "finite"),
    ({"skin": "1 mm"}, "skin", "must be a number in m"),  # units at the edges only
    ({"gear_tolerance_": 1e-4}, "gear_tolerance_", "unknown setting"),
])
def test_bad_settings_name_the_field_and_the_range(changes, field, text):
    with pytest.raises(InputError) as exc:
        EngineSettings(**changes)
    assert exc.value.field == field
    assert text in exc.value.message


def test_settings_are_frozen_listed_and_cloned():
    s = EngineSettings(integrator="auto")
    assert s.get_params()["integrator"] == "auto"
    assert set(s.get_params()) == set(EngineSettings.model_fields)
    c = s.clone(safety=0.01)
    assert (c.safety, c.integrator, s.safety) == (0.01, "auto", EngineSettings().safety)
    assert EngineSettings(**c.get_params()) == c
    with pytest.raises(Exception):  # noqa: B017 - pydantic's frozen-instance error
        s.safety = 0.5
    with pytest.raises(InputError, match="safety"):
        s.clone(safety=2.0)
    assert math.isinf(EngineSettings(auto_cost_ratio=math.inf).auto_cost_ratio)


def _setting_names() -> set[str]:
    from pdamper.models.settings import DEMSettings

    return set(DEMSettings.flat_fields()) | set(EngineSettings.model_fields)


def _checks_of_settings(tree: ast.AST, where: str) -> list[str]:
    """Calls of check_range / check_whole / _whole on a setting's name (with or without
    the ``dem.`` prefix) in ``tree``."""
    names = _setting_names()
    bad = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", "") in (
                "check_range", "check_whole", "_whole") and node.args \
                and isinstance(node.args[0], ast.Constant) \
                and str(node.args[0].value).removeprefix("dem.") in names:
            bad.append(f"{where}:{node.lineno} {node.args[0].value}")
    return bad


#: The modules that take the DEM settings from the user (the engine: its constructor).
CONSUMERS = ("models/dem.py", "models/base.py", "io/scenario.py", "cli/dem.py", "cli/map.py")


def test_constraints_come_only_from_the_declarations():
    """Where the settings are taken (the engine, the damper, the scenario, the command
    line), no range of a setting is checked again: the declaration's check is the one."""
    bad = [hit for rel in CONSUMERS
           for hit in _checks_of_settings(ast.parse((ROOT / rel).read_text()), rel)]
    tree = ast.parse((ROOT / "dem" / "simulation.py").read_text())
    engine = next(n for n in ast.walk(tree) if isinstance(n, ast.ClassDef)
                  and n.name == "DEMEngine")
    init = next(n for n in engine.body if isinstance(n, ast.FunctionDef)
                and n.name == "__init__")
    bad += _checks_of_settings(init, "DEMEngine.__init__")
    assert bad == []
    # the check itself finds what it looks for
    assert _checks_of_settings(ast.parse('check_range("dem.safety", x)'), "probe")


def test_settings_base_is_the_one_validator():
    assert issubclass(EngineSettings, Settings)
    assert EngineSettings.model_config["frozen"]
