"""Level III: reduced structural models (paper Sect. 4.1, Eq. 23).

:class:`SingleDOFStructure` is the paper's one-mode model; :mod:`pdamper.structure.modal`
keeps N modes with the damper anywhere (``ModalStructure``), and
:mod:`pdamper.structure.beam` is the Timoshenko FE cantilever both can be derived from.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pdamper.constants import STANDARD_GRAVITY
from pdamper.errors import InputError, check_range


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
        critical = 2.0 * math.sqrt(self.stiffness * self.mass)
        if not self.damping < critical:  # a damping ratio of 1 and above does not oscillate
            raise InputError("structure.damping", f"must be in [0, {critical:.4g}) kg/s, below "
                             f"the critical damping 2 sqrt(K M) (a vibrating structure: damping "
                             f"ratio < 1), got {self.damping:g} kg/s")

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

    def effective_frequency(self, added_mass: float = 0.0) -> float:
        """Undamped eigenfrequency sqrt(K / (M + m)) / 2 pi with ``added_mass`` m [kg]
        moving with the structure [Hz] (the frequency at which the pseudo force is updated).

        >>> round(SingleDOFStructure(1.514, 0.55, 1848.0).effective_frequency(0.1), 3)
        5.385
        """
        return math.sqrt(self.stiffness / (self.mass + added_mass)) / (2.0 * math.pi)

    def with_added_mass(self, mass: float) -> SingleDOFStructure:
        """This structure with a rigid ``mass`` [kg] at its point (e.g. the container, where
        M was measured without it): ``M + m``, same D and K, so
        ``f0' = f0 sqrt(M / (M + m))``.

        >>> s = SingleDOFStructure(1.0, 0.5, 1000.0).with_added_mass(0.25)
        >>> s.mass, s.damping, s.stiffness
        (1.25, 0.5, 1000.0)
        """
        m = check_range("damper.container_mass", mass, low=0.0, unit="kg")
        return SingleDOFStructure(self.mass + m, self.damping, self.stiffness)

    def min_amplitude(self, static_mass: float = 0.0, gravity: float = STANDARD_GRAVITY) -> float:
        """X_min = g / omega^2 [m] with ``static_mass`` added (paper Sect. 4.2.1)."""
        return gravity * (self.mass + static_mass) / self.stiffness
