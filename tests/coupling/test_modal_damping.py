"""Damping per mode of an N-mode free decay, from the modal coordinates."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pdamper.coupling.decrement import modal_damping_ratios


def _free_decay(f, zeta, q0, duration, rate=20000.0):
    """Two uncoupled modal equations integrated by scipy (independent of pdamper)."""
    w = 2 * np.pi * np.asarray(f)
    z = np.asarray(zeta)

    def rhs(_t, y):
        q, v = y[:2], y[2:]
        return np.concatenate([v, -2 * z * w * v - w**2 * q])

    t = np.arange(0.0, duration, 1.0 / rate)
    sol = solve_ivp(rhs, (0.0, duration), np.concatenate([q0, [0.0, 0.0]]), t_eval=t,
                    rtol=1e-11, atol=1e-14, method="DOP853")
    return t, sol.y[:2]


def test_two_mode_free_decay_damping_per_mode():
    # the machine frame's two modes (12 Hz 1 %, 31 Hz 0.8 %), released into both
    t, q = _free_decay([12.0, 31.0], [0.01, 0.008], [-1e-3, -4e-4], 2.0)
    res = modal_damping_ratios(t, q)
    assert [r.mode for r in res] == [1, 2]
    assert res[0].damping_ratio == pytest.approx(0.01, rel=1e-3)
    assert res[1].damping_ratio == pytest.approx(0.008, rel=1e-3)
    assert all(r.reason is None for r in res)
    # the beating sum at the tip would not give these: its per-cycle decrement scatters
    x = 0.2582 * q[0] - 0.3162 * q[1]
    from pdamper.coupling.decrement import damping_ratio_from_peaks, negative_peaks
    _, a = negative_peaks(t, x)
    _, z_sum = damping_ratio_from_peaks(a)
    assert np.ptp(z_sum) > 0.01


def test_growing_mode_is_not_applicable_not_negative():
    t = np.linspace(0.0, 1.0, 20001)
    q = np.vstack([np.exp(0.5 * t) * np.cos(2 * np.pi * 10 * t), np.zeros_like(t)])
    res = modal_damping_ratios(t, q)
    assert res[0].damping_ratio is None and "does not decay" in res[0].reason
    assert res[1].damping_ratio is None and "negative peaks" in res[1].reason
    assert res[0].as_dict()["not_applicable"] == res[0].reason


def test_simulate_reports_damping_per_mode_of_two_modes(tmp_path, cli):
    import json

    # the machine frame's modes (shared/user-cases/machine-frame/modes.csv)
    (tmp_path / "modes.csv").write_text(
        "frequency [Hz], damping ratio [%], damper [kg^-0.5], observation [kg^-0.5]\n"
        "12.0, 1.0, 0.2582, 0.2582\n31.0, 0.8, -0.3162, -0.3162\n")
    args = ("simulate", "--modes", tmp_path / "modes.csv", "--duration", "1s",
            "--initial-displacement", "-5mm")
    code, out, err = cli(*args, "--json")
    assert code == 0, err
    per_mode = json.loads(out)["damping_per_mode"]
    assert [m["mode"] for m in per_mode] == [1, 2]
    for m in per_mode:  # a ratio with its cycles, or not applicable with the reason
        assert (m["damping_ratio"] is not None and m["damping_ratio"] > 0) \
            or m["not_applicable"]
    code, out, err = cli(*args)
    assert code == 0, err
    assert "damping per mode" in out and "mode 1:" in out and "mode 2:" in out


def test_one_mode_run_has_no_per_mode_damping(paper_run32):
    assert paper_run32.damping_per_mode is None


def test_simulate_text_prints_no_negative_damping_ratio_on_two_modes(tmp_path, cli):
    import re

    (tmp_path / "modes.csv").write_text(
        "frequency [Hz], damping ratio [%], damper [kg^-0.5], observation [kg^-0.5]\n"
        "12.0, 1.0, 0.2582, 0.2582\n31.0, 0.8, -0.3162, -0.3162\n")
    code, out, err = cli("simulate", "--modes", tmp_path / "modes.csv", "--duration", "1s",
                         "--initial-displacement", "-5mm")
    assert code == 0, err
    assert "n/a*" in out  # this beating decay has growing peaks of the sum
    assert not re.search(r"\s-0\.\d{4}\s", out)


def test_half_power_damping_of_a_1dof_response():
    from pdamper.coupling.decrement import resonance_damping

    f = np.linspace(3.0, 9.0, 60001)
    for zeta in (0.005, 0.02, 0.1):
        r = f / 5.56
        x = 1.0 / np.abs(1.0 - r**2 + 2j * zeta * r)  # closed form, not pdamper's
        (res,) = resonance_damping(f, x)
        assert res["damping_ratio"] == pytest.approx(zeta, rel=1e-3)
        assert res["f_low"] < res["frequency"] < res["f_high"]


def test_half_power_damping_of_two_separated_modes_and_a_cut_sweep():
    from pdamper.coupling.decrement import resonance_damping

    f = np.linspace(6.0, 40.0, 40001)
    w = 2 * np.pi * f
    h = sum(p * p / ((2 * np.pi * fn) ** 2 - w**2 + 2j * z * (2 * np.pi * fn) * w)
            for fn, z, p in ((12.0, 0.01, 0.2582), (31.0, 0.008, -0.3162)))
    res = resonance_damping(f, np.abs(h))
    assert [round(r["frequency"]) for r in res] == [12, 31]
    assert res[0]["damping_ratio"] == pytest.approx(0.01, rel=0.02)
    assert res[1]["damping_ratio"] == pytest.approx(0.008, rel=0.02)
    cut = f < 12.08  # past the peak, short of its upper half-power point (~12.12 Hz)
    (r,) = resonance_damping(f[cut], np.abs(h[cut]))
    assert r["damping_ratio"] is None and "1/sqrt(2)" in r["not_applicable"]


def test_frf_reports_each_resonance_with_and_without_the_damper(tmp_path, cli):
    import json

    (tmp_path / "modes.csv").write_text(
        "frequency [Hz], damping ratio [%], damper [kg^-0.5], observation [kg^-0.5]\n"
        "12.0, 1.0, 0.2582, 0.2582\n31.0, 0.8, -0.3162, -0.3162\n")
    code, out, err = cli("frf", "--modes", tmp_path / "modes.csv", "--frequency",
                         "10Hz:14Hz:41", "--json")
    assert code == 0, err
    res = json.loads(out)["resonances"]
    assert res["method"].startswith("half-power bandwidth")
    (bare,) = res["without_damper"]
    assert bare["frequency"] == pytest.approx(12.0, abs=0.1)
    assert bare["damping_ratio"] == pytest.approx(0.01, rel=0.05)
    for name in ("up", "down"):
        (with_damper,) = res[name]
        assert with_damper["damping_ratio"] > bare["damping_ratio"]
