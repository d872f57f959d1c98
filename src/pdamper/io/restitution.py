"""COR models in scenario files and on the command line; COR tables from CSV files.

A COR model of a material pair (the ``[restitution]`` section of a scenario, entries
``particle_particle`` and ``particle_wall``) is one of

============================================  ===============================================
``0.6``                                        constant (shorthand)
``"paper"``, ``"thornton"``                    the paper's Fig. 2 curve of this pair type /
                                               Thornton's model from the materials (shorthand)
``{model = "constant", value = 0.6}``          constant
``{model = "table", file = "cor.csv"}``        measured points, PCHIP; ``fit = "exponential"``
                                               (or ``"thornton"``, ``"linear"``) fits that
                                               model instead; path relative to the scenario
``{model = "thornton"}``                       Thornton (1997) from the materials' yield
                                               strength; ``limiting_pressure = "400 MPa"``
                                               overrides p_y
``{model = "paper"}``                          the paper's reconstructed Fig. 2 curve
``{model = "exponential", e0, e_inf, v_c}``    ``e_inf + (e0 - e_inf) exp(-v / v_c)``
``{model = "linear", e0, slope, v_hold}``      ``e0 - slope min(v, v_hold)``
============================================  ===============================================

and every table form takes ``scale = s``: ``e -> 1 - s (1 - e)``. On the command line the
same models are written ``0.6``, ``paper``, ``thornton``, ``cor.csv`` (a file), each
optionally ``*s`` (``paper*1.5``); :func:`parse_model_text`.

COR tables (:func:`read_cor_table`) are CSV files with a header row naming the columns and
their units, e.g. ``velocity [m/s], cor [-], std [-]`` (``std`` optional; ``,`` ``;`` or tab
separated; lines starting with ``#`` are comments). Rows are numbered as lines of the file.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field

from pdamper.contact.restitution import (
    MAX_TABLE_VELOCITY,
    ConstantRestitution,
    ExponentialRestitution,
    LinearRestitution,
    MeasuredRestitution,
    RestitutionCurve,
)
from pdamper.errors import InputError
from pdamper.units import parse_quantity

#: The pair types of a scenario's ``[restitution]`` section.
PAIRS = ("particle_particle", "particle_wall")
#: The COR model names.
MODELS = ("constant", "table", "thornton", "paper", "exponential", "linear")
#: Models a table can be fitted with.
FIT_FORMS = ("thornton", "exponential", "linear")


# ----------------------------------------------------------------------------- CSV tables
_COLUMNS = {
    "velocity": ("velocity", "v", "impact velocity", "speed", "impact speed"),
    "cor": ("cor", "e", "restitution", "coefficient of restitution"),
    "std": ("std", "sigma", "cor std", "std cor", "standard deviation"),
}
_HEADER = re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*(?:\[(?P<unit>[^\[\]]*)\])?\s*$")


def _column(cell: str) -> tuple[str | None, str | None]:
    m = _HEADER.match(cell)
    if not m:
        return None, None
    name = m["name"].strip().lower()
    kind = next((k for k, names in _COLUMNS.items() if name in names), None)
    return kind, (None if m["unit"] is None else m["unit"].strip())


def _factor(unit: str | None, si: str, where: str, field: str) -> float:
    """Conversion factor of a column's unit to ``si``."""
    if unit is None:
        if si:
            raise InputError(field, f"{where}: needs a unit, e.g. 'velocity [m/s]'")
        return 1.0
    if not si and unit in ("", "-", "1"):
        return 1.0
    try:
        return parse_quantity(f"1 {unit}", si, "unit")
    except InputError:
        raise InputError(field, f"{where}: unknown unit [{unit}], expected a unit of "
                         f"{si or 'a dimensionless number ([-])'}") from None


