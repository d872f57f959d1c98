"""The scenario reference (docs/scenario.md), generated from the scenario schema.

Every section and key of :class:`pdamper.io.scenario.Scenario` with its type, unit, default,
allowed values and description, read from the pydantic declarations themselves: the type
from the annotation, the unit from the field's quantity validator, the constraints from its
``Field(gt=..., le=...)`` metadata and ``Literal`` choices, the default from the field (as
the example scenario writes it, with its unit, where that file sets it), the description
from the field's ``description`` or else from the comment of that key in the example
scenario (``pdamper example-scenario``), which is written next to the same defaults.

``python -m pdamper.io.scenario_reference`` prints the page; ``--write docs/scenario.md``
writes it; ``--check docs/scenario.md`` exits with status 1 if the file differs.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import re
import sys
import tomllib
import types
import typing
from typing import Annotated, Any, Literal, Union, get_args, get_origin

from pydantic import AliasChoices, BaseModel
from pydantic.fields import FieldInfo

_HEADER = """\
# Scenario reference

A scenario is a TOML file that describes a damper, its structure and the options of every
command (`--scenario FILE.toml`); `pdamper example-scenario` prints one with every key at
its default and a comment. Every section and key is optional: what is left out takes the
default below, which is the reference paper's benchmark damper on its structure. Quantities
are text with a unit (`"32 mm"`, `"10 Hz"`); bare numbers are SI. An unknown key, a value
out of range or a quantity of the wrong dimension is an error naming the key
(docs/inputs.md). A key may also be given under its alias (column "key").

This page is generated from the schema's declarations (`pdamper.io.scenario`) by
`python -m pdamper.io.scenario_reference --write docs/scenario.md`;
`tests/io/test_scenario_reference.py` checks that it is up to date.
"""

_OPS = {"gt": ">", "ge": ">=", "lt": "<", "le": "<="}
_QUANTITY = re.compile(r"parse_quantity\([^,]+,\s*\"([^\"]+)\"")
_ROLE = re.compile(r":\w+:`~?([^`]+)`")


def _strip(annotation: Any) -> tuple[Any, list[Any]]:
    """``Annotated[T, m1, m2]`` -> ``(T, [m1, m2])``, nested Annotated flattened."""
    meta: list[Any] = []
    while get_origin(annotation) is Annotated:
        args = get_args(annotation)
        annotation, meta = args[0], [*args[1:], *meta]
    return annotation, meta


def _members(annotation: Any) -> list[Any]:
    """The members of a union (one element for anything else), ``None`` left out."""
    annotation, _ = _strip(annotation)
    if get_origin(annotation) in (Union, types.UnionType):
        out = []
        for a in get_args(annotation):
            out.extend(_members(a))
        return out
    return [] if annotation is type(None) else [annotation]


def _optional(annotation: Any) -> bool:
    annotation, _ = _strip(annotation)
    return get_origin(annotation) in (Union, types.UnionType) and \
        type(None) in get_args(annotation)


def _is_model(t: Any) -> bool:
    return isinstance(t, type) and issubclass(t, BaseModel)


def _type_name(t: Any) -> str:
    t, _ = _strip(t)
    origin = get_origin(t)
    if origin is Literal:
        return " or ".join(f'`{v!r}`'.replace("'", '"') for v in get_args(t))
    if origin in (list, tuple):
        inner = ", ".join(_type_name(a) for a in get_args(t) if a is not Ellipsis)
        return f"list of {inner}"
    if origin in (Union, types.UnionType):
        names = [_type_name(a) for a in get_args(t) if a is not type(None)]
        return " or ".join(dict.fromkeys(names))
    if _is_model(t):
        return "table"
    return {int: "integer", float: "number", bool: "true/false", str: "text",
            Any: "any"}.get(t, getattr(t, "__name__", str(t)))


def _validators(meta: list[Any]) -> list[Any]:
    return [m.func for m in meta if hasattr(m, "func") and callable(m.func)]


def _unit_of(func: Any) -> str | None:
    """The unit a quantity validator reads its value in: the ``unit`` its factory closed
    over (``_q("m")``, ``_grid("Hz")``), or the unit it passes to ``parse_quantity``."""
    try:
        unit = inspect.getclosurevars(func).nonlocals.get("unit")
    except (TypeError, ValueError):
        unit = None
    if isinstance(unit, str):
        return unit
    try:
        match = _QUANTITY.search(inspect.getsource(func))
    except (OSError, TypeError):
        return None
    return match.group(1) if match else None


def _all_meta(annotation: Any, info: FieldInfo) -> list[Any]:
    """The field's metadata and that of every member of its (possibly nested) union."""
    meta = list(info.metadata)
    todo = [annotation]
    while todo:
        t, outer = _strip(todo.pop())
        meta.extend(outer)
        if get_origin(t) in (Union, types.UnionType):
            todo.extend(get_args(t))
    return meta


