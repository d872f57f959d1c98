"""Measured end-effector trajectories (paper Sect. 4, Figs. 7/8): the CSV reader, its one-line
errors, and a measurement made from a known simulation compared through the CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.io.measured import read_measured


def _write(path, text):
    path.write_text(text)
    return path


def _rows(n=20):
    return "".join(f"{k * 0.5}, {-58 + k:.1f}\n" for k in range(n))


def test_units_are_converted_to_si(tmp_path):
    p = _write(tmp_path / "a.csv", "# comment\n\ntime [ms], displacement [mm]\n" + _rows())
    m = read_measured(p)
    assert m.quantity == "displacement" and m.columns == ("time [ms]", "displacement [mm]")
    assert m.time[1] == pytest.approx(5e-4) and m.displacement[0] == pytest.approx(-0.058)
    p = _write(tmp_path / "b.csv", "t [s];v [mm/s];x [um]\n"
               + "".join(f"{k * 0.01};{100.0};{k}\n" for k in range(20)))
    m = read_measured(p)  # a displacement column is preferred over the velocity
    assert m.quantity == "displacement" and m.displacement[3] == pytest.approx(3e-6)
    p = _write(tmp_path / "c.csv", "time [s]\tvelocity [m/s]\n"
               + "".join(f"{k * 0.01}\t2.0\n" for k in range(20)))
    m = read_measured(p)  # integrated: x = 2 t
    assert m.quantity == "velocity"
    np.testing.assert_allclose(m.displacement, 2.0 * m.time, atol=1e-15)
    p = _write(tmp_path / "d.csv", "time [s], acceleration [m/s^2]\n"
               + "".join(f"{k * 0.01}, 4.0\n" for k in range(20)))
    m = read_measured(p)  # twice: x = 2 t^2 (trapezoids are exact for a linear v)
    np.testing.assert_allclose(m.displacement, 2.0 * m.time**2, atol=1e-14)


@pytest.mark.parametrize(("text", "pattern"), [
    ("0.0, -58\n0.5, -57\n" + _rows(), r"row 1: no header"),
    ("time, displacement [mm]\n" + _rows(), r"row 1, column 'time': no unit"),
    ("time [ms], displacement [blorps]\n" + _rows(),
     r"row 1, column 'displacement \[blorps\]': unknown unit 'blorps'"),
    ("time [ms], force [N]\n" + _rows(), r"row 1, column 'force \[N\]': unit 'N' is not a time"),
    ("time [ms], displacement [mm]\n" + _rows(5) + "2.5, nan\n" + _rows(20)[40:],
     r"row 7, column 'displacement \[mm\]': nan is not a finite number"),
    ("time [ms], displacement [mm]\n" + _rows(5) + "2.5, abc\n",
     r"row 7, column 'displacement \[mm\]': not a number: 'abc'"),
    ("time [ms], displacement [mm]\n0, 1\n1, 2\n0.5, 3\n" + "".join(
        f"{k}, 1\n" for k in range(2, 20)), r"row 4, column 'time \[ms\]': time must increase"),
    ("time [ms], displacement [mm]\n" + _rows(3) + "1.5\n", r"row 5: 1 values"),
    ("time [ms], displacement [mm]\n" + _rows(4), r"needs at least 10 samples"),
    ("", r"no data"),
])
def test_bad_files_get_one_line_errors_naming_file_row_and_column(tmp_path, text, pattern):
    p = _write(tmp_path / "bad.csv", text)
    with pytest.raises(InputError) as err:
        read_measured(p)
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(f"measured: {p}")
    import re

    assert re.search(pattern, msg), msg


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="measured: file not found"):
        read_measured(tmp_path / "none.csv")


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """A known simulation (model 3, Fig. 7) written as 'measured' files: other units, a
    0.2137 s rest before the release, a static offset, noise, a velocity with bias."""
    from pdamper.coupling import Simulation
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

    res = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER), -0.058).run(
        2.0, sample_rate=5000.0)
    rate, shift = 5000.0, 0.2137
    pre = np.arange(0.0, shift, 1 / rate)
    t = np.concatenate([pre, res.time + shift])
    x = np.concatenate([np.full(pre.size, -0.058), res.displacement])
    rng = np.random.default_rng(7)
    d = tmp_path_factory.mktemp("measured")
    disp = d / "displacement.csv"
    noisy = x + 0.0073 + rng.normal(0.0, 5e-5, x.size)  # 7.3 mm offset, 0.05 mm noise
    disp.write_text("# made from model 3\ntime [ms]; displacement [mm]\n" + "".join(
        f"{a:.4f}; {b:.5f}\n" for a, b in zip(t * 1e3, noisy * 1e3, strict=True)))
    vel = d / "velocity.csv"
    v = np.gradient(x, t) + 0.003  # 3 mm/s sensor bias
    vel.write_text("time [s], velocity [mm/s]\n" + "".join(
        f"{a - 1.0:.6f}, {b:.6f}\n" for a, b in zip(t, v * 1e3, strict=True)))
    return res, shift, disp, vel


def test_measurement_of_a_known_simulation_gives_near_zero_errors(reference):
    """Aligned (release time, static offset, initial deflection recovered) and compared the
    way the simulations are (Eqs. 24-25): peak RMS error < 0.3 % of the amplitude, damping
    ratios within 5e-4 in every band, phase drift below 0.02 rad."""
    from pdamper.coupling.comparison import compare_with_measurement
    from pdamper.coupling.measurement import align_measurement

    res, shift, disp, vel = reference
    for path, t_off, offset in ((disp, shift, 0.0073), (vel, shift - 1.0, None)):
        al = align_measurement(read_measured(path))
        assert al.time_offset == pytest.approx(t_off, abs=2e-4)
        assert al.initial_deflection == pytest.approx(-0.058, abs=2e-4)
        if offset is not None:
            assert al.static_offset == pytest.approx(offset, abs=5e-5)
        c = compare_with_measurement(res, al)
        assert c.peaks >= 9
        assert c.peak_rms_relative < 3e-3
        for b in c.bands:
            assert b.cycles > 0 and abs(b.error) < 5e-4
        assert np.max(np.abs(c.phase_drift)) < 0.02


def test_metrics_see_a_wrong_model(reference):
    """The same metrics have teeth: model 3 with 64 spheres against the 32-sphere
    'measurement' shows a peak error of several mm and a damping-ratio error."""
    from pdamper.coupling import Simulation
    from pdamper.coupling.comparison import compare_with_measurement
    from pdamper.coupling.measurement import align_measurement
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE

    _, _, disp, _ = reference
    other = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER.with_count(64)),
                       -0.058).run(2.0)
    c = compare_with_measurement(other, align_measurement(read_measured(disp)))
    assert c.peak_rms_error > 0.003 and c.zeta_rms_error > 0.005


def test_simulate_measured_cli_reports_a_comparison_per_model(reference, cli, tmp_path):
    _, _, disp, _ = reference
    png = tmp_path / "fig.png"
    code, out, err = cli("simulate", "--compare", "analytic", "--measured", disp, "--plot", png,
                         "--json")
    assert code == 0, err
    d = json.loads(out)
    comp = d["comparison"]
    assert comp["measured"]["time_offset"] == pytest.approx(0.2137, abs=2e-4)
    m = comp["models"]["analytic"]
    assert {"peak_rms_error", "damping_ratio_bands", "phase_drift", "final_phase_drift"} <= set(m)
    assert m["peak_rms_relative"] < 3e-3
    assert png.read_bytes()[:4] == b"\x89PNG"
    bad = _write(tmp_path / "bad.csv", "time [ms], displacement [mm]\n" + _rows(5) + "x, 1\n")
    code, out, err = cli("simulate", "--measured", bad)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith(f"error: measured: {bad}, row 7, column 'time [ms]'")


def test_too_short_a_record_is_refused(tmp_path):
    from pdamper.coupling.measurement import align_measurement

    t = np.linspace(0, 0.3, 300)
    p = _write(tmp_path / "short.csv", "time [s], displacement [m]\n" + "".join(
        f"{a}, {-0.05 * np.cos(35 * a)}\n" for a in t))
    with pytest.raises(InputError, match="needs at least 3 full oscillation cycles"):
        align_measurement(read_measured(p))


def test_a_record_orders_of_magnitude_off_the_release_is_refused_with_the_factor(reference,
                                                                                  tmp_path, cli):
    """The record of a 58 mm release with its header in furlongs (201 m), metres or
    nanometres: a release of 11.7 km, 58 m or 58 nm is no measurement of the 58 mm one; compared, its peak
    errors were kilometres and its damping bands empty. Refused before any run (CLI) and
    by compare_with_measurement (API), naming the factor; within a factor of 10 the
    comparison stands (a 20 mm simulated release against the 58 mm record)."""
    from pdamper.coupling.comparison import compare_with_measurement
    from pdamper.coupling.measurement import align_measurement

    res, _, disp, _ = reference
    text = disp.read_text()
    import re

    for unit, factor in (("furlong", "2.01e+05 times"), ("m", "1e+03 times"),
                         ("nm", "1/9.99e+05 of")):
        bad = _write(tmp_path / f"{unit}.csv", text.replace("displacement [mm]",
                                                            f"displacement [{unit}]"))
        with pytest.raises(InputError, match=f"^measured: .*{re.escape(factor)} the simulated"):
            compare_with_measurement(res, align_measurement(read_measured(bad)))
        code, out, err = cli("simulate", "--measured", bad, "--json")
        assert code == 2 and out == "" and err.count("\n") == 1, err
        assert err.startswith(f"error: measured: {bad}: released from") and factor in err
    code, out, err = cli("simulate", "--measured", disp, "--initial-displacement=-20mm",
                         "--json")
    assert code == 0, err
