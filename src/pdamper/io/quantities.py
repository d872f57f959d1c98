"""Values of a scenario as pydantic types: a quantity written with its unit (``"120 mm"``)
is converted to an SI float on validation, a bare number is taken as SI, and the type
carries the quantity's range (``PositiveLength``: > 0 m); the validators of the other
values that are parsed from text (a dask scheduler's address, a tolerance ``"5%"``).
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BeforeValidator, Field

from pdamper.errors import InputError
from pdamper.units import parse_quantity


def _q(unit: str):
    def conv(v: Any) -> Any:
        try:
            return parse_quantity(v, unit, "value")
        except InputError as exc:  # pydantic adds the location
            raise ValueError(exc.message) from None

    return BeforeValidator(conv)


Length = Annotated[float, _q("m")]
PositiveLength = Annotated[float, _q("m"), Field(gt=0)]
Frequency = Annotated[float, _q("Hz"), Field(gt=0)]
Duration = Annotated[float, _q("s"), Field(gt=0)]
Mass = Annotated[float, _q("kg"), Field(ge=0)]
PositiveMass = Annotated[float, _q("kg"), Field(gt=0)]
Stiffness = Annotated[float, _q("N/m"), Field(gt=0)]
Damping = Annotated[float, _q("kg/s"), Field(ge=0)]
Density = Annotated[float, _q("kg/m^3"), Field(gt=0)]
Modulus = Annotated[float, _q("Pa"), Field(gt=0)]
Restitution = Annotated[float, Field(gt=0, le=1)]
Gravity = Annotated[float, _q("m/s^2"), Field(ge=0, allow_inf_nan=False)]
Count = Annotated[int, Field(strict=True)]


def _scheduler(v: str) -> str:
    """The address of a dask scheduler (:func:`pdamper.sweep.cluster.check_scheduler`)."""
    from pdamper.sweep.cluster import check_scheduler

    try:
        return check_scheduler(v)
    except InputError as exc:  # pydantic adds the location
        raise ValueError(exc.message) from None


def _tolerance(v: Any) -> float:
    from pdamper.design.study import parse_tolerance

    try:
        return parse_tolerance(v)
    except InputError as exc:  # pydantic adds the location
        raise ValueError(exc.message) from None


__all__ = ["Count", "Damping", "Density", "Duration", "Frequency", "Gravity", "Length", "Mass",
           "Modulus", "PositiveLength", "PositiveMass", "Restitution", "Stiffness"]
