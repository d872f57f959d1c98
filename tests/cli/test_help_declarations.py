"""Every command's options against the scenario's declarations: an option that sets a
scenario key takes its unit, allowed values and choices from that key's declaration
(:func:`pdamper.cli._common.key_help`), and help keeps every bracketed text (rich would read
``[Hz]`` as markup and drop it)."""

from __future__ import annotations

import re

import pytest
import typer.main

from pdamper.cli import _app
from pdamper.cli._common import declared_help, help_key
from pdamper.io.scenario_reference import declaration_of, declarations

#: The options of each command that set no scenario key: what the command itself does
#: (outputs, parallel runs, sampling, ...). Any other option must name its key, so that a
#: hand-written scenario option, with its own unit and choices, fails here.
OWN = {
    "analytic": {"uncertainty", "uncertain", "uncertainty_seed", "force", "scenario",
                 "as_json"},
    "map": {"model", "out", "uncertainty", "uncertain", "uncertainty_seed", "force", "workers",
            "scheduler", "retries", "retry_failed", "keep_partial", "serial", "realisations",
            "plot", "scenario", "as_json"},
    "simulate": {"compare", "measured", "plot", "out", "uncertainty", "uncertain",
                 "uncertainty_seed", "realisations", "workers", "serial", "force", "scenario",
                 "as_json"},
    "optimize": {"plot", "realisations", "uncertainty", "uncertain", "uncertainty_seed",
                 "robust_quantile", "force", "scenario", "as_json"},
    "dem": {"out", "vtk", "realisations", "workers", "serial", "uncertainty", "uncertain",
            "uncertainty_seed", "force", "scenario", "as_json"},
    "paper": {"out", "dem", "workers", "scheduler", "realisations", "force", "scenario",
              "as_json"},
    "example-scenario": set(),
    "cor": {"pair", "velocity", "model", "plot", "force", "scenario", "as_json"},
    "cor-sensitivity": {"variants", "points", "level3", "plot", "scenario", "as_json"},
    "report": {"out", "dem", "realisations", "uncertainty", "uncertain", "uncertainty_seed",
               "workers", "force", "scenario", "as_json"},
    "frf": {"base", "max_cycles", "allow_cost", "plot", "out", "uncertainty", "uncertain",
            "uncertainty_seed", "realisations", "scenario", "as_json"},
    "explore": {"port", "no_browser", "out", "mass_limit", "scenario"},
}


def _commands():
    _app._register()
    return typer.main.get_command(_app.app).commands


def _options(name: str):
    return [p for p in _commands()[name].params if p.name not in ("help", "quiet")]


def test_every_command_is_checked():
    assert set(_commands()) == set(OWN)


@pytest.mark.parametrize("name", sorted(OWN))
def test_every_option_of_a_scenario_key_resolves_to_its_one_declaration(name):
    """Each option either names a scenario key that the schema declares (once: the key's
    row of docs/scenario.md) or is one of the command's own."""
    for p in _options(name):
        key = help_key(p.help)
        if key is None:
            assert p.name in OWN[name], (
                f"{name} --{p.name} sets no declared scenario key and is not one of the "
                "command's own: give it key_help(KEY, ...)")
            continue
        d = declaration_of(key)  # raises for a key the scenario does not have
        assert d is declarations()[d.key]
        assert p.name not in OWN[name]


@pytest.mark.parametrize("name", sorted(OWN))
def test_help_shows_the_declared_unit_and_choices(name):
    for p in _options(name):
        key = help_key(p.help)
        if key is None:
            continue
        d = declaration_of(key)
        text = declared_help(p.help)
        if d.unit not in ("", "1"):
            assert f"[{d.unit}]" in text, (name, p.name, text)
        for choice in d.choices:
            assert choice in text, (name, p.name, choice, text)
        assert d.key in text


def _help(cli, monkeypatch, *args):
    monkeypatch.setenv("COLUMNS", "250")
    monkeypatch.setenv("NO_COLOR", "1")
    code, out, err = cli(*args, "--help")
    assert code == 0 and err == "", err
    return " ".join(out.split())  # rich wraps long lines


@pytest.mark.parametrize("name", sorted(OWN))
def test_help_keeps_every_bracketed_unit(cli, monkeypatch, name):
    """rich markup is escaped: every declared unit is shown in brackets."""
    out = _help(cli, monkeypatch, name)
    for p in _options(name):
        key = help_key(p.help)
        if key is not None and declaration_of(key).unit not in ("", "1"):
            assert f"[{declaration_of(key).unit}]" in out, (name, p.name)


@pytest.mark.parametrize(("args", "texts"), [
    (("simulate",), ("[kg^-0.5]", "[Hz]", "[1]")),  # the modes file's column headers
    (("frf",), ("[kg^-0.5]",)),
    (("optimize",), ("[kg^-0.5]", "[s]")),
    (("cor",), ("tsuji",)),      # the damping law's choices from its declaration
    (("dem",), ("one of gear, verlet, auto", "[Hz]")),
])
def test_help_shows_what_rich_used_to_swallow(cli, monkeypatch, args, texts):
    out = _help(cli, monkeypatch, *args)
    for text in texts:
        assert text in out, (args, text)


def test_every_scenario_key_has_one_declaration_with_its_aliases():
    """Every key of the schema (and each alias) resolves to exactly one declaration, whose
    own key is a path of the schema."""
    from pdamper.io.scenario_reference import _tables

    paths = set()
    for _, model, where in _tables():
        for w in where:
            paths |= {f"{w}.{n}" for n in model.model_fields}
    table = declarations()
    assert paths <= set(table)
    for key, d in table.items():
        assert d.key in paths
        if key in paths:  # a key of the schema is its own declaration's key
            assert d.key == key
    with pytest.raises(KeyError, match="no key 'excitation.nonsense'"):
        declaration_of("excitation.nonsense")


def test_every_numeric_row_of_the_reference_has_a_unit_and_a_range():
    """docs/scenario.md, as generated: no number without its unit (``1`` for a ratio) and
    its allowed range."""
    from pdamper.io.scenario_reference import reference

    rows = [r for r in reference().splitlines() if r.startswith("| `")]
    numeric = 0
    for row in rows:
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]]
        if len(cells) == 6 and re.search(r"number|integer", cells[1]):
            numeric += 1
            assert cells[2] and cells[4], row
    assert numeric > 60


def test_the_declared_fidelities_are_the_registry():
    """``simulation.model`` declares its choices for help and docs; they are the registry's
    names (the one place a fidelity is named)."""
    from pdamper.models.registry import DAMPER_MODELS

    assert declaration_of("simulation.model").choices == tuple(DAMPER_MODELS)
