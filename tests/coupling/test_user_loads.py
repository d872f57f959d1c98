"""The user's loads where they act, and defaults from the user's structure: the machine
frame's unbalance at its motor (closed-form modal superposition), a run-up, the bracket's
base sine sweep, frequencies that span every mode, figures in the user's terms."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.coupling.frf import HarmonicLoad, default_frequencies, frequency_response
from pdamper.coupling.loads import LoadHistory, RunUp, simulate_load
from pdamper.errors import InputError
from pdamper.io.modes import read_modes
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT.parent.parent / "shared" / "user-cases"
EXAMPLE = ROOT / "examples" / "machine-frame"
#: The machine frame of problem.md, written out here: f_i [Hz], zeta_i, phi at the damper
#: (tip), at the motor (load) and at the sensor (tip) [kg^-0.5]; m e [kg m].
FRAME = {"f": np.array([12.0, 31.0]), "zeta": np.array([0.010, 0.008]),
         "damper": np.array([0.2582, -0.3162]), "load": np.array([0.1500, 0.2400]),
         "observation": np.array([0.2582, -0.3162])}
ME = 1.76e-3


def _frame_modes():
    """The case's modes.csv (the copy in examples/ where the shared case is absent)."""
    path = CASES / "machine-frame" / "modes.csv"
    return read_modes(path if path.is_file() else EXAMPLE / "modes.csv")


def _frame_unbalance_closed_form(f: np.ndarray, modes: dict | None = None) -> np.ndarray:
    """The observation point under m e W^2 cos(W t) at the motor, without particles:
    ``sum_i phi_o,i phi_L,i m e W^2 / (w_i^2 - W^2 + 2 i zeta_i w_i W)`` (``modes``: the
    frequencies, damping ratios and shapes, default the frame's as given)."""
    m = FRAME if modes is None else modes
    w = 2 * np.pi * m["f"]
    big_w = 2 * np.pi * np.asarray(f, float)[:, None]
    terms = (m["observation"] * m["load"] * ME * big_w**2
             / (w**2 - big_w**2 + 2j * m["zeta"] * w * big_w))
    return terms.sum(axis=1)


def _bare(damper=PAPER_DAMPER):
    return AnalyticalDamper(damper.with_count(0))


# ----------------------------------------------------------------------------- load point
def test_the_modes_file_reads_the_load_column_by_its_name():
    s = _frame_modes()
    np.testing.assert_array_equal(s.damper_shape, FRAME["damper"])
    np.testing.assert_array_equal(s.load_shape, FRAME["load"])
    np.testing.assert_array_equal(s.output_shape, FRAME["observation"])
    np.testing.assert_array_equal(s.release_shape, FRAME["damper"])  # released at the damper
    assert not s.coincident


def test_load_column_anywhere_and_one_only(tmp_path):
    p = tmp_path / "m.csv"
    p.write_text("load [kg^-0.5], frequency [Hz], damper [kg^-0.5], damping ratio [%]\n"
                 "0.15, 12, 0.2582, 1\n")
    s = read_modes(p)
    assert s.load_shape[0] == 0.15 and s.damper_shape[0] == 0.2582
    assert s.output_shape[0] == 0.2582
    p.write_text("frequency [Hz], damping ratio [%], damper [kg^-0.5], load [kg^-0.5], "
                 "load motor [kg^-0.5]\n12, 1, 0.2582, 0.15, 0.1\n")
    with pytest.raises(InputError, match="a second load column") as e:
        read_modes(p)
    assert e.value.field == "structure.modes"


def test_without_a_load_column_the_load_acts_at_the_damper(tmp_path, cli):
    p = tmp_path / "m.csv"
    p.write_text("frequency [Hz], damping ratio [%], damper [kg^-0.5], observation [kg^-0.5]\n"
                 "12, 1, 0.2582, 0.2582\n31, 0.8, -0.3162, -0.3162\n")
    s = read_modes(p)
    np.testing.assert_array_equal(s.load_shape, s.damper_shape)
    code, out, err = cli("frf", "--modes", p, "--particles", "0", "--force", "2N",
                         "--frequency", "12Hz", "--sweep", "up", "--json")
    assert code == 0, err
    assert json.loads(out)["frf_inputs"]["load_point"].startswith("the damper's point")


