"""Level III: damper models coupled to a structure (paper Sect. 4.1).

Coupling strategies: the pseudo force of models 2 and 3 (:mod:`pdamper.coupling.pseudo_force`,
on N modes :mod:`pdamper.coupling.modal`) and the co-simulation of model 1
(:mod:`pdamper.coupling.cosimulation`). Measured trajectories are aligned and compared in
:mod:`pdamper.coupling.measurement` and :mod:`pdamper.coupling.comparison`. :class:`Simulation`
runs any :class:`~pdamper.models.DamperModel` on a structure under an experiment
(:mod:`pdamper.coupling.experiments`: :class:`Release`, :class:`Loading`,
:class:`HarmonicSweep`) with the strategy the model names in the coupling table
(:data:`COUPLINGS`, :mod:`pdamper.coupling.registry`); the damping ratio follows from the
logarithmic decrement (Eqs. 24-25).
:func:`run_load` runs a damper model on a structure under a load history (a force or a base
acceleration, :mod:`pdamper.coupling.loads`).
The forced response under a harmonic force or base motion (harmonic balance and stepped
sines) is :mod:`pdamper.coupling.frf`.
"""

from pdamper.coupling.decrement import damping_ratio_from_peaks, negative_peaks
from pdamper.coupling.experiments import Experiment, HarmonicSweep, Loading, Release
from pdamper.coupling.loads import (
    LOAD_COUPLINGS,
    LoadHistory,
    LoadResponse,
    run_load,
    simulate_load,
)
from pdamper.coupling.pseudo_force import pseudo_force_coefficients
from pdamper.coupling.registry import Coupling
from pdamper.coupling.results import CycleUpdate, FreeVibrationResult
from pdamper.coupling.simulation import COUPLINGS, MODAL_COUPLINGS, Simulation

__all__ = [
    "COUPLINGS",
    "Coupling",
    "Experiment",
    "HarmonicSweep",
    "Loading",
    "Release",
    "LOAD_COUPLINGS",
    "LoadHistory",
    "LoadResponse",
    "MODAL_COUPLINGS",
    "CycleUpdate",
    "FreeVibrationResult",
    "Simulation",
    "damping_ratio_from_peaks",
    "negative_peaks",
    "pseudo_force_coefficients",
    "run_load",
    "simulate_load",
]
