"""``pdamper frf --uncertainty N``: the forced response's spread against closed forms, modal
parameters as uncertain inputs, and the inputs a fidelity does not use."""

import json
import math

import numpy as np
import pytest
from scipy import integrate
from scipy.stats import truncnorm

FORCE = 2.0  # N, the frf default


def _truncnorm(mean, sd):
    return truncnorm(-mean / sd, math.inf, loc=mean, scale=sd)


def _natural_frequency():
    from pdamper.io.scenario import load_scenario

    return load_scenario(None).structure_model().natural_frequency


def test_bare_one_dof_peak_follows_one_over_two_zeta(cli):
    # a linear 1-DOF without particles at its natural frequency: A = F / (2 zeta k)
    # exactly; zeta normal (5 % sd): A's mean and sd by integrating 1/(2 zeta k) over it
    from pdamper.io.scenario import load_scenario

    k = load_scenario(None).structure.stiffness
    fn = _natural_frequency()
    z0, sd, n = 0.01, 0.0005, 64
    code, out, err = cli("frf", "--particles", "0", "--frequency", f"{fn!r}Hz", "--sweep",
                         "up", "--max-cycles", "1", "--uncertain",
                         f"mode1.damping_ratio={z0}+-{sd}", "--uncertainty", n, "--json")
    assert code == 0, err
    u = json.loads(out)["uncertainty"]
    a = u["answers"]["peak"]
    dist = _truncnorm(z0, sd)
    lo, hi = z0 - 12 * sd, z0 + 12 * sd

    def amp(z):
        return FORCE / (2 * z * k)

    mean = integrate.quad(lambda z: amp(z) * dist.pdf(z), lo, hi, epsabs=0)[0]
    var = integrate.quad(lambda z: (amp(z) - mean) ** 2 * dist.pdf(z), lo, hi, epsabs=0)[0]
    std = math.sqrt(var)
    points = 2 * n  # the answers' statistics are those of A and B
    assert a["nominal"] == pytest.approx(amp(z0), rel=1e-9)
    assert abs(a["mean"] - mean) < 3 * std / math.sqrt(points)
    assert abs(a["std"] - std) < 3 * std / math.sqrt(2 * (points - 1))
    # first order: sd(A) = A0 sd / z0
    assert a["std"] == pytest.approx(amp(z0) * sd / z0, rel=0.03)
    assert a["driver"] == "mode1.damping_ratio" and u["not_used"] == {}


def test_sobol_split_of_damping_ratio_and_frequency(cli):
    # the resonant peak of the bare 1-DOF, F / (2 zeta m (2 pi f)^2): log A is linear in
    # log zeta and log f, so the variance splits (sd(zeta)/zeta)^2 : (2 sd(f)/f)^2,
    # 5 % and 2 x 1.25 %: 0.8 : 0.2, no interaction
    fn = _natural_frequency()
    code, out, err = cli("frf", "--particles", "0", "--frequency",
                         f"{fn * 0.935!r}Hz:{fn * 1.065!r}Hz:121", "--sweep", "up",
                         "--max-cycles", "1", "--uncertain", "mode1.damping_ratio=0.01+-0.0005",
                         "--uncertain", f"mode1.frequency={fn!r}Hz+-{fn * 0.0125!r}Hz",
                         "--uncertainty", "32", "--json")
    assert code == 0, err
    a = json.loads(out)["uncertainty"]["answers"]["peak"]
    for first in (a["first_order"], a["total_order"]):
        assert first["mode1.damping_ratio"] == pytest.approx(0.8, abs=0.08)
        assert first["mode1.frequency"] == pytest.approx(0.2, abs=0.08)
    assert a["ranking"] == ["mode1.damping_ratio", "mode1.frequency"]


def _machine_frame(tmp_path):
    # the machine frame's two modes at the tip (damper and sensor), from its FE model
    p = tmp_path / "modes.csv"
    p.write_text("frequency [Hz], damping ratio [%], damper [kg^-0.5], "
                 "observation [kg^-0.5]\n12.0, 1.0, 0.2582, 0.2582\n"
                 "31.0, 0.8, -0.3162, -0.3162\n")
    return p


