"""Helpers shared by the CLI commands: options, JSON output, scenario loading, output files.

Output paths are taken as text (``--out ""`` and ``--out newdir/`` must stay visible) and
checked by :mod:`pdamper.files` before any computation; every result goes through its
writer, standard output included.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, overload

import numpy as np
import typer

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from pdamper.io.scenario import Scenario

#: A help text that names the scenario key its option sets (:func:`key_help`): readable as
#: it stands (shell completion shows it so), completed from the declaration in help.
_KEY_HELP = re.compile(r"(?s)(?P<note>.*) \(scenario key (?P<key>[\w.]+)\)")


def key_help(key: str, note: str = "") -> str:
    """The help text of an option that sets the scenario key ``key``: the key's declaration
    (:func:`pdamper.io.scenario_reference.declaration_of`: its unit, allowed values and
    choices, and its description where ``note`` is empty) completes it when help is shown
    (:func:`declared_help`), so that the unit, range and choices the command line shows are
    the declaration's, as docs/scenario.md shows them. ``note``: what the option itself
    adds (an example of its text, what each choice means)."""
    return f"{note} (scenario key {key})"


def help_key(text: str | None) -> str | None:
    """The scenario key a help text of :func:`key_help` names (None for any other)."""
    match = _KEY_HELP.fullmatch(text or "")
    return None if match is None else match["key"]


def declared_help(text: str) -> str:
    """A help text of :func:`key_help` completed from the key's declaration: the
    description, the unit in brackets, the allowed values or the choices, and the key
    (``"Excitation frequency, e.g. '10Hz' [Hz], > 0 (scenario: excitation.frequency)."``);
    any other text as it is."""
    match = _KEY_HELP.fullmatch(text or "")
    if match is None:
        return text
    from pdamper.io.scenario_reference import declaration_of

    key, note = match["key"], match["note"]
    d = declaration_of(key)
    what = (note or d.doc.split(". ")[0]).rstrip(". ")
    unit = f" [{d.unit}]" if d.unit not in ("", "1") else ""
    allowed = (f", one of {', '.join(d.choices)}" if d.choices
               else f", {d.allowed}" if d.allowed and d.allowed != "any" else "")
    return f"{what}{unit}{allowed} (scenario: {d.key})."


ModelOpt = Annotated[str | None, typer.Option(
    "--model", "--damper", help=key_help("simulation.model", "Damper model (fidelity)"))]
#: The structure and the load histories, as the scenario's keys (simulate, optimize, frf).
ModesOpt = Annotated[Path | None, typer.Option("--modes", help=key_help(
    "structure.modes", "The structure's modes (CSV with unit headers: 'frequency [Hz], "
    "damping ratio [1], damper [kg^-0.5]'; docs/structure.md) instead of the 1-DOF"))]
LoadOpt = Annotated[Path | None, typer.Option("--load", help=key_help(
    "load.force", "Force history on the structure (CSV with unit headers, e.g. 'time [s], "
    "force [N]'; docs/forced.md)"))]
BaseAccelerationOpt = Annotated[Path | None, typer.Option("--base-acceleration", help=key_help(
    "load.base_acceleration", "Base-acceleration history (CSV with unit headers, e.g. "
    "'time [s], acceleration [m/s^2]')"))]
TailOpt = Annotated[str | None, typer.Option("--tail", help=key_help(
    "load.tail", "Free vibration after the load record, e.g. '1s' (default 0)"))]
UnbalanceOpt = Annotated[str | None, typer.Option("--unbalance", help=key_help(
    "load.unbalance", "Rotating unbalance m e at the load point, e.g. '1.76kg*mm', driven by "
    "--run-up"))]
RunUpOpt = Annotated[str | None, typer.Option("--run-up", help=key_help(
    "load.run_up", "Speed ramp of --unbalance 'start:stop:duration', e.g. "
    "'400rpm:2400rpm:20s' (a run-down: start above stop; a constant speed: equal)"))]
LoadAtOpt = Annotated[str | None, typer.Option("--load-at", help=key_help(
    "load.at", "Where a force acts: load (the structure's load point) or damper"))]
ScenarioOpt = Annotated[Path | None, typer.Option("--scenario", "-s", help="Scenario TOML file.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON for scripts.")]

ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Run although the implied memory or time is above the limits "
    "(see pdamper.resources); never beyond what this machine can hold.")]


def _default(o: Any) -> Any:
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if hasattr(o, "value") and hasattr(o, "name"):  # enums
        return o.value
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON serialisable: {type(o)}")


def _clean(o: Any) -> Any:
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
    from pdamper.files import write_stdout

    write_stdout(dumps(payload) + "\n" if as_json or human is None else human.rstrip() + "\n")


def load(scenario: Path | None, *, runs: tuple[str, ...] = (), model: str | None = None,
         force: bool = False, **overrides: Any) -> Scenario:
    """Scenario from ``--scenario`` with the command-line options applied on top, and what
    ``runs`` imply checked (:func:`pdamper.runs.resources.check_runs`).

    ``overrides`` maps ``"section__key"`` to the option's value (None: not given).
    """
    from pdamper.io.scenario import load_scenario
    from pdamper.runs.resources import check_runs

    sc = load_scenario(scenario, {k.replace("__", "."): v for k, v in overrides.items()})
    return check_runs(sc, runs, model, force)


def metadata(scenario: Any, **extra: Any) -> dict:
    """Inputs, version (and seed etc. in ``extra``) recorded with every result."""
    from pdamper import __version__

    out = {"inputs": scenario.model_dump(mode="json"), "version": __version__, **extra}
    uncertain: Sequence[Any] = getattr(scenario, "uncertain_inputs", tuple)()
    if uncertain:  # "value +- sd": the inputs hold the nominal value, this the rest
        out["uncertain_inputs"] = [u.as_dict() for u in uncertain]
    return out


@overload
def check_output(path: str, field: str = ...) -> Path: ...
@overload
def check_output(path: None, field: str = ...) -> None: ...
@overload
def check_output(path: str | None, field: str = ...) -> Path | None: ...
def check_output(path: str | None, field: str = "out") -> Path | None:
    """The file ``--out`` names, checked before any computation (None: not given)."""
    from pdamper.files import check_file_target

    return None if path is None else check_file_target(path, field)


@overload
def check_output_directory(path: str, field: str = ...) -> Path: ...
@overload
def check_output_directory(path: None, field: str = ...) -> None: ...
@overload
def check_output_directory(path: str | None, field: str = ...) -> Path | None: ...
def check_output_directory(path: str | None, field: str = "out") -> Path | None:
    """The directory ``--out``/``--vtk`` names, checked before any computation."""
    from pdamper.files import check_directory_target

    return None if path is None else check_directory_target(path, field)


#: Figure formats of every ``--plot``, by file suffix: the suffix names the format written
#: (matplotlib; JPEG through Pillow, a dependency of matplotlib).
PLOT_FORMATS = {".png": "png", ".pdf": "pdf", ".svg": "svg", ".jpg": "jpeg", ".jpeg": "jpeg"}



def plot_param(what: str) -> Any:
    """The ``--plot`` option of a command whose figure shows ``what`` (checked by
    :func:`check_plot`, written by :func:`write_figure`), as the metadata of
    ``Annotated[str | None, plot_param(what)]`` (an annotation a type checker reads)."""
    return typer.Option("--plot", help=f"Figure file of {what}; its suffix names the format "
                                       f"({', '.join(PLOT_FORMATS)}).")


def plot_option(what: str) -> Any:
    """``Annotated[str | None, plot_param(what)]``, built at run time (type checkers cannot
    read it: prefer the spelled-out form)."""
    return Annotated[str | None, plot_param(what)]


def check_plot(path: str | None, field: str = "plot") -> Path | None:
    """The figure file ``--plot`` names, checked before any computation like ``--out``,
    with a suffix of :data:`PLOT_FORMATS` (None: not given)."""
    from pdamper.errors import InputError

    target = check_output(path, field)
    if target is not None and target.suffix.lower() not in PLOT_FORMATS:
        raise InputError(field, f"must end in {', '.join(PLOT_FORMATS)} (the figure's format), "
                         f"got {target.name!r}")
    return target


def write_figure(fig: Figure, path: Path, dpi: int = 110, field: str = "plot") -> Path:
    """Write the matplotlib ``fig`` to ``path`` (checked by :func:`check_plot`) in the
    format its suffix names, atomically: rendered in memory, then written by
    :func:`pdamper.files.atomic_write_bytes`, so that a full device ends as for every
    other output, naming the option (``--plot``)."""
    import io

    from pdamper.files import atomic_write_bytes

    buf = io.BytesIO()
    fig.savefig(buf, format=PLOT_FORMATS[path.suffix.lower()], dpi=dpi)
    return atomic_write_bytes(path, buf.getbuffer(), field)


def figure_last(draw: Callable[[], Figure], path: Path, dpi: int = 110,
                field: str = "plot") -> Path:
    """Draw a figure with ``draw()`` and write it to ``path`` (:func:`write_figure`), called
    after the command's results (JSON, NetCDF) were written: a figure that cannot be drawn
    leaves them and ends as an unwritten output (one line naming ``field``, status 1),
    not as a traceback that loses the computed answer."""
    from pdamper.errors import OutputError, PdamperError

    try:
        fig = draw()
    except PdamperError:
        raise
    except Exception as exc:  # noqa: BLE001 - any drawing failure: the results stand
        raise OutputError(field, f"the figure {path.name} could not be drawn "
                          f"({type(exc).__name__}: {exc}); the results were written before "
                          "it") from exc
    return write_figure(fig, path, dpi, field)


def flag_name(flag: str) -> str:
    """The parameter of a flag: ``"--free-flight/--no-free-flight"`` -> ``"free_flight"``."""
    return flag.split("/")[0].removeprefix("--").replace("-", "_")


def with_flags(rows: tuple[tuple[str, str, type, str], ...]
               ) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Give a command one option per row ``(flag, scenario key, type, help)`` and hand their
    values to it as ``flags`` (``{"dem.safety": 0.01, ...}``, None: not given): the flags of
    scenario keys are declared in one table, not as parameters one by one. The command's
    own parameters follow them."""
    import functools
    import inspect

    def wrap(func: Callable[..., Any]) -> Callable[..., Any]:
        own = [p for p in inspect.signature(func, eval_str=True).parameters.values()
               if p.name != "flags"]
        made = [inspect.Parameter(flag_name(flag), inspect.Parameter.KEYWORD_ONLY,
                                  default=None, annotation=Annotated[
                                      kind | None, typer.Option(flag, help=key_help(
                                          key, text))])
                for flag, key, kind, text in rows]
        keys = {flag_name(flag): key for flag, key, _, _ in rows}

        @functools.wraps(func)
        def command(**kwargs: Any) -> Any:
            flags = {key: kwargs.pop(name) for name, key in keys.items()}
            return func(flags=flags, **kwargs)

        params = [*made, *(p.replace(kind=inspect.Parameter.KEYWORD_ONLY) for p in own)]
        command.__signature__ = inspect.Signature(params)  # type: ignore[attr-defined]  # (read by typer)
        command.__annotations__ = {p.name: p.annotation for p in params}
        del command.__wrapped__  # typer reads __signature__, not the wrapped function's
        return command

    return wrap
