"""One :class:`Simulation` for every damper fidelity on a structure (paper Sect. 4.2).

The coupling strategy is chosen by the model's ``coupling`` name through :data:`COUPLINGS`
(structures of one mode, :class:`~pdamper.structure.SingleDOFStructure`) or
:data:`MODAL_COUPLINGS` (N modes, :class:`~pdamper.structure.modal.ModalStructure`): a new
strategy registers here, no caller branches on the model's type. A one-mode
``ModalStructure`` whose damper, output and release points coincide is Eq. (23) and runs
with every coupling through its 1-DOF equivalent when the strategy has no N-mode form (the
DEM co-simulation's N-mode form runs it as its 1-DOF too).
"""

from __future__ import annotations

from collections.abc import Callable

from pdamper import resources
from pdamper.coupling.cosimulation import co_simulate, co_simulate_modes
from pdamper.coupling.modal import simulate_modal_pseudo_force
from pdamper.coupling.plastic import PlasticBedCoupling
from pdamper.coupling.pseudo_force import simulate_pseudo_force
from pdamper.coupling.results import FreeVibrationResult
from pdamper.errors import InputError, check_range
from pdamper.models.base import DamperModel
from pdamper.structure import SingleDOFStructure

#: Coupling strategies by name: ``f(model, structure, duration, x0, sample_rate)``.
COUPLINGS: dict[str, Callable[..., FreeVibrationResult]] = {
    "pseudo_force": simulate_pseudo_force,
    "co_simulation": co_simulate,
    PlasticBedCoupling.name: PlasticBedCoupling.free_vibration,
}

#: Coupling strategies of N-mode structures, same signature.
MODAL_COUPLINGS: dict[str, Callable[..., FreeVibrationResult]] = {
    "pseudo_force": simulate_modal_pseudo_force,
    "co_simulation": co_simulate_modes,
    PlasticBedCoupling.name: PlasticBedCoupling.free_vibration,
}


class Simulation:
    """A structure with a damper model, released from an initial deflection (Sect. 4.2).

    Parameters
    ----------
    structure
        The :class:`~pdamper.structure.SingleDOFStructure`, or a
        :class:`~pdamper.structure.modal.ModalStructure` (N modes, damper anywhere).
    model
        Any :class:`~pdamper.models.DamperModel` (analytic, effective fields, DEM).
    initial_displacement
        x0 [m], negative (the paper's -58 mm).

    Examples
    --------
    >>> from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
    >>> from pdamper.models import AnalyticalDamper
    >>> res = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER), -0.058).run(2.0)
    >>> 0.005 < res.final_amplitude < 0.015
    True
    """

    def __init__(self, structure, model, initial_displacement: float):
        from pdamper.structure.modal import ModalStructure

        if not isinstance(structure, SingleDOFStructure | ModalStructure):
            raise InputError("structure", "must be a SingleDOFStructure (e.g. "
                             "pdamper.parameters.PAPER_STRUCTURE) or a ModalStructure, got "
                             f"{type(structure).__name__}")
        if not isinstance(model, DamperModel):
            raise InputError("model", "must be a DamperModel (e.g. AnalyticalDamper(damper)), "
                             f"got {type(model).__name__}")
        if model.coupling not in COUPLINGS:
            raise InputError("model", f"coupling {model.coupling!r} of {type(model).__name__} "
                             f"is not one of {', '.join(COUPLINGS)}")
        self._strategy = COUPLINGS[model.coupling]
        if isinstance(structure, ModalStructure):
            # the DEM runs one coincident mode as its 1-DOF (Eq. 23), N modes as modes
            one_dof = (structure.modes == 1 and structure.coincident
                       and model.coupling == "co_simulation")
            if model.coupling in MODAL_COUPLINGS and not one_dof:
                self._strategy = MODAL_COUPLINGS[model.coupling]
            elif structure.modes == 1 and structure.coincident:
                structure = structure.equivalent_single_dof()
            else:
                raise InputError("structure", f"the {model.coupling} coupling of "
                                 f"{type(model).__name__} needs a single-DOF structure (or one "
                                 "mode with the damper at the output and release point); use "
                                 "a pseudo-force model (analytic, fields) for N modes")
        self.structure = structure
        self.model = model
        self.initial_displacement = check_range("structure.initial_displacement",
                                                initial_displacement, high=0.0,
                                                high_inclusive=False, unit="m")
        # the physics limits of every Level III run, whichever the model (a design study's
        # candidate, the API): the release at the (first) natural frequency
        resources.check_release(model.damper, structure.natural_frequency,
                                self.initial_displacement, contact_law=model.contact_law)

    def run(self, duration: float, sample_rate: float = 2000.0) -> FreeVibrationResult:
        """Simulate ``duration`` [s]; the trajectory is sampled at ``sample_rate`` [Hz]."""
        return self._strategy(self.model, self.structure, duration, self.initial_displacement,
                              sample_rate)