def test_machine_frame_modal_damping_moves_the_mode1_peak_band(tmp_path, cli):
    # mode 1's damping ratio 1 % +- 30 %: the bare tip amplitude at 12 Hz under 10 N at
    # the tip, its 5/50/95 % band against the modal superposition at the ratio's quantiles
    # (the amplitude falls monotonically with zeta_1)
    from pdamper.io.scenario import load_scenario

    modes = _machine_frame(tmp_path)
    sc = load_scenario(None, {"structure.modes": str(modes), "particles.count": 0})
    s = sc.structure_model()
    w = 2 * np.pi * s.frequencies
    f1 = float(s.frequencies[0])
    force = 10.0

    def amp(z1):
        z = np.array(s.damping_ratios, float)
        z[0] = z1
        h = s.damper_shape * s.output_shape / (w**2 - w[0] ** 2 + 2j * z * w * w[0])
        return abs(force * h.sum())

    code, out, err = cli("frf", "--modes", modes, "--particles", "0", "--force", "10N",
                         "--frequency", f"{f1!r}Hz", "--sweep", "up", "--max-cycles", "1",
                         "--uncertain", "mode1.damping_ratio=1%+-0.3%", "--uncertainty", "256",
                         "--json")
    assert code == 0, err
    d = json.loads(out)
    a = d["uncertainty"]["answers"]["peak"]
    assert a["nominal"] == pytest.approx(amp(0.01), rel=1e-6)
    assert a["nominal"] == pytest.approx(10.0 * 0.2582**2 / (2 * 0.01 * w[0] ** 2), rel=0.01)
    dist = _truncnorm(0.01, 0.003)
    for p in (5, 25, 50, 75, 95):
        # the p-th percentile of A is A at the (100 - p)-th of zeta_1: 512 points' error
        assert a["percentiles"][f"p{p}"] == pytest.approx(amp(dist.ppf(1 - p / 100)),
                                                          rel=0.04), p
    band = d["uncertainty"]["bands"]["amplitude"]
    assert band["frequency"] == [f1] and band["p95"][0] == pytest.approx(a["percentiles"]["p95"])
    # the nominal run used the file's ratio (the nominal): the stepped sine agrees
    assert d["inputs"]["structure"]["modes"] == str(modes)


def test_modal_input_in_the_scenario_table_and_bounds(tmp_path, cli):
    modes = _machine_frame(tmp_path)
    p = tmp_path / "s.toml"
    p.write_text(f'[structure]\nmodes = "{modes}"\n[particles]\ncount = 0\n'
                 '[uncertain]\n"mode2.frequency" = "31 Hz +- 0.5 Hz"\n'
                 '[mode1]\ndamping_ratio = "1.2 % +- 0.3 %"\n')
    from pdamper.io.scenario import load_scenario

    sc = load_scenario(p)
    assert [u.field for u in sc.uncertain_inputs()] == ["mode2.frequency",
                                                        "mode1.damping_ratio"]
    s = sc.structure_model()  # the nominal values replace the file's
    assert s.damping_ratios[0] == pytest.approx(0.012) and s.frequencies[1] == 31.0
    code, _, err = cli("frf", "--modes", modes, "--uncertain", "mode3.frequency=50Hz+-1Hz",
                       "--uncertainty", "4")
    assert code == 2 and err.startswith("error: mode3.frequency: the structure has 2 modes")
    code, _, err = cli("frf", "--uncertain", "mode1.stiffness=1+-0.1", "--uncertainty", "4")
    assert code == 2 and err.startswith("error: mode1.stiffness: a mode's uncertain "
                                        "parameters are damping_ratio, frequency")
    # the 1-DOF's damping beside a modes file: refused, naming the modal field to use
    code, _, err = cli("frf", "--modes", modes, "--uncertain", "structure.damping=1kg/s+-0.1kg/s",
                       "--uncertainty", "4")
    assert code == 2 and "mode1.damping_ratio" in err and err.count("\n") == 1
    code, _, err = cli("frf", "--uncertain", "mode1.damping_ratio=120%+-1%")
    assert code == 2 and "mode1.damping_ratio: the nominal value must be in (0, 1)" in err


