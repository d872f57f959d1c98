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


_FRAME = ("frequency [Hz], damping ratio [%], damper [kg^-0.5], load [kg^-0.5], "
          "observation [kg^-0.5]\n{z1}, 0.2582, 0.1500, 0.2582\n{f2}, 0.8, -0.3162, 0.2400, "
          "-0.3162\n")


def _frame(tmp_path, name, z1="12.0, 1.0", f2="31.0"):
    p = tmp_path / name
    p.write_text(_FRAME.format(z1=z1, f2=f2))
    return p


def test_uncertainty_written_in_the_modes_file(tmp_path, cli):
    # '1.0 +- 0.3' in the [%] column is mode 1's damping ratio 1 % +- 0.3 %: the same
    # samples and answers as the plain file with --uncertain mode1.damping_ratio=1%+-0.3%
    plain = _frame(tmp_path, "plain.csv")
    spread = _frame(tmp_path, "spread.csv", z1="12.0, 1.0 +- 0.3", f2="31.0 ± 0.5")
    run = ("frf", "--particles", "0", "--frequency", "11Hz:13Hz:3", "--max-cycles", "1",
           "--uncertainty", "4", "--json")
    code, out, err = cli(*run, "--modes", plain, "--uncertain",
                         "mode1.damping_ratio=1%+-0.3%", "--uncertain",
                         "mode2.frequency=31Hz+-0.5Hz")
    assert code == 0, err
    given = json.loads(out)["uncertainty"]
    code, out, err = cli(*run, "--modes", spread)
    assert code == 0, err
    written = json.loads(out)["uncertainty"]
    assert [u["field"] for u in written["inputs"]] == ["mode1.damping_ratio",
                                                        "mode2.frequency"]
    assert written["inputs"] == given["inputs"]
    assert written["answers"]["peak"]["mean"] == pytest.approx(
        given["answers"]["peak"]["mean"], rel=1e-12)
    assert written["answers"]["peak"]["std"] > 0
    # the nominal structure is the file's nominal values
    code, out, err = cli("frf", "--particles", "0", "--frequency", "12Hz", "--max-cycles",
                         "1", "--json", "--modes", spread)
    code2, out2, _ = cli("frf", "--particles", "0", "--frequency", "12Hz", "--max-cycles",
                         "1", "--json", "--modes", plain)
    assert code == code2 == 0 and json.loads(out)["points"] == json.loads(out2)["points"]


def test_command_line_uncertainty_replaces_the_files(tmp_path, cli):
    from pdamper.io.scenario import load_scenario

    spread = _frame(tmp_path, "spread.csv", z1="12.0, 1.0 +- 0.3")
    sc = load_scenario(None, {"structure.modes": str(spread)})
    (u,) = sc.uncertain_inputs()
    assert (u.field, u.value, u.sd) == ("mode1.damping_ratio", pytest.approx(0.01),
                                        pytest.approx(0.003))
    sc = load_scenario(None, {"structure.modes": str(spread),
                              "mode1.damping_ratio": "1 % +- 0.1 %"})
    (u,) = sc.uncertain_inputs()
    assert u.sd == pytest.approx(0.001)


@pytest.mark.parametrize("cell, msg", [
    ("1.0 +- x", "expected 'value +- sd' of two numbers"),
    ("1.0 +- 0", "the standard deviation must be > 0"),
])
def test_a_bad_uncertain_cell_names_its_row_and_column(tmp_path, cli, cell, msg):
    bad = _frame(tmp_path, "bad.csv", z1=f"12.0, {cell}")
    code, out, err = cli("frf", "--particles", "0", "--frequency", "12Hz", "--modes", bad)
    assert code == 2 and err.count("\n") == 1
    assert "row 2, column 'damping ratio [%]'" in err and msg in err


def test_the_front_carries_each_designs_spread(tmp_path, cli, monkeypatch):
    # optimize --uncertainty --plot: the mass-objective front beside the landscape, each
    # design's mean +- std as an error bar and the front's 5-95 % band
    import pdamper.cli.optimize as opt

    drawn = []

    def keep(draw, path, **kw):
        drawn.append(draw())

    monkeypatch.setattr(opt, "figure_last", keep)
    code, out, err = cli("optimize", "--vary", "particles=0:64:32", "--at", "0.8s",
                         "--uncertain", "mode1.damping_ratio=0.33%+-0.1%", "--uncertainty",
                         "4", "--json", "--plot", tmp_path / "front.png")
    assert code == 0, err
    d = json.loads(out)
    (fig,) = drawn
    front_ax = fig.axes[1]
    assert front_ax.get_xlabel() == "mass of bed and container [g]"
    (bars,) = front_ax.containers
    segments = bars.lines[2][0].get_segments()
    got = sorted((round(s[0][0], 6), s[0][1], s[1][1]) for s in segments)
    want = sorted((round(c["total_mass"] * 1e3, 6),
                   (c["objective_mean"] - c["objective_std"]) * 1e3,
                   (c["objective_mean"] + c["objective_std"]) * 1e3)
                  for c in d["candidates"])
    assert len(got) == len(want) == 3
    for g, w in zip(got, want, strict=True):
        assert g == pytest.approx(w, rel=1e-9)
    bands = [c for c in front_ax.collections if c.get_label() == "front's 5-95 %"]
    assert len(bands) == 1
    ys = bands[0].get_paths()[0].vertices[:, 1]
    lows = [c["objective_p5"] * 1e3 for c in d["front"]]
    highs = [c["objective_p95"] * 1e3 for c in d["front"]]
    assert min(ys) == pytest.approx(min(lows)) and max(ys) == pytest.approx(max(highs))


def test_frf_realisations_of_the_dem_are_its_serial_runs(tmp_path, cli, monkeypatch):
    # four spheres from random packings (seeds 3, 4), two frequencies, ten cycles: the
    # band's values are the forced responses run one by one with each seed
    def scenario(seed):
        p = tmp_path / f"dem{seed}.toml"
        p.write_text(f'[particles]\ncount = 4\n\n[dem]\npacking = "random"\nseed = {seed}\n')
        return p

    import pdamper.cli._progress as progress

    args = ("frf", "--model", "dem", "--frequency", "4Hz:4.5Hz:2", "--sweep", "up",
            "--max-cycles", "10", "--force", "0.5N", "--json")
    monkeypatch.setattr(progress, "showing", lambda: True)
    code, out, err = cli(*args, "-s", scenario(3), "--realisations", "2",
                         "--plot", tmp_path / "band.png")
    assert code == 0, err
    assert "realisations of the forced response" in err  # stderr: the JSON stays alone
    monkeypatch.setattr(progress, "showing", lambda: False)
    band = json.loads(out)["realisations"]
    assert band["count"] == 2 and band["seeds"] == [3, 4]
    runs = []
    for seed in (3, 4):
        code, out, err = cli(*args, "-s", scenario(seed))
        assert code == 0, err
        runs.append([p["up"]["amplitude"] for p in json.loads(out)["points"]])
    up = band["sweeps"]["up"]
    assert up["amplitude_min"] == pytest.approx([min(a) for a in zip(*runs, strict=True)], rel=1e-12)
    assert up["amplitude_max"] == pytest.approx([max(a) for a in zip(*runs, strict=True)], rel=1e-12)
    assert band["peak"]["up"]["values"] == pytest.approx([max(r) for r in runs], rel=1e-12)
    assert runs[0] != runs[1]  # two packings, two responses: the band is not one run
    assert (tmp_path / "band.png").stat().st_size > 0
