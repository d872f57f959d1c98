"""Timoshenko finite-element cantilever and its one-mode reduction (paper Sect. 4.1, Eq. 23).

The paper models its "simple beam-like structure" (a 680 mm steel beam, 80 mm x 6 mm,
clamped at one end, 1270 g of damper and additional mass at the free end) with 100
Timoshenko beam elements, the end masses as rigid point elements, and keeps only the first
bending mode, which gives ``M x'' + D x' + K x = F`` for the end-effector displacement x.
This module rebuilds that model so that (M, K) can be derived from the beam instead of
taken from the paper's printed constants.

Element
-------
Two-node Timoshenko element with the "interdependent interpolation" (cubic deflection,
quadratic rotation, both exact static solutions of the shear-deformable beam; Przemieniecki
1968, Friedman & Kosmatka 1993). DOFs per node are the deflection w [m] and the rotation
theta [rad] of the cross-section, with theta = w' for a shear-rigid beam. The shear
parameter is ``phi = 12 E I / (k G A L_e^2)``; with phi = 0 the element is the
Euler-Bernoulli Hermite element. The consistent mass matrix includes translational
(rho A) and rotary (rho I) inertia.

Reduction
---------
For the chosen mode shape ``v`` (generalised eigenproblem ``K v = w^2 M v`` solved with
:func:`scipy.linalg.eigh`), normalised so that the displacement of the reference point is 1,
``M_red = v^T M v`` and ``K_red = v^T K v``; then ``sqrt(K_red / M_red)`` is exactly the
mode's angular frequency and x is the reference point's displacement. Because the static
deflection shape minimises the strain energy among all shapes with unit tip displacement,
``K_red >= k_static`` (equal only if the mode shape is the static shape).

Units: SI throughout (m, kg, s, N, Pa).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from pdamper.errors import InputError, check_range

if TYPE_CHECKING:  # imported lazily: pdamper.structure may later re-export this module
    from pdamper.structure import SingleDOFStructure

__all__ = [
    "ReducedModel",
    "TimoshenkoBeam",
    "TipMass",
    "cantilever_matrices",
    "element_mass",
    "element_stiffness",
    "modal_reduction",
    "static_tip_stiffness",
]


@dataclass(frozen=True)
class TimoshenkoBeam:
    """Prismatic beam of rectangular cross-section, bending in the ``height`` direction.

    Parameters
    ----------
    length
        Free length L between clamp and tip [m].
    width
        Cross-section width b, perpendicular to the bending direction [m].
    height
        Cross-section height h, in the bending direction [m]; ``I = b h^3 / 12``.
    youngs_modulus
        E [Pa].
    poisson_ratio
        nu [-]; the shear modulus is ``G = E / (2 (1 + nu))``.
    density
        rho [kg/m^3].
    shear_coefficient
        Timoshenko shear coefficient k [-]; 5/6 for a rectangle.
    elements
        Number of equal finite elements [-].

    Examples
    --------
    >>> b = TimoshenkoBeam(length=0.68, width=0.08, height=0.006, youngs_modulus=200e9)
    >>> round(b.second_moment * 1e9, 3), round(b.mass, 4)
    (1.44, 2.5622)
    """

    length: float
    width: float
    height: float
    youngs_modulus: float
    poisson_ratio: float = 0.3
    density: float = 7850.0
    shear_coefficient: float = 5.0 / 6.0
    elements: int = 100

    def __post_init__(self) -> None:
        pos: dict[str, Any] = {"low": 0.0, "low_inclusive": False}
        check_range("beam.length", self.length, unit="m", **pos)
        check_range("beam.width", self.width, unit="m", **pos)
        check_range("beam.height", self.height, unit="m", **pos)
        check_range("beam.youngs_modulus", self.youngs_modulus, unit="Pa", **pos)
        check_range("beam.poisson_ratio", self.poisson_ratio, low=-1.0, high=0.5,
                    low_inclusive=False)
        check_range("beam.density", self.density, unit="kg/m^3", **pos)
        check_range("beam.shear_coefficient", self.shear_coefficient, high=1.0, **pos)
        if isinstance(self.elements, bool) or not isinstance(self.elements, int | np.integer):
            raise InputError("beam.elements", f"must be an integer >= 1, got {self.elements!r}")
        if self.elements < 1:
            raise InputError("beam.elements", f"must be an integer >= 1, got {self.elements}")

    @property
    def area(self) -> float:
        """Cross-section area A = b h [m^2]."""
        return self.width * self.height

    @property
    def second_moment(self) -> float:
        """Second moment of area about the bending axis, I = b h^3 / 12 [m^4]."""
        return self.width * self.height**3 / 12.0

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def bending_stiffness(self) -> float:
        """E I [N m^2]."""
        return self.youngs_modulus * self.second_moment

    @property
    def shear_stiffness(self) -> float:
        """k G A [N]."""
        return self.shear_coefficient * self.shear_modulus * self.area

    @property
    def mass(self) -> float:
        """Total beam mass rho A L [kg]."""
        return self.density * self.area * self.length

    @property
    def element_length(self) -> float:
        """L_e = L / elements [m]."""
        return self.length / self.elements

    @property
    def shear_parameter(self) -> float:
        """Element shear parameter phi = 12 E I / (k G A L_e^2) [-]."""
        return 12.0 * self.bending_stiffness / (self.shear_stiffness * self.element_length**2)


@dataclass(frozen=True)
class TipMass:
    """Rigid body attached to the free end of the beam.

    Parameters
    ----------
    mass
        m_tip [kg].
    rotary_inertia
        J_tip about the body's centre of mass, for rotation in the bending plane [kg m^2].
    offset
        Axial distance e of the centre of mass beyond the tip node [m]; the centre of mass
        moves by ``w_tip + e theta_tip``. Default 0: a plain point mass.
    """

    mass: float
    rotary_inertia: float = 0.0
    offset: float = 0.0

    def __post_init__(self) -> None:
        check_range("tip_mass.mass", self.mass, low=0.0, unit="kg")
        check_range("tip_mass.rotary_inertia", self.rotary_inertia, low=0.0, unit="kg m^2")
        check_range("tip_mass.offset", self.offset, unit="m")

    def matrix(self) -> np.ndarray:
        """2x2 mass matrix on the tip DOFs (w, theta) [kg, kg m, kg m^2]."""
        m, e = self.mass, self.offset
        return np.array([[m, m * e], [m * e, m * e * e + self.rotary_inertia]])


def _as_tip_mass(tip_mass: TipMass | float | None) -> TipMass:
    if tip_mass is None:
        return TipMass(0.0)
    if isinstance(tip_mass, TipMass):
        return tip_mass
    return TipMass(check_range("tip_mass.mass", tip_mass, low=0.0, unit="kg"))


def element_stiffness(beam: TimoshenkoBeam) -> np.ndarray:
    """Stiffness matrix of one element, DOFs (w1, theta1, w2, theta2).

    ``EI / (L^3 (1 + phi)) [[12, 6L, -12, 6L], [6L, (4+phi)L^2, -6L, (2-phi)L^2], ...]``
    (bending and shear energy of the interdependent interpolation).

    Parameters
    ----------
    beam
        The beam; its element length and shear parameter are used.

    Returns
    -------
    numpy.ndarray
        4x4 symmetric matrix [N/m, N, N m].
    """
    le, phi = beam.element_length, beam.shear_parameter
    c = beam.bending_stiffness / (le**3 * (1.0 + phi))
    return c * np.array([
        [12.0, 6.0 * le, -12.0, 6.0 * le],
        [6.0 * le, (4.0 + phi) * le**2, -6.0 * le, (2.0 - phi) * le**2],
        [-12.0, -6.0 * le, 12.0, -6.0 * le],
        [6.0 * le, (2.0 - phi) * le**2, -6.0 * le, (4.0 + phi) * le**2],
    ])


def element_mass(beam: TimoshenkoBeam) -> np.ndarray:
    """Consistent mass matrix of one element, translational plus rotary inertia.

    Friedman & Kosmatka (1993), Eqs. for ``M_rhoA`` and ``M_rhoI`` with the shear parameter
    phi; for phi = 0 the translational part is the Hermite matrix ``rho A L / 420 [156, ...]``.

    Parameters
    ----------
    beam
        The beam; its element length and shear parameter are used.

    Returns
    -------
    numpy.ndarray
        4x4 symmetric matrix [kg, kg m, kg m^2], DOFs (w1, theta1, w2, theta2).
    """
    le, p = beam.element_length, beam.shear_parameter
    q = (1.0 + p) ** 2
    rho_a = beam.density * beam.area * le / q
    m11 = 13.0 / 35.0 + 7.0 * p / 10.0 + p * p / 3.0
    m12 = (11.0 / 210.0 + 11.0 * p / 120.0 + p * p / 24.0) * le
    m13 = 9.0 / 70.0 + 3.0 * p / 10.0 + p * p / 6.0
    m14 = (13.0 / 420.0 + 3.0 * p / 40.0 + p * p / 24.0) * le
    m22 = (1.0 / 105.0 + p / 60.0 + p * p / 120.0) * le**2
    m24 = (1.0 / 140.0 + p / 60.0 + p * p / 120.0) * le**2
    translational = rho_a * np.array([
        [m11, m12, m13, -m14],
        [m12, m22, m14, -m24],
        [m13, m14, m11, -m12],
        [-m14, -m24, -m12, m22],
    ])
    rho_i = beam.density * beam.second_moment / (le * q)
    r11 = 6.0 / 5.0
    r12 = (1.0 / 10.0 - p / 2.0) * le
    r22 = (2.0 / 15.0 + p / 6.0 + p * p / 3.0) * le**2
    r24 = (-1.0 / 30.0 - p / 6.0 + p * p / 6.0) * le**2
    rotary = rho_i * np.array([
        [r11, r12, -r11, r12],
        [r12, r22, -r12, r24],
        [-r11, -r12, r11, -r12],
        [r12, r24, -r12, r22],
    ])
    return translational + rotary


def cantilever_matrices(
    beam: TimoshenkoBeam,
    tip_mass: TipMass | float | None = None,
    clamp_rotational_stiffness: float = math.inf,
) -> tuple[np.ndarray, np.ndarray]:
    """Assembled stiffness and mass matrices of the cantilever, clamped at x = 0.

    Parameters
    ----------
    beam
        The beam and its mesh.
    tip_mass
        Rigid body at x = L: a :class:`TipMass`, a plain point mass [kg], or None.
    clamp_rotational_stiffness
        Rotational spring at x = 0 [N m/rad]; ``inf`` (default) is a rigid clamp. The
        deflection at x = 0 is always fixed.

    Returns
    -------
    (K, M) : tuple of numpy.ndarray
        Square matrices over the free DOFs ``(w_1, theta_1, ..., w_n, theta_n)`` of nodes
        1..n (node 0 at the clamp removed), preceded by ``theta_0`` when the clamp
        is compliant. The tip DOFs are always the last two.
    """
    tip = _as_tip_mass(tip_mass)
    if isinstance(clamp_rotational_stiffness, int | float) and clamp_rotational_stiffness == math.inf:
        kr = math.inf
    else:
        kr = check_range("beam.clamp_rotational_stiffness", clamp_rotational_stiffness, low=0.0,
                         low_inclusive=False, unit="N m/rad")
    n = beam.elements
    ndof = 2 * (n + 1)
    k_glob = np.zeros((ndof, ndof))
    m_glob = np.zeros((ndof, ndof))
    ke, me = element_stiffness(beam), element_mass(beam)
    for e in range(n):
        s = slice(2 * e, 2 * e + 4)
        k_glob[s, s] += ke
        m_glob[s, s] += me
    m_glob[-2:, -2:] += tip.matrix()
    if math.isinf(kr):
        free = slice(2, ndof)
    else:
        k_glob[1, 1] += kr
        free = slice(1, ndof)
    return k_glob[free, free], m_glob[free, free]


def _stiffness_form(beam: TimoshenkoBeam, v: np.ndarray, clamp_rotational_stiffness: float) -> float:
    """``v^T K v`` as a sum of squares, free of the round-off of the assembled quadratic form.

    Per element, ``K_e = EI/L_e b b^T + 12 EI / (L_e^3 (1 + phi)) c c^T`` with
    ``b^T u = theta_2 - theta_1`` and ``c^T u = w_2 - w_1 - L_e (theta_1 + theta_2) / 2``.
    """
    compliant = v.shape[0] % 2 == 1
    theta0 = v[0] if compliant else 0.0
    body = v[1:] if compliant else v
    w = np.concatenate([[0.0], body[0::2]])
    th = np.concatenate([[theta0], body[1::2]])
    le, phi, ei = beam.element_length, beam.shear_parameter, beam.bending_stiffness
    bend = np.diff(th)
    shear = np.diff(w) - 0.5 * le * (th[:-1] + th[1:])
    energy = ei / le * float(bend @ bend) + 12.0 * ei / (le**3 * (1.0 + phi)) * float(shear @ shear)
    if compliant:
        energy += clamp_rotational_stiffness * theta0**2
    return energy


def static_tip_stiffness(beam: TimoshenkoBeam) -> float:
    """Closed-form Timoshenko tip stiffness ``1 / (L^3 / (3 E I) + L / (k G A))`` [N/m].

    Examples
    --------
    >>> from pdamper.parameters import paper_beam
    >>> b, _ = paper_beam()
    >>> round(static_tip_stiffness(b), 1)
    2747.6
    """
    el = beam.length
    return 1.0 / (el**3 / (3.0 * beam.bending_stiffness) + el / beam.shear_stiffness)


@dataclass(frozen=True, eq=False)
class ReducedModel:
    """One-mode reduction of the cantilever, referred to a reference-point displacement.

    Parameters
    ----------
    mass
        Modal mass M_red = v^T M v with unit reference displacement [kg].
    stiffness
        Modal stiffness K_red = v^T K v [N/m].
    mode
        Index of the retained mode (0 = first bending mode) [-].
    frequencies
        First few undamped eigenfrequencies of the full FE model [Hz].
    positions
        Node positions x along the beam, clamp (0) to tip (L) [m].
    deflection
        Mode shape's deflection w at the nodes, reference displacement = 1 [-].
    rotation
        Mode shape's rotation theta at the nodes [1/m].
    """

    mass: float
    stiffness: float
    mode: int
    frequencies: np.ndarray = field(repr=False)
    positions: np.ndarray = field(repr=False)
    deflection: np.ndarray = field(repr=False)
    rotation: np.ndarray = field(repr=False)

    @property
    def natural_frequency(self) -> float:
        """sqrt(K_red / M_red) / (2 pi) [Hz]; equals ``frequencies[mode]``."""
        return self.to_structure(0.0).natural_frequency

    def to_structure(self, damping: float) -> SingleDOFStructure:
        """Eq. (23) with this (M_red, K_red) and the given structural damping D [kg/s]."""
        from pdamper.structure import SingleDOFStructure

        return SingleDOFStructure(mass=self.mass, damping=damping, stiffness=self.stiffness)


def modal_reduction(
    beam: TimoshenkoBeam,
    tip_mass: TipMass | float | None = None,
    mode: int = 0,
    *,
    reference_offset: float = 0.0,
    clamp_rotational_stiffness: float = math.inf,
    n_frequencies: int = 5,
) -> ReducedModel:
    """Reduce the FE cantilever to one mode, referred to the end-effector displacement.

    Parameters
    ----------
    beam
        The beam and its mesh.
    tip_mass
        Rigid body at the free end (:class:`TipMass`, point mass [kg] or None).
    mode
        Index of the retained mode, 0 = first bending mode [-].
    reference_offset
        Axial distance of the reference point beyond the tip node [m]; its displacement is
        ``w_tip + offset theta_tip`` (rigid end body). Default 0: the tip node.
    clamp_rotational_stiffness
        Rotational spring of the clamp [N m/rad]; ``inf`` = rigid clamp (default).
    n_frequencies
        Number of eigenfrequencies to return [-].

    Returns
    -------
    ReducedModel
        M_red, K_red with ``sqrt(K_red / M_red)`` = the mode's eigenfrequency.

    Examples
    --------
    >>> from pdamper.parameters import paper_beam
    >>> beam, tip = paper_beam()
    >>> r = modal_reduction(beam, tip)
    >>> round(r.natural_frequency, 3), round(r.mass, 3), round(r.stiffness)
    (6.085, 1.885, 2756)
    """
    if isinstance(mode, bool) or not isinstance(mode, int | np.integer) or mode < 0:
        raise InputError("modal_reduction.mode", f"must be an integer >= 0, got {mode!r}")
    e = check_range("modal_reduction.reference_offset", reference_offset, unit="m")
    k_mat, m_mat = cantilever_matrices(beam, tip_mass, clamp_rotational_stiffness)
    ndof = k_mat.shape[0]
    if mode >= ndof:
        raise InputError("modal_reduction.mode", f"must be < {ndof} (number of DOFs), got {mode}")
    nf = min(max(int(n_frequencies), mode + 1), ndof)
    # Rotations scaled by L_e (all DOFs in metres) improve the conditioning; the returned
    # frequencies are the Rayleigh quotients of the eigenvectors, which are accurate to
    # second order in the eigenvector error and make sqrt(K_red / M_red) = frequencies[mode].
    import scipy.linalg  # here: the paper's parameters import this module, scipy costs 0.2 s

    scale = np.ones(ndof)
    scale[ndof % 2 + 1::2] = 1.0 / beam.element_length
    if ndof % 2 == 1:
        scale[0] = 1.0 / beam.element_length
    _, vecs = scipy.linalg.eigh(scale[:, None] * k_mat * scale, scale[:, None] * m_mat * scale,
                                driver="gv")
    vecs = scale[:, None] * vecs[:, :nf]
    w2 = np.array([_stiffness_form(beam, u, clamp_rotational_stiffness) / (u @ m_mat @ u)
                   for u in vecs.T])
    v = vecs[:, mode]
    ref = v[-2] + e * v[-1]
    if abs(ref) < 1e-12 * np.max(np.abs(v)):
        raise InputError("modal_reduction.mode",
                         f"mode {mode} has no displacement at the reference point")
    v = v / ref
    m_red = float(v @ m_mat @ v)
    k_red = _stiffness_form(beam, v, clamp_rotational_stiffness)
    # nodal shape incl. the clamp node (w_0 = 0; theta_0 = 0 unless the clamp is compliant)
    compliant = ndof % 2 == 1
    theta0 = v[0] if compliant else 0.0
    body = v[1:] if compliant else v
    deflection = np.concatenate([[0.0], body[0::2]])
    rotation = np.concatenate([[theta0], body[1::2]])
    return ReducedModel(
        mass=m_red,
        stiffness=k_red,
        mode=int(mode),
        frequencies=np.sqrt(np.maximum(w2, 0.0)) / (2.0 * math.pi),
        positions=np.linspace(0.0, beam.length, beam.elements + 1),
        deflection=deflection,
        rotation=rotation,
    )
