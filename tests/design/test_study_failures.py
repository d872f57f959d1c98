"""A design study names which designs failed and why, never a best because the others
failed, and says in a sentence why it names no best."""

from __future__ import annotations

import json

from pdamper.design.study import make_objective, optimize_design, parse_variable, run_design_study
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

OBJ = make_objective("amplitude-at", 0.8, -0.058, PAPER_STRUCTURE)


def _fails_with_particles(design):
    if design["particles"] > 0:
        raise RuntimeError("solver blew up")
    return 1.0, {}


def test_the_bare_structure_is_not_best_because_every_damper_failed():
    res = run_design_study(_fails_with_particles, PAPER_DAMPER,
                           [parse_variable("particles=0:32:16")], OBJ)
    assert [c.status for c in res.candidates] == ["ok", "failed", "failed"]
    assert res.best is None and res.lightest_within is None
    assert "2 of 3 designs failed" in res.no_best
    assert "only particles 0 could be evaluated" in res.no_best
    d = res.as_dict()
    assert d["best"] is None
    assert set(d["not_applicable"]) == {"best", "lightest_within"}
    assert d["failures"] == [{"particles": 16, "reason": "RuntimeError: solver blew up"},
                             {"particles": 32, "reason": "RuntimeError: solver blew up"}]


def test_one_survivor_is_not_best():
    def flaky(design):
        if design["particles"] == 32:
            raise RuntimeError("solver blew up")
        return float(design["particles"]), {}

    res = run_design_study(flaky, PAPER_DAMPER, [parse_variable("particles=16:32:16")], OBJ)
    assert res.best is None
    assert "only particles 16 could be evaluated" in res.no_best


def test_a_best_of_several_evaluated_designs_names_the_failures():
    def flaky(design):
        if design["particles"] == 48:
            raise RuntimeError("solver blew up")
        return float(design["particles"]), {}

    res = run_design_study(flaky, PAPER_DAMPER, [parse_variable("particles=0:48:16")], OBJ)
    assert res.best is not None and res.best.particles == 0
    assert res.no_best is None and "not_applicable" not in res.as_dict()
    assert [c.particles for c in res.failures] == [48]


def test_no_feasible_design_says_so():
    res = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, ["radius=20mm:30mm:2"])
    assert all(c.status == "infeasible" for c in res.candidates)
    assert res.best is None
    assert res.no_best.startswith("no design is feasible: all 2 designs")
    assert "particles.count" in res.no_best  # the reason of the first
    assert res.as_dict()["not_applicable"]["best"] == res.no_best


def test_cli_no_feasible_design_sentence(cli):
    code, out, err = cli("optimize", "--vary", "radius=20mm:30mm:2")
    assert code == 0, err
    assert "best: none: no design is feasible" in out
    code, out, err = cli("optimize", "--vary", "radius=20mm:30mm:2", "--json")
    assert code == 0
    d = json.loads(out)
    assert d["best"] is None and d["not_applicable"]["best"].startswith("no design is feasible")


def test_cli_failed_candidates_listed_without_a_traceback(cli, monkeypatch):
    import pdamper.coupling.frf as frf

    real = frf.frequency_response

    def fails_with_particles(model, *args, **kwargs):
        if model.damper.count > 0:
            raise FloatingPointError("the stroke diverged")
        return real(model, *args, **kwargs)

    monkeypatch.setattr(frf, "frequency_response", fails_with_particles)
    code, out, err = cli("optimize", "--objective", "peak-frf", "--band", "4Hz:7Hz:3",
                         "--vary", "particles=0:32:16")
    assert code == 0 and err == "", err
    assert "<- best" not in out
    assert "failed: particles 16: FloatingPointError: the stroke diverged" in out
    assert "failed: particles 32: FloatingPointError: the stroke diverged" in out
    assert "best: none: 2 of 3 designs failed" in out