def test_machine_frame_bare_unbalance_frf_is_the_modal_superposition(cli):
    """Both modes under m e W^2 at the motor, observed at the tip: the linear FRF, harmonic
    balance and the stepped sine of the frf command against the closed form written
    above; mode 1's peak is the problem's hand estimate F phi_L phi_tip / (2 zeta w^2) =
    3.4 mm."""
    code, out, err = cli("frf", "--modes", _modes_path(), "--unbalance", "1.76kg*mm",
                         "--particles", "0", "--sweep", "up", "--json")
    assert code == 0, err
    d = json.loads(out)
    f = np.array([p["frequency"] for p in d["points"]])
    ref = _frame_unbalance_closed_form(f)
    lin = np.array([p["linear_amplitude"] for p in d["points"]])
    hb = np.array([p["harmonic_balance"][0]["amplitude"] for p in d["points"]])
    ph = np.array([p["harmonic_balance"][0]["phase"] for p in d["points"]])
    np.testing.assert_allclose(lin, np.abs(ref), rtol=1e-6)
    np.testing.assert_allclose(hb, np.abs(ref), rtol=1e-6)
    np.testing.assert_allclose(np.exp(1j * ph), np.exp(1j * np.angle(ref)), atol=1e-6)
    up = np.array([p["up"]["amplitude"] for p in d["points"]])
    np.testing.assert_allclose(up, np.abs(ref), rtol=3e-3)  # the stepped sine's 0.1 % rule
    assert d["load"]["kind"] == "unbalance" and d["load"]["amplitude"] == pytest.approx(ME)
    assert d["frf_inputs"]["load_point"] == "the structure's load point"
    mode1 = (f > 10) & (f < 14)
    hand = 10.0 * 0.15 * 0.2582 / (2 * 0.01 * (2 * math.pi * 12) ** 2)
    assert hand == pytest.approx(3.4e-3, rel=0.01)
    assert np.max(lin[mode1]) == pytest.approx(hand, rel=0.02)  # F at 12 Hz is 10.005 N
    assert 12.0 in f and 31.0 in f


def _modes_path() -> Path:
    path = CASES / "machine-frame" / "modes.csv"
    return path if path.is_file() else EXAMPLE / "modes.csv"


def test_a_force_history_acts_at_the_load_point():
    """The shock at the motor, without particles: the load-history integration against an
    independent solution of ``q'' + 2 zeta w q' + w^2 q = phi_L F(t)`` (scipy, DOP853)."""
    from scipy.integrate import solve_ivp

    s = _frame_modes()
    t = np.linspace(0.0, 0.01, 41)
    h = LoadHistory(t, 1000.0 * np.sin(np.pi * t / 0.01), "force", "half-sine")
    r = simulate_load(_bare(), s, h, sample_rate=4000.0, tail=0.2)
    w = 2 * np.pi * FRAME["f"]

    def rhs(tt, z):
        q, v = z[:2], z[2:]
        force = np.interp(tt, t, h.values, right=0.0)
        return np.concatenate([v, FRAME["load"] * force - 2 * FRAME["zeta"] * w * v - w**2 * q])

    sol = solve_ivp(rhs, (0.0, r.time[-1]), np.zeros(4), method="DOP853", t_eval=r.time,
                    rtol=1e-11, atol=1e-14, max_step=2.5e-4)
    x = FRAME["observation"] @ sol.y[:2]
    assert np.max(np.abs(r.displacement - x)) < 1e-6 * np.max(np.abs(x))
    # at the damper's point instead, the response differs (the shapes differ)
    from pdamper.coupling.loads import acting_at

    r_d = simulate_load(_bare(), acting_at(s, "damper"), h, sample_rate=4000.0, tail=0.2)
    assert abs(r_d.peak - r.peak) > 0.1 * r.peak


