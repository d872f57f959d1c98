"""Timoshenko FE cantilever and one-mode reduction (paper Sect. 4.1), against closed forms."""

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq

from pdamper.errors import InputError
from pdamper.parameters.vertical_dampers_paper import PAPER_TIP_MASS, paper_beam
from pdamper.structure import SingleDOFStructure
from pdamper.structure.beam import (
    TimoshenkoBeam,
    TipMass,
    cantilever_matrices,
    element_mass,
    element_stiffness,
    modal_reduction,
    static_tip_stiffness,
)

EB_BETA_L = (1.875104068711961, 4.694091132974175, 7.854757438237613)


def slender_beam(elements: int = 100) -> TimoshenkoBeam:
    """L / h = 400: shear and rotary inertia change f3 by < 3e-4 relative."""
    return TimoshenkoBeam(length=1.0, width=0.02, height=0.0025, youngs_modulus=210e9,
                          elements=elements)


def eb_cantilever_frequency(beam: TimoshenkoBeam, beta_l: float) -> float:
    """Euler-Bernoulli cantilever f_n = (beta_n L)^2 / (2 pi L^2) sqrt(E I / (rho A)) [Hz]."""
    return beta_l**2 / (2 * math.pi * beam.length**2) * math.sqrt(
        beam.bending_stiffness / (beam.density * beam.area))


def eb_tip_mass_beta_l(mass_ratio: float) -> float:
    """Lowest root of (1 + cos cosh) + mu bL (cos sinh - sin cosh) = 0, mu = m_tip / (rho A L)."""
    def f(x: float) -> float:
        return (1 + math.cos(x) * math.cosh(x)
                + mass_ratio * x * (math.cos(x) * math.sinh(x) - math.sin(x) * math.cosh(x)))
    return brentq(f, 1e-3, 2.0, xtol=1e-14)


def fe_tip_deflection(beam: TimoshenkoBeam, force: float = 1.0) -> float:
    k, _ = cantilever_matrices(beam)
    rhs = np.zeros(k.shape[0])
    rhs[-2] = force
    return float(np.linalg.solve(k, rhs)[-2])


# --- element ---------------------------------------------------------------------------------

def _interdependent_shapes(le: float, phi: float, xi: np.ndarray):
    """Interdependent (exact static) shape functions of the Timoshenko element and d/dx."""
    c = 1.0 / (1.0 + phi)
    nw = c * np.array([
        2 * xi**3 - 3 * xi**2 - phi * xi + 1 + phi,
        le * (xi**3 - (2 + phi / 2) * xi**2 + (1 + phi / 2) * xi),
        -2 * xi**3 + 3 * xi**2 + phi * xi,
        le * (xi**3 - (1 - phi / 2) * xi**2 - phi / 2 * xi),
    ])
    dnw = c / le * np.array([
        6 * xi**2 - 6 * xi - phi,
        le * (3 * xi**2 - (4 + phi) * xi + 1 + phi / 2),
        -6 * xi**2 + 6 * xi + phi,
        le * (3 * xi**2 - (2 - phi) * xi - phi / 2),
    ])
    nt = c * np.array([
        6 / le * (xi**2 - xi),
        3 * xi**2 - (4 + phi) * xi + 1 + phi,
        -6 / le * (xi**2 - xi),
        3 * xi**2 - (2 - phi) * xi,
    ])
    dnt = c / le * np.array([
        6 / le * (2 * xi - 1),
        6 * xi - 4 - phi,
        -6 / le * (2 * xi - 1),
        6 * xi - 2 + phi,
    ])
    return nw, dnw, nt, dnt


