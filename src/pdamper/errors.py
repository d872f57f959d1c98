"""Exception types of pdamper.

Every error a user can cause by input is an :class:`InputError` that names the offending
field and the allowed range, so that the CLI can print it as one line and exit non-zero.
"""

from __future__ import annotations


class PdamperError(Exception):
    """Base class of all errors raised by pdamper."""


class InputError(PdamperError, ValueError):
    """Invalid or inconsistent user input.

    Parameters
    ----------
    field
        Dotted name of the offending input, e.g. ``"particles.count"``.
    message
        What is wrong and what is allowed, e.g. ``"must be in [0, 192], got 200"``.
    """

    def __init__(self, field: str, message: str):
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}")


class SimulationError(PdamperError, RuntimeError):
    """A simulation could not be carried out (e.g. it became numerically unstable)."""


def check_range(
    field: str,
    value: float,
    *,
    low: float | None = None,
    high: float | None = None,
    low_inclusive: bool = True,
    high_inclusive: bool = True,
    unit: str = "",
) -> float:
    """Return ``value`` as float if it is finite and inside the range, else raise InputError.

    >>> check_range("particles.radius", 0.005, low=0.0, low_inclusive=False, unit="m")
    0.005
    """
    import math

    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a number, got {value!r}") from None
    lo = "[" if low_inclusive else "("
    hi = "]" if high_inclusive else ")"
    allowed = f"{lo}{'-inf' if low is None else f'{low:g}'}, {'inf' if high is None else f'{high:g}'}{hi}"
    u = f" {unit}" if unit else ""
    if not math.isfinite(v):
        raise InputError(field, f"must be a finite number in {allowed}{u}, got {v}")
    bad_low = low is not None and (v < low or (v == low and not low_inclusive))
    bad_high = high is not None and (v > high or (v == high and not high_inclusive))
    if bad_low or bad_high:
        raise InputError(field, f"must be in {allowed}{u}, got {v:g}{u}")
    return v