def test_beam_load_position_is_the_shape_there():
    from pdamper.parameters import paper_beam
    from pdamper.structure.modal import ModalStructure

    beam, tip = paper_beam()
    s = ModalStructure.from_beam(beam, tip, 3, load_position=0.34)
    o = ModalStructure.from_beam(beam, tip, 3, output_position=0.34)
    np.testing.assert_allclose(s.load_shape, o.output_shape, rtol=1e-14)
    assert not s.coincident
    d = ModalStructure.from_beam(beam, tip, 3)
    np.testing.assert_array_equal(d.load_shape, d.damper_shape)  # default: the damper point


# ----------------------------------------------------------------------------- unbalance, rpm
def test_unbalance_parsing_and_its_force():
    ld = HarmonicLoad.parse("1.76kg*mm", "unbalance")
    assert ld.kind == "unbalance" and ld.amplitude == pytest.approx(1.76e-3, rel=1e-15)
    om = 2 * math.pi * 1440 / 60
    assert ld.reference(om) == pytest.approx(1.76e-3 * om**2, rel=1e-15)
    with pytest.raises(InputError, match="unbalance m e") as e:
        HarmonicLoad.parse("2 N", "unbalance")
    assert e.value.field == "unbalance"


def test_run_up_force_is_m_e_omega_squared_at_its_instants():
    """The force at the instants where the unbalance points up (the angle integrated from
    the ramp: 2 pi (n0 t + (n1 - n0) t^2 / 2T) = pi/2 + 2 pi k, solved here) is m e Omega^2
    with Omega = 2 pi n(t); the sampled record holds it within 2e-4."""
    r = RunUp.parse("1.76kg*mm", "400rpm:2400rpm:20s")
    n0, n1, big_t = 400 / 60, 2400 / 60, 20.0
    k = np.array([0, 1, 10, 100, 400, 460])
    a, b = 0.5 * (n1 - n0) / big_t, n0
    t = (-b + np.sqrt(b * b + 4 * a * (k + 0.25))) / (2 * a)
    omega = 2 * np.pi * (n0 + (n1 - n0) * t / big_t)
    np.testing.assert_allclose(r.force(t), ME * omega**2, rtol=1e-9)
    h = r.history()
    np.testing.assert_allclose(h.at(t), ME * omega**2, rtol=2e-4)
    assert r.speed(0.0) == pytest.approx(n0) and r.speed(big_t) == pytest.approx(n1)
    # a run-down runs the other way; a constant speed is a steady unbalance
    down = RunUp.parse("1.76kg*mm", "2400rpm:400rpm:20s")
    assert down.speed(5.0) == pytest.approx(n1 - (n1 - n0) * 5 / 20)
    steady = RunUp.parse("1.76kg*mm", "720rpm:720rpm:2s")
    tt = (np.arange(24) + 0.25) / 12.0
    np.testing.assert_allclose(steady.force(tt), ME * (2 * np.pi * 12) ** 2, rtol=1e-12)


@pytest.mark.parametrize("ramp", ["400rpm:2400rpm", "400rpm:2400rpm:0s", "0rpm:0rpm:2s",
                                  "400 mm:2400rpm:20s", "-400rpm:2400rpm:20s"])
def test_bad_ramps_name_the_key(ramp):
    with pytest.raises(InputError) as e:
        RunUp.parse("1.76kg*mm", ramp)
    assert e.value.field == "load.run_up" and "\n" not in str(e.value)


