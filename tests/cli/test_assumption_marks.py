"""The analytical model knows its limits in every output: maps (JSON, NetCDF, plots), the
forced response (JSON per row and summary, text, NetCDF, plot), and zero gravity."""

from __future__ import annotations

import json


def test_map_flags_a_scattering_cell_in_json_netcdf_and_plot(tmp_path, cli):
    import matplotlib

    matplotlib.use("Agg")
    import xarray as xr

    from pdamper.plots import plot_loss_factor_map, plot_mode_map

    path, fig = tmp_path / "map.nc", tmp_path / "map.png"
    # 25 Hz / 10 mm: the paper's damper scatters there (docs/analytical.md); 10 Hz / 32 mm
    # is a double collect-and-collide whose assumptions hold
    code, out, _ = cli("map", "--model", "analytic", "--frequency", "10Hz:25Hz:2",
                       "--amplitude", "10mm:32mm:2", "--out", path, "--plot", fig, "--json")
    assert code == 0 and fig.stat().st_size > 0
    d = json.loads(out)
    assert d["assumptions"]["points"] == 4 and d["assumptions"]["flagged"] >= 1
    assert d["assumptions"]["reasons"]["scattering"] >= 1
    assert "dem" in d["assumptions"]["use"] and "fields" in d["assumptions"]["use"]
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    hold = ds["assumptions_hold"]
    assert ds["assumptions_hold"].attrs["flag_meanings"] == "outside_assumptions assumptions_hold"
    assert int(hold.sel(frequency=25.0, amplitude=0.010)) == 0
    assert "scattering" in str(ds["assumptions"].sel(frequency=25.0, amplitude=0.010).values)
    assert int(hold.sel(frequency=10.0, amplitude=0.032)) == 1
    assert str(ds["assumptions"].sel(frequency=10.0, amplitude=0.032).values) == ""
    flagged = int((hold.values == 0).sum())
    assert flagged == d["assumptions"]["flagged"]
    for draw in (plot_loss_factor_map, plot_mode_map):
        ax = draw(ds)
        marks = [c for c in ax.collections if c.get_hatch()]
        assert len(marks) == 1 and len(marks[0].get_paths()) == flagged
        legend = [t.get_text() for t in ax.get_legend().get_texts()]
        assert any("scattering" in t and "fields from a DEM map, or dem" in t for t in legend)


def test_map_text_names_the_flagged_points(cli):
    code, out, _ = cli("map", "--model", "analytic", "--frequency", "25Hz",
                       "--amplitude", "10mm")
    assert code == 0
    assert ("analytic assumptions fail at 1 of 1 points (scattering 1): use fields from a "
            "DEM map (--model fields) or dem there") in out


def test_a_map_whose_assumptions_hold_everywhere_has_no_marks():
    import matplotlib

    matplotlib.use("Agg")
    from pdamper.analysis.fields import effective_field
    from pdamper.models import AnalyticalDamper
    from pdamper.parameters import PAPER_DAMPER
    from pdamper.plots import plot_loss_factor_map

    ds = effective_field(AnalyticalDamper(PAPER_DAMPER), [10.0], [0.032, 0.05])
    assert ds["assumptions_hold"].values.tolist() == [[1, 1]]
    assert not [c for c in plot_loss_factor_map(ds).collections if c.get_hatch()]
