"""COR curves (Level I, paper Sect. 2): tabulation for the kernels, PCHIP tables, scaling,
and the paper's Fig. 2 curves reconstructed from the text."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.contact.forces import cor_at
from pdamper.contact.restitution import (
    TABULATION_RANGE,
    TABULATION_TOLERANCE,
    ConstantRestitution,
    ExponentialRestitution,
    LinearRestitution,
    MeasuredRestitution,
    ScaledRestitution,
    TabulatedRestitution,
)
from pdamper.contact.thornton import ThorntonRestitution
from pdamper.errors import InputError
from pdamper.materials import PVC, S235, get_material
from pdamper.parameters import vertical_dampers_paper as paper

SMOOTH = {
    "paper steel-steel": paper.PAPER_COR_PP,
    "paper steel-PVC": paper.PAPER_COR_PW,
    "Thornton S235-S235": ThorntonRestitution.from_materials(S235, S235, 0.005, 0.005),
    "Thornton S235-PVC": ThorntonRestitution.from_materials(S235, PVC, 0.005),
    "Thornton 100Cr6 balls": ThorntonRestitution.from_materials(
        get_material("100Cr6"), get_material("100Cr6"), 0.005, 0.005),
    "measured (PCHIP)": MeasuredRestitution((0.05, 0.2, 0.5, 1.0, 2.0), (0.97, 0.9, 0.75, 0.6, 0.55)),
    "exponential, fast drop": ExponentialRestitution(1.0, 0.3, 0.02),
    "paper scaled x 1.5": paper.PAPER_COR_PP.scaled(1.5),
}


@pytest.mark.parametrize("name", list(SMOOTH))
def test_tabulation_error_bound(name):
    """The kernels interpolate the tabulated nodes linearly: within TABULATION_TOLERANCE
    (1e-4) of the curve over [0, 20] m/s (checked at 40 points per segment); held beyond."""
    curve = SMOOTH[name]
    v, e = curve.tabulate()
    assert v[0] == TABULATION_RANGE[0] and v[-1] == TABULATION_RANGE[1]
    t = np.linspace(0.0, 1.0, 41)[1:-1]
    x = (v[:-1, None] + t[None, :] * np.diff(v)[:, None]).ravel()
    lin = np.array([cor_at(s, v, e) for s in x])  # the kernels' own interpolation
    assert np.max(np.abs(lin - curve(x))) <= TABULATION_TOLERANCE
    assert cor_at(50.0, v, e) == pytest.approx(curve(TABULATION_RANGE[1]))
    assert len(v) < 2000  # cheap for the kernels' binary search


def test_constant_and_linear_tables_are_exact():
    """A constant and a linear table are what the kernels see, node for node."""
    c = ConstantRestitution(0.7)
    assert c(np.array([0.0, 1.0, 100.0])).tolist() == [0.7] * 3 and c(2.0) == 0.7
    t = TabulatedRestitution((0.1, 1.0), (0.9, 0.5))
    v, e = t.tabulate()
    assert [cor_at(s, v, e) for s in (0.0, 0.55, 5.0)] == pytest.approx([t(0.0), t(0.55), t(5.0)])


def test_measured_table_is_monotone_pchip_held_at_the_ends():
    """PCHIP: through every point, monotone between monotone data (no overshoot, so the COR
    stays in (0, 1]), the end values held below and above the measured range."""
    v = (0.05, 0.2, 0.5, 1.0, 2.0)
    e = (0.97, 0.9, 0.75, 0.6, 0.55)
    m = MeasuredRestitution(v, e)
    assert m(np.array(v)) == pytest.approx(np.array(e), abs=1e-12)
    x = np.linspace(0.0, 3.0, 3001)
    y = m(x)
    assert np.all(np.diff(y) <= 1e-15)
    assert y.max() <= 0.97 and y.min() >= 0.55
    assert m(0.0) == pytest.approx(0.97, abs=1e-12) and m(10.0) == pytest.approx(0.55, abs=1e-12)
    # a bump in the data stays a bump, without overshooting either neighbour
    bump = MeasuredRestitution((0.1, 0.5, 1.0), (0.8, 0.9, 0.7))
    assert bump(np.linspace(0.1, 1.0, 200)).max() <= 0.9 + 1e-12
    assert MeasuredRestitution((1.0,), (0.6,))(np.array([0.0, 5.0])).tolist() == [0.6, 0.6]


def test_scaled_curve():
    """e -> 1 - s (1 - e): s = 1 the curve itself, s = 0 elastic; the nodes scale exactly;
    a scale that makes the COR <= 0 is refused naming the allowed range."""
    base = paper.PAPER_COR_PP
    assert base.scaled(1.0) is base
    assert ScaledRestitution(base, 0.0)(np.array([0.01, 1.0])) == pytest.approx([1.0, 1.0])
    s = base.scaled(1.5)
    x = np.array([0.01, 0.3, 2.0])
    assert s(x) == pytest.approx(1 - 1.5 * (1 - base(x)))
    v, e = s.tabulate()
    assert e == pytest.approx(1 - 1.5 * (1 - base.tabulate()[1]))
    with pytest.raises(InputError, match=r"restitution.scale: must be in \[0, 1.81"):
        base.scaled(2.0)


@pytest.mark.parametrize(("make", "field"), [
    (lambda: ExponentialRestitution(1.2, 0.5, 0.1), "restitution.e0"),
    (lambda: ExponentialRestitution(0.9, 0.5, 0.0), "restitution.v_c"),
    (lambda: LinearRestitution(0.9, 0.1), "restitution.slope"),      # falls below 0 at infinity
    (lambda: LinearRestitution(0.9, 1.0, 1.0), "restitution.slope"),  # 0 at 0.9 m/s
    (lambda: MeasuredRestitution((0.5, 0.2), (0.9, 0.8)), "restitution.velocity"),
    (lambda: MeasuredRestitution((0.1, 0.2), (0.9, 1.1)), "restitution.restitution"),
    (lambda: MeasuredRestitution((0.2, 1e300, 1e305), (0.9, 0.85, 0.8)), "restitution.velocity"),
    (lambda: TabulatedRestitution((0.2, 2e4), (0.9, 0.8)), "restitution.velocity"),
    (lambda: MeasuredRestitution((0.0, 1e-300, 1.0), (0.9, 0.8, 0.7)), "restitution.velocity"),
])
def test_bad_curves(make, field):
    with pytest.raises(InputError, match=field):
        make()


def test_paper_steel_steel_shape():
    """Sect. 2 on Fig. 2 (steel-steel): 'starts close to one for small impact velocities and
    drops rapidly when the impact velocity is increased. Finally, the COR converges below 0.5.'"""
    e = paper.PAPER_COR_PP
    v = np.linspace(0.01, 2.0, 400)
    y = e(v)
    assert e(0.01) > 0.95                      # close to one
    assert np.all(np.diff(y) < 0)              # drops
    assert e(0.5) < 0.5 and e(0.3) < 0.6       # rapidly
    assert 0.4 < e(1.8) < 0.5 and abs(e(2.0) - e(1.0)) < 0.01  # converges below 0.5