@pytest.mark.parametrize("elements", [1, 3, 100])
def test_element_matrices_equal_energy_integrals_of_interdependent_shape_functions(elements):
    """K_e = int EI N_t'^T N_t' + kGA (N_w' - N_t)^T (N_w' - N_t), M_e = int rhoA N_w^T N_w +
    rhoI N_t^T N_t (Friedman & Kosmatka 1993), by 6-point Gauss quadrature (exact)."""
    beam = TimoshenkoBeam(length=0.3, width=0.05, height=0.04, youngs_modulus=70e9,
                          poisson_ratio=0.33, density=2700.0, elements=elements)
    le, phi = beam.element_length, beam.shear_parameter
    x, wq = np.polynomial.legendre.leggauss(6)
    xi, wq = 0.5 * (x + 1), 0.5 * wq * le
    nw, dnw, nt, dnt = _interdependent_shapes(le, phi, xi)
    # nodal interpolation: rows (w, theta) at xi = 0 and 1 reproduce the unit DOF vectors
    nw_ends, _, nt_ends, _ = _interdependent_shapes(le, phi, np.array([0.0, 1.0]))
    nodal = np.array([nw_ends[:, 0], nt_ends[:, 0], nw_ends[:, 1], nt_ends[:, 1]])
    assert nodal == pytest.approx(np.eye(4), abs=1e-12)
    gamma = dnw - nt
    k = (beam.bending_stiffness * (dnt * wq) @ dnt.T + beam.shear_stiffness * (gamma * wq) @ gamma.T)
    m = (beam.density * beam.area * (nw * wq) @ nw.T
         + beam.density * beam.second_moment * (nt * wq) @ nt.T)
    assert element_stiffness(beam) == pytest.approx(k, rel=1e-12, abs=1e-9 * np.abs(k).max())
    assert element_mass(beam) == pytest.approx(m, rel=1e-12, abs=1e-12 * np.abs(m).max())
    # shear strain is constant along the element (interdependent interpolation)
    assert np.ptp(gamma, axis=1) == pytest.approx(0.0, abs=1e-9 * np.abs(gamma).max())


def test_element_reduces_to_hermite_euler_bernoulli_matrices_without_shear():
    """phi -> 0 (k G A -> inf, rho I -> 0): K_e = EI/L^3 [12, 6L, ...], M_e = rhoAL/420 [156, ...]."""
    beam = TimoshenkoBeam(length=2.0, width=0.01, height=1e-5, youngs_modulus=1e9, elements=1)
    le = beam.length
    kh = beam.bending_stiffness / le**3 * np.array([
        [12, 6 * le, -12, 6 * le], [6 * le, 4 * le**2, -6 * le, 2 * le**2],
        [-12, -6 * le, 12, -6 * le], [6 * le, 2 * le**2, -6 * le, 4 * le**2]])
    mh = beam.density * beam.area * le / 420 * np.array([
        [156, 22 * le, 54, -13 * le], [22 * le, 4 * le**2, 13 * le, -3 * le**2],
        [54, 13 * le, 156, -22 * le], [-13 * le, -3 * le**2, -22 * le, 4 * le**2]])
    assert beam.shear_parameter < 1e-9
    assert element_stiffness(beam) == pytest.approx(kh, rel=1e-8)
    assert element_mass(beam) == pytest.approx(mh, rel=1e-8)


# --- statics ---------------------------------------------------------------------------------

@pytest.mark.parametrize("beam", [
    paper_beam()[0],
    TimoshenkoBeam(length=0.2, width=0.05, height=0.08, youngs_modulus=200e9, elements=7),
    TimoshenkoBeam(length=0.2, width=0.05, height=0.08, youngs_modulus=200e9, elements=1),
])
def test_static_tip_stiffness_equals_timoshenko_closed_form(beam):
    """k = 1 / (L^3 / (3 E I) + L / (k G A)); the interdependent element is exact for this."""
    k_closed = 1.0 / (beam.length**3 / (3 * beam.bending_stiffness) + beam.length / beam.shear_stiffness)
    assert static_tip_stiffness(beam) == pytest.approx(k_closed, rel=1e-15)
    assert 1.0 / fe_tip_deflection(beam) == pytest.approx(k_closed, rel=1e-9)


