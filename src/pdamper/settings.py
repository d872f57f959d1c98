"""Settings and quantities, each declared once: type, unit, default, constraint, docstring.

A setting is a field of a frozen :class:`Settings` model declared with :func:`setting`; a
quantity of a frozen dataclass (the damper's, :class:`pdamper.damper.ParticleDamper`) is
declared by the metadata :func:`declared` makes, from the same arguments. The declaration is the
one place of a value's constraint (checked by :func:`check_setting`, with the messages of
:func:`pdamper.errors.check_range`), its unit (SI inside; the scenario and the command line
parse quantities with this unit at the edges) and its description (the docstring of the
field, the scenario reference and the command line's help).

:func:`declaration` reads one field's declaration and :func:`declarations` every field's,
of a settings model or a declared dataclass alike: the scenario's sections, the uncertain
inputs, the design variables and the command line derive from them.

Settings objects list their values (:meth:`Settings.get_params`) and are copied with
changes (:meth:`Settings.clone`), as scikit-learn's estimators are.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Any, ClassVar, Self

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from pdamper.errors import InputError, check_range, check_whole

if TYPE_CHECKING:  # pragma: no cover
    from pydantic.json_schema import JsonDict

#: Kinds of value a setting holds (the check its declaration implies): ``material`` is a
#: :class:`~pdamper.materials.Material` (at the edges a library name or an inline table),
#: ``curve`` a COR curve e(v) (at the edges a constant COR in the declared range); their
#: owners check the type.
KINDS = ("number", "whole", "flag", "choice", "cycles", "material", "curve")


def _declare(default: Any, *, unit: str = "", low: float | None = None,
             high: float | None = None, low_inclusive: bool = True,
             high_inclusive: bool = True, choices: tuple[str, ...] = (), kind: str = "",
             infinite: bool = False, none: str = "", key: str = "") -> JsonDict:
    if not kind:
        kind = ("choice" if choices else "flag" if isinstance(default, bool)
                else "whole" if isinstance(default, int) else "number")
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    return {"unit": unit, "kind": kind, "low": low, "high": high,
            "low_inclusive": low_inclusive, "high_inclusive": high_inclusive,
            "choices": list(choices), "infinite": infinite, "none": none, "key": key}


def setting(default: Any, doc: str, *, unit: str = "", low: float | None = None,
            high: float | None = None, low_inclusive: bool = True,
            high_inclusive: bool = True, choices: tuple[str, ...] = (), kind: str = "",
            infinite: bool = False, none: str = "", key: str = "") -> Any:
    """Declare a setting: its ``default``, docstring ``doc`` and ``unit`` (SI, "" for
    dimensionless), its range (``low``/``high`` as :func:`~pdamper.errors.check_range`;
    ``infinite``: ``inf`` allowed too) or ``choices``; ``kind`` (default: from the
    default's type), ``none``: what None means (empty: None not allowed) and ``key``: the
    scenario key ``section.name`` where the value is a quantity of another object (the
    damper's)."""
    extra = _declare(default, unit=unit, low=low, high=high, low_inclusive=low_inclusive,
                     high_inclusive=high_inclusive, choices=choices, kind=kind,
                     infinite=infinite, none=none, key=key)
    return Field(default, description=doc, json_schema_extra=extra)


def declared(doc: str, *, kind: str, unit: str = "", low: float | None = None,
             high: float | None = None, low_inclusive: bool = True,
             high_inclusive: bool = True, choices: tuple[str, ...] = (),
             infinite: bool = False, none: str = "", key: str = "") -> dict[str, Any]:
    """The metadata that declares a field of a frozen dataclass as :func:`setting` declares
    a setting: ``dataclasses.field(metadata=declared(doc, kind=..., unit=..., low=...))``
    (with ``default=`` where it has one; the type checker sees a plain dataclass field).
    :func:`declaration` and :func:`declarations` read it; the dataclass checks its values
    with :func:`check_setting` (``__post_init__``)."""
    decl = _declare(None, unit=unit, low=low, high=high, low_inclusive=low_inclusive,
                    high_inclusive=high_inclusive, choices=choices, kind=kind,
                    infinite=infinite, none=none, key=key)
    return {"declaration": decl, "doc": doc}


def declaration(cls: type, name: str) -> dict:
    """The declaration (unit, kind, range, choices, key) of field ``name`` of ``cls``: a
    :class:`Settings` model (any pydantic model whose fields use :func:`setting`) or a
    dataclass whose fields carry :func:`declared` metadata; empty for a field declared without."""
    if dataclasses.is_dataclass(cls):
        fields = {f.name: f for f in dataclasses.fields(cls)}
        return dict(fields[name].metadata.get("declaration", {}))
    extra = cls.model_fields[name].json_schema_extra  # type: ignore[attr-defined]
    return dict(extra) if isinstance(extra, dict) else {}


def declarations(cls: type) -> dict[str, dict]:
    """Every field's declaration of ``cls`` (as :func:`declaration`) with its ``doc`` and
    ``default`` (None for a required field of a dataclass)."""
    if dataclasses.is_dataclass(cls):
        return {f.name: {**declaration(cls, f.name), "doc": f.metadata.get("doc", ""),
                         "default": None if f.default is dataclasses.MISSING else f.default}
                for f in dataclasses.fields(cls)}
    return {name: {**declaration(cls, name), "doc": f.description, "default": f.default}
            for name, f in cls.model_fields.items()}  # type: ignore[attr-defined]


def redeclare(cls: type[BaseModel], name: str, default: Any, doc: str, **changes: Any) -> Any:
    """The declaration of setting ``name`` of ``cls`` (its unit, kind and range, declared
    once there) for another concern that holds the same quantity with its own ``default``
    and meaning ``doc``; ``changes``: entries of the declaration that differ (``none``).

    >>> from pdamper.dem.settings import EngineSettings
    >>> d = declaration(EngineSettings, "seed")
    >>> f = redeclare(EngineSettings, "seed", 0, "Seed of the packing.", none="")
    >>> f.json_schema_extra["low"] == d["low"], f.json_schema_extra["none"]
    (True, '')
    """
    extra: JsonDict = {**declaration(cls, name), **changes}
    return Field(default, description=doc, json_schema_extra=extra)


def allowed(decl: dict) -> str:
    """The allowed values of a declaration, as the error messages write them."""
    if decl["kind"] == "choice":
        return "one of " + ", ".join(decl["choices"])
    if decl["kind"] == "flag":
        return "true or false"
    if decl["kind"] == "cycles":
        return "'auto' or a whole number >= 1"
    if decl["kind"] == "material":
        return "a material: a library name or an inline table"
    lo = "[" if decl["low_inclusive"] else "("
    hi = "]" if decl["high_inclusive"] else ")"
    low, high = decl["low"], decl["high"]
    text = f"{lo}{'-inf' if low is None else f'{low:g}'}, {'inf' if high is None else f'{high:g}'}{hi}"
    return f"whole number >= {low:g}" if decl["kind"] == "whole" else text


def check_setting(name: str, value: Any, decl: dict) -> Any:
    """``value`` checked against the declaration ``decl`` of setting ``name``; raises
    :class:`~pdamper.errors.InputError` naming ``name`` and the allowed range."""
    if value is None and decl.get("none"):
        return None
    kind = decl["kind"]
    if kind == "choice":
        if value not in decl["choices"]:
            raise InputError(name, f"must be one of {', '.join(decl['choices'])}, "
                             f"got {value!r}")
        return value
    if kind == "flag":
        import numpy as np

        if not isinstance(value, bool | np.bool_):
            raise InputError(name, f"must be true or false, got {value!r}")
        return bool(value)
    if kind == "cycles":
        if value == "auto":
            return "auto"
        if isinstance(value, str):
            raise InputError(name, f"must be 'auto' or a whole number >= 1, got {value!r}")
        return check_whole(name, value, low=1)
    if kind == "material":  # its owner checks the type (a library name at the edges)
        return value
    if kind == "curve" and not isinstance(value, int | float):  # a curve: its owner's check
        return value
    if kind == "whole":
        return check_whole(name, value, low=None if decl["low"] is None else int(decl["low"]))
    if decl["infinite"] and isinstance(value, int | float) and value == math.inf:
        return math.inf
    return check_range(name, value, low=decl["low"], high=decl["high"],
                       low_inclusive=decl["low_inclusive"],
                       high_inclusive=decl["high_inclusive"], unit=decl["unit"])


class Settings(BaseModel):
    """Frozen settings of one concern; every field declared with :func:`setting`.

    Construction checks every value against its declaration and raises
    :class:`~pdamper.errors.InputError` (the field named with :attr:`prefix`).
    """

    model_config = ConfigDict(frozen=True, extra="forbid", validate_default=False)

    #: Prefix of the field names in errors (``"dem."``: as the scenario's section).
    prefix: ClassVar[str] = ""

    def __init__(self, **data: Any) -> None:
        try:
            super().__init__(**data)
        except ValidationError as exc:
            raise self._error(exc) from None

    @classmethod
    def _error(cls, exc: ValidationError) -> InputError:
        err = exc.errors()[0]
        name = ".".join(str(p) for p in err["loc"])
        if err["type"] == "extra_forbidden":
            return InputError(cls.prefix + name, f"unknown setting of {cls.__name__}; known: "
                              f"{', '.join(cls.model_fields)}")
        return InputError(cls.prefix + name, err["msg"].removeprefix("Value error, "))

    @classmethod
    def _edge(cls, name: str, value: Any, decl: dict) -> Any:
        """A value as given at the edge, made a value of the setting (the scenario parses
        quantities with units here); identity for the Python API (SI)."""
        return value

    @field_validator("*", mode="before")
    @classmethod
    def _declared(cls, value: Any, info) -> Any:
        decl = declaration(cls, info.field_name)
        if not decl:  # a field of a subclass not declared with setting()
            return value
        try:
            return check_setting(info.field_name, cls._edge(info.field_name, value, decl), decl)
        except InputError as exc:  # pydantic adds the location
            raise ValueError(exc.message) from None

    # -- scikit-learn style ------------------------------------------------------------
    def get_params(self) -> dict[str, Any]:
        """Every setting by name (the defaults included)."""
        return {name: getattr(self, name) for name in type(self).model_fields}

    def clone(self, **changes: Any) -> Self:
        """A copy with ``changes`` (checked as at construction)."""
        return type(self)(**{**self.get_params(), **changes})

    @classmethod
    def declarations(cls) -> dict[str, dict]:
        """Every field's declaration: ``unit``, ``kind``, range, ``choices``, ``doc`` and
        ``default``."""
        return declarations(cls)


__all__ = ["KINDS", "Settings", "allowed", "check_setting", "declaration", "declarations",
           "declared", "setting"]