_ATTR_DOC = re.compile(r"^\s*#:\s?(.*)$")
_ATTR = re.compile(r"^\s*(\w+)\s*:")


def _attribute_docs(model: type) -> dict[str, str]:
    """``#: text`` comments above the fields of ``model`` (Sphinx's attribute docs)."""
    docs: dict[str, str] = {}
    for cls in reversed(model.__mro__):
        if not (isinstance(cls, type) and issubclass(cls, BaseModel)) or cls is BaseModel:
            continue
        try:
            lines = inspect.getsource(cls).splitlines()
        except (OSError, TypeError):
            continue
        pending: list[str] = []
        for line in lines[1:]:
            if m := _ATTR_DOC.match(line):
                pending.append(m.group(1))
            elif (m := _ATTR.match(line)) and pending:
                docs[m.group(1)] = " ".join(pending)
                pending = []
            else:
                pending = []
    return docs


def _declared(info: FieldInfo) -> dict:
    """The declaration of a field declared with :func:`pdamper.settings.setting` (empty
    for one that is not)."""
    extra = info.json_schema_extra
    return dict(extra) if isinstance(extra, dict) and "kind" in extra else {}


def _declared_constraint(decl: dict) -> str:
    if decl["kind"] == "cycles":
        from pdamper.settings import allowed

        return allowed(decl).replace("'", '"')
    if decl["kind"] not in ("number", "whole", "curve"):
        return ""
    parts = []
    if decl["low"] is not None:
        parts.append(f"{'>=' if decl['low_inclusive'] else '>'} {decl['low']:g}")
    if decl["high"] is not None:
        parts.append(f"{'<=' if decl['high_inclusive'] else '<'} {decl['high']:g}")
    return ", ".join(parts)


def _unit(annotation: Any, info: FieldInfo) -> str:
    if decl := _declared(info):
        return decl["unit"]
    for func in _validators(_all_meta(annotation, info)):
        unit = _unit_of(func)
        if unit:
            return unit
    return ""


def _constraint(annotation: Any, info: FieldInfo) -> str:
    if decl := _declared(info):
        return _declared_constraint(decl)
    extra = info.json_schema_extra
    allowed = extra.get("allowed") if isinstance(extra, dict) else None
    if isinstance(allowed, str):
        return allowed  # a value parsed from text says its range in words
    parts = []
    meta = _all_meta(annotation, info)
    for m in list(meta):  # a Field(...) inside an Annotated member keeps its own metadata
        if isinstance(m, FieldInfo):
            meta.extend(m.metadata)
    for m in meta:
        for name, op in _OPS.items():
            value = getattr(m, name, None)
            if value is not None and type(m).__name__.lower() in (name, "interval",
                                                                    "fieldinfo"):
                text = f"{op} {value:g}" if isinstance(value, float) else f"{op} {value}"
                if text not in parts:
                    parts.append(text)
        if getattr(m, "allow_inf_nan", None) is False and "finite" not in parts:
            parts.append("finite")
    choices = [a for a in _members(annotation) if get_origin(a) is Literal]
    if choices and len(_members(annotation)) == 1:
        parts.append("one of the values named")
    return ", ".join(parts)


