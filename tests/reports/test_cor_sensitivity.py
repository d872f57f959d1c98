"""The COR sensitivity study (paper Sect. 2: 'the CORs' values are of minor importance'):
variants reach the DEM unchanged, results carry their stationarity. Reduced runs (4 cycles,
0.8 s); the study itself is benchmarks/bench_cor_sensitivity.py."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pdamper.contact.restitution import ConstantRestitution, ScaledRestitution
from pdamper.errors import InputError
from pdamper.io.scenario import load_scenario
from pdamper.models import DEMDamper
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.reports.cor_sensitivity import sensitivity_figure
from pdamper.runs.cor_sensitivity import (
    cor_variant,
    run_cor_sensitivity,
    split_variant,
    study_scenario,
)

REDUCED = {"dem.cycles": 4, "dem.skip_cycles": 2, "simulation.duration": "0.8 s"}


def test_variants():
    d = paper.PAPER_DAMPER
    v = cor_variant("0.6/0.85", d)
    assert (v.restitution_pp, v.restitution_pw) == (ConstantRestitution(0.6), ConstantRestitution(0.85))
    v = cor_variant("paper*1.5", d)
    assert v.restitution_pp == ScaledRestitution(paper.PAPER_COR_PP, 1.5)
    assert v.restitution_pw == ScaledRestitution(paper.PAPER_COR_PW, 1.5)
    assert cor_variant("thornton", d).restitution_pp.describe().startswith("Thornton S235-S235")
    for bad in ("0.6/0.8/0.9", "fancy", "paper*9"):
        with pytest.raises(InputError, match="^variants"):
            cor_variant(bad, d)


def test_study_reaches_the_dem_and_labels_transients():
    """A variant's Level II result is exactly the DEM run of the damper with its curves; the
    stationarity flag compares the loss factor over the two halves of the window; Level III
    gives one amplitude per variant; the analytical block model is the reference."""
    sc = load_scenario(None, REDUCED)
    study = run_cor_sensitivity(sc, ["0.6/0.85", "paper"], [(10.0, 0.032)], level3=True)
    ds = study.level2
    assert (ds.attrs["cycles"], ds.attrs["skip_cycles"]) == (4, 2)  # the scenario's, as set
    direct = DEMDamper(paper.PAPER_DAMPER_CURVES, cycles=4, skip_cycles=2).run(10.0, 0.032)
    assert float(ds["loss_factor"].sel(variant="paper")[0]) == direct.complex_power(2).loss_factor
    a, b = ds["loss_factor_first_half"].values, ds["loss_factor_second_half"].values
    assert np.array_equal(ds["stationary"].values,
                          np.abs(a - b) <= 0.1 * np.abs(ds["loss_factor"].values))
    assert float(ds["loss_factor_analytical"][0]) > 1.0  # double CaC near X_opt
    assert set(study.runs) == {"0.6/0.85", "paper"}
    amp = study.level3["amplitude_0p75s"].values
    assert np.all(np.isfinite(amp)) and amp[0] != amp[1]
    text = study.markdown()
    assert "| paper |" in text and "analytical" in text
    d = json.loads(json.dumps(study.as_dict()))
    assert len(d["level2"]) == 2 and len(d["level3"]) == 2
    fig = sensitivity_figure(study)
    assert len(fig.axes) == 2


def test_cli(cli, tmp_path):
    png = tmp_path / "s.png"
    code, out, err = cli("cor-sensitivity", "--variants", "0.6/0.85,paper*0.5", "--points",
                         "10Hz/32mm", "--cycles", "4", "--skip-cycles", "2", "--no-level3",
                         "--plot", png, "--json")
    assert code == 0, err
    d = json.loads(out)
    assert [v["name"] for v in d["variants"]] == ["0.6/0.85", "paper*0.5"]
    assert {"loss_factor", "stationary", "effective_mass_ratio"} <= set(d["level2"][0])
    assert "level3" not in d and png.read_bytes()[:4] == b"\x89PNG"
    code, out, err = cli("cor-sensitivity", "--points", "10Hz")
    assert code == 2 and err.startswith("error: points: expected FREQUENCY/AMPLITUDE")


def test_default_window_outlasts_the_initial_transient():
    """Without cycles in the scenario the study averages cycles 17-48, not the DEM's 3-8;
    the scenario's own values and explicit arguments win."""
    dem = study_scenario(load_scenario(None)).dem
    assert (dem.cycles, dem.skip_cycles) == (48, 16)
    dem = study_scenario(load_scenario(None, {"dem.cycles": 20})).dem
    assert (dem.cycles, dem.skip_cycles) == (20, 16)
    assert study_scenario(load_scenario(None), 12, 4).dem.cycles == 12


def test_tables_given_by_path(tmp_path, monkeypatch):
    """A COR table's path holds '/' too: the variant splits at the one '/' that leaves a
    model on both sides, so tables can be named by relative or absolute path; the old
    forms read as before."""
    table = "velocity [m/s], cor [-]\n0.2, 0.89\n0.6, 0.86\n1.8, 0.80\n"
    (tmp_path / "tab").mkdir()
    for name in ("pp.csv", "pw.csv"):
        (tmp_path / "tab" / name).write_text(table)
    monkeypatch.chdir(tmp_path)
    pp, pw = tmp_path / "tab" / "pp.csv", tmp_path / "tab" / "pw.csv"
    assert split_variant(str(pw)) == (str(pw), str(pw))
    assert split_variant(f"{pp}/{pw}") == (str(pp), str(pw))
    assert split_variant("tab/pp.csv/tab/pw.csv") == ("tab/pp.csv", "tab/pw.csv")
    assert split_variant("0.6/tab/pw.csv*1.2") == ("0.6", "tab/pw.csv*1.2")
    assert split_variant("paper*0.5/tab/pw.csv") == ("paper*0.5", "tab/pw.csv")
    assert split_variant("0.6/0.85") == ("0.6", "0.85")
    v = cor_variant(f"{pp}/{pw}*1.2", paper.PAPER_DAMPER)
    assert v.restitution_pp.describe().startswith("table pp.csv")
    assert v.restitution_pw.describe().startswith("table pw.csv")
    assert v.restitution_pw.describe().endswith("dissipation x 1.2")
    # a file named like a split of another: both readings exist, the error lists them
    (tmp_path / "0.6").mkdir()
    (tmp_path / "0.6" / "pw.csv").write_text(table)
    (tmp_path / "pw.csv").write_text(table)
    with pytest.raises(InputError, match=r"^variants: '0.6/pw.csv' reads as several variants "
                                         r"\(0.6/pw.csv for both; 0.6 / pw.csv\)"):
        split_variant("0.6/pw.csv")
    with pytest.raises(InputError, match="^variants: 'paper/none/x.csv': no such COR table"):
        split_variant("paper/none/x.csv")
    with pytest.raises(InputError, match="COR table not found: none.csv"):
        cor_variant("none.csv", paper.PAPER_DAMPER)


@pytest.mark.parametrize("count", [32, 16])
def test_points_outside_the_dem_limits_are_refused_before_any_run(count):
    """10 Hz / 100 m used to start DEM runs that stopped advising a smaller Gear tolerance
    (and with 16 spheres reported a loss factor)."""
    sc = load_scenario(None, {"particles.count": count})
    for point in ((10.0, 100.0), (10.0, 5.0)):
        with pytest.raises(InputError) as info:
            run_cor_sensitivity(sc, ["0.6/0.85"], [(10.0, 0.032), point], level3=False)
        assert info.value.field == "points"