def test_thick_beam_static_stiffness_is_below_euler_bernoulli():
    """Shear flexibility L / (k G A): for L / h = 2.5 the tip stiffness is ~11 % below 3EI/L^3."""
    beam = TimoshenkoBeam(length=0.2, width=0.05, height=0.08, youngs_modulus=200e9, elements=10)
    k_eb = 3 * beam.bending_stiffness / beam.length**3
    assert 1.0 / fe_tip_deflection(beam) < 0.9 * k_eb


# --- free vibration --------------------------------------------------------------------------

def test_slender_beam_converges_to_euler_bernoulli_cantilever():
    """beta_n L = 1.8751, 4.6941, 7.8548: f_n = (beta_n L)^2 / (2 pi L^2) sqrt(EI / rhoA), 0.1 %."""
    beam = slender_beam()
    r = modal_reduction(beam, None)
    for n, bl in enumerate(EB_BETA_L):
        assert r.frequencies[n] == pytest.approx(eb_cantilever_frequency(beam, bl), rel=1e-3)


def test_thick_beam_frequencies_are_below_euler_bernoulli():
    """L / h = 5: shear deformation and rotary inertia lower every f_n below the EB value,
    increasingly with the mode number (mode 3 by more than 10 %)."""
    beam = TimoshenkoBeam(length=0.25, width=0.05, height=0.05, youngs_modulus=200e9, elements=100)
    f = modal_reduction(beam, None).frequencies
    ratio = [f[n] / eb_cantilever_frequency(beam, bl) for n, bl in enumerate(EB_BETA_L)]
    assert all(r < 1.0 for r in ratio)
    assert ratio[0] > ratio[1] > ratio[2]
    assert ratio[2] < 0.9


def test_paper_beam_with_tip_mass_matches_euler_bernoulli_tip_mass_equation():
    """(1 + cos bL cosh bL) + mu bL (cos bL sinh bL - sin bL cosh bL) = 0, mu = m_tip / (rho A L),
    solved with brentq; f1 = (bL)^2 / (2 pi L^2) sqrt(EI / rhoA), within 0.2 %."""
    beam, tip = paper_beam()
    mu = tip.mass / beam.mass
    bl = eb_tip_mass_beta_l(mu)
    assert 1.0 < bl < EB_BETA_L[0]
    r = modal_reduction(beam, tip)
    assert r.frequencies[0] == pytest.approx(eb_cantilever_frequency(beam, bl), rel=2e-3)
    # and without the tip mass the same equation gives 1.8751
    assert eb_tip_mass_beta_l(0.0) == pytest.approx(EB_BETA_L[0], rel=1e-12)


def test_mesh_convergence_is_monotonic():
    """Consistent mass + exact-static element: f_n(10) >= f_n(50) >= f_n(100) (from above),
    with the change from 50 to 100 smaller than from 10 to 50 (round-off tolerance 1e-9)."""
    beam_tip = TipMass(PAPER_TIP_MASS)
    f = [modal_reduction(paper_beam(n)[0], beam_tip, n_frequencies=4).frequencies for n in (10, 50, 100)]
    for mode in range(4):
        a, b, c = (fi[mode] for fi in f)
        assert a >= b * (1 - 1e-9) and b >= c * (1 - 1e-9)
        assert abs(b - c) <= abs(a - b) + 1e-9 * c
    assert f[0][3] > f[1][3] > f[2][3]  # strictly for a higher mode


# --- reduction -------------------------------------------------------------------------------

