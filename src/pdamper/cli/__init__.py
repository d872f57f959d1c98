"""The ``pdamper`` command line: one entry point, one module per command.

Commands are registered explicitly in :func:`_register` (a missing module is an import
error, not a silently absent command). Errors a user can cause are printed as one line
naming the field and what is allowed, with exit status 2; a result that cannot be written
ends with one line and status 1; Ctrl-C and SIGTERM end with ``interrupted`` and status 130
or 143 (:mod:`pdamper.cli._signals`). The commands only parse, call the library and format
its results; what their inputs imply is judged before they run
(:mod:`pdamper.resources`), and every output goes through :mod:`pdamper.files`.
"""

from __future__ import annotations

import errno
import sys
from typing import Annotated

import typer
from typer.core import TyperCommand, TyperGroup

from pdamper.cli import _quiet


def _untyped(params: list) -> list:
    """Options without the column of type names (``<str>``, ``<bool>``) that typer's help
    shows: an empty metavar is what that column prints (the help text says what a value
    is; click's own error messages name the option, not the metavar)."""
    for p in params:
        if p.metavar is None:
            p.metavar = ""
    return params


class _Group(TyperGroup):
    """The ``pdamper`` group: help without type names."""

    def get_params(self, ctx):
        return _untyped(super().get_params(ctx))


class _Command(TyperCommand):
    """A command: help without type names, and the group's ``--quiet`` accepted after the
    command name too (``pdamper map ... --quiet``), the one option declared once."""

    def get_params(self, ctx):
        params = super().get_params(ctx)
        root = ctx.find_root().command
        if root is not self:  # before --help, which click puts last
            params = [*(p for p in params if p.name != "help"),
                      *(p for p in root.params if p.name == "quiet"),
                      *(p for p in params if p.name == "help")]
        return _untyped(params)


app = typer.Typer(
    name="pdamper",
    help="Design particle dampers for vertically vibrating structures.",
    cls=_Group,
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_enable=False,
)


def _print_version(value: bool) -> None:
    if value:
        from pdamper import __version__
        from pdamper.files import write_stdout

        write_stdout(f"pdamper {__version__}\n")
        raise typer.Exit(0)


@app.callback()
def _options(
    version: Annotated[bool, typer.Option(
        "--version", callback=_print_version, is_eager=True, expose_value=False,
        help="Print the version ('pdamper X.Y.Z') and exit.")] = False,
    quiet: Annotated[bool, typer.Option(
        "--quiet", "-q", callback=_quiet.set_quiet, is_eager=True, expose_value=False,
        help="Nothing on stderr but errors: no progress display, notes or warnings "
             "(results and --json output are unchanged). Before or after the command "
             "name.")] = False,
) -> None:
    """Design particle dampers for vertically vibrating structures."""


_registered = False


def _register() -> None:
    global _registered
    if _registered:
        return
    from pdamper.cli import (
        analytic,
        cor,
        cor_sensitivity,
        dem,
        map,
        optimize,
        paper,
        scenario,
        simulate,
    )

    for name, function in (("analytic", analytic.analytic), ("map", map.map_),
                           ("simulate", simulate.simulate), ("optimize", optimize.optimize),
                           ("dem", dem.dem), ("paper", paper.paper),
                           ("example-scenario", scenario.example_scenario), ("cor", cor.cor),
                           ("cor-sensitivity", cor_sensitivity.cor_sensitivity)):
        app.command(name, cls=_Command)(function)
    _registered = True


def _say(line: str, status: int) -> int:
    """Print one line on stderr; returns ``status``."""
    try:
        sys.stderr.write(line + "\n")
        sys.stderr.flush()
    except (OSError, ValueError):  # stderr closed as well: the status still tells
        pass
    return status


def _usage(exc: Exception) -> str:
    """One line for a usage error of click (vendored by recent typer as typer._click):
    a bad value names the option, as input errors name their field."""
    param = getattr(exc, "param", None)
    raw = getattr(exc, "message", None)
    opts = getattr(param, "opts", None)
    if opts and raw:
        return f"error: {max(opts, key=len)}: {raw}"
    return f"error: {exc.format_message()}"


