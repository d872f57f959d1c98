"""A structure reduced to its first N modes, with the damper anywhere on it (extends the
paper's one-mode Eq. 23, Sect. 4.1).

In modal coordinates q (N of them, mass-normalised modes), with the damper force F acting
at the damper point, whose displacement is ``x_d = phi_d . q``::

    q_i'' + 2 zeta_i w_i q_i' + w_i^2 q_i = phi_d,i F        (i = 1..N)

With one mode and the damper at the point the mode is normalised to, this is Eq. (23) with
``M = 1 / phi_d^2``, ``K = w^2 M``, ``D = 2 zeta w M``. Three points of the structure are
named: the damper point (where F acts and whose minima update the pseudo force), the
output point (whose displacement the results report; the paper's end-effector) and the
release point (where the counterweight pulls before release); all default to the tip.

:meth:`ModalStructure.from_beam` builds it from the Timoshenko FE cantilever of
:mod:`pdamper.structure.beam`: the modes are the FE eigenvectors, interpolated at any point
with the element's own deflection shape functions (exact static shape of the
interdependent-interpolation element); extra point masses (e.g. a container placed along the
beam) enter the FE mass matrix consistently. Modal damping ratios are per mode (default:
the same ratio for all).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from pdamper.errors import InputError, check_range
from pdamper.structure import SingleDOFStructure
from pdamper.structure.beam import TimoshenkoBeam, TipMass, _stiffness_form, cantilever_matrices


def interpolation_vector(beam: TimoshenkoBeam, position: float,
                         compliant_clamp: bool = False) -> np.ndarray:
    """Row vector n over the cantilever's free DOFs with ``w(position) = n . u``.

    Uses the deflection shape functions of the interdependent-interpolation Timoshenko
    element (Friedman & Kosmatka 1993; Hermite cubics for phi = 0) of the element holding
    ``position`` [m].

    Examples
    --------
    >>> b = TimoshenkoBeam(length=1.0, width=0.05, height=0.01, youngs_modulus=2e11, elements=4)
    >>> n = interpolation_vector(b, 0.75)
    >>> int(np.argmax(n)), float(n.max())   # on node 3: its deflection DOF, weight 1
    (4, 1.0)
    """
    p = check_range("structure.position", position, low=0.0, high=beam.length, unit="m")
    ne, le, phi = beam.elements, beam.element_length, beam.shear_parameter
    e = min(int(p / le), ne - 1)
    xi = (p - e * le) / le
    c = 1.0 / (1.0 + phi)
    shape = c * np.array([
        2 * xi**3 - 3 * xi**2 - phi * xi + 1 + phi,
        le * (xi**3 - (2 + phi / 2) * xi**2 + (1 + phi / 2) * xi),
        -(2 * xi**3 - 3 * xi**2 - phi * xi),
        le * (xi**3 - (1 - phi / 2) * xi**2 - phi / 2 * xi),
    ])
    full = np.zeros(2 * (ne + 1))
    full[2 * e: 2 * e + 4] = shape
    return full[1:] if compliant_clamp else full[2:]


@dataclass(frozen=True, eq=False)
class ModalStructure:
    """N modes of a structure, mass-normalised, with the damper's, output and release points.

    Parameters
    ----------
    frequencies
        Undamped eigenfrequencies f_i [Hz], ascending.
    damping_ratios
        Modal damping ratios zeta_i [-].
    damper_shape
        Mode shapes at the damper point phi_d,i [1/sqrt(kg)].
    output_shape, release_shape
        Mode shapes at the output and release points (default: the damper point).
    positions
        (damper, output, release) positions along the structure [m], for the record.
    participation
        Modal participation factors of a translation of the base, ``Gamma_i = phi_i^T M r``
        [sqrt(kg)] (``r``: the rigid translation), for base motion; None where unknown
        (:meth:`from_beam` computes them).
    load_shape
        Mode shapes at the load point, where a force on the structure acts (a harmonic
        force, an unbalance, a force history) [1/sqrt(kg)]; default the release point
        (which defaults to the damper point).

    Examples
    --------
    One mode equals Eq. (23):

    >>> s = ModalStructure.from_single_dof(SingleDOFStructure(1.514, 0.55, 1848.0))
    >>> e = s.equivalent_single_dof()
    >>> round(e.mass, 3), round(e.damping, 3), round(e.stiffness, 1)
    (1.514, 0.55, 1848.0)
    """

    frequencies: np.ndarray
    damping_ratios: np.ndarray
    damper_shape: np.ndarray
    # None stands for the damper point; __post_init__ replaces it by the array, so every
    # instance holds arrays (read them through _shapes() where the type must say so)
    output_shape: np.ndarray | None = None
    release_shape: np.ndarray | None = None
    positions: tuple[float, float, float] | None = field(default=None)
    participation: np.ndarray | None = field(default=None)
    # None stands for the release point (filled in by __post_init__)
    load_shape: np.ndarray | None = field(default=None)

    def __post_init__(self) -> None:
        f = np.atleast_1d(np.asarray(self.frequencies, float))
        n = f.size
        if n < 1 or not np.all(np.isfinite(f)) or np.any(f <= 0) or np.any(np.diff(f) < 0):
            raise InputError("structure.frequencies", "must be one or more finite positive "
                             "frequencies in ascending order")
        z = np.broadcast_to(np.asarray(self.damping_ratios, float), (n,)).copy()
        if not np.all((z >= 0) & (z < 1)):  # NaN fails both
            raise InputError("structure.damping_ratios", f"must be in [0, 1) (a vibration "
                             f"mode: at a ratio of 1 and above it does not oscillate), got "
                             f"{', '.join(f'{v:g}' for v in z)}")
        shapes: dict[str, np.ndarray] = {}
        for name in ("damper_shape", "output_shape", "release_shape", "load_shape"):
            v = getattr(self, name)
            if v is None:
                v = shapes["release_shape" if name == "load_shape" else "damper_shape"]
            else:
                v = np.asarray(v, float).ravel()
            if v.size != n or not np.all(np.isfinite(v)):
                raise InputError(f"structure.{name}", f"must hold {n} finite values, one per mode")
            shapes[name] = v
        if not np.any(shapes["damper_shape"] != 0):
            raise InputError("structure.damper_shape", "the damper point does not move in any "
                             "retained mode")
        if self.participation is not None:
            g = np.asarray(self.participation, float).ravel()
            if g.size != n or not np.all(np.isfinite(g)):
                raise InputError("structure.participation", f"must hold {n} finite values, "
                                 "one per mode")
            object.__setattr__(self, "participation", g)
        object.__setattr__(self, "frequencies", f)
        object.__setattr__(self, "damping_ratios", z)
        for name, v in shapes.items():
            object.__setattr__(self, name, v)

    # ------------------------------------------------------------------ builders
    @classmethod
    def from_single_dof(cls, structure: SingleDOFStructure) -> ModalStructure:
        """Eq. (23) as one mass-normalised mode (``phi = 1 / sqrt(M)``)."""
        return cls(np.array([structure.natural_frequency]), np.array([structure.damping_ratio]),
                   np.array([1.0 / math.sqrt(structure.mass)]))

    @classmethod
    def from_beam(
        cls,
        beam: TimoshenkoBeam,
        tip_mass: TipMass | float | None = None,
        modes: int = 1,
        *,
        damper_position: float | None = None,
        output_position: float | None = None,
        release_position: float | None = None,
        damping_ratio: float | Sequence[float] = 0.0,
        point_masses: Sequence[tuple[float, float]] = (),
        clamp_rotational_stiffness: float = math.inf,
        load_position: float | None = None,
    ) -> ModalStructure:
        """The first ``modes`` bending modes of the FE cantilever.

        Parameters
        ----------
        beam, tip_mass, clamp_rotational_stiffness
            As :func:`pdamper.structure.beam.cantilever_matrices`.
        modes
            Number of retained modes N [-].
        damper_position, output_position, release_position
            Distance from the clamp [m]; default the tip (x = L).
        damping_ratio
            Modal damping ratio, one for all modes or one per mode [-].
        point_masses
            Extra rigid point masses ``(position [m], mass [kg])`` on the beam axis.
        load_position
            Where a force on the beam acts, from the clamp [m]; default the release point.

        Examples
        --------
        >>> from pdamper.structure.beam import modal_reduction
        >>> b = TimoshenkoBeam(length=0.68, width=0.08, height=0.006, youngs_modulus=2e11)
        >>> s = ModalStructure.from_beam(b, TipMass(1.27), modes=3)
        >>> [round(float(v), 1) for v in s.frequencies]   # as modal_reduction (docs/beam.md)
        [6.1, 50.9, 155.5]
        >>> r = modal_reduction(b, TipMass(1.27))
        >>> e = ModalStructure.from_beam(b, TipMass(1.27)).equivalent_single_dof()
        >>> bool(np.isclose(e.mass, r.mass, rtol=1e-9)), bool(np.isclose(e.stiffness, r.stiffness, rtol=1e-9))
        (True, True)
        """
        import scipy.linalg

        if isinstance(modes, bool) or not isinstance(modes, int | np.integer) or modes < 1:
            raise InputError("structure.modes", f"must be a whole number >= 1, got {modes!r}")
        k_mat, m_mat = cantilever_matrices(beam, tip_mass, clamp_rotational_stiffness)
        ndof = k_mat.shape[0]
        if modes > ndof:
            raise InputError("structure.modes", f"must be <= {ndof} (DOFs of the mesh), got "
                             f"{modes}")
        compliant = ndof % 2 == 1
        for k, item in enumerate(point_masses):
            try:
                pos, mass = item
            except (TypeError, ValueError):
                raise InputError(f"structure.point_masses[{k}]",
                                 "must be (position [m], mass [kg])") from None
            check_range(f"structure.point_masses[{k}].mass", mass, low=0.0, unit="kg")
            n = interpolation_vector(beam, pos, compliant)
            m_mat = m_mat + mass * np.outer(n, n)
        kr = clamp_rotational_stiffness
        # rotations scaled by L_e for conditioning, as in modal_reduction
        scale = np.ones(ndof)
        scale[ndof % 2 + 1::2] = 1.0 / beam.element_length
        if compliant:
            scale[0] = 1.0 / beam.element_length
        _, vecs = scipy.linalg.eigh(scale[:, None] * k_mat * scale,
                                    scale[:, None] * m_mat * scale, driver="gv")
        vecs = scale[:, None] * vecs[:, :modes]
        vecs = vecs / np.sqrt(np.einsum("ij,ik,kj->j", vecs, m_mat, vecs))  # m_i = 1
        w2 = np.array([_stiffness_form(beam, u, kr) for u in vecs.T])
        pts: list[float] = []
        given: tuple[tuple[str, float | None], ...] = (
            ("damper_position", damper_position), ("output_position", output_position),
            ("release_position", release_position))
        for name, at in given:
            p: float = beam.length if at is None else check_range(f"structure.{name}", at, low=0.0,
                                                            high=beam.length, unit="m")
            pts.append(p)
        shapes = [interpolation_vector(beam, p, compliant) @ vecs for p in pts]
        # fix the sign: positive deflection of each mode at the damper point (or output)
        ref = np.where(shapes[0] != 0, shapes[0], shapes[1])
        sign = np.where(ref < 0, -1.0, 1.0)
        zeta = np.broadcast_to(np.asarray(damping_ratio, float), (modes,))
        # a translation of the clamp: every deflection DOF moves by 1, no rotation
        rigid = np.zeros(2 * (beam.elements + 1))
        rigid[0::2] = 1.0
        rigid = rigid[1:] if compliant else rigid[2:]
        gamma = vecs.T @ (m_mat @ rigid)
        load = None
        if load_position is not None:
            at = check_range("structure.load_position", load_position, low=0.0,
                             high=beam.length, unit="m")
            load = interpolation_vector(beam, at, compliant) @ vecs * sign
        return cls(np.sqrt(np.maximum(w2, 0.0)) / (2.0 * math.pi), zeta,
                   shapes[0] * sign, shapes[1] * sign, shapes[2] * sign, (pts[0], pts[1], pts[2]),
                   gamma * sign, load)

    # ------------------------------------------------------------------ properties
    @property
    def modes(self) -> int:
        """Number of retained modes N."""
        return int(self.frequencies.size)

    @property
    def angular_frequencies(self) -> np.ndarray:
        """omega_i [rad/s]."""
        return 2.0 * math.pi * self.frequencies

    @property
    def natural_frequency(self) -> float:
        """First undamped eigenfrequency [Hz]."""
        return float(self.frequencies[0])

    @property
    def stiffness(self) -> float:
        """Static stiffness at the damper point of the retained modes,
        ``1 / sum(phi_d,i^2 / w_i^2)`` [N/m] (for the particles' static offset)."""
        return 1.0 / float(np.sum(self.damper_shape**2 / self.angular_frequencies**2))

    def effective_frequency(self, added_mass: float = 0.0) -> float:
        """First undamped eigenfrequency with ``added_mass`` [kg] rigidly at the damper point
        [Hz] (the frequency at which the pseudo force is updated)."""
        w2 = self.angular_frequencies**2
        if added_mass == 0.0:
            return float(math.sqrt(w2[0]) / (2.0 * math.pi))
        import scipy.linalg

        k = np.diag(w2)
        m = np.eye(self.modes) + added_mass * np.outer(self.damper_shape, self.damper_shape)
        lam = scipy.linalg.eigh(k, m, eigvals_only=True, subset_by_index=[0, 0])
        return float(math.sqrt(max(lam[0], 0.0)) / (2.0 * math.pi))

    def with_added_mass(self, mass: float) -> ModalStructure:
        """This structure with a rigid point ``mass`` [kg] at the damper point (e.g. the
        container, where the modes were measured or computed without it).

        Solves the mass-modified eigenproblem in the retained modal coordinates,
        ``diag(w_i^2) v = w'^2 (I + m phi_d phi_d^T) v`` (v mass-normalised against the
        modified mass matrix), and re-expresses the damper, output, release and load shapes
        (``phi' = V^T phi``) and the base participation (``Gamma' = V^T (Gamma + m phi_d)``)
        in the new modes. The modal damping matrix ``diag(2 zeta_i w_i)`` is projected on
        the new modes and its diagonal kept: ``zeta'_i = (V^T C V)_ii / (2 w'_i)`` [-].
        Each new mode keeps the sign of the old mode it stems from. One mode with
        ``phi = 1 / sqrt(M)`` gives ``f0 sqrt(M / (M + m))``.

        >>> s = ModalStructure.from_single_dof(SingleDOFStructure(1.0, 0.0, 1000.0))
        >>> round(s.with_added_mass(0.25).natural_frequency / s.natural_frequency, 6)
        0.894427
        """
        m = check_range("damper.container_mass", mass, low=0.0, unit="kg")
        if m == 0.0:
            return self
        import scipy.linalg

        w = self.angular_frequencies
        phi = self.damper_shape
        lam, v = scipy.linalg.eigh(np.diag(w**2), np.eye(self.modes) + m * np.outer(phi, phi))
        # keep each mode's sign (the largest component of its eigenvector positive)
        k = np.argmax(np.abs(v), axis=0)
        v = v * np.where(v[k, np.arange(self.modes)] < 0, -1.0, 1.0)
        w_new = np.sqrt(np.maximum(lam, 0.0))
        c_new = v.T @ np.diag(2.0 * self.damping_ratios * w) @ v
        with np.errstate(divide="ignore", invalid="ignore"):
            zeta = np.where(w_new > 0, np.diag(c_new) / (2.0 * w_new), 0.0)
        gamma = None if self.participation is None else v.T @ (self.participation + m * phi)
        return ModalStructure(w_new / (2.0 * math.pi), zeta, v.T @ phi,
                              v.T @ self._filled(self.output_shape),
                              v.T @ self._filled(self.release_shape), self.positions, gamma,
                              load_shape=v.T @ self._filled(self.load_shape))

    def release_state(self, displacement: float) -> np.ndarray:
        """Modal coordinates q at rest under a static point load at the release point that
        deflects it by ``displacement`` [m] in this N-mode model."""
        psi = self._filled(self.release_shape)
        flex = float(np.sum(psi**2 / self.angular_frequencies**2))
        if flex == 0.0:
            raise InputError("structure.release_shape", "the release point does not move in "
                             "any retained mode")
        return psi / self.angular_frequencies**2 * (displacement / flex)

    def equivalent_single_dof(self) -> SingleDOFStructure:
        """Eq. (23) of a one-mode structure at its damper point."""
        if self.modes != 1:
            raise InputError("structure.modes", f"only a one-mode structure is a 1-DOF "
                             f"structure, this one has {self.modes}")
        phi = float(self.damper_shape[0])
        m = 1.0 / phi**2
        w = float(self.angular_frequencies[0])
        return SingleDOFStructure(mass=m, damping=2.0 * float(self.damping_ratios[0]) * w * m,
                                  stiffness=w * w * m)

    @property
    def coincident(self) -> bool:
        """Whether damper, output, release and load points coincide."""
        return bool(np.array_equal(self.damper_shape, self._filled(self.output_shape))
                    and np.array_equal(self.damper_shape, self._filled(self.release_shape))
                    and np.array_equal(self.damper_shape, self._filled(self.load_shape)))

    @staticmethod
    def _filled(shape: np.ndarray | None) -> np.ndarray:
        """A shape __post_init__ has filled in (never None on an instance)."""
        assert shape is not None
        return shape

    def __repr__(self) -> str:
        f = ", ".join(f"{v:.3g}" for v in self.frequencies)
        return f"ModalStructure(modes={self.modes}, frequencies=[{f}] Hz)"
