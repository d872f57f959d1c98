"""The scenario's sections of the damper: ``[container]``, ``[particles]`` and the inline
material table of either.

Every key of ``[container]`` and ``[particles]`` is a quantity of
:class:`~pdamper.damper.ParticleDamper`, declared there once (unit, range, doc and its
scenario key); the sections derive their keys from those declarations
(:func:`~pdamper.damper.quantity_setting`) with the paper's damper as the defaults, read
quantities with their unit at the edge, and list their keys' declarations with
``declarations()`` (:meth:`pdamper.settings.Settings.declarations`).
"""

from __future__ import annotations

from typing import Any, ClassVar

from pydantic import BaseModel, ConfigDict

from pdamper.damper import quantity_setting
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.settings import Settings, setting
from pdamper.units import parse_quantity

_D = paper.PAPER_DAMPER


class _DeclaredSection(Settings):
    """A section whose keys are declared (:func:`~pdamper.settings.setting`): each value
    checked against its declaration, a quantity read with its unit at the edge;
    :meth:`declarations` lists them."""

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True,
                              validate_default=False)
    # validated inside the scenario: its errors name the field (_first_error)
    __init__ = BaseModel.__init__

    @classmethod
    def _edge(cls, name: str, value: Any, decl: dict) -> Any:
        if decl["unit"] and decl["kind"] == "number" and value is not None:
            return parse_quantity(value, decl["unit"], name)
        return value


class MaterialSpec(_DeclaredSection):
    """A material given by its constants instead of a library name."""

    prefix: ClassVar[str] = "material."

    name: str
    youngs_modulus: float = setting(..., "Young's modulus E.", unit="Pa", low=0.0,
                                    low_inclusive=False, kind="number")
    poisson_ratio: float = setting(..., "Poisson's ratio nu.", low=-1.0, high=0.5,
                                   low_inclusive=False, high_inclusive=False, kind="number")
    density: float = setting(..., "Density rho.", unit="kg/m^3", low=0.0, low_inclusive=False,
                             kind="number")
    yield_strength: float | None = setting(
        None, "Yield strength (Thornton's COR curve).", unit="Pa", low=0.0,
        low_inclusive=False, kind="number", none="not given")


class ContainerSpec(_DeclaredSection):
    """Cuboid particle container, inner dimensions.

    Every key is a quantity of :class:`~pdamper.damper.ParticleDamper`, declared there
    (:func:`~pdamper.damper.quantity_setting`)."""

    prefix: ClassVar[str] = "container."

    length: float = quantity_setting("container.length", _D.length)
    width: float = quantity_setting("container.width", _D.width)
    depth: float = quantity_setting("container.depth", _D.depth)
    material: str | MaterialSpec = quantity_setting("container.material",
                                                    _D.wall_material.name)
    mass: float = quantity_setting("container.mass", _D.container_mass)


class ParticlesSpec(_DeclaredSection):
    """Equal spheres of one material.

    Every key is a quantity of :class:`~pdamper.damper.ParticleDamper`, declared there
    (:func:`~pdamper.damper.quantity_setting`)."""

    prefix: ClassVar[str] = "particles."

    count: int = quantity_setting("particles.count", _D.count)
    radius: float = quantity_setting("particles.radius", _D.particle_radius)
    material: str | MaterialSpec = quantity_setting("particles.material",
                                                    _D.particle_material.name)
    friction: float = quantity_setting("particles.friction", paper.PAPER_FRICTION, none="")


def material(spec: MaterialSpec | str, field: str) -> Any:
    """The :class:`~pdamper.materials.Material` of a ``material`` key: a table of its own
    constants, or a library name (:func:`~pdamper.materials.get_material`); ``field``
    names the key in errors."""
    from pdamper.materials import Material, get_material

    if isinstance(spec, MaterialSpec):
        return Material(spec.name, spec.youngs_modulus, spec.poisson_ratio, spec.density,
                        spec.yield_strength)
    return get_material(spec, field)


__all__ = ["ContainerSpec", "MaterialSpec", "ParticlesSpec", "material"]