@pytest.mark.parametrize("tip", [None, 1.27, TipMass(1.27, rotary_inertia=2e-3, offset=0.05)])
def test_reduced_model_reproduces_fe_eigenfrequency_and_exceeds_static_stiffness(tip):
    """sqrt(K_red / M_red) = omega_1 of the FE model (eigh of the assembled K, M, 1e-7); with the
    mode normalised to unit tip deflection, K_red = v^T K v >= k_static = min over shapes with
    unit tip deflection of the strain energy (equality only for the static shape)."""
    beam, _ = paper_beam()
    r = modal_reduction(beam, tip)
    k, m = cantilever_matrices(beam, tip)
    w1 = math.sqrt(scipy.linalg.eigh(k, m, eigvals_only=True, driver="gv")[0])
    assert 2 * math.pi * r.natural_frequency == pytest.approx(w1, rel=1e-7)
    assert r.natural_frequency == pytest.approx(r.frequencies[0], rel=1e-12)
    v = np.empty(k.shape[0])
    v[0::2], v[1::2] = r.deflection[1:], r.rotation[1:]
    assert r.deflection[-1] == pytest.approx(1.0, rel=1e-15)
    assert r.mass == pytest.approx(v @ m @ v, rel=1e-12)
    assert r.stiffness == pytest.approx(v @ k @ v, rel=1e-6)
    k_static = static_tip_stiffness(beam)
    assert k_static <= r.stiffness <= 1.05 * k_static


def test_reduced_mass_without_tip_mass_is_a_quarter_of_the_beam_mass():
    """EB cantilever, first mode normalised to unit tip deflection: int phi^2 dm = m_beam / 4."""
    beam = slender_beam()
    assert modal_reduction(beam, None).mass == pytest.approx(beam.mass / 4, rel=1e-3)


def test_heavy_tip_mass_reduces_to_static_stiffness_and_rayleigh_mass():
    """m_tip >> m_beam: mode -> static shape, K_red -> k_static, M_red -> m_tip + 33/140 m_beam."""
    beam, _ = paper_beam()
    tip = 1000 * beam.mass
    r = modal_reduction(beam, tip)
    assert r.stiffness == pytest.approx(static_tip_stiffness(beam), rel=1e-6)
    assert r.mass == pytest.approx(tip + 33 / 140 * beam.mass, rel=1e-6)


def test_tip_rotary_inertia_and_offset_lower_the_frequency():
    """J_tip and a centre-of-mass offset e add m e^2 + J to the tip rotation: f1 decreases."""
    beam, tip = paper_beam(50)
    f0 = modal_reduction(beam, tip).natural_frequency
    f_j = modal_reduction(beam, TipMass(tip.mass, rotary_inertia=3e-3)).natural_frequency
    f_e = modal_reduction(beam, TipMass(tip.mass, offset=0.06)).natural_frequency
    assert f_j < f0 and f_e < f_j


def test_compliant_clamp_lowers_stiffness_and_tends_to_rigid():
    """Rotational clamp spring k_r: tip flexibility adds L^2 / k_r; k_r -> inf recovers the clamp."""
    beam, tip = paper_beam(50)
    kr = 2.0e4
    k, _ = cantilever_matrices(beam, tip, clamp_rotational_stiffness=kr)
    rhs = np.zeros(k.shape[0])
    rhs[-2] = 1.0
    flex = np.linalg.solve(k, rhs)[-2]
    assert flex == pytest.approx(1 / static_tip_stiffness(beam) + beam.length**2 / kr, rel=1e-9)
    r_rigid = modal_reduction(beam, tip)
    r_stiff = modal_reduction(beam, tip, clamp_rotational_stiffness=1e12)
    r_soft = modal_reduction(beam, tip, clamp_rotational_stiffness=kr)
    assert r_stiff.natural_frequency == pytest.approx(r_rigid.natural_frequency, rel=1e-6)
    assert r_soft.natural_frequency < r_rigid.natural_frequency
    assert r_soft.rotation[0] != 0.0 and r_rigid.rotation[0] == 0.0