def test_paper_steel_pvc_shape():
    """Sect. 2 on Fig. 2 (steel-PVC): 'starts at about 0.9 ... a slight almost linear
    reduction ... At the highest measurable impact velocity of 1.8 m/s the COR still has a
    value of 0.8.'"""
    e = paper.PAPER_COR_PW
    v = np.linspace(0.0, paper.PAPER_COR_MAX_VELOCITY, 200)
    assert e(0.01) == pytest.approx(0.9, abs=0.005)
    assert e(1.8) == pytest.approx(0.8, abs=0.005)
    chord = e(0.0) + (e(1.8) - e(0.0)) * v / 1.8
    assert np.max(np.abs(e(v) - chord)) < 0.01   # almost linear
    assert e(3.0) == e(1.8)                       # held beyond the measured range


def test_tables_over_the_whole_admissible_range_interpolate_without_warnings():
    """Nodes 1e-12 m/s apart, or up to 10 km/s next to 1 mm/s, give a finite monotone curve
    (PCHIP's slope means overflowed, with RuntimeWarnings, for nodes 300 orders apart)."""
    import warnings

    for v, e in (((0.0, 1e-12, 1.0), (0.9, 0.8, 0.7)),
                 ((1e-3, 0.5, 1e4), (0.95, 0.9, 0.5)),
                 ((0.0, 1e-9, 2e-9, 1e4), (1.0, 0.99, 0.98, 0.1))):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            c = MeasuredRestitution(v, e)
            x = np.geomspace(1e-15, 2e4, 400)
            y = c(x)
            nodes = c.tabulate()[1]
        assert np.all(np.isfinite(y)) and np.all(np.isfinite(nodes))
        assert np.all(np.diff(y) <= 1e-15) and min(e) <= y.min() and y.max() <= max(e)
