"""``--quiet``: nothing on standard error but errors, for scripts.

Progress displays, notes and warnings (pdamper's and dask's log records below ERROR,
Python warnings) are left out; the one-line error of a failed command, its exit status and
what a command prints on standard output (its result, ``--json``) are not. The state lasts
one command line (:func:`scope`).
"""

from __future__ import annotations

import contextlib
import logging
import warnings

_quiet = False

#: Loggers whose notes and warnings ``--quiet`` silences.
LOGGERS = ("pdamper", "distributed")


def quiet() -> bool:
    """``--quiet`` was given: show no progress display, notes or warnings."""
    return _quiet


def set_quiet(value: bool = True) -> bool:
    """Turn quiet on when ``value`` (the callback of ``--quiet``); returns ``value``."""
    global _quiet
    if value and not _quiet:
        _quiet = True
        for name in LOGGERS:
            logging.getLogger(name).setLevel(logging.ERROR)
        warnings.simplefilter("ignore")
    return value


def _one_line(message, category, filename, lineno, file=None, line=None) -> None:
    """A Python warning as a user reads it: one line, ``warning: TEXT (Category)``, without
    the source file, line number and code line that Python's default shows (they name
    pdamper's internals, not the user's input)."""
    import sys

    text = " ".join(str(message).split())
    out = sys.stderr if file is None else file
    try:
        out.write(f"warning: {text} ({category.__name__})\n")
    except (OSError, ValueError):  # a closed or broken stderr loses the warning, not the run
        pass


@contextlib.contextmanager
def scope():
    """One command line: whatever ``--quiet`` changed is undone at its end (the state of
    the loggers and warning filters, for a caller of :func:`pdamper.cli.main` in-process)."""
    global _quiet
    levels = {name: logging.getLogger(name).level for name in LOGGERS}
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _one_line  # restored by catch_warnings
            yield
    finally:
        _quiet = False
        for name, level in levels.items():
            logging.getLogger(name).setLevel(level)
