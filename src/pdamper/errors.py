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

    def __reduce__(self):
        # pickled across processes (dask workers): rebuilt from its two arguments
        return (type(self), (self.field, self.message))


class SimulationError(PdamperError, RuntimeError):
    """A simulation could not be carried out (e.g. it became numerically unstable)."""


class OutputError(PdamperError):
    """A result could not be written (a full device, a closed pipe, a vanished directory).

    Problems a user can see before a run starts (a missing directory, a directory where a
    file should go) are :class:`InputError`; this is what happens while writing.

    Parameters
    ----------
    field
        The output: ``"out"``, ``"vtk"``, ``"stdout"``.
    message
        What went wrong, e.g. ``"cannot write map.nc: No space left on device"``.
    """

    def __init__(self, field: str, message: str):
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}")

    def __reduce__(self):
        # pickled across processes (dask workers): rebuilt from its two arguments
        return (type(self), (self.field, self.message))


class Interrupted(BaseException):  # noqa: N818 - a signal, like KeyboardInterrupt
    """A signal (SIGINT, SIGTERM, SIGHUP) asked pdamper to stop.

    Raised by the command line's signal handlers so that every ``finally`` and every
    cleanup of the atomic writer runs; like :class:`KeyboardInterrupt` it is no
    :class:`Exception`, so that no ``except Exception`` swallows it.

    Parameters
    ----------
    signum
        The signal number; the command line exits with ``128 + signum``.
    """

    def __init__(self, signum: int):
        self.signum = int(signum)
        super().__init__(f"interrupted by signal {self.signum}")

    def __reduce__(self):
        return (type(self), (self.signum,))


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

    # text is for the edges (pdamper.units): "0.005" is no number here, nor is True
    if isinstance(value, str | bytes | bool) or value is None:
        raise InputError(field, f"must be a number{f' in {unit}' if unit else ''}, got "
                         f"{value!r} ({type(value).__name__})")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a number, got {value!r} ({type(value).__name__})") \
            from None
    except OverflowError:
        v = math.inf
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


def check_whole(field: str, value, low: int | None = None) -> int:
    """Return ``value`` as int if it is a whole number (>= ``low``), else raise InputError.

    Integral floats and numpy integers are whole; ``1.5``, ``True`` and ``"2"`` are not.

    >>> check_whole("dem.skip_cycles", 2.0, low=0)
    2
    """
    import numbers

    ok = isinstance(value, numbers.Real) and not isinstance(value, bool)
    if ok:
        try:
            ok = float(value) == int(value)
        except (OverflowError, ValueError):
            ok = False
    at_least = "" if low is None else f" >= {low}"
    if not ok:
        raise InputError(field, f"must be a whole number{at_least}, got {value!r}")
    n = int(value)
    if low is not None and n < low:
        raise InputError(field, f"must be a whole number{at_least}, got {n}")
    return n
