"""``pdamper simulate --load / --base-acceleration``: JSON, NetCDF, plot, the scenario's
[load] section, the one-mode structure."""

import json
import math

import numpy as np
import pytest

from pdamper.coupling.loads import simulate_load
from pdamper.io.loads import read_load
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE


@pytest.fixture
def shock(tmp_path):
    t = np.arange(0.0, 1.5005, 1e-3)
    f = np.where(t < 0.04, 40.0 * np.sin(math.pi * t / 0.04), 0.0)
    p = tmp_path / "shock.csv"
    p.write_text("# half-sine\ntime [ms], force [N]\n"
                 + "".join(f"{a * 1e3:.0f}, {b:.6f}\n" for a, b in zip(t, f, strict=True)))
    return p


def test_simulate_load_json_netcdf_plot(cli, tmp_path, shock):
    import xarray as xr

    nc, png = tmp_path / "r.nc", tmp_path / "r.png"
    code, out, _ = cli("simulate", "--load", shock, "--tail", "0.5 s", "--out", nc,
                       "--plot", png, "--json")
    assert code == 0
    d = json.loads(out)
    ref = simulate_load(AnalyticalDamper(PAPER_DAMPER), PAPER_STRUCTURE, read_load(shock),
                        tail=0.5)
    assert d["peak"] == pytest.approx(ref.peak, rel=1e-12)
    assert d["rms"] == pytest.approx(ref.rms, rel=1e-12)
    assert d["dissipated_energy"] == pytest.approx(ref.dissipated_energy, rel=1e-12)
    assert d["dissipated_energy"] > 0
    assert abs(d["energy_balance_error"]) < 1e-3
    assert d["load"]["kind"] == "force" and d["load"]["tail"] == 0.5
    assert d["load"]["interpolation"] == "linear" and d["units"]["peak"] == "m"
    assert d["cycles"] and d["inputs"]["load"]["tail"] == 0.5
    ds = xr.open_dataset(nc)
    assert ds["displacement"].attrs["units"] == "m" and ds["load"].attrs["units"] == "N"
    assert float(ds.time[-1]) == pytest.approx(2.0)
    assert png.stat().st_size > 10_000


def test_scenario_load_section_relative_path(cli, tmp_path, shock):
    sc = tmp_path / "sc.toml"
    sc.write_text('[load]\nforce = "shock.csv"\n')
    code, out, _ = cli("simulate", "--scenario", sc, "--json")
    assert code == 0
    code2, out2, _ = cli("simulate", "--load", shock, "--json")
    assert json.loads(out)["peak"] == json.loads(out2)["peak"]


def test_one_mode_modes_file_gives_the_1dof_result(cli, tmp_path, shock):
    s = PAPER_STRUCTURE
    modes = tmp_path / "modes.csv"
    modes.write_text("frequency [Hz], damping ratio [1], damper [kg^-0.5]\n"
                     f"{s.natural_frequency!r}, {s.damping_ratio!r}, "
                     f"{1 / math.sqrt(s.mass)!r}\n")
    a = json.loads(cli("simulate", "--load", shock, "--json")[1])
    b = json.loads(cli("simulate", "--load", shock, "--modes", modes, "--json")[1])
    for key in ("peak", "rms", "peak_acceleration", "dissipated_energy"):
        assert b[key] == pytest.approx(a[key], rel=1e-9)


def test_base_acceleration_human_output(cli, tmp_path):
    t = np.arange(0.0, 2.0, 2e-3)
    p = tmp_path / "acc.csv"
    p.write_text("time [s]; acceleration [g0]\n"
                 + "".join(f"{a:.3f}; {0.2 * math.sin(2 * math.pi * 5 * a):.6f}\n" for a in t))
    code, out, _ = cli("simulate", "--base-acceleration", p, "--compare", "analytic")
    assert code == 0
    assert "base acceleration" in out and "relative to the base" in out
