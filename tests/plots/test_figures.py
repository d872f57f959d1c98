"""Plot functions: take ax=None, return the Axes they drew on, never show or save."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pdamper import plots  # noqa: E402
from pdamper.analysis.analytical import bed_trajectory  # noqa: E402
from pdamper.analysis.fields import effective_field  # noqa: E402
from pdamper.coupling import Simulation  # noqa: E402
from pdamper.dem.impacts import check_restitution  # noqa: E402
from pdamper.design import optimize_particle_count  # noqa: E402
from pdamper.io.scenario import load_scenario  # noqa: E402
from pdamper.materials import PVC, S235  # noqa: E402
from pdamper.models import AnalyticalDamper, DEMDamper  # noqa: E402
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE  # noqa: E402
from pdamper.parameters import vertical_dampers_paper as paper  # noqa: E402
from pdamper.runs.cor_sensitivity import run_cor_sensitivity  # noqa: E402


@pytest.fixture(scope="module")
def inputs():
    model = AnalyticalDamper(PAPER_DAMPER)
    ds = effective_field(model, np.linspace(2, 20, 5), np.linspace(0.005, 0.1, 6))
    run = Simulation(PAPER_STRUCTURE, model, -0.058).run(1.0)
    opt = optimize_particle_count(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, 0.8, counts=[0, 32, 64])
    dem = ds.copy()  # a DEM-like field: a transient cell, a failed one, a rattling bed
    dem["loss_factor"][0, 0] = 2.5
    dem["stationary"][1, 1] = 0
    dem["status"][2, 2] = 1
    dem["motion_mode"][2, 2] = -1
    dem["motion_mode"][3, 3] = 6
    dem_run = DEMDamper(PAPER_DAMPER, cycles=2, skip_cycles=1, snapshot_rate=200.0).run(10.0, 0.032)
    check = check_restitution([0.1, 1.0], paper.PAPER_COR_PW, S235, PVC, 0.005)
    study = run_cor_sensitivity(load_scenario(None, {"dem.cycles": 2, "dem.skip_cycles": 0}),
                                ["0.6/0.85", "paper"], [(10.0, 0.032)], level3=False)
    from pdamper.coupling.comparison import compare_with_measurement
    from pdamper.coupling.modal import ModeCountStudy
    from pdamper.design import make_objective, parse_variable, run_design_study

    obj = make_objective("amplitude-at", 0.8, -0.058, PAPER_STRUCTURE)
    design = run_design_study(lambda d: (d["particles"] * d["radius"], {}), PAPER_DAMPER,
                             [parse_variable("particles=32:160:64"),
                              parse_variable("radius=4mm:6mm:2")], obj)
    comparisons = {"analytic": compare_with_measurement(run, run)}
    from pdamper.dem import HarmonicMotion

    profiled = DEMDamper(PAPER_DAMPER).build_engine(HarmonicMotion(0.032, 10.0)).run(
        0.2, sample_rate=1000.0, step_profile=True)
    return {
        "plot_step_profile": (profiled.step_profile(10, skip_cycles=1),),
        "plot_cor_check": (check,),
        "plot_cor_sensitivity": (study,),
        "plot_material_table": ({"sphere": S235, "wall": PVC},),
        "plot_restitution_curves": ({"steel-steel": paper.PAPER_COR_PP},),
        "plot_design_landscape": (design,),
        "plot_design_front": (design,),
        "plot_mode_study": (ModeCountStudy((0.34, 0.68), (1, 2), ((0.03, 0.031), (0.02, 0.02)),
                                           0.75),),
        "plot_model_trajectories": ({"analytic": run}, None, comparisons),
        "plot_model_damping_ratios": ({"analytic": run}, None, comparisons),
        "plot_phase_drift": (comparisons,),
        "plot_bed_trajectory": (bed_trajectory(18.0, 0.05, 0.1),),
        "plot_mode_map": (dem,),
        "plot_effective_mass_map": (dem,),
        "plot_field_difference": (dem, ds),
        "plot_particle_snapshots": (dem_run,),
        "plot_loss_factor_map": (dem,),
        "plot_free_vibration": (run,),
        "plot_damping_ratio": (run,),
        "plot_optimization": (opt,),
        # realisations: a band of runs (pdamper.runs.realisations.Level3Band)
        "plot_trajectory_band": (_band(run),),
        "plot_damping_ratio_band": (_band(run),),
    }


def _band(run):
    from pdamper.runs.realisations import Level3Band

    return Level3Band("analytic", [run, run], 0.75)


@pytest.mark.parametrize("name", plots.__all__)
def test_plot_uses_given_axes_and_returns_it(inputs, name, monkeypatch):
    monkeypatch.setattr(plt, "show", lambda *a, **k: pytest.fail("show() called"))
    monkeypatch.setattr(plt.Figure, "savefig", lambda *a, **k: pytest.fail("savefig() called"))
    fig, ax = plt.subplots()
    out = getattr(plots, name)(*inputs[name], ax=ax)
    assert out is ax
    assert ax.has_data() or ax.tables  # Fig. 2-left is a table
    new = getattr(plots, name)(*inputs[name])
    assert new is not ax and (new.has_data() or new.tables)
    plt.close("all")


def test_loss_factor_scale_shows_values_above_one():
    """Fig. 5c saturated at 1 and hid 1.0-1.27: the colour scale now reaches 4/pi (or the
    field's maximum)."""
    model = AnalyticalDamper(PAPER_DAMPER)
    ds = effective_field(model, np.linspace(8, 20, 4), np.linspace(0.02, 0.05, 4))
    ax = plots.plot_loss_factor_map(ds)
    norm = ax.collections[0].norm
    assert norm.vmax == pytest.approx(4 / np.pi) and norm.vmin == pytest.approx(0.1)
    assert float(ds["loss_factor"].max()) > 1.0  # the band the old scale hid
    ds["loss_factor"][0, 0] = 2.0
    assert plots.plot_loss_factor_map(ds).collections[0].norm.vmax == pytest.approx(2.0)
    plt.close("all")
