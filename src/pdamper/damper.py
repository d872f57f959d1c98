"""The physical particle damper: a box container partly filled with equal spheres.

This is the design object of all three levels: Level II characterises it under harmonic
excitation, Level III mounts it on a structure and optimises its filling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from pdamper.errors import InputError, check_range
from pdamper.materials import PVC, S235, Material

_TOL = 1e-9  # so that 40 mm / 10 mm counts exactly 4 diameters


def lattice_fit(length: float, radius: float, gap: float = 0.0) -> int:
    """How many spheres of ``radius`` [m] fit side by side, ``gap`` [m] apart, in ``length`` [m].

    >>> lattice_fit(0.04, 0.005), lattice_fit(0.12, 0.005)
    (4, 12)
    """
    pitch = 2.0 * radius + gap
    return max(0, math.floor((length + gap) / pitch * (1.0 + _TOL)))


def spheres_per_layer(width: float, depth: float, radius: float) -> int:
    """Spheres of radius ``radius`` in one square-lattice layer of a ``width x depth`` box."""
    return lattice_fit(width, radius) * lattice_fit(depth, radius)


@dataclass(frozen=True)
class ParticleDamper:
    """A rectangular container with ``count`` equal spheres.

    Parameters
    ----------
    length
        Inner height L of the container along the excitation (vertical) [m].
    width, depth
        Inner horizontal dimensions [m].
    particle_radius
        Sphere radius [m].
    count
        Number of spheres n_p [-], 0 <= n_p <= n_max.
    particle_material, wall_material
        :class:`~pdamper.materials.Material` of spheres and walls.
    container_mass
        m_con [kg], the container alone (used by Eq. 4 of the complex power method).
    friction
        Sliding friction coefficient mu [-] of every contact.

    Examples
    --------
    The paper's benchmark damper with 32 spheres:

    >>> d = ParticleDamper(count=32)
    >>> d.max_count, round(d.clearance, 4), round(d.bed_mass * 1000, 1)
    (192, 0.1, 132.4)
    """

    length: float = 0.120
    width: float = 0.040
    depth: float = 0.040
    particle_radius: float = 0.005
    count: int = 32
    particle_material: Material = S235
    wall_material: Material = PVC
    container_mass: float = 0.0
    friction: float = 0.1

    def __post_init__(self) -> None:
        for name in ("length", "width", "depth", "particle_radius"):
            check_range(f"container.{name}" if name != "particle_radius" else "particles.radius",
                        getattr(self, name), low=0.0, low_inclusive=False, unit="m")
        check_range("container.mass", self.container_mass, low=0.0, unit="kg")
        check_range("particles.friction", self.friction, low=0.0)
        d = 2.0 * self.particle_radius
        if min(self.width, self.depth, self.length) < d * (1 - _TOL):
            raise InputError("particles.radius",
                             f"sphere diameter {d * 1000:g} mm must fit the container "
                             f"({self.width * 1000:g} x {self.depth * 1000:g} x "
                             f"{self.length * 1000:g} mm)")
        if isinstance(self.count, bool) or int(self.count) != self.count:
            raise InputError("particles.count", f"must be a whole number, got {self.count!r}")
        if not 0 <= self.count <= self.max_count:
            raise InputError("particles.count",
                             f"must be in [0, {self.max_count}] (n_max of this container), "
                             f"got {self.count}")

    @property
    def per_layer(self) -> int:
        """Spheres per lattice layer (16 in the benchmark container)."""
        return spheres_per_layer(self.width, self.depth, self.particle_radius)

    @property
    def max_count(self) -> int:
        """n_max: spheres in full lattice layers up to the lid (192 in the benchmark)."""
        return self.per_layer * lattice_fit(self.length, self.particle_radius)

    @property
    def particle_mass(self) -> float:
        """Mass of one sphere [kg]."""
        return 4.0 / 3.0 * math.pi * self.particle_radius**3 * self.particle_material.density

    @property
    def bed_mass(self) -> float:
        """m_bed, mass of all spheres [kg]."""
        return self.count * self.particle_mass

    @property
    def clearance(self) -> float:
        """h = L (1 - n_p / n_max) [m] (paper Sect. 3.1.1)."""
        return self.length * (1.0 - self.count / self.max_count)

    @property
    def optimal_stroke(self) -> float:
        """X_opt = h / pi [m] (Eq. 19)."""
        return self.clearance / math.pi

    def with_count(self, count: int) -> ParticleDamper:
        """The same damper with another particle count."""
        return replace(self, count=count)
