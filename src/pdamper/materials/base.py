"""The material type of Level I (its library is :mod:`pdamper.materials.library`)."""

from __future__ import annotations

from dataclasses import dataclass

from pdamper.errors import check_range


@dataclass(frozen=True)
class Material:
    """An isotropic elastic (-plastic) material.

    Parameters
    ----------
    name
        Identifier used in scenario files (``"S235"``, ``"PVC"``); the DEM tells materials
        apart by it.
    youngs_modulus
        E [Pa].
    poisson_ratio
        nu [-], in (-1, 0.5).
    density
        rho [kg/m^3].
    yield_strength
        Uniaxial (tensile, 0.2 % proof) yield strength Y [Pa]; None where not known or not
        meaningful (brittle ceramics and glass, rubber). Only Thornton's COR model needs it.
    """

    name: str
    youngs_modulus: float
    poisson_ratio: float
    density: float
    yield_strength: float | None = None

    def __post_init__(self) -> None:
        check_range(f"material {self.name}.youngs_modulus", self.youngs_modulus, low=0.0,
                    low_inclusive=False, unit="Pa")
        check_range(f"material {self.name}.poisson_ratio", self.poisson_ratio, low=-1.0,
                    high=0.5, low_inclusive=False, high_inclusive=False)
        check_range(f"material {self.name}.density", self.density, low=0.0,
                    low_inclusive=False, unit="kg/m^3")
        if self.yield_strength is not None:
            check_range(f"material {self.name}.yield_strength", self.yield_strength, low=0.0,
                        low_inclusive=False, unit="Pa")

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
