"""The ``pdamper`` command line: one entry point, one module per command.

Commands are registered explicitly in :func:`pdamper.cli._app._register` (a missing module
is an import error, not a silently absent command). Errors a user can cause are printed as one line
naming the field and what is allowed, with exit status 2; a result that cannot be written
ends with one line and status 1; Ctrl-C and SIGTERM end with ``interrupted`` and status 130
or 143 (:mod:`pdamper.cli._signals`). The commands only parse, call the library and format
its results; what their inputs imply is judged before they run
(:mod:`pdamper.resources`), and every output goes through :mod:`pdamper.files`.
"""

from __future__ import annotations

import contextlib
import errno
import sys
from collections.abc import Sequence


def _register() -> None:
    """Register the commands (:mod:`pdamper.cli._app`, imported here: typer with it)."""
    from pdamper.cli import _app

    _app._register()


def __getattr__(name: str):
    # ``pdamper.cli.app`` and the group's classes live in pdamper.cli._app, imported on
    # first use (after the signal handlers of main() are in place)
    if name in ("app", "_Group", "_Command"):
        from pdamper.cli import _app

        return getattr(_app, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _say(line: str, status: int) -> int:
    """Print ``line`` on stderr as one line (line breaks of a library's message become
    blanks); returns ``status``."""
    from pdamper.files import one_line

    try:
        sys.stderr.write(one_line(line) + "\n")
        sys.stderr.flush()
    except (OSError, ValueError, AttributeError):  # stderr closed as well: the status tells
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
    return f"error: {exc.format_message()}"  # type: ignore[attr-defined]  # click's UsageError


def _stdout_is_null() -> bool:
    """Standard output is /dev/null (where rich and click put it after a broken pipe)."""
    import os

    try:
        a, b = os.fstat(sys.stdout.fileno()), os.stat(os.devnull)
    except (OSError, ValueError, AttributeError):
        return False
    return (a.st_ino, a.st_dev, a.st_rdev) == (b.st_ino, b.st_dev, b.st_rdev)


#: Errors of a failed write to a stream (what click lets through from its help text).
_STREAM_ERRNOS = {errno.EPIPE, errno.ENOSPC, errno.EIO, errno.EDQUOT, errno.EFBIG, errno.EBADF}


class _ClosedStream:
    """Standard output or error that was closed when the process started (``>&-``): every
    write fails as a write to a closed descriptor does, so that it ends as such a failure
    (one line, status 1) and not in an ``AttributeError`` of ``None``."""

    encoding, errors = "utf-8", "strict"

    def write(self, _text: str) -> int:
        raise OSError(errno.EBADF, "the stream is closed")

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False


def _standard_streams() -> None:
    """Descriptors 0-2 that were closed at start-up point at the null device (so that no
    file opened later becomes standard output or error), and ``sys.stdout`` or
    ``sys.stderr`` that Python set to None become :class:`_ClosedStream`\\ s."""
    import os

    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            try:
                null = os.open(os.devnull, os.O_RDWR)
            except OSError:  # pragma: no cover - no null device
                continue
            if null != fd:
                os.dup2(null, fd)
                os.close(null)
    if sys.stdout is None:
        sys.stdout = _ClosedStream()
    if sys.stderr is None:
        sys.stderr = _ClosedStream()


def _run(argv: list[str] | None, received: Sequence[int] = ()) -> int:
    from pdamper.errors import Interrupted, OutputError, PdamperError
    from pdamper.files import stdout_error

    was_null = _stdout_is_null()
    try:
        try:
            from pdamper.cli import _app, _quiet  # typer and the commands: imported here

            _app._register()
            with _quiet.scope():
                status = _app.app(args=argv, standalone_mode=False)
        except (Interrupted, KeyboardInterrupt):
            raise
        except BaseException as exc:
            # a signal that a library turned into an error of its own (an extension
            # module's "ImportError: initialization failed", click's Abort): interrupted
            if received:
                raise Interrupted(received[0]) from exc
            raise
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

    _standard_streams()
    try:
        with raising_interrupts() as received:
            return _run(argv, received)
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

    from pdamper.files import checked_stdout, stdout_error

    if sys.stdout is not None:  # Python's own stream took a short write for a complete one
        sys.stdout = checked_stdout(sys.stdout)
    status = main()
    # the command's outcome is decided: a further signal (a second Ctrl-C, or the copy of
    # the first that the relay of pdamper.cli._signals hands to the main thread) must not
    # cut the exit handlers short, or multiprocessing's would leave a semaphore unlinked
    # but registered, which its resource tracker then reports on stderr
    import signal

    from pdamper.files import DEFERRED_SIGNALS

    for s in DEFERRED_SIGNALS:
        with contextlib.suppress(OSError, ValueError):
            signal.signal(s, signal.SIG_IGN)
    atexit._run_exitfuncs()
    try:  # what click printed (help, usage) may still sit in the buffer
        if sys.stdout is not None:
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
