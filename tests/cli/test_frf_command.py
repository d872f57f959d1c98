"""``pdamper frf``: closed form without particles, identical one-mode input, outputs."""

import json
import math

import numpy as np
import pytest

from pdamper.parameters import PAPER_STRUCTURE


def closed_form(force, f):
    s = PAPER_STRUCTURE
    w = 2 * math.pi * np.asarray(f)
    return force / (s.stiffness - s.mass * w**2 + 1j * w * s.damping)


def test_frf_without_particles_is_the_closed_form(cli):
    code, out, err = cli("frf", "--particles", "0", "--force", "2N", "--frequency",
                         "3Hz:9Hz:13", "--sweep", "up", "--json")
    assert code == 0, err
    d = json.loads(out)
    f = np.array([p["frequency"] for p in d["points"]])
    np.testing.assert_allclose(f, np.linspace(3, 9, 13))
    hb = np.array([p["harmonic_balance"][0]["amplitude"] for p in d["points"]])
    ph = np.array([p["harmonic_balance"][0]["phase"] for p in d["points"]])
    ref = closed_form(2.0, f)
    np.testing.assert_allclose(hb, np.abs(ref), rtol=1e-6)
    np.testing.assert_allclose(ph, np.angle(ref), rtol=1e-6, atol=1e-9)
    assert all(len(p["harmonic_balance"]) == 1 for p in d["points"])
    assert d["units"]["amplitude"] == "m" and d["load"] == {"kind": "force", "amplitude": 2.0,
                                                            "unit": "N", "acceleration": False}
    assert d["version"] and d["inputs"]["particles"]["count"] == 0
    assert d["frf_inputs"]["sweep"] == "up" and len(d["frf_inputs"]["frequency"]) == 13


def test_modes_csv_equal_to_the_1dof_gives_identical_frf(cli, tmp_path):
    s = PAPER_STRUCTURE
    csv = tmp_path / "modes.csv"
    csv.write_text("frequency [Hz], damping ratio [1], damper [kg^-0.5]\n"
                   f"{s.natural_frequency!r}, {s.damping_ratio!r}, {1 / math.sqrt(s.mass)!r}\n")
    args = ("frf", "--frequency", "4.5Hz:6.5Hz:9", "--json")
    a = json.loads(cli(*args)[1])
    b = json.loads(cli(*args, "--modes", csv)[1])
    for pa, pb in zip(a["points"], b["points"], strict=True):
        for key in ("harmonic_balance", "up", "down"):
            assert pa[key] == pb[key]


def test_frf_writes_netcdf_and_figure(cli, tmp_path):
    import xarray as xr

    code, out, err = cli("frf", "--base", "1mm", "--frequency", "4Hz:7Hz:7", "--out",
                         tmp_path / "frf.nc", "--plot", tmp_path / "frf.png")
    assert code == 0, err
    assert "harmonic balance" in out and "up" in out
    with xr.open_dataset(tmp_path / "frf.nc") as ds:
        assert ds["frequency"].attrs["units"] == "Hz"
        assert ds["sweep_amplitude"].attrs["units"] == "m"
        assert ds.attrs["load_kind"] == "base" and ds.attrs["pdamper_version"]
        assert ds.sizes["frequency"] == 7
    assert (tmp_path / "frf.png").stat().st_size > 10_000


def test_base_acceleration_in_g(cli):
    code, out, err = cli("frf", "--base", "0.3g", "--particles", "0", "--frequency", "4Hz",
                         "--sweep", "up", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["load"]["acceleration"] and d["load"]["amplitude"] == pytest.approx(0.3 * 9.80665)


def test_optimize_peak_frf(cli):
    code, out, err = cli("optimize", "--objective", "peak-frf", "--frf-load", "2N", "--band",
                         "4.5Hz:6.5Hz:11", "--vary", "particles=0:32:32", "--json")
    assert code == 0, err
    d = json.loads(out)
    zero = next(c for c in d["candidates"] if c["particles"] == 0)
    f = np.linspace(4.5, 6.5, 11)
    assert zero["objective"] == pytest.approx(np.abs(closed_form(2.0, f)).max(), rel=5e-3)
    assert d["best"]["particles"] == 32
    assert d["objective_name"] == "peak-frf" and d["frf_load"]["amplitude"] == 2.0