def test_reference_offset_refers_the_model_to_another_point():
    """x = w_tip + e theta_tip: the same mode, so the same frequency; M_red, K_red scale by
    (w_tip / x)^2."""
    beam, tip = paper_beam(50)
    r0 = modal_reduction(beam, tip)
    r1 = modal_reduction(beam, tip, reference_offset=0.1)
    scale = (1.0 / (1.0 + 0.1 * r0.rotation[-1])) ** 2
    assert r1.natural_frequency == pytest.approx(r0.natural_frequency, rel=1e-12)
    assert r1.stiffness == pytest.approx(r0.stiffness * scale, rel=1e-9)
    assert r1.stiffness < r0.stiffness


def test_to_structure_and_paper_numbers():
    """Eq. (23) from the reduction; the paper beam gives f1 ~ 6.08 Hz, M ~ 1.885 kg, K ~ 2756 N/m
    (paper prints 5.56 Hz, 1.139 kg, 1848 N/m: not reproduced, see docs/beam.md)."""
    beam, tip = paper_beam()
    assert beam.elements == 100 and tip.mass == pytest.approx(1.27)
    r = modal_reduction(beam, tip)
    s = r.to_structure(0.55)
    assert isinstance(s, SingleDOFStructure)
    assert s.natural_frequency == pytest.approx(r.natural_frequency, rel=1e-12)
    assert s.damping == 0.55
    assert r.natural_frequency == pytest.approx(6.085, abs=0.001)
    assert r.mass == pytest.approx(1.885, abs=0.001)
    assert r.stiffness == pytest.approx(2756, abs=1)


def test_higher_mode_reduction():
    """mode=1 retains the second bending mode: sqrt(K_red / M_red) = f_2."""
    beam, tip = paper_beam(50)
    r = modal_reduction(beam, tip, mode=1)
    assert r.natural_frequency == pytest.approx(r.frequencies[1], rel=1e-12)
    assert r.natural_frequency > 5 * r.frequencies[0]


# --- input errors ----------------------------------------------------------------------------

@pytest.mark.parametrize(("kw", "name"), [
    ({"length": -0.68}, "beam.length"),
    ({"length": float("nan")}, "beam.length"),
    ({"height": 0.0}, "beam.height"),
    ({"width": float("inf")}, "beam.width"),
    ({"youngs_modulus": -1.0}, "beam.youngs_modulus"),
    ({"poisson_ratio": 0.6}, "beam.poisson_ratio"),
    ({"density": float("nan")}, "beam.density"),
    ({"shear_coefficient": 0.0}, "beam.shear_coefficient"),
    ({"elements": 0}, "beam.elements"),
    ({"elements": 2.5}, "beam.elements"),
])
def test_bad_beam_input_names_the_field(kw, name):
    args = {"length": 0.68, "width": 0.08, "height": 0.006, "youngs_modulus": 200e9, **kw}
    with pytest.raises(InputError) as info:
        TimoshenkoBeam(**args)
    assert info.value.field == name
    assert str(info.value).startswith(name + ":")


@pytest.mark.parametrize(("call", "name"), [
    (lambda: TipMass(-1.0), "tip_mass.mass"),
    (lambda: TipMass(1.0, rotary_inertia=float("nan")), "tip_mass.rotary_inertia"),
    (lambda: modal_reduction(paper_beam(10)[0], -0.5), "tip_mass.mass"),
    (lambda: modal_reduction(paper_beam(10)[0], 1.0, mode=-1), "modal_reduction.mode"),
    (lambda: modal_reduction(paper_beam(2)[0], 1.0, mode=4), "modal_reduction.mode"),
    (lambda: modal_reduction(paper_beam(10)[0], 1.0, clamp_rotational_stiffness=-1.0),
     "beam.clamp_rotational_stiffness"),
    (lambda: modal_reduction(paper_beam(10)[0], 1.0, clamp_rotational_stiffness=float("nan")),
     "beam.clamp_rotational_stiffness"),
])
def test_bad_tip_and_reduction_input_names_the_field(call, name):
    with pytest.raises(InputError) as info:
        call()
    assert info.value.field == name