def test_inputs_the_analytic_fidelity_does_not_use_are_named(cli):
    # friction and restitution do not enter the analytical bed: named as not used by it,
    # with the fidelity that uses them, in JSON and text (not a bare zero sensitivity)
    args = ("frf", "--particles", "32", "--frequency", "5Hz:6Hz:3", "--sweep", "up",
            "--max-cycles", "20", "--uncertain", "particles.friction=0.1+-0.03",
            "--uncertain", "dem.restitution_pp=0.6+-0.05", "--uncertainty", "4")
    code, out, err = cli(*args, "--json")
    assert code == 0, err
    u = json.loads(out)["uncertainty"]
    assert set(u["not_used"]) == {"particles.friction", "dem.restitution_pp"}
    for why in u["not_used"].values():
        assert why["fidelity"] == "analytic" and why["used_by"] == ["dem"]
        assert "plastic block" in why["reason"]
    code, out, _ = cli(*args)
    assert code == 0
    assert "particles.friction: not used by the analytic fidelity (used by: dem)" in out
    assert "no spread: its inputs are not used by this fidelity" in out
    assert "driver none" not in out


def test_analytic_names_friction_as_not_used(cli):
    code, out, err = cli("analytic", "--uncertain", "particles.friction=0.1+-0.03",
                         "--uncertain", "container.length=120mm+-1mm", "--uncertainty", "4",
                         "--json")
    assert code == 0, err
    u = json.loads(out)["uncertainty"]
    assert list(u["not_used"]) == ["particles.friction"]
    assert u["answers"]["loss_factor"]["driver"] == "container.length"


def test_fidelities_declare_what_they_do_not_use():
    from pdamper.models.registry import DAMPER_MODELS, input_users, not_used

    assert input_users("particles.friction") == ["dem"]
    assert input_users("restitution.particle_wall[pc2]") == ["dem"]
    assert input_users("container.length") == list(DAMPER_MODELS)
    assert not_used(DAMPER_MODELS["dem"], ["particles.friction"]) == {}


def test_frf_realisations_of_a_fields_map(tmp_path, cli):
    # a map with two realisations (the second's loss factor 0.7 times the first's): the
    # band's peaks are those of the forced response on each realisation's map alone
    import xarray as xr

    from pdamper.files import atomic_write_netcdf
    from pdamper.runs.realisations import combine_realisations, realisation_map

    m = tmp_path / "m.nc"
    code, _, err = cli("map", "--model", "analytic", "--particles", "32", "--frequency",
                       "2Hz:12Hz:11", "--amplitude", "log:0.5mm:200mm:30", "--out", m)
    assert code == 0, err
    first = xr.load_dataset(m)
    second = first.copy(deep=True)
    second["loss_factor"] = second["loss_factor"] * 0.7
    both = combine_realisations([first, second], [0, 1])
    mr = tmp_path / "mr.nc"
    atomic_write_netcdf(mr, both)
    args = ("frf", "--model", "fields", "--particles", "32", "--frequency", "4Hz:7Hz:7",
            "--sweep", "up", "--max-cycles", "300", "--json")
    code, out, err = cli(*args, "--fields", mr, "--realisations", "2",
                         "--plot", tmp_path / "band.png")
    assert code == 0, err
    band = json.loads(out)["realisations"]
    assert band["count"] == 2 and band["map_realisations"] == [0, 1]
    peaks = []
    for k in range(2):
        one = tmp_path / f"r{k}.nc"
        atomic_write_netcdf(one, realisation_map(both, k))
        code, out, err = cli(*args, "--fields", one)
        assert code == 0, err
        peaks.append(max(p["up"]["amplitude"] for p in json.loads(out)["points"]))
    assert band["peak"]["up"]["values"] == pytest.approx(peaks, rel=1e-9)
    assert peaks[1] > peaks[0]  # less damping, a higher peak: the band is not one run
    up = band["sweeps"]["up"]
    assert max(up["amplitude_max"]) == pytest.approx(peaks[1], rel=1e-9)
    code, _, err = cli("frf", "--realisations", "2")
    assert code == 2 and err.startswith("error: realisations: must be 1 for the analytic")
