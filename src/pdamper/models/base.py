"""The damper interface shared by every fidelity, and its response type."""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from pdamper.damper import ParticleDamper
from pdamper.errors import InputError


@dataclass(frozen=True)
class DamperResponse:
    """Response of a damper under harmonic vertical excitation ``x_c = X sin(2 pi f t)``.

    Attributes
    ----------
    frequency, amplitude
        f [Hz] and X [m], broadcast to the shape of the results.
    mode
        :class:`~pdamper.analysis.modes.MotionMode` codes [-] (-1: not classified).
    loss_factor
        Effective loss factor eta [-] (Eq. 3).
    dissipated_energy_per_cycle
        E~_diss [J] (Eq. 2).
    effective_mass_ratio
        Effective particle mass over bed mass [-] (Eq. 4 or Eq. 22).
    bed_mass
        m_bed [kg].
    details
        What the model computed on the way: the analytical
        :class:`~pdamper.analysis.analytical.BedResponse`, or for the DEM an object array of
        :class:`~pdamper.dem.DEMResult`, one per point (``details.item()`` for one point).
    """

    frequency: np.ndarray
    amplitude: np.ndarray
    mode: np.ndarray
    loss_factor: np.ndarray
    dissipated_energy_per_cycle: np.ndarray
    effective_mass_ratio: np.ndarray
    bed_mass: float
    details: Any = field(default=None, repr=False, compare=False)

    @property
    def effective_mass(self) -> np.ndarray:
        """Effective particle mass [kg]."""
        return self.effective_mass_ratio * self.bed_mass


class DamperModel(ABC):
    """A particle damper model of some fidelity.

    Subclasses implement :meth:`response` (Level II); ``coupling`` names the Level III
    strategy of :mod:`pdamper.coupling` that puts the model on a structure
    (``"pseudo_force"``: Sect. 4.1 models 2 and 3; ``"co_simulation"``: model 1).

    Parameters
    ----------
    damper
        The physical damper (container, spheres, materials).
    """

    #: Name of the fidelity (``"analytic"``, ``"fields"``, ``"dem"``).
    fidelity: ClassVar[str] = ""
    #: Name of the Level III coupling strategy.
    coupling: ClassVar[str] = "pseudo_force"
    #: Whether one Level III run costs seconds or more (design studies then evaluate
    #: designs on parallel workers by default).
    expensive: ClassVar[bool] = False

    def __init__(self, damper: ParticleDamper):
        if not isinstance(damper, ParticleDamper):
            raise InputError("damper", f"must be a ParticleDamper (e.g. "
                             f"pdamper.parameters.PAPER_DAMPER), got {type(damper).__name__}")
        self.damper = damper

    @property
    def bed_mass(self) -> float:
        """m_bed [kg]."""
        return self.damper.bed_mass

    @abstractmethod
    def response(self, frequency, amplitude) -> DamperResponse:
        """Response under harmonic excitation with frequency f [Hz] and stroke X [m]."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}(count={self.damper.count})"