def read_cor_table(path: str | Path, field: str = "restitution.file") -> MeasuredRestitution:
    """Read measured COR points from a CSV file (module docstring).

    Every problem (missing file or column, unknown column or unit, a value that is not a
    number, NaN, a COR outside (0, 1], velocities not strictly increasing, a negative std)
    raises one :class:`~pdamper.errors.InputError` naming the file, the row and the column.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(field, f"COR table not found: {p}")
    try:
        lines = p.read_text(encoding="utf-8-sig").splitlines()
    except UnicodeDecodeError:
        raise InputError(field, f"{p.name} is not UTF-8 text") from None
    rows = [(i + 1, ln) for i, ln in enumerate(lines) if ln.strip() and not ln.lstrip().startswith("#")]
    if not rows:
        raise InputError(field, f"{p.name}: empty (expected a header such as "
                         "'velocity [m/s], cor [-]' and data rows)")
    head_no, head = rows[0]
    sep = next((s for s in (",", ";", "\t") if s in head), ",")
    cells = [c.strip() for c in head.split(sep)]
    kinds: list[str] = []
    factors: list[float] = []
    for j, cell in enumerate(cells, 1):
        where = f"{p.name}: row {head_no}, column {j} '{cell}'"
        kind, unit = _column(cell)
        if kind is None:
            raise InputError(field, f"{where}: unknown column; expected velocity [unit], "
                             "cor [-] and optionally std [-]")
        if kind in kinds:
            raise InputError(field, f"{where}: column '{kind}' appears twice")
        kinds.append(kind)
        factors.append(_factor(unit, "m/s" if kind == "velocity" else "", where, field))
    for kind in ("velocity", "cor"):
        if kind not in kinds:
            raise InputError(field, f"{p.name}: row {head_no}: missing column '{kind}' (header "
                             f"{head.strip()!r}; expected e.g. 'velocity [m/s], cor [-]')")
    data: dict[str, list[float]] = {k: [] for k in kinds}
    for no, line in rows[1:]:
        vals = [c.strip() for c in line.split(sep)]
        if len(vals) != len(kinds):
            raise InputError(field, f"{p.name}: row {no}: {len(vals)} values, the header has "
                             f"{len(kinds)} columns")
        for j, (kind, text, fac) in enumerate(zip(kinds, vals, factors, strict=True)):
            where = f"{p.name}: row {no}, column {j + 1} '{cells[j]}'"
            try:
                x = float(text) * fac
            except ValueError:
                raise InputError(field, f"{where}: not a number: {text!r}") from None
            if not math.isfinite(x):
                raise InputError(field, f"{where}: must be a finite number, got {text!r}")
            if kind == "velocity":
                if x < 0:
                    raise InputError(field, f"{where}: velocity must be >= 0, got {text}")
                if x > MAX_TABLE_VELOCITY:
                    raise InputError(field, f"{where}: velocity must be <= "
                                     f"{MAX_TABLE_VELOCITY:g} m/s, got {x:.3g} m/s: faster "
                                     "than sound in any solid (check the column's unit)")
                if data["velocity"] and x <= data["velocity"][-1]:
                    raise InputError(field, f"{where}: velocities must increase strictly "
                                     f"({x:g} m/s after {data['velocity'][-1]:g} m/s); average "
                                     "repeated measurements and give their std")
            elif kind == "cor" and not 0.0 < x <= 1.0:
                raise InputError(field, f"{where}: COR must be in (0, 1], got {text}")
            elif kind == "std" and x < 0:
                raise InputError(field, f"{where}: std must be >= 0, got {text}")
            data[kind].append(x)
    if not data["velocity"]:
        raise InputError(field, f"{p.name}: no data rows below the header (row {head_no})")
    return MeasuredRestitution(tuple(data["velocity"]), tuple(data["cor"]),
                               tuple(data["std"]) if "std" in data else None, source=p.name)


# ------------------------------------------------------------------------- scenario specs
def _velocity(v: Any) -> Any:
    try:
        return parse_quantity(v, "m/s", "value")
    except InputError as exc:
        raise ValueError(exc.message) from None


def _pressure(v: Any) -> Any:
    try:
        return parse_quantity(v, "Pa", "value")
    except InputError as exc:
        raise ValueError(exc.message) from None


def _slope(v: Any) -> Any:
    try:
        return parse_quantity(v, "s/m", "value")
    except InputError as exc:
        raise ValueError(exc.message) from None


Cor = Annotated[float, Field(gt=0, le=1)]
Velocity = Annotated[float, BeforeValidator(_velocity), Field(gt=0)]


class _Spec(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    #: ``e -> 1 - scale (1 - e)`` (1: the model itself).
    scale: Annotated[float, Field(ge=0)] = 1.0


class ConstantCOR(_Spec):
    model: Literal["constant"] = "constant"
    value: Cor


class TableCOR(_Spec):
    model: Literal["table"] = "table"
    file: str
    fit: Literal["thornton", "exponential", "linear"] | None = None


class ThorntonCOR(_Spec):
    model: Literal["thornton"] = "thornton"
    limiting_pressure: Annotated[float, BeforeValidator(_pressure), Field(gt=0)] | None = None


class PaperCOR(_Spec):
    model: Literal["paper"] = "paper"


class ExponentialCOR(_Spec):
    model: Literal["exponential"] = "exponential"
    e0: Cor
    e_inf: Cor
    v_c: Velocity


class LinearCOR(_Spec):
    model: Literal["linear"] = "linear"
    e0: Cor
    slope: Annotated[float, BeforeValidator(_slope)]
    v_hold: Velocity | None = None  # None: never held (only for slope <= 0)


def _shorthand(v: Any) -> Any:
    if isinstance(v, bool):
        raise ValueError(f"must be a COR model, got {v!r}")
    if isinstance(v, int | float):
        return {"model": "constant", "value": v}
    if isinstance(v, str):
        if v.strip().lower() in ("paper", "thornton"):
            return {"model": v.strip().lower()}
        raise ValueError(f"must be a number, \"paper\", \"thornton\" or a table such as "
                         f"{{ model = \"table\", file = \"cor.csv\" }}, got {v!r}")
    return v


#: One COR model (see the module docstring).
CORSpec = Annotated[ConstantCOR | TableCOR | ThorntonCOR | PaperCOR | ExponentialCOR | LinearCOR,
                    Field(discriminator="model"), BeforeValidator(_shorthand)]


class RestitutionSpec(BaseModel):
    """The ``[restitution]`` section: the COR model of each pair type (None: not given
    here; ``[dem] restitution_pp / restitution_pw`` or the defaults apply)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    particle_particle: CORSpec | None = None
    particle_wall: CORSpec | None = None


