"""Read a structure's modes from CSV (a few modes of the user's own FE model).

Same format as the measured records (:mod:`pdamper.io.measured`): a header row naming each
column with its unit in brackets, then one row per mode; ``#`` starts a comment line; the
separator is ``,``, ``;`` or a tab. ::

    # first two bending modes of the FE model, mass-normalised
    frequency [Hz], damping ratio [1], damper [kg^-0.5], load [kg^-0.5], observation [kg^-0.5]
    5.56, 0.0052, 0.8127, 0.4, 0.8127
    46.3, 0.01, -0.911, 0.7, -0.911

Columns are found by their units: the natural frequency f_i (a frequency: ``Hz``,
``1/min``, ``rpm`` ...), the modal damping ratio zeta_i (dimensionless: ``1`` or ``%``),
and one to three mass-normalised mode-shape values (unit ``kg^-0.5``). A shape column
whose name starts with ``load`` is the **load point**, where a force on the structure acts
(a harmonic force, an unbalance, a force history; default: the damper's point); of the
others the first is at the damper's point, the second (optional) at the observation point
whose displacement the results report (default: the damper's point). The structure is
released from a static deflection at the damper's point. Rows are sorted by frequency.

A frequency or damping-ratio cell may carry the value's uncertainty, ``value +- sd`` in
the column's unit (a standard deviation: the mode's parameter is then normal with that
mean and deviation, truncated to its range, as ``--uncertain mode1.damping_ratio=...``
gives it; :mod:`pdamper.io.uncertain`)::

    frequency [Hz], damping ratio [%], damper [kg^-0.5]
    12.0, 1.0 +- 0.3, 0.2582
    31.0 +- 0.5, 0.8, -0.3162

The structure is built from the nominal values; the uncertainties are the scenario's
uncertain inputs ``mode1.damping_ratio`` and ``mode2.frequency``
(:func:`modes_uncertainty`, numbered after sorting by frequency), sampled by
``--uncertainty N``.

Problems (no header, a column without a unit, an unknown unit, a missing or repeated
column, a value that is not a finite number, a frequency <= 0, a damping ratio outside
[0, 1), a
damper point that does not move in any mode) are one-line
:class:`~pdamper.errors.InputError` naming the file, the row (line number in the file) and
the column.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from pdamper.io.measured import _err, read_unit_table

FIELD = "structure.modes"
#: SI unit of each recognised column quantity.
_DIMENSIONS = (("frequency", "Hz"), ("damping ratio", ""), ("mode shape", "kg^-0.5"))
_KINDS = "frequency, damping ratio (1 or %) or mass-normalised mode shape (kg^-0.5)"
_EXAMPLE = "'frequency [Hz], damping ratio [1], damper [kg^-0.5]'"


def _nominal(text: str) -> str:
    """The nominal value of a cell ``"value +- sd"`` (its text before ``+-``)."""
    from pdamper.io.uncertain import _SPLIT

    return _SPLIT.split(text.strip())[0]


def _is_load(name: str) -> bool:
    """Whether the column headed ``name`` (``"load [kg^-0.5]"``) holds the load point."""
    return name.split("[")[0].strip().lower().startswith("load")


def read_modes(path: str | Path):
    """The :class:`~pdamper.structure.modal.ModalStructure` in ``path`` (module docstring).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "modes.csv"
    >>> _ = p.write_text("frequency [Hz], damping ratio [%], damper [kg^-0.5]\\n"
    ...                  "5.5, 0.5, 0.8\\n")
    >>> s = read_modes(p)
    >>> s.modes, float(s.damping_ratios[0]), s.coincident
    (1, 0.005, True)
    >>> _ = p.write_text("frequency [Hz], damping ratio [%], damper [kg^-0.5], "
    ...                  "load [kg^-0.5]\\n5.5, 0.5, 0.8, 0.4\\n")
    >>> float(read_modes(p).load_shape[0]), float(read_modes(p).output_shape[0])
    (0.4, 0.8)
    """
    return _read(path)[0]


@functools.lru_cache(maxsize=16)
def modes_uncertainty(path: str, mtime_ns: int = 0, size: int = 0) -> dict:
    """``{"mode<k>.<parameter>": UncertainInput}`` of the cells of the modes file ``path``
    written ``value +- sd`` (module docstring; k in the order of frequency, from 1);
    ``mtime_ns`` and ``size`` key the cache to the file's version.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "modes.csv"
    >>> _ = p.write_text("frequency [Hz], damping ratio [%], damper [kg^-0.5]\\n"
    ...                  "31 +- 0.5, 0.8, -0.3\\n12, 1 +- 0.3, 0.26\\n")
    >>> {f: (round(u.value, 6), round(u.sd, 6)) for f, u in modes_uncertainty(str(p)).items()}
    {'mode1.damping_ratio': (0.01, 0.003), 'mode2.frequency': (31.0, 0.5)}
    """
    return _read(path)[1]


def _read(path: str | Path):
    """The structure in ``path`` and the uncertainties of its cells (:func:`read_modes`,
    :func:`modes_uncertainty`)."""
    from pdamper.errors import InputError
    from pdamper.io.uncertain import cell_uncertainty, is_uncertain
    from pdamper.structure.modal import ModalStructure

    t = read_unit_table(path, FIELD, _DIMENSIONS, _EXAMPLE, _KINDS)
    kinds = [q for q, _ in t.units]
    cols = {}
    for kind in ("frequency", "damping ratio"):
        found = [k for k, q in enumerate(kinds) if q == kind]
        if not found:
            raise _err(t.path, t.header_row, None, f"no {kind} column, e.g. {_EXAMPLE}", FIELD)
        if len(found) > 1:
            raise t.error(t.header_row, found[1], f"a second {kind} column")
        cols[kind] = found[0]
    all_shapes = [k for k, q in enumerate(kinds) if q == "mode shape"]
    loads = [k for k in all_shapes if _is_load(t.names[k])]
    if len(loads) > 1:
        raise t.error(t.header_row, loads[1], "a second load column (one load point)")
    shapes = [k for k in all_shapes if k not in loads]
    if not shapes:
        raise _err(t.path, t.header_row, None, "no mode-shape column (mass-normalised, unit "
                   f"kg^-0.5) at the damper's point, e.g. {_EXAMPLE}", FIELD)
    if len(shapes) > 2:
        raise t.error(t.header_row, shapes[2], "at most two mode-shape columns besides the "
                      "load: the damper's point, then the observation point")
    if not t.rows:
        raise _err(t.path, t.header_row, None, "no modes: one row per mode after the header",
                   FIELD)
    order = [cols["frequency"], cols["damping ratio"], *shapes, *loads]
    spread: dict[tuple[int, str], tuple[int, int, str]] = {}  # (row, parameter) -> cell
    for r, (row, cells) in enumerate(t.rows):
        for name, c in (("frequency", cols["frequency"]),
                        ("damping_ratio", cols["damping ratio"])):
            if c < len(cells) and is_uncertain(cells[c]):
                spread[r, name] = (row, c, cells[c])
                cells[c] = _nominal(cells[c])
    data = t.values(order)
    for c, ok, msg in ((0, data[:, 0] > 0, "the frequency must be > 0"),
                       (1, data[:, 1] >= 0, "the damping ratio must be >= 0"),
                       (1, data[:, 1] < 1, "the damping ratio must be below 1, in [0, 1) "
                                           "(a vibration mode: at 1 and above it does not "
                                           "oscillate)")):
        bad = np.flatnonzero(~ok)
        if bad.size:
            raise t.error(t.rows[bad[0]][0], order[c], msg)
    if not np.any(data[:, 2] != 0):
        raise t.error(t.rows[-1][0], shapes[0], "the damper's point does not move in any mode")
    rank = np.argsort(data[:, 0], kind="stable")
    uncertain = {}
    for (r, name), (row, c, text) in spread.items():
        field = f"mode{int(np.flatnonzero(rank == r)[0]) + 1}.{name}"
        try:
            uncertain[field] = cell_uncertainty(text, field, t.units[c][1])
        except InputError as exc:
            raise t.error(row, c, exc.message) from None
    data = data[rank]
    uncertain = dict(sorted(uncertain.items(),  # in the order of the modes
                            key=lambda kv: (int(kv[0][4:].partition(".")[0]), kv[0])))
    try:
        return ModalStructure(data[:, 0], data[:, 1], data[:, 2],
                              data[:, 3] if len(shapes) == 2 else None,
                              load_shape=data[:, -1] if loads else None), uncertain
    except InputError as exc:  # not reached for a file that passed the checks above
        raise InputError(FIELD, f"{t.path}: {exc.message}") from None


def file_inputs(scenario) -> dict:
    """``{field: UncertainInput}`` written in the scenario's modes file
    (:func:`modes_uncertainty`; empty without one), read once per version of the file."""
    path = scenario.structure.modes
    if path is None:
        return {}
    import os

    try:
        st = os.stat(path)
    except OSError:  # a missing file is the structure's error, where it is read
        return {}
    return modes_uncertainty(str(path), st.st_mtime_ns, st.st_size)
