"""The typer application of the ``pdamper`` command line: the group, its options
(``--version``, ``--quiet``), help without type names, and the commands, registered
explicitly in :func:`_register` (a missing module is an import error, not a silently absent
command).

Imported by :mod:`pdamper.cli` when a command runs, after its signal handlers are in
place: a Ctrl-C during the import of typer, too, ends with ``interrupted``.
"""

from __future__ import annotations

from typing import Annotated

import typer
from typer.core import TyperCommand, TyperGroup

from pdamper.cli import _quiet


def _declared(command, ctx) -> None:
    """Before help is shown: the help of each option that sets a scenario key completed
    from the key's declaration (:func:`pdamper.cli._common.declared_help`; only then, so that
    a command's start-up reads no schema), and every help text escaped for rich, which
    otherwise takes a bracketed unit (``[Hz]``, ``[kg^-0.5]``, ``[dem] cycles``) for
    markup and drops it."""
    from rich.markup import escape

    from pdamper.cli._common import declared_help

    if command.help and not getattr(command, "_escaped", False):
        command.help = escape(command.help)
        command._escaped = True
    for p in command.get_params(ctx):
        if getattr(p, "help", None) and not getattr(p, "_escaped", False):
            p.help = escape(declared_help(p.help))
            p._escaped = True


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

    def format_help(self, ctx, formatter):
        _declared(self, ctx)
        for name in self.list_commands(ctx):
            sub = self.get_command(ctx, name)
            if sub is not None and sub.short_help and not getattr(sub, "_escaped_short",
                                                                  False):
                from rich.markup import escape

                sub.short_help = escape(sub.short_help)
                setattr(sub, "_escaped_short", True)  # noqa: B010 (click's own class)
        return super().format_help(ctx, formatter)


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

    def format_help(self, ctx, formatter):
        _declared(self, ctx)
        return super().format_help(ctx, formatter)


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
        explore,
        frf,
        map,
        optimize,
        paper,
        report,
        scenario,
        simulate,
    )

    for name, function in (("analytic", analytic.analytic), ("map", map.map_),
                           ("simulate", simulate.simulate), ("optimize", optimize.optimize),
                           ("dem", dem.dem), ("paper", paper.paper),
                           ("example-scenario", scenario.example_scenario), ("cor", cor.cor),
                           ("cor-sensitivity", cor_sensitivity.cor_sensitivity),
                           ("report", report.report), ("frf", frf.frf),
                           ("explore", explore.explore)):
        app.command(name, cls=_Command, short_help=_summary(function))(function)
    _registered = True


def _summary(function) -> str:
    """The first paragraph of a command's docstring on one line: the main help's list of
    commands (typer keeps the docstring's line breaks, which then break the list's column
    at random places)."""
    return " ".join((function.__doc__ or "").split("\n\n")[0].split())
