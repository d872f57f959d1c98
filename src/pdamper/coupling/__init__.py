"""Level III: damper models coupled to a structure (paper Sect. 4.1).

One damper interface, several fidelities: :class:`DamperModel` answers Level II questions
(:meth:`~DamperModel.response` under harmonic excitation) and Level III ones
(:meth:`~DamperModel.free_vibration` on a structure). :class:`Simulation` runs any of them.
"""

from pdamper.coupling.analytical import AnalyticalDamper
from pdamper.coupling.base import DamperModel, PseudoForceDamper
from pdamper.coupling.decrement import damping_ratio_from_peaks, negative_peaks
from pdamper.coupling.dem import DEMDamper
from pdamper.coupling.free_vibration import CycleUpdate, FreeVibrationResult, Simulation

__all__ = [
    "AnalyticalDamper",
    "CycleUpdate",
    "DEMDamper",
    "DamperModel",
    "FreeVibrationResult",
    "PseudoForceDamper",
    "Simulation",
    "damping_ratio_from_peaks",
    "negative_peaks",
]
