"""Figs. 7/8 of the case study with the three damper models: which map model 2 reads."""

from __future__ import annotations

import numpy as np

from pdamper.analysis.fields import effective_field
from pdamper.io.scenario import load_scenario
from pdamper.models import AnalyticalDamper, EffectiveFieldDamper
from pdamper.parameters import PAPER_DAMPER
from pdamper.runs.paper_case_study import CaseStudy, _fields_model


def _map(f=(4.0, 8.0, 5)):
    return effective_field(AnalyticalDamper(PAPER_DAMPER), np.linspace(*f),
                           np.linspace(0.005, 0.065, 13))


def test_model2_prefers_the_scenario_file_then_the_dem_map_then_the_analytical_map(tmp_path):
    sc = load_scenario(None)
    cs = CaseStudy(field_map=_map())
    m, source = _fields_model(sc, cs, PAPER_DAMPER)
    assert isinstance(m, EffectiveFieldDamper) and source.startswith("analytical Fig. 5 map")
    assert m.extrapolation == "clamp"
    cs.dem_map = _map((4.5, 6.5, 3))  # as the case study stores its DEM map
    m, source = _fields_model(sc, cs, PAPER_DAMPER)
    assert source.startswith("DEM map") and m.frequency_range == (4.5, 6.5)
    path = tmp_path / "mine.nc"
    _map((3.0, 9.0, 4)).to_netcdf(path, engine="h5netcdf")
    sc = load_scenario(None, {"fields.file": str(path)})
    m, source = _fields_model(sc, cs, PAPER_DAMPER)
    assert source == f"map {path}" and m.frequency_range == (3.0, 9.0)
    assert m.extrapolation == "error"  # the user's map with the user's options