# ----------------------------------------------------------------------------- defaults
def test_default_frequencies_span_every_mode_with_points_per_bandwidth():
    """Without --frequency: from half the first to 1.5 times the last natural frequency,
    every natural frequency on the grid and points no farther apart than f_i zeta_i / 2
    over five half-power bandwidths either side (four per bandwidth 2 zeta_i f_i)."""
    s = _frame_modes()
    f = default_frequencies(s)
    assert f[0] == pytest.approx(6.0) and f[-1] == pytest.approx(46.5)
    for f_i, z_i in zip(FRAME["f"], FRAME["zeta"], strict=True):
        assert np.min(np.abs(f - f_i)) < 1e-9 * f_i
        near = f[np.abs(f - f_i) <= 5 * 2 * z_i * f_i * (1 + 1e-9)]
        assert np.max(np.diff(near)) <= f_i * z_i / 2 * (1 + 1e-9)
        half_power = f[np.abs(f - f_i) <= z_i * f_i * (1 + 1e-9)]
        assert half_power.size >= 4
    # the bed tunes the modes down: the refined grid reaches there
    heavy = default_frequencies(s, added_mass=0.5)
    tuned = 12.0 / math.sqrt(1 + 0.5 * 0.2582**2)
    assert np.max(np.diff(heavy[(heavy > tuned - 0.05) & (heavy < 12.0)])) <= 0.06 + 1e-9


def test_optimize_default_band_spans_every_mode():
    from pdamper.design.study import make_objective

    o = make_objective("peak-frf", 0.8, -0.003, _frame_modes())
    band = np.array(o.band)
    assert band[0] == pytest.approx(6.0) and band[-1] == pytest.approx(46.5)
    assert 12.0 in band and 31.0 in band


def _bracket(tmp_path) -> Path:
    """The bracket of bracket-sweep/problem.md: a 1-DOF of 0.8 kg at 45 Hz, 0.5 %, under a
    50 g damper of 3 mm steel spheres in an aluminium box."""
    m = 0.8
    k = m * (2 * math.pi * 45.0) ** 2
    d = 2 * 0.005 * math.sqrt(k * m)
    p = tmp_path / "bracket.toml"
    p.write_text(f'[structure]\nmass = "{m} kg"\nstiffness = "{k} N/m"\n'
                 f'damping = "{d} kg/s"\ninitial_displacement = "-1 mm"\n'
                 '[container]\nlength = "20 mm"\nwidth = "24 mm"\ndepth = "24 mm"\n'
                 'material = "aluminium"\nmass = "12 g"\n'
                 '[particles]\nradius = "1.5 mm"\nmaterial = "100Cr6"\ncount = 300\n'
                 '[frf]\nbase_acceleration = "0.5 g0"\n')
    return p


@pytest.mark.long  # 20 s: 99 frequencies up and down with 300 spheres
def test_bracket_base_sweep_up_and_down_with_every_mode_in_the_band(tmp_path, cli):
    """The bracket's base sine sweep of 0.5 g, up and down, without --frequency: the band
    holds 45 Hz; bare, the board moves 1/(2 zeta) = 100 times the base at resonance; the
    analytical damper lowers the peak in both directions."""
    code, out, err = cli("frf", "--scenario", _bracket(tmp_path), "--json")
    assert code == 0, err
    d = json.loads(out)
    f = np.array([p["frequency"] for p in d["points"]])
    assert f[0] < 45.0 < f[-1] and np.min(np.abs(f - 45.0)) < 1e-9
    assert d["load"] == {"kind": "base", "amplitude": pytest.approx(0.5 * 9.80665),
                         "unit": "m/s^2", "acceleration": True}
    assert d["frf_inputs"]["sweep"] == "both"
    y = 0.5 * 9.80665 / (2 * np.pi * f) ** 2
    lin = np.array([p["linear_amplitude"] for p in d["points"]]) / y
    assert np.max(lin) == pytest.approx(math.sqrt(1 + 0.01**2) / 0.01, rel=1e-3)
    for way in ("up", "down"):
        a = np.array([p[way]["amplitude"] for p in d["points"]]) / y
        assert np.max(a) < 0.8 * np.max(lin), way


