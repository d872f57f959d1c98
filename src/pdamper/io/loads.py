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

The scenario's ``[frf]`` section (:class:`FRFSpec`), the harmonic load of a forced
response, is declared here too.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, ClassVar

import numpy as np
from pydantic import Field, model_validator

from pdamper.io.damper_sections import _DeclaredSection
from pdamper.io.grids import _grid
from pdamper.io.measured import _err, read_unit_table
from pdamper.io.quantities import _q
from pdamper.settings import redeclare, setting

if TYPE_CHECKING:  # pragma: no cover
    from pdamper.coupling.loads import LoadHistory, RunUp

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


# ----------------------------------------------------------------------------- [frf]
#: The load keys of ``[frf]``, one of which may be given, and the
#: :class:`~pdamper.coupling.frf.HarmonicLoad` each makes.
FRF_LOAD_KEYS = ("force", "unbalance", "base_displacement", "base_acceleration")


class FRFSpec(_DeclaredSection):
    """The forced response's load and frequencies (``pdamper frf``, and the forced response
    of ``pdamper report``): one harmonic load (``force``, ``unbalance``,
    ``base_displacement`` or ``base_acceleration``; none: a force of 2 N at the load point),
    the frequencies (none: every mode of the structure, resolved for its damping,
    :func:`pdamper.coupling.frf.default_frequencies`) and the stepped sine's direction."""

    prefix: ClassVar[str] = "frf."

    force: float | None = setting(
        None, "Harmonic force amplitude at the structure's load point (the damper's point "
        "unless the modes name a load point).", unit="N", low=0.0, low_inclusive=False,
        kind="number", none="not given")
    unbalance: float | None = setting(
        None, "Rotating unbalance m e at the load point, e.g. '1.76 kg*mm': the force "
        "m e Omega^2 at each speed Omega.", unit="kg*m", low=0.0, low_inclusive=False,
        kind="number", none="not given")
    base_displacement: float | None = setting(
        None, "Harmonic base displacement amplitude (one-mode structures).", unit="m",
        low=0.0, low_inclusive=False, kind="number", none="not given")
    base_acceleration: float | None = setting(
        None, "Harmonic base acceleration amplitude, e.g. '0.5 g0' (one-mode structures).",
        unit="m/s^2", low=0.0, low_inclusive=False, kind="number", none="not given")
    #: frequencies "start:stop:count" or one; none: every mode of the structure, resolved
    #: for its damping
    frequency: Annotated[str, _grid("Hz")] | None = None
    sweep: str = setting("both", "Stepped-sine direction: up, down or both.",
                         choices=("up", "down", "both"))
    at: str = setting("load", "Where a force or an unbalance acts: load (the structure's "
                      "load point: the modes file's load column, the beam's load_position; "
                      "the damper's point where the structure names none) or damper.",
                      choices=("load", "damper"))

    @model_validator(mode="after")
    def _one_load(self):
        given = [k for k in FRF_LOAD_KEYS if getattr(self, k) is not None]
        if len(given) > 1:
            raise ValueError(f"give one harmonic load, not {' and '.join(given)}")
        return self

    def load(self):
        """The :class:`~pdamper.coupling.frf.HarmonicLoad` of the section (None: none
        given)."""
        from pdamper.coupling.frf import HarmonicLoad

        for key, kind, accel in (("force", "force", False), ("unbalance", "unbalance", False),
                                 ("base_displacement", "base", False),
                                 ("base_acceleration", "base", True)):
            v = getattr(self, key)
            if v is not None:
                try:
                    return HarmonicLoad(kind, v, acceleration=accel)
                except Exception as exc:  # its range, named by this key
                    from pdamper.errors import InputError

                    if isinstance(exc, InputError):
                        raise InputError(f"frf.{key}", exc.message) from None
                    raise
        return None

    def frequencies(self, structure, added_mass: float = 0.0):
        """The frequencies [Hz] of ``frequency``, or the structure's default
        (:func:`pdamper.coupling.frf.default_frequencies`)."""
        if self.frequency is None:
            from pdamper.coupling.frf import default_frequencies

            return default_frequencies(structure, added_mass)
        from pdamper.coupling.frf import MAX_FREQUENCIES
        from pdamper.errors import InputError
        from pdamper.io.grids import grid, parse_axis

        count = parse_axis(self.frequency, "Hz", "frf.frequency")[2]  # before the grid exists
        if count > MAX_FREQUENCIES:
            raise InputError("frf.frequency", f"at most {MAX_FREQUENCIES} frequencies, got "
                             f"{count}")
        return grid(self.frequency, "Hz", "frf.frequency")


