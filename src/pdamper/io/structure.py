"""The structure a scenario describes (``[structure]``): the 1-DOF of Eq. (23), N modes
from a CSV file (:mod:`pdamper.io.modes`) or the Timoshenko cantilever of Sect. 4.1 with a
tip mass, reduced to its first bending modes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pdamper.errors import InputError
from pdamper.parameters import vertical_dampers_paper as paper

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.io.scenario import BeamSpec, Scenario
    from pdamper.structure import SingleDOFStructure
    from pdamper.structure.modal import ModalStructure

#: The paper's beam (Sect. 4.1): the defaults of ``[structure] beam``.
_BEAM, _ = paper.paper_beam()


def structure_model(sc: Scenario) -> SingleDOFStructure | ModalStructure:
    """The :class:`~pdamper.structure.SingleDOFStructure` of Eq. (23) (M defaults to the
    paper's, see :mod:`pdamper.parameters.vertical_dampers_paper`), or the
    :class:`~pdamper.structure.modal.ModalStructure` of ``[structure] modes`` or
    ``beam``: :func:`given_structure` with the container's mass added at the damper's point
    unless the data include it (:func:`includes_container_mass`)."""
    structure = given_structure(sc)
    if not includes_container_mass(sc):
        structure = structure.with_added_mass(sc.container.mass)
    return structure


def given_structure(sc: Scenario) -> SingleDOFStructure | ModalStructure:
    """The structure as the scenario's data give it (the modes file, the beam, the 1-DOF),
    before the container's mass is added: what a report shows as the user's data."""
    from pdamper.structure import SingleDOFStructure

    s = sc.structure
    structure: SingleDOFStructure | ModalStructure
    if s.modes is not None:
        from pdamper.io.modes import read_modes

        structure = read_modes(s.modes)
    elif s.beam is not None:
        structure = beam_structure(s.beam)
    else:
        structure = SingleDOFStructure(mass=paper.PAPER_MASS if s.mass is None else s.mass,
                                       damping=s.damping, stiffness=s.stiffness)
    return structure


def includes_container_mass(sc: Scenario) -> bool:
    """Whether the scenario's structure already includes the container's mass
    (``[structure] includes_container_mass``; unset: true for the 1-DOF and the beam,
    false for a modes file)."""
    given = sc.structure.includes_container_mass
    return sc.structure.modes is None if given is None else bool(given)


def beam_structure(spec: BeamSpec) -> ModalStructure:
    """The :class:`~pdamper.structure.modal.ModalStructure` of ``[structure] beam``: the
    Timoshenko beam (:class:`~pdamper.structure.beam.TimoshenkoBeam`, default the paper's)
    with its tip mass, damper and release at ``damper_position``, results at
    ``observation_position`` (both default the tip; positions [m] from the clamp)."""
    from pdamper.io.damper_sections import material as _material
    from pdamper.structure.beam import TimoshenkoBeam, TipMass
    from pdamper.structure.modal import ModalStructure

    if spec.material is not None:
        m = _material(spec.material, "structure.beam.material")
        e, nu, rho = m.youngs_modulus, m.poisson_ratio, m.density
    else:
        constants = ("youngs_modulus", "poisson_ratio", "density")
        given = [k for k in constants if getattr(spec, k) is not None]
        if given and len(given) < len(constants):
            # the rest would silently be the paper's beam's: a beam of two materials
            missing = [k for k in constants if k not in given]
            raise InputError(f"structure.beam.{missing[0]}", f"give all three constants "
                             f"({', '.join(constants)}) or a material; got only "
                             f"{', '.join(given)}, missing {', '.join(missing)}")
        e, nu, rho = (_BEAM.youngs_modulus if spec.youngs_modulus is None
                      else spec.youngs_modulus,
                      _BEAM.poisson_ratio if spec.poisson_ratio is None
                      else spec.poisson_ratio,
                      _BEAM.density if spec.density is None else spec.density)
    zeta = spec.damping_ratio
    if isinstance(zeta, list) and len(zeta) != spec.modes:
        raise InputError("structure.beam.damping_ratio", f"must be one ratio or one per "
                         f"mode ({spec.modes}), got {len(zeta)}")
    pos = {}
    for key in ("damper_position", "observation_position", "load_position"):
        v = getattr(spec, key)
        if v is not None and v > spec.length * (1.0 + 1e-12):
            raise InputError(f"structure.beam.{key}", f"must be in (0, {spec.length:g}] m "
                             f"(the beam's length), got {v:g} m")
        # "700 mm" is 0.7000000000000001 m: the tip of a 0.7 m beam, not beyond it
        pos[key] = None if v is None else min(v, spec.length)
    try:
        beam = TimoshenkoBeam(length=spec.length, width=spec.width, height=spec.height,
                              youngs_modulus=e, poisson_ratio=nu, density=rho,
                              shear_coefficient=spec.shear_coefficient,
                              elements=spec.elements)
        return ModalStructure.from_beam(
            beam, TipMass(spec.tip_mass), spec.modes,
            damper_position=pos["damper_position"],
            output_position=pos["observation_position"],
            release_position=pos["damper_position"], damping_ratio=zeta,
            load_position=pos["load_position"])
    except InputError as exc:
        field = exc.field.removeprefix("beam.").removeprefix("structure.")
        raise InputError(f"structure.beam.{field}", exc.message) from None
