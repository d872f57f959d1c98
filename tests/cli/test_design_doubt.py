"""Doubt on a design study: its cost judged before any design, the spread of every design
on the front, the modes file's own uncertainties, progress on uncertainty runs."""

import json
import time

import pytest


@pytest.fixture
def no_design_work(monkeypatch):
    """Any sample built or design evaluated fails the test: a refusal comes before work."""
    import pdamper.design.study as study
    import pdamper.runs.uncertainty as unc

    def work(*_a, **_k):
        raise AssertionError("the study started work before its cost was judged")

    monkeypatch.setattr(unc, "design_evaluator", work)
    monkeypatch.setattr(study, "run_design_study", work)
    monkeypatch.setattr(study, "optimize_design", work)


def test_optimize_uncertainty_beyond_one_run_is_refused_before_work(cli, no_design_work):
    # the default free-decay study runs in this process, one design after the other: its
    # 2 N + 1 runs of 12 designs are one run's time (about 10 h at N = 65536, above 1 h)
    t = time.perf_counter()
    code, out, err = cli("optimize", "--uncertain", "particles.friction=0.1+-0.03",
                         "--uncertainty", "65536", "--json")
    assert time.perf_counter() - t < 20
    assert code == 2 and out == ""
    assert err.count("\n") == 1
    assert err.startswith("error: uncertainty: the optimisation under the uncertain inputs "
                          "would take about ")
    assert "above the limit of 1 h" in err and "--force" in err


def test_optimize_uncertainty_from_the_scenario_refused_before_work(tmp_path, cli,
                                                                    no_design_work):
    p = tmp_path / "s.toml"
    p.write_text('[particles]\nfriction = "0.1 +- 0.03"\n\n[optimization]\nat = "0.8s"\n')
    code, out, err = cli("optimize", "--scenario", p, "--uncertainty", "65536")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("error: uncertainty: ")


def test_in_process_study_judged_as_one_run():
    # the same study's cost is a sweep's on workers (each design's 2 N + 1 runs one task)
    from pdamper.io.scenario import load_scenario
    from pdamper.runs.uncertainty import check_design_cost, study_in_process

    sc = load_scenario(None, {"particles.friction": "0.1+-0.03"})
    assert study_in_process(sc)
    check_design_cost(sc, 16)  # 33 runs of the default study: seconds
    with pytest.raises(Exception, match="above the limit of 1 h"):
        check_design_cost(sc, 65536)
    on_workers = load_scenario(None, {"particles.friction": "0.1+-0.03",
                                      "optimization.workers": 4})
    assert not study_in_process(on_workers)
    check_design_cost(on_workers, 4096)  # 8193 x 12 designs in parallel: a sweep's time


def test_optimize_uncertainty_keeps_the_mass_limit(cli):
    # under the uncertain inputs the limits still choose: the best is the lightest
    # feasible design, not the heavier ones that lower the amplitude more
    code, out, err = cli("optimize", "--vary", "particles=0:64:32", "--at", "0.8s",
                         "--uncertain", "mode1.damping_ratio=0.33%+-0.1%", "--uncertainty",
                         "4", "--max-mass", "50g", "--json")
    assert code == 0, err
    d = json.loads(out)
    feasible = [c for c in d["candidates"] if c.get("feasible", True)]
    assert [c["particles"] for c in feasible] == [0]
    assert d["best"]["particles"] == 0


@pytest.mark.parametrize("args", [
    ("frf", "--frequency", "3Hz:9Hz:5", "--particles", "0", "--max-cycles", "1"),
    ("simulate", "--duration", "1s", "--particles", "0"),
    ("optimize", "--vary", "particles=0:32:32", "--at", "0.3s"),
], ids=["frf", "simulate", "optimize"])
def test_uncertainty_runs_show_progress_on_stderr_only(args, cli, monkeypatch):
    import pdamper.cli._progress as progress

    monkeypatch.setattr(progress, "showing", lambda: True)
    spread = ("--uncertain", "structure.damping=4kg/s+-0.4kg/s", "--uncertainty", "4", "--json")
    code, out, err = cli(*args, *spread)
    assert code == 0, err
    assert json.loads(out)["uncertainty"]  # stdout: the JSON alone
    word = "designs evaluated" if args[0] == "optimize" else "uncertainty runs"
    assert word in err
    monkeypatch.setattr(progress, "showing", lambda: False)
    code, out, err = cli(*args, *spread)
    assert code == 0 and err == ""