class LoadSpec(_DeclaredSection):
    """A load history on the structure (:mod:`pdamper.io.loads`, docs/forced.md): a force
    (``force``, a CSV file), a base acceleration (``base_acceleration``) or a rotating
    unbalance on a speed ramp (``unbalance`` with ``run_up``,
    :class:`~pdamper.coupling.loads.RunUp`), one of them; a relative path is taken
    relative to the scenario file. The run lasts the record plus ``tail`` of free
    vibration. A force acts at the structure's load point (``at = "load"``: the modes
    file's load column, the beam's ``load_position``; the damper's point where the
    structure names none) or at the damper's point (``at = "damper"``: a shock on the
    damper's housing)."""

    prefix: ClassVar[str] = "load."

    force: str | None = None
    base_acceleration: str | None = None
    unbalance: float | None = redeclare(
        FRFSpec, "unbalance", None, "Rotating unbalance m e of the run-up at the load point, "
        "e.g. '1.76 kg*mm'.")
    #: speed ramp of the unbalance "start:stop:duration", e.g. "400rpm:2400rpm:20s"
    run_up: str | None = None
    tail: Annotated[float, _q("s"), Field(ge=0, allow_inf_nan=False)] = 0.0
    at: str = redeclare(FRFSpec, "at", "load", "Where a force acts: load (the structure's "
                        "load point: the modes file's load column, the beam's load_position; "
                        "the damper's point where the structure names none) or damper.")

    @model_validator(mode="after")
    def _one_load(self):
        given = [k for k in ("force", "base_acceleration", "run_up")
                 if getattr(self, k) is not None]
        if len(given) > 1:
            raise ValueError(f"give the load as one of force, base_acceleration or run_up, "
                             f"not {' and '.join(given)}")
        if (self.run_up is None) != (self.unbalance is None):
            raise ValueError("a run-up needs both unbalance (m e, e.g. '1.76 kg*mm') and "
                             "run_up (the speed ramp, e.g. '400rpm:2400rpm:20s')")
        self.run_up_load()  # its ramp checked here
        return self

    @property
    def given(self) -> bool:
        return (self.force is not None or self.base_acceleration is not None
                or self.run_up is not None)

    @classmethod
    def override(cls, section: dict[str, Any], name: str, value: Any) -> None:
        """Set ``name`` to ``value`` in the ``[load]`` table ``section`` as read from a file:
        a load given on the command line (a force, a base acceleration, a run-up or its
        unbalance) replaces the file's load of another kind, and where it acts (``at``)
        unless the command line says that too (it is set after)."""
        drop = {"force": ("base_acceleration", "run_up", "unbalance"),
                "base_acceleration": ("force", "run_up", "unbalance"),
                "run_up": ("force", "base_acceleration"),
                "unbalance": ("force", "base_acceleration")}.get(name)
        if drop is not None:
            for other in (*drop, "at"):
                section.pop(other, None)
        section[name] = value

    def run_up_load(self) -> RunUp | None:
        """The :class:`~pdamper.coupling.loads.RunUp` (None: none given)."""
        from pdamper.coupling.loads import RunUp

        if self.run_up is None or self.unbalance is None:
            return None
        return RunUp.parse(self.unbalance, self.run_up)

    def history(self) -> LoadHistory | None:
        """The :class:`~pdamper.coupling.loads.LoadHistory` (None: no load given)."""
        from pdamper.io.loads import read_load

        if self.force is not None:
            return read_load(self.force, "force")
        if self.base_acceleration is not None:
            return read_load(self.base_acceleration, "base_acceleration")
        run_up = self.run_up_load()
        return None if run_up is None else run_up.history()