def test_bracket_fields_follow_the_analytic_sweep(tmp_path):
    """The effective fields of an analytical map over the bracket's strokes follow the
    analytical sweep (the same describing function, interpolated)."""
    from pdamper.analysis.fields import effective_field
    from pdamper.io.scenario import load_scenario
    from pdamper.models import EffectiveFieldDamper

    sc = load_scenario(_bracket(tmp_path))
    s, damper = sc.structure_model(), sc.damper()
    load = sc.frf.load()
    f = np.array([40.0, 43.0, 44.0, 45.0, 46.0, 48.0])
    analytic = AnalyticalDamper(damper)
    fmap = effective_field(analytic, np.linspace(38.0, 50.0, 25),
                           np.geomspace(1e-5, 2e-2, 60))
    fields = EffectiveFieldDamper(damper, field=fmap, extrapolation="analytic")
    a = frequency_response(analytic, s, load, f, sweep="up")
    b = frequency_response(fields, s, load, f, sweep="up")
    np.testing.assert_allclose(b.sweeps["up"].amplitude, a.sweeps["up"].amplitude, rtol=0.05)


# ----------------------------------------------------------------------------- figures
def test_user_figures_carry_no_paper_figure_numbers(paper_run32):
    """simulate's and frf's figures of a user's results: titles in the user's terms."""
    from pdamper.cli.simulate import _figure as decay_figure
    from pdamper.plots.frf import plot_frf

    s = _frame_modes()
    res = frequency_response(_bare(), s, HarmonicLoad("unbalance", ME), [11.0, 12.0, 13.0],
                             sweep="up")
    axes = plot_frf(res)
    fig = decay_figure({"analytic": paper_run32}, None, {}, {})
    titles = [a.get_title() for a in (*axes, *fig.axes)]
    assert titles and not any("Fig" in t for t in titles), titles
    assert "unbalance 1.76 kg mm" in axes[0].get_title()
    labels = [t.get_text() for t in axes[0].get_legend().get_texts()]
    assert any("bare structure" in t for t in labels)
    assert axes[2].get_ylabel().startswith("damper loss factor")


# ----------------------------------------------------------------------------- the example
@pytest.mark.long  # 30 s: the report's map, decays, forced responses and design study
def test_machine_frame_example_runs_simulate_frf_and_report(tmp_path, cli):
    """examples/machine-frame/scenario.toml (written from the case's problem.md) end to
    end with the analytical fidelity: the shock at the tip, a run-up of the unbalance at
    the motor, the unbalance's forced response and the report over both modes."""
    scenario = EXAMPLE / "scenario.toml"
    code, out, err = cli("simulate", "--scenario", scenario, "--json")
    assert code == 0, err
    shock = json.loads(out)
    assert shock["load"]["point"].startswith("the damper's point")
    assert shock["peak"] > 0 and shock["energy_balance_error"] < 1e-3

    code, out, err = cli("simulate", "--scenario", scenario, "--unbalance", "1.76kg*mm",
                         "--run-up", "600rpm:1000rpm:3s", "--tail", "0s", "--json")
    assert code == 0, err
    run = json.loads(out)
    assert run["load"]["point"] == "the structure's load point"
    assert run["load"]["run_up"]["start_speed"] == pytest.approx(10.0)
    assert run["load"]["run_up"]["stop_speed"] == pytest.approx(1000 / 60)
    assert 0 < run["peak"] < 0.01

    code, out, err = cli("frf", "--scenario", scenario, "--sweep", "up", "--json")
    assert code == 0, err
    d = json.loads(out)
    f = np.array([p["frequency"] for p in d["points"]])
    # the grid spans the modes of the structure as run: the modes file's 12 and 31 Hz with
    # the box's 69 g added at the tip (a modes file does not include it)
    from pdamper.io.scenario import load_scenario

    run = load_scenario(scenario).structure_model()  # the mass-modified modes (structure/)
    f1, f2 = run.frequencies
    assert 11.9 < f1 < 12.0 and 30.5 < f2 < 31.0
    assert f[0] == pytest.approx(f1 / 2) and np.isclose(f, f1).any() and np.isclose(f, f2).any()
    lin = np.array([p["linear_amplitude"] for p in d["points"]])
    modes = {"f": np.asarray(run.frequencies), "zeta": np.asarray(run.damping_ratios),
             "observation": np.asarray(run.output_shape), "load": np.asarray(run.load_shape)}
    np.testing.assert_allclose(lin, np.abs(_frame_unbalance_closed_form(f, modes)), rtol=1e-6)

    code, out, err = cli("report", "--scenario", scenario, "--out", tmp_path / "r", "--json")
    assert code == 0, err
    fr = json.loads((tmp_path / "r" / "results.json").read_text())["forced_response"]
    assert fr["load"]["kind"] == "unbalance" and "unbalance" in fr["load_text"]
    for m in fr["models"].values():
        # the modes as run (with the box); mode 1's bare peak within 1 % of the given
        # modes' 3.408 mm (69 g on the 15 kg referred to the tip)
        assert [k["natural_frequency"] for k in m["modes"]] == pytest.approx([f1, f2])
        assert m["modes"][0]["no_particles_peak_amplitude"] == pytest.approx(3.408e-3,
                                                                             rel=1e-2)
        assert all(k["peak_amplitude"] < k["no_particles_peak_amplitude"] for k in m["modes"])
    page = (tmp_path / "r" / "report.html").read_text()
    assert "Unbalance 1.76 kg mm" in page and "Fig." not in page.split("Forced response")[1]


