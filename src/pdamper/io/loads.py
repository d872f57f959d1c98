"""Read a load history from CSV: a force on the structure or an acceleration of its base
(a shock, a random record, a measured operating load).

Same format as the measured records (:mod:`pdamper.io.measured`): a header row naming each
column with its unit in brackets, then one row per sample; ``#`` starts a comment line; the
separator is ``,``, ``;`` or a tab. Exactly two columns: the time (a unit of time) and the
load: a force (``N``, ``kN``, ``lbf`` ...) for ``--load``, an acceleration (``m/s^2``,
``g0`` ...) for ``--base-acceleration``. ::

    # half-sine shock, 20 ms
    time [ms], force [N]
    0, 0
    1, 1.56
    ...

Times must increase from row to row; the run starts at the first time. Between samples the
load is linear; after the last it is zero (:mod:`pdamper.coupling.loads`).

Problems (no header, a column without a unit, an unknown unit, a column that is neither
the time nor the expected load, a missing or extra column, a value that is not a finite
number, a time that does not increase, fewer than two samples) are one-line
:class:`~pdamper.errors.InputError` naming the file, the row (line number in the file) and
the column; the field is ``load`` or ``base_acceleration``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pdamper.io.measured import _err, read_unit_table

#: Per load kind: the error field, the column quantity and its SI unit, an example header.
_KINDS = {
    "force": ("load", ("force", "N"), "'time [s], force [N]'", "time or force"),
    "base_acceleration": ("base_acceleration", ("acceleration", "m/s^2"),
                          "'time [s], acceleration [m/s^2]'", "time or acceleration"),
}
#: Fewest samples of a load history (two define a ramp).
MIN_ROWS = 2


def read_load(path: str | Path, kind: str = "force"):
    """The :class:`~pdamper.coupling.loads.LoadHistory` in ``path`` (module docstring), in
    SI units; ``kind`` is ``"force"`` or ``"base_acceleration"``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "f.csv"
    >>> _ = p.write_text("time [ms], force [kN]\\n0, 0\\n10, 0.002\\n")
    >>> h = read_load(p)
    >>> float(h.time[1]), float(h.values[1]), h.kind
    (0.01, 2.0, 'force')
    """
    from pdamper.coupling.loads import LoadHistory
    from pdamper.errors import InputError

    if kind not in _KINDS:
        raise InputError("load", f"kind must be one of {', '.join(_KINDS)}, got {kind!r}")
    field, signal, example, kinds = _KINDS[kind]
    t = read_unit_table(path, field, (("time", "s"), signal), example, kinds)
    quantities = [q for q, _ in t.units]
    for want in ("time", signal[0]):
        found = [k for k, q in enumerate(quantities) if q == want]
        if not found:
            raise _err(t.path, t.header_row, None, f"no {want} column, e.g. {example}", field)
        if len(found) > 1:
            raise t.error(t.header_row, found[1], f"a second {want} column (give exactly two "
                          f"columns, e.g. {example})")
    if len(t.rows) < MIN_ROWS:
        raise _err(t.path, t.rows[-1][0] if t.rows else t.header_row, None,
                   f"needs at least {MIN_ROWS} samples, got {len(t.rows)}", field)
    tc, sc = quantities.index("time"), quantities.index(signal[0])
    data = t.values([tc, sc])
    bad = np.flatnonzero(np.diff(data[:, 0]) <= 0)
    if bad.size:
        k = int(bad[0]) + 1
        f = t.units[tc][1]
        raise t.error(t.rows[k][0], tc, f"time must increase from row to row "
                      f"({data[k, 0] / f:g} after {data[k - 1, 0] / f:g})")
    return LoadHistory(data[:, 0], data[:, 1], kind, str(t.path))
