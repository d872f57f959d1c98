"""Quantities with units at the edges, plain SI floats inside.

Inputs such as ``"32 mm"``, ``"10 Hz"`` or ``"7900 kg/m^3"`` are parsed with pint and
converted to SI floats. A bare number is taken as already in SI units.
"""

from __future__ import annotations

import functools
import math
import re

from pdamper.errors import InputError

#: SI unit of each physical dimension used by pdamper (pint spelling).
SI = {
    "length": "m",
    "frequency": "Hz",
    "time": "s",
    "mass": "kg",
    "density": "kg/m^3",
    "pressure": "Pa",
    "stiffness": "N/m",
    "damping": "kg/s",
    "velocity": "m/s",
    "acceleration": "m/s^2",
    "force": "N",
    "energy": "J",
    "dimensionless": "",
}


@functools.cache
def _registry():
    import pint

    return pint.UnitRegistry()


def parse_quantity(value: str | float | int, unit: str, field: str) -> float:
    """Convert ``value`` to a float in ``unit`` (a pint unit string).

    Parameters
    ----------
    value
        A number (taken as already in ``unit``) or a string with units.
    unit
        Target unit, e.g. ``"m"``, ``"Hz"``.
    field
        Name of the input, used in error messages.

    Returns
    -------
    float
        Magnitude in ``unit``.

    Examples
    --------
    >>> parse_quantity("32 mm", "m", "amplitude")
    0.032
    >>> parse_quantity("10 Hz", "Hz", "frequency")
    10.0
    >>> parse_quantity(0.5, "s", "duration")
    0.5
    """
    if isinstance(value, bool):
        raise InputError(field, f"must be a quantity in {unit or 'dimensionless'}, got {value!r}")
    if isinstance(value, int | float):
        v = float(value)
        if not math.isfinite(v):
            raise InputError(field, f"must be a finite quantity, got {v}")
        return v
    if not isinstance(value, str) or not value.strip():
        raise InputError(field, f"must be a quantity such as '1 {unit}', got {value!r}")
    import pint

    ureg = _registry()
    text = value.strip()
    # pint reads "7900 kg/m^3" fine; accept the unicode "·" and "²/³" people paste too.
    text = text.replace("·", "*").replace("²", "^2").replace("³", "^3")
    try:
        q = ureg.Quantity(text)
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError) as exc:
        raise InputError(field, f"unknown unit in {value!r} ({exc}); "
                         f"expected a unit of {unit or 'dimensionless'}") from None
    except Exception:
        raise InputError(field, f"cannot read {value!r} as a quantity; expected e.g. '1 {unit}'") from None
    try:
        if isinstance(q, int | float):
            mag = float(q)
        else:
            mag = float(q.to(unit).magnitude) if unit else float(q.to("").magnitude)
    except pint.errors.DimensionalityError:
        raise InputError(field, f"{value!r} is not convertible to "
                         f"{unit or 'a dimensionless number'}") from None
    if not math.isfinite(mag):
        raise InputError(field, f"must be a finite quantity, got {value!r}")
    return mag


_RANGE = re.compile(r"^\s*(?P<a>[^:]+):(?P<b>[^:]+):(?P<n>\s*\d+\s*)$")


def parse_range(value: str, unit: str, field: str) -> tuple[float, float, int]:
    """Parse ``"start:stop:count"`` (e.g. ``"2Hz:20Hz:14"``) into SI floats and a count.

    >>> parse_range("1mm:200mm:24", "m", "amplitude")
    (0.001, 0.2, 24)
    """
    m = _RANGE.match(value)
    if not m:
        try:
            v = parse_quantity(value, unit, field)
        except InputError:
            raise InputError(field, f"expected 'start:stop:count' such as '1{unit}:2{unit}:10' "
                             f"or one quantity, got {value!r}") from None
        return v, v, 1
    a = parse_quantity(m["a"], unit, field)
    b = parse_quantity(m["b"], unit, field)
    n = int(m["n"])
    if n < 1:
        raise InputError(field, f"count must be >= 1, got {n}")
    return a, b, n


def format_quantity(value: float, unit: str, digits: int = 4) -> str:
    """Format an SI float with its unit for echoing back to the user.

    >>> format_quantity(0.032, "mm")
    '32 mm'
    """
    ureg = _registry()
    base = SI_OF.get(unit)
    mag = value if base is None else float(ureg.Quantity(value, base).to(unit).magnitude)
    return f"{mag:.{digits}g} {unit}".strip()


#: SI base of common display units, for :func:`format_quantity`.
SI_OF = {
    "mm": "m", "cm": "m", "m": "m", "um": "m",
    "Hz": "Hz", "s": "s", "ms": "s",
    "g": "kg", "kg": "kg",
    "N/m": "N/m", "kg/s": "kg/s", "J": "J", "mJ": "J", "m/s": "m/s", "GPa": "Pa",
    "kg/m^3": "kg/m^3",
}
