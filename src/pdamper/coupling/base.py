"""The damper interface shared by every fidelity."""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import TYPE_CHECKING, ClassVar

from pdamper.analysis.fields import DamperResponse
from pdamper.damper import ParticleDamper

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.coupling.free_vibration import FreeVibrationResult
    from pdamper.structure import SingleDOFStructure


class DamperModel(ABC):
    """A particle damper model of some fidelity.

    Subclasses implement :meth:`response` (Level II) and :meth:`free_vibration` (Level III).
    A new fidelity is a new subclass.
    """

    #: Name of the fidelity (``"analytic"``, ``"fields"``, ``"dem"``).
    fidelity: ClassVar[str] = ""

    def __init__(self, damper: ParticleDamper):
        self.damper = damper

    @property
    def bed_mass(self) -> float:
        """m_bed [kg]."""
        return self.damper.bed_mass

    @abstractmethod
    def response(self, frequency, amplitude) -> DamperResponse:
        """Response under harmonic excitation with frequency f [Hz] and stroke X [m]."""

    @abstractmethod
    def free_vibration(self, structure: SingleDOFStructure, duration: float,
                       initial_displacement: float, sample_rate: float) -> FreeVibrationResult:
        """Free vibration of ``structure`` carrying this damper, released from rest."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}(count={self.damper.count})"


class PseudoForceDamper(DamperModel):
    """A damper acting as the pseudo force ``F = -(m_eff x'' + d x')`` (Sect. 4.1, models 2
    and 3), with ``d = E~ / (pi W X^2)``, both updated once per cycle at each minimum of the
    end-effector."""

    def pseudo_force_coefficients(self, frequency: float, amplitude: float):
        """Effective mass m_eff [kg], viscous damping d [kg/s] and the response at one
        (f, X) point."""
        r = self.response(frequency, amplitude)
        w = 2.0 * math.pi * frequency
        d = float(r.dissipated_energy_per_cycle) / (math.pi * w * amplitude**2)
        return float(r.effective_mass), d, r

    def free_vibration(self, structure, duration, initial_displacement, sample_rate=2000.0):
        from pdamper.coupling.free_vibration import simulate_pseudo_force

        return simulate_pseudo_force(self, structure, duration, initial_displacement,
                                     sample_rate)