def _format_default(value: Any, unit: str = "") -> str:
    if value is None:
        return "none"
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, float):
        return f'`"{value:g} {unit}"`' if unit else f"`{value:g}`"
    if isinstance(value, str):
        return f'`"{value}"`'
    if isinstance(value, BaseModel):
        return "the table's defaults"
    if isinstance(value, list | tuple):
        return "`[" + ", ".join(_format_default(v).strip("`") for v in value) + "]`"
    return f"`{value}`"


def _example_values() -> dict[str, Any]:
    from pdamper.io.scenario import EXAMPLE_SCENARIO

    return tomllib.loads(EXAMPLE_SCENARIO)


_KEY = re.compile(r"^(#\s*)?(\w+)\s*=\s*(.*?)\s{2,}#\s?(.*)$")
_SECTION = re.compile(r"^\[(\w+)\]\s*(?:#\s?(.*))?$")
_MORE = re.compile(r"^\s{20,}#\s?(.*)$")


def _example_comments() -> tuple[dict[str, str], dict[tuple[str, str], list[tuple[str, bool,
                                                                                   str]]]]:
    """Comments of the example scenario: per section, and per (section, key) a list of
    ``(value, commented_out, comment)`` (a key may be shown with several values)."""
    from pdamper.io.scenario import EXAMPLE_SCENARIO

    sections: dict[str, str] = {}
    keys: dict[tuple[str, str], list[tuple[str, bool, str]]] = {}
    section, last = "", None
    for line in EXAMPLE_SCENARIO.splitlines():
        if m := _SECTION.match(line):
            section = m.group(1)
            sections[section] = m.group(2) or ""
            last = ("section", section)
        elif (m := _MORE.match(line)) and last is not None:
            if last[0] == "section":
                sections[last[1]] += " " + m.group(1)
            else:
                value, commented, text = keys[last][-1]
                keys[last][-1] = (value, commented, f"{text} {m.group(1)}")
        elif m := _KEY.match(line):
            key = (section, m.group(2))
            keys.setdefault(key, []).append((m.group(3), bool(m.group(1)), m.group(4)))
            last = key
        else:
            last = None
    return sections, keys


def _description(info: FieldInfo, notes: list[tuple[str, bool, str]],
                 attribute_doc: str = "") -> str:
    if info.description:
        return " ".join(info.description.split())
    if attribute_doc:
        return _ROLE.sub(_role, attribute_doc)
    if not notes:
        return ""
    if len(notes) == 1:
        value, commented, text = notes[0]
        return text + (f" (e.g. `{value}`)" if commented else "")
    return "; ".join(f"`{value}`: {text}" for value, _, text in notes)


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _aliases(name: str, info: FieldInfo) -> list[str]:
    names = [name]
    alias = info.validation_alias
    if isinstance(alias, AliasChoices):
        names += [a for a in alias.choices if isinstance(a, str) and a not in names]
    elif isinstance(alias, str) and alias not in names:
        names.append(alias)
    if info.alias and info.alias not in names:
        names.append(info.alias)
    return names


def _doc(cls: type) -> str:
    doc = inspect.getdoc(cls) or ""
    if cls.__doc__ is None or doc == inspect.getdoc(BaseModel):
        return ""
    first = doc.split("\n\n")[0]
    return _ROLE.sub(_role, " ".join(first.split()))


def _role(match: re.Match) -> str:
    return "`" + match.group(1).replace(" ", "") + "`"


