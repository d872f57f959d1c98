"""``pdamper report`` under the uncertain inputs on the user's own questions: the forced
response of ``[frf]`` and the response to ``[load]`` sampled (the band in the forced
response's figure, the spread in the tables), and the chosen design's sensitivity
drivers."""

from __future__ import annotations

import numpy as np
import pytest

#: The machine frame's modes with the damping ratios known to +-30 % (written in the file).
MODES = ("frequency [Hz], damping ratio [%], damper [kg^-0.5], load [kg^-0.5], "
         "observation [kg^-0.5]\n12.0, 1.0 +- 0.3, 0.2582, 0.1500, 0.2582\n"
         "31.0, 0.8 +- 0.24, -0.3162, 0.2400, -0.3162\n")


@pytest.fixture(scope="module")
def doubt_report(tmp_path_factory):
    from pdamper.io.scenario import load_scenario
    from pdamper.runs.damper_report import run_damper_report

    tmp = tmp_path_factory.mktemp("doubt")
    (tmp / "modes.csv").write_text(MODES)
    t = np.linspace(0.0, 0.02, 41)
    f = np.where(t <= 0.01, 1000.0 * np.sin(np.pi * t / 0.01), 0.0)
    (tmp / "shock.csv").write_text("time [s], force [N]\n" + "\n".join(
        f"{a:.6g}, {b:.9g}" for a, b in zip(t, f, strict=True)))
    (tmp / "frame.toml").write_text("""title = "machine frame under doubt"
[container]
length = "60 mm"
width = "50 mm"
depth = "50 mm"
material = "aluminium"
mass = "69 g"
[particles]
count = 100
radius = "4 mm"
material = "100Cr6"
[structure]
modes = "modes.csv"
initial_displacement = "-3 mm"
[simulation]
duration = "1 s"
[load]
force = "shock.csv"
at = "damper"
tail = "0.2 s"
[frf]
unbalance = "1.76 kg*mm"
frequency = "10Hz:14Hz:9"
sweep = "up"
[optimization]
objective = "peak-frf"
frf_load = "10 N"
band = "11 Hz:13 Hz:5"
vary = ["particles=0:120:60"]
[map]
frequency = "4Hz:36Hz:4"
amplitude = "log:1mm:50mm:4"
""")
    sc = load_scenario(tmp / "frame.toml")
    return sc, run_damper_report(sc, uncertainty=4)


def test_the_users_questions_are_sampled(doubt_report):
    _, rep = doubt_report
    assert set(rep.uncertainty) == {"level2", "level3", "frf", "load"}
    frf = rep.uncertainty["frf"]
    # the modal damping ratios move the forced response: mode 1's under the unbalance
    assert frf.answers["peak"].std > 0
    assert frf.answers["peak"].driver == "mode1.damping_ratio"
    nominal = next(iter(rep.forced.values()))
    np.testing.assert_allclose(frf.bands["amplitude"]["frequency"], nominal.frequency)
    load = rep.uncertainty["load"]
    assert load.answers["rms"].std > 0 and "envelope" in load.bands


def test_the_forced_response_figure_has_the_band(doubt_report):
    from pdamper.reports.damper_report import _forced_figure

    _, rep = doubt_report
    fig = _forced_figure(rep)
    band = rep.uncertainty["frf"].bands["amplitude"]
    (shade,) = [c for c in fig.axes[0].collections
                if c.get_label().startswith("5-95 % under the uncertain inputs")]
    ys = shade.get_paths()[0].vertices[:, 1]
    assert max(ys) == pytest.approx(max(band["p95"]) * 1e3)
    assert min(ys) == pytest.approx(min(band["p5"]) * 1e3)


def test_the_chosen_designs_drivers(doubt_report):
    from pdamper.reports.damper_report import render_damper_report

    _, rep = doubt_report
    dd = rep.design_drivers
    best = rep.study.best
    assert dd["design"] == best.as_dict() and dd["level"] == "frf" and dd["answer"] == "peak"
    a = dd["result"].answers["peak"]
    # sampled at the chosen design: its nominal run (harmonic balance) is the study's
    # objective of that design (stepped sines) within their difference, far from the others
    assert a.nominal == pytest.approx(best.objective, rel=0.01)
    others = [c.objective for c in rep.study.candidates if c is not best]
    assert min(abs(a.nominal - o) for o in others) > 5 * abs(a.nominal - best.objective)
    assert a.driver == "mode1.damping_ratio" and a.std > 0
    html = render_damper_report(rep)
    assert "What the chosen design is sensitive to" in html
    assert "<td>chosen design</td><td>peak</td><td>mode1.damping_ratio</td><td class=\"num\">" in html
    for level in ("frf", "load"):
        assert f"<td>{level}</td>" in html
    d = rep.as_dict()
    assert d["design_drivers"]["result"]["answers"]["peak"]["driver"] == "mode1.damping_ratio"
