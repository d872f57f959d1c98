"""Helpers shared by the CLI commands: options, JSON output, scenario loading, output files."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

ScenarioOpt = Annotated[Path | None, typer.Option("--scenario", "-s", help="Scenario TOML file.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON for scripts.")]
ModelOpt = Annotated[str | None, typer.Option(
    "--model", "--damper", help="Damper model (fidelity): analytic or dem.")]


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


def load(scenario: Path | None, **overrides):
    """Scenario from ``--scenario`` with the command-line options applied on top.

    ``overrides`` maps ``"section__key"`` to the option's value (None: not given).
    """
    from pdamper.io.scenario import load_scenario

    return load_scenario(scenario, {k.replace("__", "."): v for k, v in overrides.items()})


def metadata(scenario, **extra) -> dict:
    """Inputs, version (and seed etc. in ``extra``) recorded with every result."""
    from pdamper import __version__

    return {"inputs": scenario.model_dump(mode="json"), "version": __version__, **extra}


def check_output(path: Path | None, field: str = "out") -> Path | None:
    """Refuse an output file whose directory is missing, before any computation."""
    from pdamper.errors import InputError

    if path is None:
        return None
    path = Path(path)
    if not path.parent.is_dir():
        raise InputError(field, f"directory does not exist: {path.parent}")
    if path.is_dir():
        raise InputError(field, f"{path} is a directory; give a file name")
    return path


def write_atomic(path: Path, writer) -> Path:
    """Write an output file through the one atomic writer (:mod:`pdamper.files`)."""
    from pdamper.files import atomic_write

    check_output(path)
    return atomic_write(path, writer)
