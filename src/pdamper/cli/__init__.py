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

import typer

app = typer.Typer(
    name="pdamper",
    help="Design particle dampers for vertically vibrating structures.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

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

    app.command("analytic")(analytic.analytic)
    app.command("map")(map.map_)
    app.command("simulate")(simulate.simulate)
    app.command("optimize")(optimize.optimize)
    app.command("dem")(dem.dem)
    app.command("paper")(paper.paper)
    app.command("example-scenario")(scenario.example_scenario)
    app.command("cor")(cor.cor)
    app.command("cor-sensitivity")(cor_sensitivity.cor_sensitivity)
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
