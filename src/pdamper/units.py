"""Quantities with units at the edges, plain SI floats inside.

Inputs such as ``"32 mm"``, ``"10 Hz"`` or ``"7900 kg/m^3"`` are parsed with pint and
converted to SI floats. A quantity as text is a number and a unit, nothing more (no
arithmetic, nothing after the unit); a bare number (a TOML or Python float) is taken as
already in SI units. Ranges ``"start:stop:count"`` describe grids.
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


def _import_pint():
    """pint, imported without dask.

    pint looks for dask at import and imports it when installed (0.1 s of CPU, a quarter of
    a ``pdamper analytic``) for its methods on dask-array magnitudes (``Quantity.compute``,
    ``persist``, ``visualize``); pdamper's quantities are numbers at the edges, never dask
    arrays, and a command that runs no sweep should not pay for dask. While pint is first
    imported, dask is therefore marked absent, unless something imported it already (a
    sweep, a user's script): in a process where pdamper imports pint first, pint has no
    dask methods."""
    import sys

    if "pint" in sys.modules or "dask" in sys.modules:
        import pint

        return pint
    sys.modules["dask"] = None  # type: ignore[assignment]  # find_spec: "not installed"
    try:
        import pint
    finally:
        if sys.modules.get("dask", 0) is None:
            del sys.modules["dask"]
    return pint


def _cache_folder():
    """A private per-user directory for pint's parsed unit definitions, or None.

    ``$XDG_CACHE_HOME/pdamper/pint``, ``~/.cache/pdamper/pint`` or a private directory in the
    system's temporary directory: the first that is ours, not a symlink, and writable
    (:func:`pdamper._numba_cache.candidates`, the same rules as numba's cache)."""
    from pdamper._numba_cache import _private, candidates

    for directory in candidates(kind="pint"):
        if _private(directory):
            return directory
    return None


@functools.cache
def _registry():
    """pint's unit registry, built once per process.

    Parsing pint's definitions file takes 0.2-0.6 s; pint caches the parsed definitions on
    disk (``cache_folder``, named by a hash of the file, pint's and Python's versions), so
    that later processes load them in a few milliseconds. A cache that cannot be read (a
    file another process is still writing, a full disk) is dropped and written afresh, or
    the definitions are parsed without a cache: the registry is the same either way.
    """
    pint = _import_pint()
    folder = _cache_folder()
    for _ in range(2 if folder is not None else 0):  # a damaged cache is written afresh
        try:
            return pint.UnitRegistry(cache_folder=folder)
        except Exception:  # noqa: BLE001 - a damaged cache must not stop a run
            for stale in folder.glob("*.pickle"):
                try:
                    stale.unlink()
                except OSError:
                    pass
    return pint.UnitRegistry()


#: A quantity as text: a decimal number, then (after optional blanks) a unit expression.
_NUMBER = re.compile(r"^\s*(?P<num>[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?)\s*(?P<unit>.*?)\s*$",
                     re.DOTALL)
#: What a unit expression may contain: names, digits (powers, ``1/min``), ``* / ^ ( )``.
_UNIT_CHARS = re.compile(r"^[A-Za-z\u00b5\u03bc\u03a9\u2126_0-9 .*/^()%\-]*$")
#: Characters people paste, in the spelling pint reads: minus sign, dot operators and
#: superscript powers (``cm⁻³`` -> ``cm^-3``).
_PASTED = str.maketrans({"\u2212": "-", "\u00b7": "*", "\u22c5": "*"})
_SUPERSCRIPT = re.compile("\u207b?[\u2070\u00b9\u00b2\u00b3\u2074-\u2079]+")
_SUPERSCRIPT_DIGITS = str.maketrans("\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079",
                                    "-0123456789")


def _pasted(text: str) -> str:
    text = text.translate(_PASTED)
    return _SUPERSCRIPT.sub(lambda m: "^" + m[0].translate(_SUPERSCRIPT_DIGITS), text)


def _example(unit: str) -> str:
    return f"'1 {unit}'" if unit else "'0.5'"


def parse_quantity(value: str | float | int, unit: str, field: str) -> float:
    """Convert ``value`` to a float in ``unit`` (a pint unit string).

    A string must be a decimal number followed by a unit expression of the dimension of
    ``unit`` (``"32 mm"``, ``"7.9 g/cm^3"``, ``"600 1/min"``) and nothing else: a unit
    without a number (``"Hz"``), arithmetic (``"10 Hz * 2"``), anything after the unit
    (``"10 Hz!"``) and angle units in a frequency (``"62.8 rad/s"``, ``"10 turn/s"``: pint
    would read them as 2 pi times too large) are errors. ``rpm`` (revolutions per minute)
    is a frequency: ``"600 rpm"`` is 10 Hz, one revolution being one cycle. A bare number (``float``/``int``)
    is taken as already in ``unit``; a bare number as text only for a dimensionless
    ``unit``.

    Parameters
    ----------
    value
        A number (taken as already in ``unit``) or a string with units.
    unit
        Target unit, e.g. ``"m"``, ``"Hz"`` (``""``: dimensionless).
    field
        Name of the input, used in error messages.

    Returns
    -------
    float
        Magnitude in ``unit``, finite.

    Examples
    --------
    >>> parse_quantity("32 mm", "m", "amplitude")
    0.032
    >>> parse_quantity("10 Hz", "Hz", "frequency")
    10.0
    >>> parse_quantity(0.5, "s", "duration")
    0.5
    >>> parse_quantity("1440 rpm", "Hz", "speed")
    24.0
    """
    if isinstance(value, bool):
        raise InputError(field, f"must be a quantity such as {_example(unit)}, got {value!r}")
    if isinstance(value, int | float):
        try:
            v = float(value)
        except OverflowError:
            v = math.inf
        if not math.isfinite(v):
            raise InputError(field, f"must be a finite quantity, got {value!r}")
        return v
    if not isinstance(value, str) or not value.strip():
        raise InputError(field, f"must be a quantity such as {_example(unit)}, got {value!r}")
    text = _pasted(value)
    m = _NUMBER.match(text)
    if m is None:
        raise InputError(field, f"must start with a number, as in {_example(unit)}; "
                         f"got {value!r}")
    number, unit_text = float(m["num"]), m["unit"]
    if not math.isfinite(number):
        raise InputError(field, f"must be a finite quantity, got {value!r}")
    if not unit_text:
        if unit:
            raise InputError(field, f"{value!r} has no unit; write e.g. "
                             f"'{m['num']} {unit}'")
        return number
    if not _UNIT_CHARS.match(unit_text):
        raise InputError(field, f"unexpected characters in the unit of {value!r}; expected "
                         f"a number and a unit, as in {_example(unit)}")
    magnitude = number * _unit_factor(unit_text, unit, field, value)
    if not math.isfinite(magnitude):  # "1.7e305 km" overflows in m
        raise InputError(field, f"must be a finite quantity, got {value!r}")
    return magnitude


#: ``rpm`` as a word of a unit expression: revolutions per minute.
_RPM = re.compile(r"(?<![A-Za-z_])rpm(?![A-Za-z_0-9])")


def _unit_factor(unit_text: str, unit: str, field: str, value: str) -> float:
    """Magnitude of one ``unit_text`` in ``unit``."""
    ureg = _registry()
    import pint

    if unit == "Hz":
        # a revolution per minute is a cycle per minute: 1/60 Hz (pint's rpm is 2 pi rad/min,
        # an angle rate that reads 2 pi times too large as a frequency)
        unit_text = _RPM.sub("(1/min)", unit_text)

    try:
        parsed = ureg.parse_units(unit_text)
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError) as exc:
        raise InputError(field, f"unknown unit in {value!r} ({exc}); "
                         f"expected a unit of {unit or 'dimensionless'}") from None
    except Exception:
        raise InputError(field, f"cannot read the unit of {value!r}; expected a number and a "
                         f"unit, as in {_example(unit)}") from None
    if unit:
        # angles are dimensionless to pint: "600 rpm" would become 62.8 Hz, not 10 Hz
        root = ureg.get_root_units(parsed)[1]
        named = sorted({name for u in (parsed, root) for name in getattr(u, "_units", {})
                        if ureg.Unit(name).dimensionless})
        if named:
            raise InputError(field, f"{value!r}: {', '.join(named)} is dimensionless and has no "
                             f"place in a quantity of {unit} (an angle would be read 2 pi "
                             f"times too large); write e.g. {_example(unit)}")
    try:
        factor = float(ureg.Quantity(1.0, parsed).to(unit or "").magnitude)
    except pint.errors.DimensionalityError:
        raise InputError(field, f"{value!r} is not convertible to "
                         f"{unit or 'a dimensionless number'}") from None
    return factor


def parse_range(value: str, unit: str, field: str) -> tuple[float, float, int]:
    """Parse ``"start:stop:count"`` (e.g. ``"2Hz:20Hz:14"``) into SI floats and a count.

    A range is well-formed when it has exactly three parts, both ends are quantities,
    ``start < stop`` and the count is a whole number >= 2; one quantity alone is a range of
    one point. Nothing is allocated: the count may be checked against the resource limits
    (:mod:`pdamper.resources`) before a grid is built.

    >>> parse_range("1mm:200mm:24", "m", "amplitude")
    (0.001, 0.2, 24)
    >>> parse_range("5 Hz", "Hz", "frequency")
    (5.0, 5.0, 1)
    """
    if not isinstance(value, str):
        raise InputError(field, f"must be text 'start:stop:count' such as "
                         f"'1{unit}:2{unit}:10', or one quantity; got {value!r}")
    form = f"'start:stop:count' such as '1{unit}:2{unit}:10'"
    parts = value.split(":")
    if len(parts) == 1:
        v = parse_quantity(value, unit, field)
        return v, v, 1
    if len(parts) != 3:
        raise InputError(field, f"expected {form} or one quantity, got {value!r} "
                         f"({len(parts)} parts)")
    for name, part in zip(("start", "stop", "count"), parts, strict=True):
        if not part.strip():
            raise InputError(field, f"the {name} of {value!r} is empty; expected {form}")
    a = parse_quantity(parts[0], unit, field)
    b = parse_quantity(parts[1], unit, field)
    count = parts[2].strip()
    if not count.isdigit() or not count.isascii():
        raise InputError(field, f"the count of {value!r} must be a whole number, got {count!r}")
    n = int(count)
    if n < 2:
        raise InputError(field, f"the count of {value!r} must be >= 2 (one point: give one "
                         f"quantity), got {n}")
    if not a < b:
        raise InputError(field, f"start must be below stop in {value!r}")
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


#: The unit people read for an SI unit of a result, and the factor from SI: lengths in mm,
#: masses in g, energies in mJ (tables and text; JSON keeps SI).
DISPLAY_OF = {"m": ("mm", 1e3), "kg": ("g", 1e3), "J": ("mJ", 1e3)}


def display(value: float, unit: str) -> tuple[float, str]:
    """``value`` [``unit``, SI] in the unit people read (:data:`DISPLAY_OF`; others as
    given).

    >>> display(0.0042, "m")
    (4.2, 'mm')
    """
    shown, factor = DISPLAY_OF.get(unit, (unit, 1.0))
    return value * factor, shown


#: SI base of common display units, for :func:`format_quantity`.
SI_OF = {
    "mm": "m", "cm": "m", "m": "m", "um": "m",
    "Hz": "Hz", "s": "s", "ms": "s",
    "g": "kg", "kg": "kg",
    "N/m": "N/m", "kg/s": "kg/s", "J": "J", "mJ": "J", "m/s": "m/s", "GPa": "Pa",
    "kg/m^3": "kg/m^3",
}
