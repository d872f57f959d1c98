"""Design studies on the forced response: the peak-frf and rms-frf objectives."""

import math

import numpy as np
import pytest

from pdamper.design.study import OBJECTIVES, make_objective, optimize_design
from pdamper.errors import InputError
from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
from pdamper.structure.modal import ModalStructure

BAND = np.linspace(4.5, 6.5, 11)


def closed_form(force, f):
    s = PAPER_STRUCTURE
    w = 2 * math.pi * np.asarray(f)
    return np.abs(force / (s.stiffness - s.mass * w**2 + 1j * w * s.damping))


@pytest.mark.parametrize("name", ["peak-frf", "rms-frf"])
def test_frf_objectives_without_particles_are_the_closed_form(name):
    r = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, ["particles=0:32:32"],
                        objective=name, band=BAND, frf_load="2 N")
    zero = next(c for c in r.candidates if c.particles == 0)
    lin = closed_form(2.0, BAND)
    ref = lin.max() if name == "peak-frf" else math.sqrt(np.mean(lin**2))
    # the stepped sine is steady to 0.1 % per window
    assert zero.objective == pytest.approx(ref, rel=5e-3)
    assert zero.extra["steady"]
    # particles damp the resonance: the design with spheres wins
    assert r.best.particles == 32 and r.best.objective < 0.6 * zero.objective
    d = r.as_dict()
    assert d["objective_name"] == name and d["band"] == pytest.approx(list(BAND))
    assert d["frf_load"]["kind"] == "force" and d["frf_load"]["amplitude"] == 2.0


def test_one_mode_equal_to_the_1dof_gives_identical_designs():
    one = ModalStructure.from_single_dof(PAPER_STRUCTURE)
    a = optimize_design(PAPER_STRUCTURE, PAPER_DAMPER, -0.058, ["particles=16:48:16"],
                        objective="peak-frf", band=BAND)
    b = optimize_design(one, PAPER_DAMPER, -0.058, ["particles=16:48:16"],
                        objective="peak-frf", band=BAND)
    assert [c.objective for c in a.candidates] == [c.objective for c in b.candidates]


def test_default_band_is_around_the_natural_frequency():
    o = make_objective("peak-frf", 0.8, -0.058, PAPER_STRUCTURE)
    f0 = PAPER_STRUCTURE.natural_frequency
    assert o.band[0] == pytest.approx(0.5 * f0) and o.band[-1] == pytest.approx(1.5 * f0)
    assert o.frf_load.kind == "force" and o.frf_load.amplitude == 2.0
    assert {"peak-frf", "rms-frf"} <= set(OBJECTIVES)


@pytest.mark.parametrize("kwargs, field", [
    ({"band": [0.0, 5.0]}, "optimization.band"),
    ({"band": []}, "optimization.band"),
    ({"frf_load": "3 s"}, "optimization.frf_load"),
    ({"frf_load": "-2 N"}, "optimization.frf_load"),
])
def test_bad_frf_objective_inputs_name_the_field(kwargs, field):
    with pytest.raises(InputError) as e:
        make_objective("rms-frf", 0.8, -0.058, PAPER_STRUCTURE, **kwargs)
    assert e.value.field == field
