"""Reading a scenario file: its TOML text, the files it names (relative to it), and the
validation's errors as one line naming the field (:class:`~pdamper.errors.InputError`).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from pydantic import ValidationError

from pdamper import resources
from pdamper.errors import InputError
from pdamper.io.restitution import MODELS as COR_MODELS
from pdamper.io.restitution import resolve_files


def read_toml(p: Path) -> dict:
    """The parsed TOML of the scenario file ``p``: a regular UTF-8 file of at most
    :data:`pdamper.resources.MAX_SCENARIO_BYTES` bytes."""
    if not p.exists():
        raise InputError("scenario", f"file not found: {p}")
    if not p.is_file():
        raise InputError("scenario", f"{p} is not a regular file; give a scenario file")
    try:
        size = p.stat().st_size
        if size > resources.MAX_SCENARIO_BYTES:
            raise InputError("scenario", f"{p} has {size} bytes; a scenario file describes one "
                             f"damper in at most {resources.MAX_SCENARIO_BYTES} bytes")
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError("scenario", f"cannot read {p}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise InputError("scenario", f"{p} is not UTF-8 text") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("scenario", f"malformed TOML in {p}: {exc}") from None
    except RecursionError:
        raise InputError("scenario", f"malformed TOML in {p}: tables or arrays nested too "
                         f"deeply") from None


def resolve_paths(data: dict, base: Path) -> None:
    """Make the files a scenario names absolute, a relative one taken relative to the
    scenario file's directory ``base`` (``data`` changed in place): the COR tables, model 2's
    map (``[fields] file``), the modes (``[structure] modes``) and the load histories."""
    resolve_files(data, base)
    for section, keys in (("fields", ("file",)), ("structure", ("modes",)),
                          ("load", ("force", "base_acceleration"))):
        table = data.get(section)
        if not isinstance(table, dict):
            continue
        for key in keys:
            if isinstance(table.get(key), str) and not Path(table[key]).expanduser().is_absolute():
                table[key] = str((base / table[key]).resolve())


def first_error(exc: ValidationError) -> InputError:
    """The first error of a scenario's validation as one line naming its field (the
    key's dotted path), without pydantic's internal names."""
    errors = exc.errors()
    # a table where a union (``str | MaterialSpec``) allows a name or a table: the table's
    # own error names the sub-key, not "should be a valid string"
    err = next((e for e in errors if not (e["type"] == "string_type"
                                          and isinstance(e.get("input"), dict))), errors[0])
    cause = (err.get("ctx") or {}).get("error")
    if isinstance(cause, InputError):  # raised by a section's own checks: names its field
        return cause
    loc = ".".join(str(p) for p in err["loc"]
                   if str(p) not in ("str", "MaterialSpec", *COR_MODELS)
                   and not str(p).startswith("function-"))
    msg = err["msg"].removeprefix("Value error, ")
    union = [e for e in errors if e["loc"][:-1] == err["loc"][:-1]]
    if err["type"] == "string_type" and any(e["type"] == "model_type" for e in union):
        msg = (f"must be a name (e.g. \"S235\") or an inline table {{ name, youngs_modulus, "
               f"poisson_ratio, density }}, got {repr(err.get('input'))[:60]}")
    if err["type"] == "extra_forbidden":
        msg = "unknown key (check the spelling; `pdamper example-scenario` lists the keys)"
    elif "input" in err and err["type"] != "missing" and repr(err["input"]) not in msg \
            and "got" not in msg:
        got = repr(err["input"])
        msg = f"{msg} (got {got if len(got) <= 60 else got[:57] + '...'})"
    return InputError(loc or "scenario", msg)