# ----------------------------------------------------------------------------- inputs
@pytest.mark.parametrize(("values", "field"), [
    ({"frf.force": "2 N", "frf.unbalance": "1 kg*mm"}, "frf"),
    ({"frf.unbalance": "2 N"}, "frf.unbalance"),
    ({"frf.sweep": "sideways"}, "frf.sweep"),
    ({"frf.at": "motor"}, "frf.at"),
    ({"frf.frequency": "40Hz:6Hz:10"}, "frf.frequency"),
    ({"load.unbalance": "1.76 kg*mm"}, "load"),
    ({"load.run_up": "400rpm:2400rpm:20s"}, "load"),
])
def test_bad_frf_and_load_keys_name_the_key(values, field):
    from pdamper.io.scenario import load_scenario

    with pytest.raises(InputError) as e:
        load_scenario(None, values)
    assert e.value.field == field and "\n" not in str(e.value)


def test_the_command_line_load_replaces_the_scenario_load(tmp_path, cli):
    """The scenario's shock at the damper, the command line's run-up: the run-up runs, at
    the load point (the scenario's ``at`` belonged to its shock); two loads on the command
    line are refused."""
    from pdamper.io.scenario import load_scenario

    p = tmp_path / "s.toml"
    p.write_text(f'[structure]\nmodes = "{_modes_path()}"\n'
                 '[load]\nforce = "shock.csv"\nat = "damper"\n')
    sc = load_scenario(p, {"load.unbalance": "1.76 kg*mm",
                           "load.run_up": "600rpm:600rpm:1s"})
    assert sc.load.force is None and sc.load.at == "load"
    assert sc.load.run_up_load().start == pytest.approx(10.0)
    code, _, err = cli("simulate", "--scenario", p, "--load", p,
                       "--run-up", "600rpm:600rpm:1s", "--unbalance", "1g*mm")
    assert code == 2 and "load: give one load" in err


def test_a_huge_frf_frequency_count_is_refused_before_the_grid(tmp_path, cli):
    p = tmp_path / "s.toml"
    p.write_text('[frf]\nfrequency = "4Hz:7Hz:1000000000"\n')
    code, _, err = cli("frf", "--scenario", p)
    assert code == 2 and err.startswith("error: frf.frequency: at most")


def test_frf_takes_a_grid_in_rpm(cli):
    code, out, err = cli("frf", "--modes", _modes_path(), "--unbalance", "1.76kg*mm",
                         "--particles", "0", "--frequency", "600rpm:1200rpm:3", "--sweep",
                         "up", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert [p["frequency"] for p in d["points"]] == pytest.approx([10.0, 15.0, 20.0])
    assert d["frf_inputs"]["frequency_source"] == "--frequency"
