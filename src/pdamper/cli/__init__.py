"""The ``pdamper`` command line: one entry point, one module per command.

Commands are registered explicitly in :func:`_register` (a missing module is an import
error, not a silently absent command). Errors a user can cause are printed as one line
naming the field and what is allowed, with exit status 2. The commands only parse, call
the library and format its results.
"""

from __future__ import annotations

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
