"""The peak and rms objectives of a design study: the response to a load history."""

import dataclasses
import math

import numpy as np
import pytest

from pdamper.coupling.loads import LoadHistory, simulate_load
from pdamper.design import optimize_design
from pdamper.design.study import make_objective
from pdamper.errors import InputError
from pdamper.models import AnalyticalDamper
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
from pdamper.structure.modal import ModalStructure

COUNTS = "particles=0:160:32"


def _direct(load, objective):
    """Each count's objective from its own simulate_load run (not through the study)."""
    out = {}
    for n in range(0, 161, 32):
        r = simulate_load(AnalyticalDamper(dataclasses.replace(PAPER_DAMPER, count=n)),
                          PAPER_STRUCTURE, load)
        out[n] = r.peak if objective == "peak" else r.rms
    return out


@pytest.mark.parametrize("objective", ["peak", "rms"])
def test_below_resonance_the_best_is_no_particles(objective):
    """2 N at 5.0 Hz, below the bare structure's 5.56 Hz: the particles' effective mass
    pulls the resonance down onto the forcing (and at these amplitudes they barely
    dissipate), so every particle adds response: the study picks 0, and its landscape is
    each count's own run."""
    load = LoadHistory.harmonic(2.0, 5.0, 10.0, samples_per_period=100)
    res = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, [COUNTS], objective,
                          load=load)
    direct = _direct(load, objective)
    assert res.best.particles == 0 == min(direct, key=direct.get)
    for c in res.candidates:
        assert c.objective == pytest.approx(direct[c.particles], rel=1e-12)
    assert res.as_dict()["objective_name"] == objective


def test_at_resonance_the_best_is_the_most_particles():
    """2 N at the bare structure's natural frequency: without particles the response
    grows to the linear resonance, ``F / (D W) (1 - e^(-zeta W t))`` (within 1 %); every
    bed damps it, the largest most."""
    s = PAPER_STRUCTURE
    f = s.natural_frequency
    load = LoadHistory.harmonic(2.0, f, 10.0, samples_per_period=100)
    res = optimize_design(s, PAPER_DAMPER, -0.058, [COUNTS], "peak", load=load)
    by_count = {c.particles: c.objective for c in res.candidates}
    w = 2 * math.pi * f
    linear = 2.0 / (s.damping * w) * (1 - math.exp(-s.damping_ratio * w * 10.0))
    assert by_count[0] == pytest.approx(linear, rel=1e-2)
    assert res.best.particles == 160
    assert all(by_count[0] > 3 * v for n, v in by_count.items() if n)


def test_one_mode_model_gives_the_1dof_study():
    """The study on a one-mode model equal to the 1-DOF gives the same objectives."""
    load = LoadHistory.harmonic(2.0, 5.5, 4.0, samples_per_period=100)
    one = ModalStructure.from_single_dof(PAPER_STRUCTURE)
    a = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, ["particles=0:64:32"], "rms",
                        load=load)
    b = optimize_design(one, PAPER_DAMPER, -0.058, ["particles=0:64:32"], "rms", load=load)
    np.testing.assert_allclose([c.objective for c in b.candidates],
                               [c.objective for c in a.candidates], rtol=1e-9)


def test_load_objectives_need_a_load():
    with pytest.raises(InputError) as e:
        make_objective("peak", 0.8, -0.058, PAPER_STRUCTURE)
    assert e.value.field == "optimization.objective"
    h = LoadHistory.harmonic(1.0, 5.0, 2.0)
    o = make_objective("rms", 0.8, -0.058, PAPER_STRUCTURE, load=h, tail=1.0)
    assert o.duration == pytest.approx(3.0) and o.sense == "min"
