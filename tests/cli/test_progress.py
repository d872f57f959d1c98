"""Progress displays of the long commands: on standard error only, standard output (the
result, --json) untouched; none with --quiet or when standard error is not a terminal."""

from __future__ import annotations

import json

import pdamper.cli._progress as progress


def test_optimize_shows_its_designs_on_stderr_only(cli, monkeypatch):
    monkeypatch.setattr(progress, "showing", lambda: True)
    code, out, err = cli("optimize", "--vary", "particles=0:32:32", "--json")
    assert code == 0, err
    assert [c["particles"] for c in json.loads(out)["candidates"]] == [0, 32]
    assert "designs evaluated" in err


def test_no_display_when_stderr_is_not_a_terminal(cli):
    # under pytest stderr is captured: not a terminal
    assert not progress.showing()
    code, out, err = cli("optimize", "--vary", "particles=0:32:32", "--json")
    assert code == 0 and err == ""
    json.loads(out)


def test_quiet_turns_the_display_off(cli, monkeypatch):
    import sys

    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    assert progress.showing()
    code, out, err = cli("--quiet", "optimize", "--vary", "particles=0:32:32", "--json")
    assert code == 0 and err == ""
    json.loads(out)


def test_a_bar_adds_the_batches_of_an_optimiser(capsys):
    with progress.Bar("designs evaluated", force=True) as bar:
        assert bar is not None
        for done in (1, 2, 3):
            bar(done, 3)
        bar(1, 2)  # the next generation
        assert bar._bar.tasks[0].completed == 4 and bar._bar.tasks[0].total == 5
    with progress.Bar("designs evaluated", force=False) as none:
        assert none is None
