"""N-mode structure from the Timoshenko FE cantilever (beyond the paper's one mode,
Sect. 4.1): interpolation, modes, point masses, release shape, effective frequency."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from pdamper.errors import InputError
from pdamper.parameters import PAPER_STRUCTURE, paper_beam
from pdamper.structure import SingleDOFStructure
from pdamper.structure.beam import TimoshenkoBeam, TipMass, cantilever_matrices, modal_reduction
from pdamper.structure.modal import ModalStructure, interpolation_vector


@pytest.fixture(scope="module")
def beam_tip():
    return paper_beam()


def test_interpolation_is_the_exact_static_shape_of_a_timoshenko_cantilever():
    """Tip load P on a clamped Timoshenko beam: w(x) = P (L x^2 / 2 - x^3 / 6) / EI + P x / kGA.
    The interdependent-interpolation element is exact in statics, so the interpolated
    deflection between nodes is exact too (a stubby beam, where shear matters)."""
    b = TimoshenkoBeam(length=0.3, width=0.05, height=0.06, youngs_modulus=2e11, elements=3)
    k, _ = cantilever_matrices(b)
    load = np.zeros(k.shape[0])
    load[-2] = 1000.0
    u = np.linalg.solve(k, load)
    for x in (0.0, 0.05, 0.1, 0.137, 0.2, 0.29, 0.3):
        exact = 1000.0 * (0.3 * x**2 / 2 - x**3 / 6) / b.bending_stiffness \
            + 1000.0 * x / b.shear_stiffness
        assert interpolation_vector(b, x) @ u == pytest.approx(exact, rel=1e-10, abs=1e-15)


def test_modes_match_the_one_mode_reduction(beam_tip):
    beam, tip = beam_tip
    r = modal_reduction(beam, tip, n_frequencies=4)
    s = ModalStructure.from_beam(beam, tip, modes=4)
    np.testing.assert_allclose(s.frequencies, r.frequencies[:4], rtol=1e-9)
    e = ModalStructure.from_beam(beam, tip).equivalent_single_dof()
    assert e.mass == pytest.approx(r.mass, rel=1e-9)
    assert e.stiffness == pytest.approx(r.stiffness, rel=1e-9)
    assert np.all(s.damper_shape > 0) or s.damper_shape[0] > 0


def test_point_mass_on_the_tip_equals_a_tip_mass(beam_tip):
    beam, _ = beam_tip
    a = ModalStructure.from_beam(beam, TipMass(1.0), modes=3, point_masses=[(0.68, 0.27)])
    b = ModalStructure.from_beam(beam, TipMass(1.27), modes=3)
    np.testing.assert_allclose(a.frequencies, b.frequencies, rtol=1e-12)


def test_point_mass_inside_an_element_matches_a_mesh_with_a_node_there(beam_tip):
    """A point mass between nodes (consistent mass through the shape functions) against the
    same mass on a node of a finer mesh: the first three frequencies (shifted by up to
    15 % by the mass) agree within 5e-5, the size of the meshes' own difference."""
    beam, tip = beam_tip
    coarse = TimoshenkoBeam(**{**beam.__dict__, "elements": 20})   # nodes every 34 mm
    fine = TimoshenkoBeam(**{**beam.__dict__, "elements": 40})     # 0.357 m is not a node
    pos = 0.68 * 21 / 40                                            # a node of the fine mesh
    a = ModalStructure.from_beam(coarse, tip, 3, point_masses=[(pos, 0.5)])
    b = ModalStructure.from_beam(fine, tip, 3, point_masses=[(pos, 0.5)])
    np.testing.assert_allclose(a.frequencies, b.frequencies, rtol=5e-5)
    assert a.frequencies[0] < ModalStructure.from_beam(coarse, tip, 1).frequencies[0]


def test_release_state_is_the_static_shape_under_a_point_load(beam_tip):
    """The release point sits at x0 in every N-mode model; with all modes the whole shape
    is the FE static deflection under a point load there."""
    beam, tip = beam_tip
    small = TimoshenkoBeam(**{**beam.__dict__, "elements": 6})
    k, _ = cantilever_matrices(small, tip)
    n_all = k.shape[0]
    for release in (0.68, 0.3):
        s = ModalStructure.from_beam(small, tip, n_all, release_position=release,
                                     output_position=0.5)
        q = s.release_state(-0.058)
        assert s.release_shape @ q == pytest.approx(-0.058, rel=1e-12)
        load = np.zeros(n_all)
        nvec = interpolation_vector(small, release)
        u = np.linalg.solve(k, nvec)
        u *= -0.058 / (nvec @ u)
        assert s.output_shape @ q == pytest.approx(interpolation_vector(small, 0.5) @ u,
                                                   rel=1e-8)
        del load
        one = ModalStructure.from_beam(small, tip, 1, release_position=release)
        assert one.release_shape @ one.release_state(-0.058) == pytest.approx(-0.058)


def test_effective_frequency_with_an_added_mass(beam_tip):
    """One mode: sqrt(K / (M + m)) of the 1-DOF structure. Six modes: the FE model with the
    mass added at the tip, within 1e-4 (modal truncation)."""
    beam, tip = beam_tip
    one = ModalStructure.from_beam(beam, tip, 1)
    e = one.equivalent_single_dof()
    assert one.effective_frequency(0.1) == pytest.approx(e.effective_frequency(0.1), rel=1e-12)
    six = ModalStructure.from_beam(beam, tip, 6)
    fe = modal_reduction(beam, TipMass(1.37)).natural_frequency
    assert six.effective_frequency(0.1) == pytest.approx(fe, rel=1e-4)
    s = ModalStructure.from_single_dof(PAPER_STRUCTURE)
    assert s.effective_frequency(0.05) == pytest.approx(PAPER_STRUCTURE.effective_frequency(0.05))
    k = np.diag((2 * math.pi * six.frequencies) ** 2)
    m = np.eye(6) + 0.1 * np.outer(six.damper_shape, six.damper_shape)
    lam = scipy.linalg.eigh(k, m, eigvals_only=True)[0]
    assert six.effective_frequency(0.1) == pytest.approx(math.sqrt(lam) / (2 * math.pi))


def test_one_mode_at_the_tip_is_eq23():
    s = ModalStructure.from_single_dof(SingleDOFStructure(1.514, 0.55, 1848.0))
    assert s.coincident and s.modes == 1
    assert s.stiffness == pytest.approx(1848.0)


@pytest.mark.parametrize(("kw", "field"), [
    ({"modes": 0}, "structure.modes"),
    ({"modes": 2, "damper_position": 0.9}, "structure.damper_position"),
    ({"modes": 2, "damper_position": -0.1}, "structure.damper_position"),
    ({"modes": 1, "point_masses": [(0.3,)]}, "structure.point_masses[0]"),
    ({"modes": 1, "point_masses": [(0.3, -1.0)]}, "structure.point_masses[0].mass"),
])
def test_bad_modal_inputs(beam_tip, kw, field):
    beam, tip = beam_tip
    with pytest.raises(InputError, match=field.replace("[", r"\[").replace("]", r"\]")):
        ModalStructure.from_beam(beam, tip, **kw)


def test_damper_at_the_clamp_is_refused(beam_tip):
    beam, tip = beam_tip
    with pytest.raises(InputError, match="damper point does not move"):
        ModalStructure.from_beam(beam, tip, 2, damper_position=0.0)
