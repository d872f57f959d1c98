"""Grid axes of a scenario: ``"start:stop:count"`` (linear), ``"log:start:stop:count"``
(geometric) or one quantity, with units (``[map]``, ``[optimization] band``, the command
line's ``--frequency``), and particle-count axes; read and checked without building the
grid, so that a grid's size is judged before it exists.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pydantic import AfterValidator

from pdamper.errors import InputError
from pdamper.units import parse_range

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np


def _range_text(spec: tuple[float, float, int], unit: str, scale: float) -> str:
    a, b, n = spec
    return f"{a * scale:g}{unit}:{b * scale:g}{unit}:{n}"


def _grid(unit: str):
    def check(v: str) -> str:
        try:
            parse_axis(v, unit, "value")
        except InputError as exc:  # pydantic adds the location
            raise ValueError(exc.message) from None
        return v

    return AfterValidator(check)


def grid(text: str, unit: str, field: str) -> np.ndarray:
    """A grid from ``"start:stop:count"`` (linear), ``"log:start:stop:count"`` (geometric)
    or one quantity; values must be > 0.

    >>> grid("log:1mm:100mm:3", "m", "map.amplitude").round(4).tolist()
    [0.001, 0.01, 0.1]
    """
    import numpy as np

    a, b, n, log = parse_axis(text, unit, field)
    return np.geomspace(a, b, n) if log else np.linspace(a, b, n)


def parse_axis(text: str, unit: str, field: str) -> tuple[float, float, int, bool]:
    """``(start, stop, count, log)`` of a grid axis (see :func:`grid`), checked, without
    building it; values must be > 0."""
    log = isinstance(text, str) and text.strip().lower().startswith("log:")
    body = text.strip()[4:] if log else text
    a, b, n = parse_range(body, unit, field)
    if min(a, b) <= 0:
        raise InputError(field, f"grid values must be > 0, got {min(a, b):g}")
    return a, b, n, log


def count_grid(value: Any, field: str) -> np.ndarray:
    """Whole particle counts from ``N``, ``"start:stop:count"`` or ``"log:..."`` (rounded;
    counts must be >= 1 and distinct).

    >>> count_grid("16:96:6", "map.particles").tolist()
    [16, 32, 48, 64, 80, 96]
    """
    import numpy as np

    if isinstance(value, int) and not isinstance(value, bool):
        counts = np.array([value])
    else:
        text = str(value).strip()
        log = text.lower().startswith("log:")
        body = text[4:] if log else text
        parts = body.split(":")
        try:
            nums = [float(p) for p in parts]
        except ValueError:
            raise InputError(field, f"expected N, 'start:stop:count' or 'log:start:stop:count' "
                             f"of particle counts, got {value!r}") from None
        if len(parts) == 1:
            raw = np.array(nums)
        elif len(parts) == 3 and nums[2] == int(nums[2]) and 1 <= nums[2] <= 100_000:
            if min(nums[:2]) <= 0 and log:
                raise InputError(field, f"log spacing needs counts > 0, got {value!r}")
            raw = (np.geomspace if log else np.linspace)(nums[0], nums[1], int(nums[2]))
        else:
            raise InputError(field, f"expected N, 'start:stop:count' or 'log:start:stop:count' "
                             f"of particle counts, got {value!r}")
        counts = np.rint(raw)
        if not log and np.any(np.abs(raw - counts) > 1e-9):
            raise InputError(field, f"{value!r} gives counts that are not whole: "
                             f"{', '.join(f'{v:g}' for v in raw)}")
    counts = counts.astype(int)
    if np.any(counts < 1):
        raise InputError(field, f"particle counts must be >= 1, got {counts.min()}")
    if len(set(counts.tolist())) != counts.size:
        raise InputError(field, f"{value!r} gives repeated counts {counts.tolist()}")
    return counts