@dataclasses.dataclass(frozen=True)
class Declaration:
    """What the scenario declares of one key: the row of docs/scenario.md, and the help of
    every command-line option that sets the key (:mod:`pdamper.cli._common`)."""

    #: Dotted path of the key (``"excitation.frequency"``, ``"dem.safety"``).
    key: str
    #: Every name the key may be written under in its table (the first is the key's own).
    names: tuple[str, ...]
    #: Type as the page writes it (``"number"``, ``"integer (optional)"``, ...).
    type: str
    #: SI unit a bare number is read in; ``"1"`` for a dimensionless number, ``""`` for a
    #: value that is not a number.
    unit: str
    #: Default as the page writes it.
    default: str
    #: Allowed values (``"> 0"``, ``">= 0, <= 1"``, ``"any"``), ``""`` for a non-number.
    allowed: str
    #: Description.
    doc: str
    #: The allowed choices of a choice (``("exact", "gonthier", "tsuji")``), else empty.
    choices: tuple[str, ...] = ()

    @property
    def numeric(self) -> bool:
        """The key takes a number (possibly also something else)."""
        return any(w in self.type for w in ("number", "integer"))


def _choices(annotation: Any, info: FieldInfo) -> tuple[str, ...]:
    extra = info.json_schema_extra
    if isinstance(extra, dict) and extra.get("choices"):
        return tuple(str(c) for c in extra["choices"])  # type: ignore[union-attr]
    out: list[str] = []
    for member in _members(annotation):
        if get_origin(member) is Literal:
            out += [str(v) for v in get_args(member)]
    return tuple(out)


def _declarations_of(path: str, model: type[BaseModel], defaults: dict[str, Any],
                     notes: dict[tuple[str, str], list[tuple[str, bool, str]]]
                     ) -> list[Declaration]:
    section = path.split(".")[0]
    out = []
    attribute_docs = _attribute_docs(model)
    for name, info in model.model_fields.items():
        annotation = info.annotation
        type_name = _type_name(annotation) + (" (optional)" if _optional(annotation) else "")
        numeric = any(w in type_name for w in ("number", "integer"))
        unit = _unit(annotation, info) or ("1" if numeric else "")
        if info.is_required():
            default = "required"
        elif "." not in path and name in defaults:
            default = _format_default(defaults[name])
        else:
            default = _format_default(info.default, _unit(annotation, info))
        key_notes = notes.get((section, name), []) if "." not in path else []
        allowed = _constraint(annotation, info) or ("any" if numeric else "")
        out.append(Declaration(
            f"{path}.{name}", tuple(_aliases(name, info)), type_name, unit, default, allowed,
            _description(info, key_notes, attribute_docs.get(name, "")),
            _choices(annotation, info)))
    return out


def _table(declarations: list[Declaration]) -> list[str]:
    rows = ["| key | type | unit | default | allowed | description |",
            "|---|---|---|---|---|---|"]
    for d in declarations:
        rows.append("| " + " | ".join(_cell(c) for c in (
            ", ".join(f"`{k}`" for k in d.names), d.type, d.unit, d.default, d.allowed,
            d.doc)) + " |")
    return rows


def _tables() -> list[tuple[str, type[BaseModel], list[str]]]:
    """Every table of the scenario once: ``(path, model, every path it stands at)``."""
    from pdamper.io.scenario import Scenario

    top = {n for n, i in Scenario.model_fields.items()
           if not any(_is_model(m) for m in _members(i.annotation))}
    order: list[tuple[str, type[BaseModel]]] = []
    for name, info in Scenario.model_fields.items():
        if name not in top:
            _walk(name, info.annotation, order)
    paths: dict[type, list[str]] = {}
    for path, model in order:
        paths.setdefault(model, []).append(path)
    return [(path, model, list(dict.fromkeys(paths[model]))) for path, model in order
            if paths[model][0] == path]


