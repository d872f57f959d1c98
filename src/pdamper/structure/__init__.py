"""Level III: reduced structural models (paper Sect. 4.1, Eq. 23)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from pdamper.constants import STANDARD_GRAVITY
from pdamper.errors import check_range


@dataclass(frozen=True)
class SingleDOFStructure:
    """``M x'' + D x' + K x = F`` for the end-effector displacement x (Eq. 23).

    Parameters
    ----------
    mass
        Modal mass M [kg] (container included, particles excluded).
    damping
        Structural damping D [kg/s].
    stiffness
        Modal stiffness K [N/m].

    Examples
    --------
    >>> s = SingleDOFStructure(mass=1.514, damping=0.55, stiffness=1848.0)
    >>> round(s.natural_frequency, 2), round(s.damping_ratio, 4)
    (5.56, 0.0052)
    """

    mass: float
    damping: float
    stiffness: float

    def __post_init__(self) -> None:
        check_range("structure.mass", self.mass, low=0.0, low_inclusive=False, unit="kg")
        check_range("structure.damping", self.damping, low=0.0, unit="kg/s")
        check_range("structure.stiffness", self.stiffness, low=0.0, low_inclusive=False,
                    unit="N/m")

    @property
    def angular_frequency(self) -> float:
        """Undamped omega_0 = sqrt(K / M) [rad/s]."""
        return math.sqrt(self.stiffness / self.mass)

    @property
    def natural_frequency(self) -> float:
        """Undamped f_0 [Hz]."""
        return self.angular_frequency / (2.0 * math.pi)

    @property
    def damping_ratio(self) -> float:
        """zeta = D / (2 sqrt(K M)) [-]."""
        return self.damping / (2.0 * math.sqrt(self.stiffness * self.mass))

    def min_amplitude(self, static_mass: float = 0.0, gravity: float = STANDARD_GRAVITY) -> float:
        """X_min = g / omega^2 [m] with ``static_mass`` added (paper Sect. 4.2.1)."""
        return gravity * (self.mass + static_mass) / self.stiffness
