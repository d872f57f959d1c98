"""Read a measured end-effector trajectory from CSV (paper Sect. 4: laser vibrometer).

Format: a header row naming each column with its unit in brackets, then one row per
sample; ``#`` starts a comment line; the separator is ``,``, ``;`` or a tab. ::

    # free decay, 32 spheres
    time [ms], displacement [mm]
    0.0, -58.01
    0.5, -57.98

The time column is the one whose unit is a time (or named ``t``/``time``); the signal is the
first column whose unit is a length (displacement), a velocity or an acceleration, a
displacement preferred. Velocities and accelerations are integrated to a displacement
(:class:`pdamper.coupling.measurement.MeasuredTrajectory`; drift removed on alignment).
Units are anything pint reads (``ms``, ``s``, ``mm``, ``um``, ``m/s``, ``mm/s``, ``g0`` ...).

Problems (no header, a column without a unit, an unknown unit, a value that is not a finite
number, a time that does not increase) are one-line :class:`~pdamper.errors.InputError`
naming the file, the row (line number in the file) and the column.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdamper.coupling.measurement import MeasuredTrajectory
from pdamper.errors import InputError

#: SI unit of each recognised column quantity.
_DIMENSIONS = (("time", "s"), ("displacement", "m"), ("velocity", "m/s"),
               ("acceleration", "m/s^2"))
_HEADER = re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*\[(?P<unit>[^\[\]]+)\]\s*$")
#: Fewest samples of a usable record.
MIN_ROWS = 10
FIELD = "measured"


def _err(path: Path, row: int, column: str | None, msg: str,
         field: str = FIELD) -> InputError:
    where = f"{path}, row {row}" + (f", column {column!r}" if column else "")
    return InputError(field, f"{where}: {msg}")


def _unit_of(path: Path, row: int, header: str, unit: str,
             dimensions: tuple[tuple[str, str], ...] = _DIMENSIONS,
             field: str = FIELD,
             kinds: str = "time, length, velocity or acceleration") -> tuple[str, float]:
    """(quantity, factor to SI) of a column unit: the first of ``dimensions``
    (``(quantity, SI unit)`` pairs) that ``unit`` converts to."""
    from pdamper.units import parse_quantity

    for quantity, si in dimensions:
        try:
            return quantity, parse_quantity(f"1 {unit}", si, "unit")
        except InputError as exc:
            if "unknown unit" in exc.message:
                raise _err(path, row, header, f"unknown unit {unit!r}", field) from None
            continue
    raise _err(path, row, header, f"unit {unit!r} is not a {kinds}", field)


@dataclass(frozen=True)
class UnitTable:
    """A CSV file with a unit header, read but not yet converted (:func:`read_unit_table`).

    Attributes
    ----------
    path
        The file.
    header_row
        Line number of the header in the file.
    names
        The column headers as written (``"time [ms]"``).
    units
        ``(quantity, factor to SI)`` of each column.
    rows
        ``(line number, cells)`` of each data row (:meth:`values` checks their count).
    field
        Name of the input in error messages.
    """

    path: Path
    header_row: int
    names: list[str]
    units: list[tuple[str, float]]
    rows: list[tuple[int, list[str]]]
    field: str

    def error(self, row: int, column: int | None, msg: str) -> InputError:
        """One-line error naming the file, ``row`` (line number) and ``column`` (index)."""
        return _err(self.path, row, None if column is None else self.names[column], msg,
                    self.field)

    def values(self, columns: list[int]) -> np.ndarray:
        """``columns`` (indices) of every data row, shape (rows, columns), in SI units; a
        cell that is not a finite number is an error naming its row and column (the first
        such cell, row by row)."""
        out = np.empty((len(self.rows), len(columns)))
        for r, (row, cells) in enumerate(self.rows):
            if len(cells) != len(self.names):
                raise self.error(row, None, f"{len(cells)} values, the header has "
                                 f"{len(self.names)} columns")
            for c, col in enumerate(columns):
                text = cells[col].strip()
                try:
                    v = float(text)
                except ValueError:
                    raise self.error(row, col, f"not a number: {text!r}") from None
                if not math.isfinite(v):
                    raise self.error(row, col, f"{text} is not a finite number")
                out[r, c] = v * self.units[col][1]
        return out


def read_unit_table(path: str | Path, field: str = FIELD,
                    dimensions: tuple[tuple[str, str], ...] = _DIMENSIONS,
                    example: str = "'time [ms], displacement [mm]'",
                    kinds: str = "time, length, velocity or acceleration") -> UnitTable:
    """The CSV file ``path`` with a unit header (module docstring): its header checked
    (every column ``name [unit]``, each unit one of ``dimensions``), its rows split into
    cells (:meth:`UnitTable.values` converts them); errors are
    :class:`~pdamper.errors.InputError` of ``field``."""
    p = Path(path)
    if not p.is_file():
        raise InputError(field, f"file not found: {p}")
    try:
        lines = p.read_text(encoding="utf-8-sig").splitlines()
    except UnicodeDecodeError:
        raise InputError(field, f"{p} is not UTF-8 text") from None
    rows = [(k + 1, ln) for k, ln in enumerate(lines)
            if ln.strip() and not ln.lstrip().startswith("#")]
    if not rows:
        raise InputError(field, f"{p}: no data (empty file)")
    row0, head = rows[0]
    sep = ";" if ";" in head else ("\t" if "\t" in head else ",")
    names = [c.strip() for c in head.split(sep)]
    units = []
    for name in names:
        mt = _HEADER.match(name)
        if mt is None:
            if _is_number(name):
                raise _err(p, row0, None, "no header: the first row must name the columns "
                           f"with units, e.g. {example}", field)
            raise _err(p, row0, name, "no unit: write the column as 'name [unit]', e.g. "
                       f"{example.split(',')[0]}'", field)
        units.append(_unit_of(p, row0, name, mt["unit"].strip(), dimensions, field,
                              kinds))
    return UnitTable(p, row0, names, units, [(row, line.split(sep)) for row, line in rows[1:]],
                     field)


def read_measured(path: str | Path) -> MeasuredTrajectory:
    """The measured trajectory in ``path`` (module docstring), in SI units.

    Examples
    --------
    >>> import tempfile, pathlib, numpy as np
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "m.csv"
    >>> t = np.arange(20) * 0.5
    >>> _ = p.write_text("time [ms], displacement [mm]\\n" + "".join(
    ...     f"{a}, {-58 + a:.1f}\\n" for a in t))
    >>> m = read_measured(p)
    >>> m.quantity, float(m.time[1]), round(float(m.displacement[0]), 4)
    ('displacement', 0.0005, -0.058)
    """
    table = read_unit_table(path)
    p, row0, names, rows = table.path, table.header_row, table.names, table.rows
    kinds = [q for q, _ in table.units]
    time_col = next((k for k, q in enumerate(kinds) if q == "time"), None)
    if time_col is None:
        raise _err(p, row0, None, "no time column (a column with a unit of time, e.g. "
                   "'time [s]')")
    signal_col = next((k for q in ("displacement", "velocity", "acceleration")
                       for k, kk in enumerate(kinds) if kk == q), None)
    if signal_col is None:
        raise _err(p, row0, None, "no displacement, velocity or acceleration column")
    data = table.values([time_col, signal_col])
    if data.shape[0] < MIN_ROWS:
        raise _err(p, (rows[-1][0] if rows else row0), None, f"needs at least {MIN_ROWS} "
                   f"samples, got {data.shape[0]}")
    units = table.units
    bad = np.flatnonzero(np.diff(data[:, 0]) <= 0)
    if bad.size:
        k = int(bad[0]) + 1
        raise _err(p, rows[k][0], names[time_col], "time must increase from row to row "
                   f"({data[k, 0] / units[time_col][1]:g} after "
                   f"{data[k - 1, 0] / units[time_col][1]:g})")
    return MeasuredTrajectory.from_signal(data[:, 0], data[:, 1], kinds[signal_col],
                                          source=str(p), columns=(names[time_col],
                                                                  names[signal_col]))


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
