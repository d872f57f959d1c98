"""Per-point result files of a sweep: written atomically as each point finishes.

A store is a directory of small JSON files, one per finished point, named by the point's
key: a hash of the point function's name, the sweep's context (everything the results
depend on besides the point's own parameters: model inputs, pdamper version, seeds) and the
point's parameters. A point whose file exists is not computed again; changing any input
changes the key, so stale files are never reused (they stay until the directory is removed).
Every file goes through :func:`pdamper.files.atomic_write`: a sweep stopped at any moment
leaves complete files or none.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pdamper.errors import InputError
from pdamper.files import atomic_write_text

#: Version of the file layout (part of every key).
STORE_FORMAT = 1


def plain(value: Any) -> Any:
    """``value`` as plain JSON-able Python (numpy scalars and arrays to numbers and lists).

    >>> import numpy as np
    >>> plain({"a": np.float64(0.5), "b": np.arange(2), "c": (np.int8(3), True)})
    {'a': 0.5, 'b': [0, 1], 'c': [3, True]}
    """
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain(v) for v in value]
    if hasattr(value, "tolist"):  # numpy scalars (np.float64 is a float) and arrays
        return plain(value.tolist())
    if isinstance(value, bool | int | float | str) or value is None:
        return value
    if hasattr(value, "item"):
        return plain(value.item())
    raise InputError("sweep", f"point values must be numbers, strings, lists or dicts, "
                     f"got {type(value).__name__}")


def function_name(function) -> str:
    """Dotted name of a point function (of the wrapped function for a partial)."""
    inner = getattr(function, "func", function)
    return f"{getattr(inner, '__module__', '')}.{getattr(inner, '__qualname__', type(inner).__name__)}"


def point_key(function, context: Mapping | None, params: Mapping) -> str:
    """16 hex digits identifying a point: function name, context and parameters.

    >>> point_key(abs, {"v": 1}, {"x": 1.0}) == point_key(abs, {"v": 1}, {"x": 1.0})
    True
    >>> point_key(abs, {"v": 1}, {"x": 1.0}) == point_key(abs, {"v": 2}, {"x": 1.0})
    False
    """
    text = json.dumps({"format": STORE_FORMAT, "function": function_name(function),
                       "context": plain(dict(context or {})), "params": plain(dict(params))},
                      sort_keys=True, allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class PointStore:
    """The directory of a sweep's per-point results.

    Parameters
    ----------
    directory
        Created (with its parents' existence checked) on first use.
    """

    def __init__(self, directory: str | Path):
        self.directory = Path(directory)
        if self.directory.exists() and not self.directory.is_dir():
            raise InputError("store", f"{self.directory} exists and is not a directory")
        if not self.directory.parent.is_dir():
            raise InputError("store", f"directory does not exist: {self.directory.parent}")

    def path(self, key: str) -> Path:
        return self.directory / f"{key}.json"

    def load_all(self) -> dict[str, dict]:
        """Every readable record in the store, by key (unreadable files are skipped: they
        cannot exist after an atomic write, but a user may have edited one)."""
        out: dict[str, dict] = {}
        if not self.directory.is_dir():
            return out
        for p in self.directory.glob("*.json"):
            try:
                rec = json.loads(p.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                continue
            if isinstance(rec, dict) and rec.get("key") == p.stem:
                out[p.stem] = rec
        return out

    def save(self, record: Mapping) -> Path:
        """Write one point's record atomically."""
        self.directory.mkdir(exist_ok=True)
        rec = plain(dict(record))
        return atomic_write_text(self.path(rec["key"]), json.dumps(rec, allow_nan=True) + "\n")

    def remove(self) -> None:
        """Delete the store's files and the directory (after the final result is written)."""
        if not self.directory.is_dir():
            return
        for p in self.directory.iterdir():
            if p.is_file() and (p.suffix == ".json" or p.name.endswith(".tmp")):
                p.unlink()
        if not any(self.directory.iterdir()):
            self.directory.rmdir()

    def __len__(self) -> int:
        return len(list(self.directory.glob("*.json"))) if self.directory.is_dir() else 0

