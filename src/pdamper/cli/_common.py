"""Helpers shared by the CLI commands: JSON output and scenario loading."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np


def _default(o: Any):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if hasattr(o, "value") and hasattr(o, "name"):  # enums
        return o.value
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON serialisable: {type(o)}")


def _clean(o: Any):
    """Replace non-finite floats by None so that the output is strict JSON."""
    if isinstance(o, float) and not math.isfinite(o):
        return None
    if isinstance(o, dict):
        return {k: _clean(v) for k, v in o.items()}
    if isinstance(o, list | tuple):
        return [_clean(v) for v in o]
    return o


def dumps(payload: dict) -> str:
    """Strict JSON text of a result payload."""
    return json.dumps(_clean(json.loads(json.dumps(payload, default=_default))), indent=2)


def emit(payload: dict, as_json: bool, human: str | None = None) -> None:
    """Print ``payload`` as JSON (``--json``) or a human-readable text."""
    if as_json or human is None:
        sys.stdout.write(dumps(payload) + "\n")
    else:
        sys.stdout.write(human.rstrip() + "\n")