def resolve_files(data: dict, base: Path) -> dict:
    """Make the table paths of a parsed scenario's ``[restitution]`` section absolute,
    relative to ``base`` (the scenario file's directory). ``data`` is changed in place."""
    section = data.get("restitution")
    if not isinstance(section, dict):
        return data
    for pair in PAIRS:
        spec = section.get(pair)
        if isinstance(spec, dict) and isinstance(spec.get("file"), str):
            f = Path(spec["file"]).expanduser()
            spec["file"] = str(f if f.is_absolute() else (base / f).resolve())
    return data


def build_curve(spec, pair: str, sphere, partner, radius: float) -> RestitutionCurve:
    """The :class:`~pdamper.contact.restitution.RestitutionCurve` that ``spec`` (a
    :data:`CORSpec`) describes for a sphere of ``sphere`` material and ``radius`` [m] hitting
    an equal sphere (``pair = "particle_particle"``) or a wall of ``partner`` material."""
    field = f"restitution.{pair}"
    try:
        curve = _curve(spec, pair, sphere, partner, radius, field)
        return curve.scaled(spec.scale)
    except InputError as exc:
        if exc.field.startswith(field):
            raise
        sub = exc.field.removeprefix("restitution").lstrip(".")
        raise InputError(f"{field}.{sub}" if sub else field, exc.message) from None


