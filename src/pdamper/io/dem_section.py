"""The scenario's ``[dem]`` section (:class:`DEMSpec`): the settings of the DEM damper
(:class:`~pdamper.models.settings.DEMSettings`) one table per concern, with the flat keys
and the old table names as aliases, and the constant CORs of the damper."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, ValidationError, model_serializer, model_validator
from pydantic.fields import FieldInfo

from pdamper.dem.settings import Settings
from pdamper.errors import InputError
from pdamper.io.quantities import Restitution
from pdamper.models.settings import CONCERN_NAMES, FIELD, FLAT, FLAT_NAME, DEMSettings
from pdamper.parameters import vertical_dampers_paper as paper
from pdamper.units import parse_quantity

_D = paper.PAPER_DAMPER


#: Settings of the DEM damper that the scenario takes from another section.
DEM_SET_ELSEWHERE = {"gravity": "excitation.gravity"}
#: Keys of ``[dem]`` that are not settings of the DEM damper: the constant CORs of the damper
#: (or ``[restitution]``).
DEM_SCENARIO_ONLY = ("restitution_pp", "restitution_pw")
#: ``[dem.<table>]``: the settings of one concern in a table of its own, the canonical form
#: (:data:`~pdamper.models.settings.CONCERN_NAMES`); flat ``[dem]`` keys and the old table
#: names of :data:`DEM_TABLE_ALIASES` are aliases.
DEM_TABLES: dict[str, type[Settings]] = dict(CONCERN_NAMES)
#: Old names of the ``[dem.<table>]`` tables -> their canonical name.
DEM_TABLE_ALIASES = {"steady_state": "steady", "accuracy_target": "accuracy"}


def _elsewhere(name: str) -> str:
    section, _, key = DEM_SET_ELSEWHERE[name].partition(".")
    return f"is set by [{section}] {key}"


class DEMSpec(DEMSettings):
    """Options of the DEM model (``pdamper dem``, ``--model dem``), one table per concern:
    ``[dem.plan]``, ``[dem.steady]``, ``[dem.accuracy]``, ``[dem.contact]`` and
    ``[dem.engine]`` (:class:`~pdamper.models.settings.DEMSettings`; g is ``[excitation]
    gravity``, the seed and the transient tolerance are ``[dem.plan]``'s). Each key may
    also be written flat in ``[dem]`` (``cycles = 8`` is ``[dem.plan] cycles = 8``), the
    old tables ``[dem.steady_state]`` and ``[dem.accuracy_target]`` are
    ``[dem.steady]`` and ``[dem.accuracy]``; a key given twice is an error, a command-line
    option replaces the key in whichever form the file gives it. ``restitution_pp`` and
    ``restitution_pw``: constant CORs (or ``[restitution]``)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=False)

    restitution_pp: Restitution = _D.restitution_pp.e  # type: ignore[union-attr]
    restitution_pw: Restitution = _D.restitution_pw.e  # type: ignore[union-attr]

    @classmethod
    def _edge_concern(cls, concern: str, values: dict[str, Any]) -> dict[str, Any]:
        decls = DEM_TABLES[concern].declarations()
        out = {}
        for name, value in values.items():
            unit = decls[name]["unit"] if name in decls else ""
            out[name] = (parse_quantity(value, unit, name)
                         if unit and value is not None else value)
        return out

    @classmethod
    def canonical(cls, data: dict[str, Any]) -> dict[str, Any]:
        """``data`` as given in the file with the old table names made canonical; refuses
        the settings another section sets (:data:`DEM_SET_ELSEWHERE`)."""
        out: dict[str, Any] = {}
        for key, value in data.items():
            table = DEM_TABLE_ALIASES.get(key, key)
            if table in DEM_TABLES and isinstance(value, dict):
                if table in out:
                    raise InputError("dem", f"[dem.{table}] given twice (also as [dem.{key}])")
                for name in value:
                    if name in DEM_SET_ELSEWHERE:
                        raise InputError(cls.prefix + name, _elsewhere(name))
                out[table] = value
            elif key not in FLAT and key not in DEM_SCENARIO_ONLY and "__" not in key \
                    and key not in DEM_TABLES:
                raise InputError(cls.prefix + key, "unknown key (check the spelling; `pdamper "
                                 "example-scenario` lists the keys)")
            elif key in DEM_SET_ELSEWHERE:
                raise InputError(cls.prefix + key, _elsewhere(key))
            else:
                out[key] = value
        return out

    @model_validator(mode="before")
    @classmethod
    def _tables(cls, data: Any) -> Any:
        if not isinstance(data, dict):
            return data
        return cls.concerns_of(cls.canonical(data))

    def __init__(self, **data: Any) -> None:
        try:
            BaseModel.__init__(self, **data)
        except ValidationError as exc:
            from pdamper.io.reading import first_error

            raise first_error(exc) from None

    @classmethod
    def override(cls, section: dict[str, Any], name: str, value: Any) -> None:
        """Set setting ``name`` (a flat name, ``concern.name`` or ``concern__name``) to
        ``value`` in the ``[dem]`` table ``section`` as read from a file, replacing it in
        whichever form the file gives it (flat, ``[dem.<concern>]`` or an old table name):
        a command-line option overrides the file."""
        aliases = cls.aliases()
        canonical = aliases.get(name) or aliases.get(name.replace(".", "__")) or name
        if canonical not in DEMSettings.declarations():
            section[name] = value  # not a setting: validated (and refused) as given
            return
        concern, _, key = canonical.partition(".")
        flat = FLAT_NAME[(concern, key)]
        section.pop(flat, None)
        tables = [t for t in (concern, *(a for a, c in DEM_TABLE_ALIASES.items()
                                         if c == concern)) if isinstance(section.get(t), dict)]
        for table in tables:
            section[table].pop(key, None)
            section[table].pop(flat, None)
        # into the table the file writes the concern in (an old name stays the one table)
        target = tables[0] if tables else concern
        section.setdefault(target, {})
        if not isinstance(section[target], dict):
            raise InputError(f"dem.{target}", "must be a table")
        section[target][key] = value

    @classmethod
    def declarations(cls) -> dict[str, dict]:
        """Every key of the section under its canonical dotted name (``"engine.
        gear_tolerance"``, ``"restitution_pp"``) with ``unit``, ``kind``, range, ``doc`` and
        ``default``; the other names are in :meth:`aliases`."""
        out = {k: v for k, v in DEMSettings.declarations().items()
               if v["name"] not in DEM_SET_ELSEWHERE}
        for name in DEM_SCENARIO_ONLY:
            f = cls.model_fields[name]
            out[name] = {"unit": "", "kind": "number", "low": 0.0, "high": 1.0,
                         "low_inclusive": True, "high_inclusive": True, "choices": [],
                         "infinite": False, "none": "", "doc": f.description or
                         "Constant coefficient of restitution (or [restitution]).",
                         "default": f.default, "concern": "", "name": name}
        return out

    @classmethod
    def aliases(cls) -> dict[str, str]:
        """Alias -> canonical dotted name: flat keys (``cycles`` -> ``plan.cycles``), the old
        tables (``steady_state.steady_windows`` -> ``steady.windows``) and
        ``concern__name``."""
        decls = cls.declarations()
        out = {k: v for k, v in DEMSettings.aliases().items() if v in decls}
        for old, new in DEM_TABLE_ALIASES.items():
            for k, decl in decls.items():
                if k.startswith(new + "."):
                    out[f"{old}.{k.partition('.')[2]}"] = k
                    out[f"{old}.{decl['name']}"] = k  # the old tables' flat names
        return out

    @model_serializer(mode="wrap")
    def _flat_dump(self, handler: Any) -> dict[str, Any]:
        # the section's values written flat, under the keys the JSON outputs and the map
        # files' keys have always used
        data = handler(self)
        out = {name: data[name] for name in DEM_SCENARIO_ONLY}
        for name, concern in FLAT.items():
            if name not in DEM_SET_ELSEWHERE:
                out[name] = data[concern][FIELD[name]]
        return out

    @classmethod
    def flat_fields(cls) -> dict[str, FieldInfo]:
        """Every key of the section by its flat name (the constant CORs included)."""
        return {**{n: cls.model_fields[n] for n in DEM_SCENARIO_ONLY},
                **{n: f for n, f in DEMSettings.flat_fields().items()
                   if n not in DEM_SET_ELSEWHERE}}

    def options(self) -> dict:
        """Keyword arguments of :class:`pdamper.models.DEMDamper`: the five concerns."""
        return {name: getattr(self, name) for name in DEM_TABLES}
