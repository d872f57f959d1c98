"""Numbers promised, numbers delivered: every value of the JSON of every command with JSON
output (``simulate``: free decay, load histories, base motion, measured data; ``analytic``,
``optimize``, ``cor``, ``cor-sensitivity``, ``dem``, ``map``, ``frf``, ``report``,
``paper``) is a finite number, or null and listed with its reason in a sibling
``not_applicable`` (``{key: reason}``)."""

from __future__ import annotations

import json
import math

import pytest

from hostile_corpus import FILES, SCENARIOS

#: Subtrees that echo the inputs (a scenario's unset options are null there by design).
_INPUTS = ("inputs", "frf_inputs")


def unexplained(obj, path: str = "$") -> list[str]:
    """Paths of the nulls and non-finite numbers of a JSON value that no sibling
    ``not_applicable`` explains with a non-empty reason."""
    out: list[str] = []
    if isinstance(obj, dict):
        why = obj.get("not_applicable") or {}
        for key, v in obj.items():
            if key in _INPUTS or key == "not_applicable":
                continue
            if v is None or isinstance(v, float) and not math.isfinite(v):
                if not (isinstance(why.get(key), str) and why[key].strip()):
                    out.append(f"{path}.{key}")
            else:
                out += unexplained(v, f"{path}.{key}")
        for key in why:  # a reason for a key that is a number is a stale reason
            if obj.get(key) is not None:
                out.append(f"{path}.not_applicable.{key} (but {key} is {obj.get(key)!r})")
    elif isinstance(obj, list):
        for k, v in enumerate(obj):
            if v is None or isinstance(v, float) and not math.isfinite(v):
                out.append(f"{path}[{k}]")
            else:
                out += unexplained(v, f"{path}[{k}]")
    return out


def test_the_walker_finds_bare_nulls():
    assert unexplained({"a": None, "b": [1.0, None], "inputs": {"x": None}}) == ["$.a",
                                                                             "$.b[1]"]
    assert unexplained({"a": None, "not_applicable": {"a": "no load"}}) == []
    assert unexplained({"a": 1.0, "not_applicable": {"a": "stale"}}) != []


@pytest.fixture
def files(tmp_path):
    for name, text in FILES.items():
        (tmp_path / name).write_text(text)
    for name, text in SCENARIOS.items():
        (tmp_path / f"{name}.toml").write_text(text)
    (tmp_path / "load_zero.csv").write_text("time [s], force [N]\n0, 0\n0.5, 0\n1, 0\n")
    (tmp_path / "load_tiny.csv").write_text("time [s], force [N]\n0, 0\n0.5, 1e-200\n1, 0\n")
    (tmp_path / "load_base.toml").write_text('[load]\nbase_acceleration = "load_acc.csv"\n')
    return tmp_path


