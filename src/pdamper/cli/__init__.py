"""The ``pdamper`` command line: one entry point, one module per command.

Each command module registers itself on :data:`app`. Errors a user can cause are printed as
one line naming the field and what is allowed, with exit status 2.
"""

from __future__ import annotations

import importlib
import sys

import typer

app = typer.Typer(
    name="pdamper",
    help="Design particle dampers for vertically vibrating structures.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

#: Command modules, imported lazily by :func:`main` so that ``import pdamper`` stays fast.
COMMAND_MODULES = ("analytic", "map", "simulate", "optimize", "paper", "scenario", "dem")


def _register() -> None:
    for name in COMMAND_MODULES:
        try:
            importlib.import_module(f"pdamper.cli.{name}")
        except ModuleNotFoundError as exc:  # a command whose module is not there yet
            if exc.name != f"pdamper.cli.{name}":
                raise


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit status."""
    from pdamper.errors import PdamperError

    _register()
    try:
        app(args=argv, standalone_mode=False)
    except PdamperError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except SystemExit as exc:  # pragma: no cover - typer may still exit
        return int(exc.code or 0)
    except Exception as exc:
        # usage errors of click (vendored by recent typer as typer._click): duck-typed
        message = getattr(exc, "format_message", None)
        code = getattr(exc, "exit_code", None)
        if callable(message) and isinstance(code, int):
            if message():  # empty for "no arguments: help shown"
                print(f"error: {message()}", file=sys.stderr)
            return code
        if type(exc).__name__ == "Abort":
            return 1
        raise
    return 0


def entry() -> None:  # pragma: no cover
    sys.exit(main())
