"""The forced response's answers under doubt (``pdamper.runs.uncertainty.frf_answers``)."""

from __future__ import annotations

import numpy as np

from pdamper.coupling.frf import EDGE, HarmonicLoad, harmonic_balance
from pdamper.io.scenario import load_scenario
from pdamper.models import AnalyticalDamper
from pdamper.runs.uncertainty import frf_answers


def test_a_frequency_held_at_an_edge_counts_its_edge_not_rest():
    """The paper's damper under 8 N: at 4.4 Hz the harmonic balance has no stable solution,
    only an edge (the response held at a jump of the describing function). A sample there
    answers the edge's amplitude, not 0 (which pulled the band's lower edge to rest)."""
    sc = load_scenario(None, {})
    load = HarmonicLoad("force", 8.0)
    f = np.array([4.4, 5.0])
    hb = harmonic_balance(AnalyticalDamper(sc.damper()), sc.structure_model(), load, f)
    assert not hb.steady[0].any() and hb.branch[0, 0] == EDGE  # the case this is about
    amp = frf_answers(sc, load, f, model="analytic")({})["amplitude"]
    assert amp[0] == hb.amplitude[0, 0] > 0
    assert amp[1] == np.nanmax(np.where(hb.steady[1], hb.amplitude[1], np.nan))