CASES = {
    "free-decay": ["simulate", "--duration", "0.5s"],
    "measured": ["simulate", "--measured", "{tmp}/decay_mm.csv"],
    "force": ["simulate", "--load", "{tmp}/load_force.csv"],
    "force-zero": ["simulate", "--load", "{tmp}/load_zero.csv"],
    "force-tiny": ["simulate", "--load", "{tmp}/load_tiny.csv"],
    "base-1dof": ["simulate", "--base-acceleration", "{tmp}/load_acc.csv"],
    "base-one-mode": ["simulate", "--base-acceleration", "{tmp}/load_acc.csv", "--modes",
                      "{tmp}/modes_one.csv"],
    "base-beam": ["simulate", "--base-acceleration", "{tmp}/load_acc.csv", "--scenario",
                  "{tmp}/beam_three_modes.toml"],
    "base-scenario": ["simulate", "--scenario", "{tmp}/load_base.toml"],
    "base-compare": ["simulate", "--compare", "analytic", "--base-acceleration",
                     "{tmp}/load_acc.csv"],
    "analytic": ["analytic"],
    "analytic-gravity-0": ["analytic", "--gravity", "0 m/s^2"],
    # design studies: a grid (no seed, no bounds), an interval searched by the seeded
    # optimiser (no values), designs that cannot be built (no mass, no objective, no best)
    "optimize-grid": ["optimize", "--vary", "particles=0:32:16"],
    "optimize-interval": ["optimize", "--vary", "radius=3mm:6mm", "--method", "optimize",
                          "--max-evaluations", "8"],
    "optimize-infeasible": ["optimize", "--vary", "radius=20mm:30mm:2"],
    "optimize-peak-frf": ["optimize", "--scenario", "{tmp}/study_peak_frf.toml"],
    # every other command with JSON output, each run kept to seconds
    "cor": ["cor"],
    "cor-table": ["cor", "--model", "{tmp}/cor.csv"],
    "cor-sensitivity": ["cor-sensitivity", "--variants", "{tmp}/cor.csv", "--points",
                        "10Hz/32mm", "--no-level3", "--cycles", "3", "--skip-cycles", "1",
                        "--scenario", "{tmp}/four_spheres.toml"],
    "map": ["map", "--frequency", "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2"],
    "frf": ["frf", "--frequency", "5Hz:6Hz:3"],
    "frf-base": ["frf", "--base", "0.05g", "--frequency", "4Hz:7Hz:4"],
    "frf-modes": ["frf", "--frequency", "5Hz:7Hz:3", "--scenario",
                  "{tmp}/beam_three_modes.toml"],
    "report": ["report", "--out", "{tmp}/report"],
    "paper": ["paper", "--no-dem", "--out", "{tmp}/paper"],
}


CASES_DEM = {
    "dem": ["dem", "--particles", "4", "--cycles", "2", "--skip-cycles", "1"],
    "dem-verlet": ["dem", "--particles", "4", "--cycles", "2", "--skip-cycles", "1",
                   "--integrator", "verlet"],
}


@pytest.mark.parametrize("name", [*CASES, *CASES_DEM])
def test_every_number_is_finite_or_not_applicable(cli, files, name):
    args = [a.replace("{tmp}", str(files)) for a in {**CASES, **CASES_DEM}[name]]
    code, out, err = cli(*args, "--json")
    assert code == 0, err
    data = json.loads(out)
    assert unexplained(data) == []


def test_a_short_dem_run_says_why_it_has_no_standard_error(cli):
    code, out, err = cli("dem", "--particles", "4", "--cycles", "2", "--skip-cycles", "1",
                         "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["loss_factor_stderr"] is None
    assert "cycle" in data["not_applicable"]["loss_factor_stderr"]


def test_base_motion_says_why_it_has_no_energy_balance(cli, files):
    code, out, _ = cli("simulate", "--base-acceleration", f"{files}/load_acc.csv", "--json")
    why = json.loads(out)["not_applicable"]
    assert set(why) == {"input_work", "structural_dissipation", "energy_change",
                        "energy_balance_error"}
    assert "base" in why["input_work"]


def test_a_band_without_cycles_says_so():
    from pdamper.coupling.comparison import Band

    d = Band(0.01, 0.02, 0, *[float("nan")] * 4).as_dict()
    assert d["measured_zeta"] is None
    assert "no measured cycle" in d["not_applicable"]["measured_zeta"]
    assert unexplained(d) == []


def test_analytic_names_the_sections_it_does_not_use(cli, files):
    code, out, _ = cli("analytic", "--scenario", f"{files}/load_force.toml", "--json")
    assert code == 0
    assert set(json.loads(out)["unused_inputs"]) == {"load"}
    code, out, _ = cli("analytic", "--scenario", f"{files}/load_force.toml")
    assert code == 0
    assert [ln for ln in out.splitlines() if ln.startswith("unused: [load]")]


def test_analytic_without_unused_sections_has_no_unused_inputs(cli, files):
    code, out, _ = cli("analytic", "--scenario", f"{files}/glass.toml", "--json")
    assert code == 0
    assert "unused_inputs" not in json.loads(out)