def _curve(spec, pair, sphere, partner, radius, field) -> RestitutionCurve:
    if isinstance(spec, ConstantCOR):
        return ConstantRestitution(spec.value)
    if isinstance(spec, PaperCOR):
        from pdamper.parameters import vertical_dampers_paper as paper

        return paper.PAPER_COR_PP if pair == "particle_particle" else paper.PAPER_COR_PW
    if isinstance(spec, ThorntonCOR):
        from pdamper.contact.thornton import ThorntonRestitution

        return ThorntonRestitution.from_materials(
            sphere, partner, radius, radius if pair == "particle_particle" else math.inf,
            pressure=spec.limiting_pressure)
    if isinstance(spec, ExponentialCOR):
        return ExponentialRestitution(spec.e0, spec.e_inf, spec.v_c)
    if isinstance(spec, LinearCOR):
        return LinearRestitution(spec.e0, spec.slope,
                                 math.inf if spec.v_hold is None else spec.v_hold)
    if isinstance(spec, TableCOR):
        table = read_cor_table(spec.file, f"{field}.file")
        if spec.fit is None:
            return table
        from pdamper.contact.fit import fit_restitution

        return fit_restitution(table.velocity, table.restitution, table.std, spec.fit,
                               name=f"{spec.fit} fit of {table.source} "
                                    f"({len(table.velocity)} points)").curve
    raise InputError(field, f"unknown COR model {spec!r}")  # pragma: no cover


_TEXT = re.compile(r"^\s*(?P<model>[^*]+?)\s*(?:\*\s*(?P<scale>[^*]+))?\s*$")


def parse_model_text(text: str, field: str = "model") -> dict:
    """A COR model written on the command line as a scenario entry (a dict).

    ``"0.6"``, ``"paper"``, ``"thornton"``, ``"cor.csv"`` (a file; ``csv:NAME`` for any
    name), each optionally ``*scale``.

    >>> parse_model_text("paper*1.5")
    {'model': 'paper', 'scale': 1.5}
    >>> parse_model_text("0.6")
    {'model': 'constant', 'value': 0.6}
    """
    m = _TEXT.match(str(text))
    if not m:
        raise InputError(field, f"expected a COR model such as 0.6, paper, thornton or "
                         f"cor.csv, optionally *scale; got {text!r}")
    model, scale = m["model"], m["scale"]
    try:
        spec: dict = {"model": "constant", "value": float(model)}
    except ValueError:
        low = model.lower()
        if low in ("paper", "thornton"):
            spec = {"model": low}
        elif low.startswith("csv:") or low.endswith(".csv") or Path(model).is_file():
            spec = {"model": "table", "file": model[4:] if low.startswith("csv:") else model}
        else:
            raise InputError(field, f"unknown COR model {model!r}; expected a number, paper, "
                             "thornton or a CSV file, optionally *scale") from None
    if scale is not None:
        try:
            spec["scale"] = float(scale)
        except ValueError:
            raise InputError(field, f"scale must be a number, got {scale!r}") from None
    return spec


def validate_spec(spec: dict, field: str = "model"):
    """A :data:`CORSpec` from a dict (e.g. from :func:`parse_model_text`)."""
    from pydantic import TypeAdapter, ValidationError

    try:
        return TypeAdapter(CORSpec).validate_python(spec)
    except ValidationError as exc:
        err = exc.errors()[0]
        loc = ".".join(str(p) for p in err["loc"] if str(p) not in MODELS
                       and not str(p).startswith("function-"))
        msg = err["msg"].removeprefix("Value error, ")
        raise InputError(f"{field}.{loc}" if loc else field, msg) from None


__all__ = ["CORSpec", "FIT_FORMS", "MODELS", "PAIRS", "RestitutionSpec", "build_curve",
           "parse_model_text", "read_cor_table", "resolve_files", "validate_spec"]
