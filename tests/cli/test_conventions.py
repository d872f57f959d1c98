"""Conventions of a command-line tool: ``--version``, help screens without a column of type
names, shell completion, ``--quiet`` for scripts."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

from proc import command, env

#: Every command of ``pdamper --help``.
COMMANDS = ("analytic", "map", "simulate", "optimize", "dem", "paper", "example-scenario", "cor",
            "cor-sensitivity", "report")


def _run(*args, **extra_env):
    return subprocess.run(command(*args), capture_output=True, text=True, env=env(**extra_env),
                          timeout=300)


def test_version_prints_the_installed_version():
    p = _run("--version")
    assert p.returncode == 0 and p.stderr == ""
    assert re.fullmatch(r"pdamper \d+\.\d+\.\d+\S*\n", p.stdout), p.stdout
    try:  # the distribution's metadata, where pdamper is installed
        from importlib.metadata import PackageNotFoundError, version
        installed = version("pdamper")
    except PackageNotFoundError:
        installed = None
    if installed is not None:
        assert p.stdout == f"pdamper {installed}\n"


def test_version_comes_first_whatever_follows():
    """Eager: ``--version`` answers before a command would run or complain."""
    p = _run("--version", "analytic", "--frequency", "nonsense")
    assert p.returncode == 0 and p.stdout.startswith("pdamper ") and p.stderr == ""


#: Type names typer or click print in help: ``<str>`` etc. in typer's column, TEXT etc. in
#: click's metavars.
_TYPE_NAME = re.compile(r"<(str|bool|int|float|path|text|choice)[^>]*>|\b(TEXT|INTEGER|FLOAT|"
                        r"BOOLEAN|PATH|FILENAME)\b", re.IGNORECASE)


@pytest.mark.parametrize("args", [(), *((c,) for c in COMMANDS)],
                         ids=["pdamper", *COMMANDS])
def test_help_has_no_type_names(cli, monkeypatch, args):
    monkeypatch.setenv("COLUMNS", "200")
    code, out, err = cli(*args, "--help")
    assert code == 0 and err == ""
    assert "--help" in out and "--quiet" in out
    assert _TYPE_NAME.search(out) is None, _TYPE_NAME.search(out)


def test_help_still_lists_every_option_with_its_text(cli, monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")
    code, out, _ = cli("dem", "--help")
    assert code == 0
    for option, text in (("--frequency", "Excitation frequency f"), ("--integrator", "gear"),
                         ("--error-estimate", "--no-error-estimate"), ("--scenario", "-s")):
        line = next(ln for ln in out.splitlines() if option in ln)
        assert text in line, line


def test_main_help_offers_version_quiet_and_completion(cli, monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")
    code, out, _ = cli("--help")
    assert code == 0
    for option in ("--version", "--quiet", "-q", "--install-completion", "--show-completion"):
        assert option in out


def test_main_help_lists_each_command_with_its_first_paragraph_on_one_line(cli, monkeypatch):
    """At 200 columns each command's summary fits its line: the docstring's own line breaks
    used to cut the list's column mid-sentence ('under harmonic excitation' / 'and apply')."""
    monkeypatch.setenv("COLUMNS", "200")
    code, out, _ = cli("--help")
    assert code == 0
    line = next(x for x in out.splitlines() if " dem " in x)
    assert "under harmonic excitation and apply the complex power method (Eqs. 1-4)." in line


def _as_pdamper(*args, **extra_env):
    """The console script's process: the program name is ``pdamper`` (shell completion keys
    its environment variable on it)."""
    code = "import sys; sys.argv[0] = 'pdamper'; from pdamper.cli import entry; entry()"
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                          env=env(**extra_env), timeout=120)


def test_shell_completion_of_commands_and_options():
    p = _as_pdamper(_PDAMPER_COMPLETE="complete_bash", COMP_WORDS="pdamper an", COMP_CWORD="1")
    assert p.returncode == 0 and p.stdout.split() == ["analytic"], (p.stdout, p.stderr)
    p = _as_pdamper(_PDAMPER_COMPLETE="complete_bash", COMP_WORDS="pdamper dem --fr",
                    COMP_CWORD="2")
    assert p.returncode == 0
    assert {"--frequency", "--friction", "--free-flight"} <= set(p.stdout.split()), p.stdout


def test_show_completion_prints_a_script():
    p = _as_pdamper("--show-completion", "bash", _TYPER_COMPLETE_TEST_DISABLE_SHELL_DETECTION="1")
    assert p.returncode == 0
    assert "_pdamper_completion()" in p.stdout and "_PDAMPER_COMPLETE" in p.stdout


# ------------------------------------------------------------------------------- --quiet
@pytest.fixture(scope="module")
def noisy_scenario(tmp_path_factory):
    """A scenario whose loading logs a warning on stderr: a map for another container,
    used anyway (``strict = false``)."""
    d = tmp_path_factory.mktemp("quiet")
    p = _run("map", "--model", "analytic", "--frequency", "2Hz:20Hz:4",
             "--amplitude", "1mm:200mm:5", "--out", d / "m.nc")
    assert p.returncode == 0, p.stderr
    s = d / "s.toml"
    s.write_text('[container]\nlength = "110 mm"\n\n[simulation]\nmodel = "fields"\n\n'
                 f'[fields]\nfile = "{d / "m.nc"}"\nstrict = false\n')
    return s


def test_quiet_silences_warnings_not_results(noisy_scenario):
    loud = _run("analytic", "-s", noisy_scenario, "--json")
    assert loud.returncode == 0 and "does not match the damper" in loud.stderr
    for args in (("--quiet", "analytic", "-s", noisy_scenario, "--json"),
                 ("analytic", "-s", noisy_scenario, "--json", "-q")):
        p = _run(*args)
        assert p.returncode == 0 and p.stderr == "", p.stderr
        assert json.loads(p.stdout) == json.loads(loud.stdout)
    human = _run("-q", "analytic", "-s", noisy_scenario)
    assert human.returncode == 0 and human.stderr == "" and "motion mode" in human.stdout


def test_quiet_keeps_errors_and_their_status():
    for args in (("-q", "analytic", "--frequency", "10"),
                 ("analytic", "--frequency", "10", "--quiet")):
        p = _run(*args)
        assert p.returncode == 2 and p.stdout == ""
        assert p.stderr.startswith("error: excitation.frequency:") and \
            p.stderr.count("\n") == 1, p.stderr
    p = _run("-q", "analytic", "--no-such-option")
    assert p.returncode == 2 and p.stderr.startswith("error:"), p.stderr


def test_quiet_lasts_one_command_line(cli):
    """In-process callers of :func:`pdamper.cli.main`: the next command line is not quiet."""
    import logging
    import warnings

    from pdamper.cli import _quiet

    cli("example-scenario")  # modules that add warning filters when imported are imported
    level = logging.getLogger("pdamper").level
    filters = list(warnings.filters)
    code, out, _ = cli("-q", "example-scenario")
    assert code == 0 and out
    assert not _quiet.quiet()
    assert logging.getLogger("pdamper").level == level and warnings.filters == filters
