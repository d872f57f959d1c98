"""Level I: materials of particles and container walls.

The two materials of the reference paper (Fig. 2-left) are available as
:data:`S235` (steel spheres) and :data:`PVC` (container walls).
"""

from __future__ import annotations

from dataclasses import dataclass

from pdamper.errors import InputError, check_range


@dataclass(frozen=True)
class Material:
    """An isotropic elastic material.

    Parameters
    ----------
    name
        Identifier used in scenario files (``"S235"``, ``"PVC"``).
    youngs_modulus
        E [Pa].
    poisson_ratio
        nu [-], in (-1, 0.5).
    density
        rho [kg/m^3].
    """

    name: str
    youngs_modulus: float
    poisson_ratio: float
    density: float

    def __post_init__(self) -> None:
        check_range(f"material {self.name}.youngs_modulus", self.youngs_modulus, low=0.0,
                    low_inclusive=False, unit="Pa")
        check_range(f"material {self.name}.poisson_ratio", self.poisson_ratio, low=-1.0,
                    high=0.5, low_inclusive=False, high_inclusive=False)
        check_range(f"material {self.name}.density", self.density, low=0.0,
                    low_inclusive=False, unit="kg/m^3")

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))


#: Structural steel of the spheres (paper Fig. 2-left).
S235 = Material("S235", youngs_modulus=208e9, poisson_ratio=0.3, density=7900.0)
#: Polyvinyl chloride of the container walls (paper Fig. 2-left).
PVC = Material("PVC", youngs_modulus=3e9, poisson_ratio=0.38, density=1400.0)

MATERIALS: dict[str, Material] = {m.name: m for m in (S235, PVC)}


def get_material(name: str, field: str = "material") -> Material:
    """Look up a built-in material by name (case-insensitive)."""
    for key, mat in MATERIALS.items():
        if key.lower() == str(name).lower():
            return mat
    raise InputError(field, f"unknown material {name!r}; known: {', '.join(MATERIALS)}")


__all__ = ["Material", "S235", "PVC", "MATERIALS", "get_material"]
