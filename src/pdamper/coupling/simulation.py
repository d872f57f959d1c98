"""One :class:`Simulation` for every damper fidelity on a structure (paper Sect. 4.2).

The coupling strategy is chosen by the model's ``coupling`` name through the coupling table
:data:`COUPLINGS` (:mod:`pdamper.coupling.registry`, its rows in
:mod:`pdamper.coupling.strategies`): a new strategy is one row there, no caller branches on
the model's type. A one-mode ``ModalStructure`` whose damper, output and release points
coincide is Eq. (23) and runs with every coupling (the DEM co-simulation included) through
its 1-DOF equivalent when the strategy has no N-mode form.
"""

from __future__ import annotations

from typing import Any

from pdamper.coupling import strategies as _strategies  # noqa: F401 (fills the table)
from pdamper.coupling.experiments import Release, as_experiment, with_run
from pdamper.coupling.registry import (
    COUPLINGS,  # noqa: F401 (the coupling table, importable from here)
    MODES,
    RELEASE,
    Coupling,
    CouplingView,
    coupling_of,
)
from pdamper.coupling.results import FreeVibrationResult
from pdamper.errors import InputError
from pdamper.models.base import DamperModel
from pdamper.structure import SingleDOFStructure

#: The release of N-mode structures by coupling name (a view of :data:`COUPLINGS`):
#: ``f(model, structure, duration, x0, sample_rate)``.
MODAL_COUPLINGS = CouplingView(lambda c: c.modal_free_vibration,
                               lambda c: MODES in c.answers.get(RELEASE, ()))


class Simulation:
    """A structure carrying a damper model, and what is done to it (Sect. 4.2).

    The structure and the damper are the model; the experiment
    (:mod:`pdamper.coupling.experiments`) says what is done to them; the coupling strategy
    of the damper model (:data:`COUPLINGS`) solves it. :meth:`solve` returns the
    experiment's result: a :class:`~pdamper.coupling.results.FreeVibrationResult` of a
    :class:`~pdamper.coupling.experiments.Release`, a
    :class:`~pdamper.coupling.loads.LoadResponse` of a
    :class:`~pdamper.coupling.experiments.Loading`, a
    :class:`~pdamper.coupling.frf.FRFResult` of a
    :class:`~pdamper.coupling.experiments.HarmonicSweep`. What the coupling cannot run (an
    experiment it does not answer, a structure it does not take) is refused here, before
    any run.

    Parameters
    ----------
    structure
        The :class:`~pdamper.structure.SingleDOFStructure`, or a
        :class:`~pdamper.structure.modal.ModalStructure` (N modes, damper anywhere).
    model
        Any :class:`~pdamper.models.DamperModel` (analytic, effective fields, DEM, plastic).
    experiment
        A :class:`~pdamper.coupling.experiments.Experiment`; a number is the initial
        displacement x0 [m] of a :class:`~pdamper.coupling.experiments.Release` (negative,
        the paper's -58 mm; its duration given to :meth:`run`), a
        :class:`~pdamper.coupling.loads.LoadHistory` its
        :class:`~pdamper.coupling.experiments.Loading`.

    Examples
    --------
    >>> from pdamper.coupling.experiments import Release
    >>> from pdamper.parameters import PAPER_DAMPER, PAPER_STRUCTURE
    >>> from pdamper.models import AnalyticalDamper
    >>> res = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER),
    ...                  Release(-0.058, duration=2.0)).solve()
    >>> 0.005 < res.final_amplitude < 0.015
    True
    >>> res2 = Simulation(PAPER_STRUCTURE, AnalyticalDamper(PAPER_DAMPER), -0.058).run(2.0)
    >>> bool(res2.final_amplitude == res.final_amplitude)
    True
    """

    def __init__(self, structure, model, experiment: Any = None, *,
                 initial_displacement: float | None = None):
        from pdamper.structure.modal import ModalStructure

        if not isinstance(structure, SingleDOFStructure | ModalStructure):
            raise InputError("structure", "must be a SingleDOFStructure (e.g. "
                             "pdamper.parameters.PAPER_STRUCTURE) or a ModalStructure, got "
                             f"{type(structure).__name__}")
        if not isinstance(model, DamperModel):
            raise InputError("model", "must be a DamperModel (e.g. AnalyticalDamper(damper)), "
                             f"got {type(model).__name__}")
        if (experiment is None) == (initial_displacement is None):
            raise InputError("experiment", "give one experiment (Release, Loading, "
                             "HarmonicSweep) or an initial displacement [m]")
        self._strategy = coupling_of(model)
        self.experiment = as_experiment(experiment if experiment is not None
                                        else initial_displacement)
        self.structure = self.experiment.prepare(self._strategy, model, structure)
        self.model = model

    @property
    def coupling(self) -> Coupling:
        """The coupling strategy that solves the experiment (a row of :data:`COUPLINGS`)."""
        return self._strategy

    @property
    def initial_displacement(self) -> float | None:
        """x0 [m] of a release (None for another experiment)."""
        return getattr(self.experiment, "initial_displacement", None)

    def solve(self) -> Any:
        """Run the experiment; its result (the class docstring)."""
        return self.experiment.solve(self._strategy, self.model, self.structure)

    def run(self, duration: float, sample_rate: float = 2000.0) -> FreeVibrationResult:
        """The release over ``duration`` [s], the trajectory sampled at ``sample_rate`` [Hz]
        (this call's duration and rate, whatever the release says)."""
        if not isinstance(self.experiment, Release):
            raise InputError("experiment", "run(duration) runs a release; solve() runs a "
                             f"{type(self.experiment).__name__}")
        return with_run(self.experiment, duration, sample_rate).solve(
            self._strategy, self.model, self.structure)