def _stdout_is_null() -> bool:
    """Standard output is /dev/null (where rich and click put it after a broken pipe)."""
    import os

    try:
        a, b = os.fstat(sys.stdout.fileno()), os.stat(os.devnull)
    except (OSError, ValueError, AttributeError):
        return False
    return (a.st_ino, a.st_dev, a.st_rdev) == (b.st_ino, b.st_dev, b.st_rdev)


#: Errors of a failed write to a stream (what click lets through from its help text).
_STREAM_ERRNOS = {errno.EPIPE, errno.ENOSPC, errno.EIO, errno.EDQUOT, errno.EFBIG}


def _run(argv: list[str] | None) -> int:
    from pdamper.errors import OutputError, PdamperError
    from pdamper.files import stdout_error

    _register()
    was_null = _stdout_is_null()
    try:
        with _quiet.scope():
            status = app(args=argv, standalone_mode=False)
    except OutputError as exc:
        return _say(f"error: {exc}", 1)
    except PdamperError as exc:
        return _say(f"error: {exc}", 2)
    except MemoryError:
        return _say("error: memory: this machine ran out of memory; lower the sizes", 1)
    except SystemExit as exc:
        # rich (help text) and click end this way on a broken pipe, stdout moved to /dev/null
        wrapped = getattr(sys.stdout, "wrapped", None)
        if type(sys.stdout).__name__ == "PacifyFlushWrapper" and wrapped is not None:
            sys.stdout = wrapped
            sys.stderr = getattr(sys.stderr, "wrapped", sys.stderr)
        if exc.code == 1 and not was_null and _stdout_is_null():
            return _say(f"error: {stdout_error(BrokenPipeError(errno.EPIPE, 'pipe'))}", 1)
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except OSError as exc:  # help and usage text of click on a full device
        if exc.errno not in _STREAM_ERRNOS:
            raise
        return _say(f"error: {stdout_error(exc)}", 1)
    except Exception as exc:
        # usage errors of click: duck-typed
        message = getattr(exc, "format_message", None)
        code = getattr(exc, "exit_code", None)
        if callable(message) and isinstance(code, int):
            return _say(_usage(exc), code) if message() else code  # "": help shown
        if type(exc).__name__ == "Abort":
            return 1
        raise
    if status == 130:  # typer's answer to a KeyboardInterrupt it caught itself
        return _say("interrupted", 130)
    return status if isinstance(status, int) else 0


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit status.

    0: done; 1: a result could not be written (a full device, a closed pipe); 2: bad input
    or usage, one line naming the field; 128 + signal (130 Ctrl-C, 143 SIGTERM):
    interrupted, one line ``interrupted``.
    """
    from pdamper.cli._signals import raising_interrupts
    from pdamper.errors import Interrupted

    try:
        with raising_interrupts():
            return _run(argv)
    except Interrupted as exc:
        return _say("interrupted", 128 + exc.signum)
    except KeyboardInterrupt:
        return _say("interrupted", 130)


def entry() -> None:  # pragma: no cover - run as a process by the tests
    """The console script: run :func:`main` and end the process with its status.

    The exit handlers run and the streams are flushed, but the interpreter's teardown of
    every imported module (0.3-0.7 s for numpy, scipy, xarray and pint here) is skipped, so
    that an interrupted command really ends within a second.
    """
    import atexit
    import os

    from pdamper.files import stdout_error

    status = main()
    atexit._run_exitfuncs()
    try:  # what click printed (help, usage) may still sit in the buffer
        sys.stdout.flush()
    except OSError as exc:
        status = _say(f"error: {stdout_error(exc)}", 1) if status == 0 else status
    except ValueError:
        pass
    try:
        sys.stderr.flush()
    except (OSError, ValueError):
        status = status or 1
    os._exit(status)
