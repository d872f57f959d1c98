"""The DEM damper's settings by concern (plan, steady, accuracy, contact, engine): typed for
the type checker, scikit-learn's nested parameters, one declaration per key on every surface
(Python, scenario tables, flat aliases, command-line overrides), the lattice's tolerance in
the declaration."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from pdamper.dem import EngineSettings
from pdamper.dem.settings import LATTICE_GEAR_TOLERANCE
from pdamper.errors import InputError
from pdamper.io.scenario import DEMSpec, load_scenario, scenario_from_dict
from pdamper.models import DEMDamper
from pdamper.models.settings import DEMSettings, RunPlan, SteadyState
from pdamper.parameters import PAPER_DAMPER

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.long  # CI's long group runs it: about 10 s of mypy from a cold cache
def test_mypy_rejects_a_misspelt_setting_on_the_engine_and_on_the_damper(tmp_path):
    snippet = tmp_path / "probe.py"
    snippet.write_text(textwrap.dedent("""
        from pdamper.dem import EngineSettings
        from pdamper.models.dem import DEMDamper
        from pdamper.parameters import PAPER_DAMPER

        model = DEMDamper(PAPER_DAMPER, cycles=8)
        ok: float | None = model.engine.gear_tolerance
        cycles: int | str = model.plan.cycles
        flat: int | str = model.cycles
        a = EngineSettings().gear_tolerence
        b = model.engine.gear_tolerence
        c = model.cyclez
    """))
    proc = subprocess.run(
        [sys.executable, "-m", "mypy", "--config-file", str(ROOT / "pyproject.toml"),
         "--no-error-summary", "--follow-imports=silent",
         "--cache-dir", str(tmp_path / "mypy_cache"), str(snippet)],
        capture_output=True, text=True, cwd=ROOT, timeout=600,
        env={**os.environ, "MYPYPATH": str(ROOT / "src")})
    lines = [ln for ln in proc.stdout.splitlines() if "probe.py" in ln]
    assert proc.returncode == 1, proc.stdout + proc.stderr
    bad = sorted(int(ln.split(":")[1]) for ln in lines if "error" in ln)
    # the three misspellings (lines 10-12), nothing on the correct reads (lines 7-9)
    assert bad == [10, 11, 12], proc.stdout
    assert all("has no attribute" in ln for ln in lines if "error" in ln), proc.stdout


def test_the_damper_takes_concerns_and_lists_them_nested():
    m = DEMDamper(PAPER_DAMPER, plan=RunPlan(cycles=8, skip_cycles=2),
                  steady=SteadyState(window_cycles=5), engine=EngineSettings(gear_tolerance=1e-6))
    assert isinstance(m.plan, RunPlan) and isinstance(m.engine, EngineSettings)
    assert (m.plan.cycles, m.steady.window_cycles, m.engine.gear_tolerance) == (8, 5, 1e-6)
    # an EngineSettings object contributes what is set on it: the damper's Gear stays
    assert m.engine.integrator == "gear"
    # the flat keywords are aliases of the same settings
    flat = DEMDamper(PAPER_DAMPER, cycles=8, skip_cycles=2, window_cycles=5,
                     gear_tolerance=1e-6)
    assert flat.settings == m.settings
    shallow = m.get_params()
    assert set(shallow) == {"damper", "plan", "steady", "accuracy", "contact", "engine"}
    deep = m.get_params(deep=True)
    assert deep["engine__gear_tolerance"] == 1e-6 and deep["plan__cycles"] == 8
    assert "engine__seed" not in deep  # the run's, not a setting of the damper's engine
    # scikit-learn's keys construct, clone and set as the flat names do
    assert DEMDamper(PAPER_DAMPER, engine__gear_tolerance=1e-6, plan__cycles=8,
                     plan__skip_cycles=2, steady__window_cycles=5).settings == m.settings
    c = m.clone(engine__gear_tolerance=1e-7)
    assert (c.engine.gear_tolerance, m.engine.gear_tolerance, c.plan.cycles) == (1e-7, 1e-6, 8)
    assert m.set_params(plan__cycles=9) is m and m.plan.cycles == 9 and m.cycles == 9
    with pytest.raises(InputError) as exc:
        DEMDamper(PAPER_DAMPER, cycles=8, plan__cycles=9)
    assert exc.value.field == "dem" and "given twice" in exc.value.message
    with pytest.raises(InputError) as exc:
        DEMDamper(PAPER_DAMPER, engine__cycles=3)
    assert exc.value.field == "dem" and "EngineSettings (engine) has no setting 'cycles'" in \
        exc.value.message
    with pytest.raises(AttributeError):
        m.cyclez  # noqa: B018 - no forwarding: a misspelt name is an error at run time too


def test_accuracy_is_the_concern_and_a_number_its_target():
    m = DEMDamper(PAPER_DAMPER, accuracy=0.05)
    assert m.accuracy.accuracy == 0.05 and m.accuracy.max_refinements == 2


def test_the_lattice_tolerance_is_the_declared_default_by_start():
    decl = EngineSettings.declarations()["gear_tolerance"]
    assert decl["default"] is None and "lattice" in decl["none"] and "1e-9" in decl["none"]
    lattice = DEMDamper(PAPER_DAMPER)
    assert lattice.engine.gear_tolerance is None
    assert lattice.gear_tolerance_for("lattice") == LATTICE_GEAR_TOLERANCE == 1e-9
    assert lattice.gear_tolerance_for("random") == 1e-5
    assert DEMDamper(PAPER_DAMPER, gear_tolerance=1e-5).gear_tolerance_for("lattice") == 1e-5
    verlet = DEMDamper(PAPER_DAMPER, integrator="verlet").protocol()
    assert verlet["gear_tolerance"] is None and verlet["not_applicable"]["gear_tolerance"]


def test_the_dem_section_declares_every_key_under_its_canonical_name():
    decls, aliases = DEMSpec.declarations(), DEMSpec.aliases()
    assert decls["engine.gear_tolerance"]["unit"] == ""
    assert decls["plan.sample_rate"]["unit"] == "Hz" and decls["plan.sample_rate"]["low"] == 0
    assert decls["engine.integrator"]["default"] == "gear"  # the damper's default
    assert "engine.gravity" not in decls  # [excitation] gravity
    for key, decl in decls.items():
        assert {"unit", "kind", "doc", "default"} <= set(decl), key
    assert aliases["gear_tolerance"] == "engine.gear_tolerance"
    assert aliases["steady_state.steady_windows"] == "steady.windows"
    assert aliases["steady_windows"] == "steady.windows" and aliases["steady_rtol"] == "steady.rtol"
    assert aliases["accuracy_target.accuracy"] == "accuracy.accuracy"
    assert set(aliases.values()) <= set(decls)
    # every flat key of the section resolves to one declaration
    flat = set(DEMSpec.flat_fields()) - {"restitution_pp", "restitution_pw"}
    assert {aliases[k] for k in flat} == {k for k in decls if "." in k}


@pytest.mark.parametrize("dem", [
    {"gear_tolerance": 2e-6},
    {"engine": {"gear_tolerance": 2e-6}},
    {"engine__gear_tolerance": 2e-6},
])
def test_gear_tolerance_walks_from_the_file_to_the_engine_through_one_declaration(dem):
    sc = scenario_from_dict({"dem": dem})
    # the declaration the scenario resolves the key to is the engine's own field
    canonical = DEMSpec.aliases().get(next(iter(dem)), "engine.gear_tolerance")
    assert canonical == "engine.gear_tolerance"
    concern, _, name = canonical.partition(".")
    field = type(getattr(sc.dem, concern)).model_fields[name]
    assert field is EngineSettings.model_fields["gear_tolerance"]
    model = sc.model("dem")
    assert model.engine.gear_tolerance == 2e-6  # unchanged, no rename on the way
    from pdamper.dem import HarmonicMotion

    assert model.build_engine(HarmonicMotion(0.01, 10.0)).gear_tolerance == 2e-6
    # and as a command-line override (`--...` options write dem.<key> overrides)
    assert load_scenario(None, {"dem.gear_tolerance": 2e-6}).dem.engine.gear_tolerance == 2e-6


TABLE_FORMS = {
    "flat": "[dem]\ncycles = 5\nintegrator = \"verlet\"\n",
    "tables": "[dem.plan]\ncycles = 5\n[dem.engine]\nintegrator = \"verlet\"\n",
    "old tables": "[dem.steady_state]\nsteady_windows = 3\n[dem.plan]\ncycles = 5\n"
                  "[dem.engine]\nintegrator = \"verlet\"\n",
}


@pytest.mark.parametrize("form", list(TABLE_FORMS))
def test_a_command_line_option_overrides_the_key_in_every_table_form(form, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(TABLE_FORMS[form])
    plain = load_scenario(path)
    assert (plain.dem.cycles, plain.dem.integrator) == (5, "verlet")
    sc = load_scenario(path, {"dem.cycles": 3, "dem.integrator": "gear",
                              "dem.steady_windows": 4})
    assert (sc.dem.cycles, sc.dem.integrator, sc.dem.steady.steady_windows) == (3, "gear", 4)
    # the same option as the file: no "given twice"
    assert load_scenario(path, {"dem.integrator": "verlet"}).dem.integrator == "verlet"


def test_the_dem_command_overrides_a_nested_table(cli, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("[dem.engine]\nintegrator = \"verlet\"\n[dem.plan]\ncycles = 5\n")
    code, out, err = cli("dem", "--scenario", path, "--particles", "4", "--cycles", "2",
                         "--skip-cycles", "1", "--integrator", "gear", "--json")
    assert code == 0, err
    payload = json.loads(out)
    assert payload["protocol"]["integrator"] == "gear"
    assert payload["protocol"]["gear_tolerance"] == LATTICE_GEAR_TOLERANCE
    assert payload["inputs"]["dem"]["cycles"] == 2


def test_the_settings_path_builds_no_model_at_run_time():
    for rel in ("src/pdamper/models/settings.py", "src/pdamper/models/dem.py",
                "src/pdamper/io/scenario.py", "src/pdamper/dem/settings.py"):
        text = (ROOT / rel).read_text()
        assert "create_model" not in text, rel
        assert "def __getattr__(self" not in text, rel
    assert DEMSettings.declarations()["engine.gear_tolerance"]["concern"] == "engine"


def test_every_flat_name_reads_typed_through_its_concern():
    from pdamper.models.settings import FLAT, FlatSettings

    s = DEMSettings(cycles=7, gear_tolerance=3e-6, damping_model="tsuji")
    for name, concern in FLAT.items():
        if name == "accuracy":  # the concern's name: its target is accuracy.accuracy
            continue
        assert isinstance(getattr(FlatSettings, name), property), name
        assert getattr(s, name) == getattr(getattr(s, concern), name), name


def test_a_copy_with_a_flat_update_reaches_the_concern():
    sc = load_scenario(None, {"dem.packing": "random"})
    copy = sc.dem.model_copy(update={"seed": 6, "packing": "lattice"})
    assert (copy.seed, copy.plan.seed, copy.packing) == (6, 6, "lattice")
    assert sc.dem.seed == 0


def test_the_seed_and_the_transient_tolerance_are_declared_once_by_the_engine():
    from pdamper.dem.settings import declaration

    for plan_name, engine_name in (("seed", "seed"),
                                   ("transient_tolerance", "gear_transient_tolerance")):
        plan, engine = declaration(RunPlan, plan_name), declaration(EngineSettings, engine_name)
        # unit, kind and range come from the engine's declaration; only what None means
        # (and the default) is the plan's
        assert {k: v for k, v in plan.items() if k != "none"} == \
            {k: v for k, v in engine.items() if k != "none"}, plan_name
    with pytest.raises(InputError, match="dem.transient_tolerance"):
        DEMDamper(PAPER_DAMPER, transient_tolerance=0.0)


def test_the_settings_given_are_known_by_flat_name_in_every_form():
    assert DEMSettings().model_fields_set == set()
    assert DEMSettings(cycles=3, engine__safety=0.01).model_fields_set == {"cycles", "safety"}
    assert DEMSettings(plan=RunPlan(seed=2)).model_fields_set == {"seed"}
    sc = scenario_from_dict({"dem": {"plan": {"cycles": 4}, "restitution_pp": 0.5}})
    assert sc.dem.model_fields_set == {"cycles", "restitution_pp"}
    # a copy keeps what was given and adds the change
    assert sc.dem.clone(packing="random").model_fields_set == {"cycles", "restitution_pp",
                                                               "packing"}
    with pytest.raises(InputError, match="restitution.pp"):
        scenario_from_dict({"dem": {"restitution_pp": 0.5},
                            "restitution": {"pp": {"model": "constant", "e": 0.6}}})


def test_steady_state_is_the_criterion_under_its_own_names():
    import dataclasses

    from pdamper.analysis.stationarity import SteadyStateCriterion

    names = {f.name for f in dataclasses.fields(SteadyStateCriterion)}
    assert set(SteadyState.model_fields) <= names  # no field under another name
    s = SteadyState(windows=4, rtol=0.2, atol=0.05, window_cycles=3)
    c = s.criterion(skip_cycles=2)
    assert (c.windows, c.rtol, c.atol, c.window_cycles, c.skip_cycles) == (4, 0.2, 0.05, 3, 2)
    # the old names stay aliases: keyword, flat [dem] key, old table, attribute, error name
    assert SteadyState(steady_windows=4) == SteadyState(windows=4)
    assert s.steady_windows == 4 and DEMDamper(PAPER_DAMPER, steady_rtol=0.2).steady.rtol == 0.2
    a = scenario_from_dict({"dem": {"steady_windows": 4}}).dem.steady
    b = scenario_from_dict({"dem": {"steady": {"windows": 4}}}).dem.steady
    c2 = scenario_from_dict({"dem": {"steady_state": {"steady_windows": 4}}}).dem.steady
    assert a == b == c2 and a.windows == 4
    with pytest.raises(InputError) as exc:
        scenario_from_dict({"dem": {"steady": {"windows": 1}}})
    assert exc.value.field == "dem.steady_windows"
