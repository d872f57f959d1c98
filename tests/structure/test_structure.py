"""Reduced structural model, paper Eq. (23), and the choice of M (NOTES.md)."""

import math

import pytest

from pdamper.errors import InputError
from pdamper.parameters import PAPER_STRUCTURE
from pdamper.parameters.vertical_dampers_paper import PAPER_MASS
from pdamper.structure import SingleDOFStructure


def test_paper_mass_reproduces_the_measured_eigenfrequency():
    """M = K / (2 pi 5.56 Hz)^2 = 1.514 kg; the printed 1.139 kg would give 6.41 Hz."""
    assert PAPER_MASS == pytest.approx(1.514, abs=0.001)
    assert PAPER_STRUCTURE.natural_frequency == pytest.approx(5.56, abs=1e-9)
    printed = SingleDOFStructure(1.139, 0.55, 1848.0)
    assert printed.natural_frequency == pytest.approx(6.41, abs=0.01)
    assert PAPER_STRUCTURE.damping_ratio == pytest.approx(0.55 / (2 * math.sqrt(1848 * PAPER_MASS)))


@pytest.mark.parametrize("kw", [{"mass": 0.0}, {"stiffness": -1.0}, {"damping": -0.1},
                                {"mass": float("nan")}])
def test_bad_structure(kw):
    args = {"mass": 1.0, "damping": 0.5, "stiffness": 100.0, **kw}
    with pytest.raises(InputError, match="structure."):
        SingleDOFStructure(**args)