@functools.cache
def declarations() -> dict[str, Declaration]:
    """Every key of the scenario by its dotted path (each path of a table that stands at
    several), with its aliases' paths: what the command line's help reads. docs/scenario.md
    renders the same rows (:func:`_declarations_of`) table by table; where a union's
    variant tables share a path (the COR models of ``[restitution]``), the page shows each
    and this table the first.

    >>> d = declarations()["excitation.frequency"]
    >>> d.unit, d.allowed
    ('Hz', '> 0')
    """
    example = _example_values()
    _, notes = _example_comments()
    out: dict[str, Declaration] = {}
    for path, model, paths in _tables():
        rows = _declarations_of(path, model, example.get(path, {}) if "." not in path
                                else {}, notes)
        for where in paths:
            for d in rows:
                row = d if where == path else dataclasses.replace(
                    d, key=where + d.key[len(path):])
                for name in d.names:
                    out.setdefault(f"{where}.{name}", row)
    for _, model, paths in _tables():  # a table's other names for its keys (flat [dem])
        aliases = getattr(model, "aliases", None)
        if not callable(aliases):
            continue
        for where in paths:
            for alias, canonical in aliases().items():
                if f"{where}.{canonical}" in out:
                    out.setdefault(f"{where}.{alias}", out[f"{where}.{canonical}"])
    return out


def declaration_of(key: str) -> Declaration:
    """The declaration of the scenario key ``key`` (a dotted path, or an alias of one);
    ``KeyError`` naming the key for one the scenario does not have."""
    try:
        return declarations()[key]
    except KeyError:
        raise KeyError(f"the scenario has no key {key!r}") from None


def reference() -> str:
    """The text of docs/scenario.md."""
    from pdamper.io.scenario import Scenario

    section_notes, notes = _example_comments()
    out = [_HEADER]
    top = {n: i for n, i in Scenario.model_fields.items()
           if not any(_is_model(m) for m in _members(i.annotation))}
    if top:
        out += ["## Top level", ""]
        rows = ["| key | type | default | description |", "|---|---|---|---|"]
        for name, info in top.items():
            rows.append(f"| `{name}` | {_type_name(info.annotation)} | "
                        f"{_format_default(info.default)} | "
                        f"{_cell(_description(info, notes.get(('', name), [])))} |")
        out += [*rows, ""]
    example = _example_values()
    for path, model, paths in _tables():  # each table once, under all its names
        variants = [m for m in _members(_field_annotation(Scenario, path)) if _is_model(m)]
        names = ", ".join(f"`[{p}]`" if "." not in p else f"`{p}`" for p in paths)
        title = names + (f" as {model.__name__}" if len(variants) > 1 else "")
        out += [f"{'##' if '.' not in path else '###'} {title}", ""]
        text = _doc(model) or (section_notes.get(path, "") if "." not in path else "")
        if text:
            out += [text[0].upper() + text[1:], ""]
        # per table, not by path: the variants of a union (a COR model's tables) share one
        out += [*_table(_declarations_of(path, model, example.get(path, {})
                                         if "." not in path else {}, notes)), ""]
    return "\n".join(out).rstrip("\n") + "\n"


def _walk(path: str, annotation: Any, order: list[tuple[str, type[BaseModel]]]) -> None:
    """Every table reachable from ``annotation`` at ``path``, depth first."""
    for model in _members(annotation):
        if _is_model(model):
            order.append((path, model))
            for name, info in model.model_fields.items():
                _walk(f"{path}.{name}", info.annotation, order)


def _field_annotation(root: type[BaseModel], path: str) -> Any:
    annotation: Any = root
    for part in path.split("."):
        model = next(m for m in _members(annotation) if _is_model(m)
                     and part in m.model_fields)
        annotation = model.model_fields[part].annotation
    return annotation


def main(argv: typing.Sequence[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    text = reference()
    if len(args) == 2 and args[0] == "--write":
        with open(args[1], "w", encoding="utf-8") as f:
            f.write(text)
        return 0
    if len(args) == 2 and args[0] == "--check":
        with open(args[1], encoding="utf-8") as f:
            same = f.read() == text
        if not same:
            print(f"{args[1]} is out of date: python -m pdamper.io.scenario_reference "
                  f"--write {args[1]}", file=sys.stderr)
        return 0 if same else 1
    if args:
        print("usage: python -m pdamper.io.scenario_reference [--write PATH | --check PATH]",
              file=sys.stderr)
        return 2
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
