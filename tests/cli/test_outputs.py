"""Output files and streams of the command line (issue 11): every result file goes through
the one writer (:mod:`pdamper.files`), checked before any computation; stdout failures end
with one line and status 1; the same policy in every command."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import time

import pytest

from answers import check_answer
from proc import command, env, unprivileged_prefix

_MAP = ["map", "--frequency", "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2"]


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@pytest.mark.parametrize("args", [
    ["analytic"],
    [*_MAP, "--json"],
], ids=["analytic", "map-json"])
def test_stdout_on_a_full_device_is_one_line_and_status_1(args):
    with open("/dev/full", "w") as full:
        p = subprocess.run(command(*args), stdout=full, stderr=subprocess.PIPE, text=True,
                           env=env(), timeout=120)
    assert p.returncode == 1, p.stderr
    assert p.stderr.count("\n") == 1 and p.stderr.startswith("error: stdout: "), p.stderr


def test_broken_pipe_is_one_line_and_status_1():
    p = subprocess.Popen(command("example-scenario"), stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, env=env(), text=True)
    p.stdout.close()  # the reader went away before the first byte
    err = p.stderr.read()
    assert p.wait(timeout=120) == 1, err
    assert err.count("\n") == 1 and err.startswith("error: stdout: "), err


def test_every_result_file_is_0644_less_umask(tmp_path, cli):
    """``dem --out`` files used to be 0600 while the others were 0644."""
    files = {"map": tmp_path / "m.nc", "simulate": tmp_path / "s.nc", "dem": tmp_path / "d.nc"}
    assert cli(*_MAP, "--out", files["map"])[0] == 0
    assert cli("simulate", "--duration", "0.5s", "--out", files["simulate"])[0] == 0
    assert cli("dem", "--particles", 4, "--cycles", 2, "--skip-cycles", 1, "--integrator",
               "verlet", "--out", files["dem"])[0] == 0
    for name, path in files.items():
        assert _mode(path) == 0o666 & ~_umask(), name


@pytest.mark.parametrize("args", [
    [*_MAP, "--out", "{missing}/m.nc"],
    ["simulate", "--duration", "0.5s", "--out", "{missing}/s.nc"],
    ["dem", "--particles", 4, "--cycles", 2, "--skip-cycles", 1, "--out", "{missing}/d.nc"],
    ["dem", "--particles", 4, "--cycles", 2, "--skip-cycles", 1, "--vtk", "{missing}/vtk"],
    ["paper", "--no-dem", "--out", "{missing}/paper"],
], ids=["map", "simulate", "dem-out", "dem-vtk", "paper"])
def test_missing_directories_are_refused_alike(tmp_path, cli, args):
    """A missing directory is refused by every command (``dem`` used to create it); a
    command creates at most the output directory it is asked for, never its parents."""
    missing = tmp_path / "missing"
    code, out, err = cli(*[str(a).replace("{missing}", str(missing)) for a in args])
    check_answer(code, out, err, field="vtk" if "--vtk" in args else "out")
    assert "does not exist" in err
    assert not missing.exists()


def test_out_with_a_trailing_slash_is_not_a_file(tmp_path, cli):
    code, out, err = cli(*_MAP, "--out", f"{tmp_path / 'newdir'}/")
    check_answer(code, out, err, field="out")
    assert not (tmp_path / "newdir").exists()


def test_refused_before_any_computation(tmp_path, cli):
    """A bad target answers at once, not after the run (a 2 s DEM here)."""
    t0 = time.perf_counter()
    code, out, err = cli("dem", "--particles", 32, "--cycles", 20, "--out", "/proc/x.nc")
    check_answer(code, out, err, field="out")
    assert time.perf_counter() - t0 < 1.0


def test_a_fifo_or_device_is_never_replaced(tmp_path, cli):
    """Writing by rename would replace a FIFO (or ``/dev/null`` for root) by a file."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    code, out, err = cli(*_MAP, "--out", fifo)
    check_answer(code, out, err, field="out")
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)


def test_symlinked_target_is_written_through(tmp_path, cli):
    real = tmp_path / "real.nc"
    real.write_text("old")
    link = tmp_path / "link.nc"
    link.symlink_to(real)
    code, out, err = cli(*_MAP, "--out", link, "--json")
    check_answer(code, out, err, ok=True)
    assert link.is_symlink() and real.stat().st_size > 3


def _fake_case_study(monkeypatch):
    """Stand-ins for the case study: no rows, two files."""
    import types

    import pdamper.reports.paper_case_study as study
    from pdamper.files import atomic_write_text

    monkeypatch.setattr(study, "run_case_study",
                        lambda scenario, progress=None, dem=True, **kw: types.SimpleNamespace(rows=[]))
    monkeypatch.setattr(study, "write_case_study", lambda cs, out, progress=None: [
        atomic_write_text(out / "a.txt", "A"), atomic_write_text(out / "b.txt", "B")])


def test_paper_out_existing_directory_keeps_other_files(tmp_path, cli, monkeypatch):
    """``paper --out DIR``: an existing directory gets the new files and keeps the others;
    a new directory appears only complete, with the usual permissions."""
    _fake_case_study(monkeypatch)
    out = tmp_path / "results"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    (out / "a.txt").write_text("old A")
    code, stdout, err = cli("paper", "--no-dem", "--out", out, "--json")
    check_answer(code, stdout, err, ok=True)
    assert (out / "notes.txt").read_text() == "mine"
    assert (out / "a.txt").read_text() == "A"
    new = tmp_path / "fresh"
    code, stdout, err = cli("paper", "--no-dem", "--out", new, "--json")
    check_answer(code, stdout, err, ok=True)
    assert sorted(p.name for p in new.iterdir()) == ["a.txt", "b.txt"]
    assert json.loads(stdout)["files"] == [str(new / "a.txt"), str(new / "b.txt")]
    assert _mode(new) == 0o777 & ~_umask()
    assert _mode(new / "a.txt") == 0o666 & ~_umask()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_paper_failure_leaves_no_directory(tmp_path, cli, monkeypatch):
    import pdamper.reports.paper_case_study as study

    _fake_case_study(monkeypatch)

    def broken(cs, out, progress=None):
        (out / "a.txt").write_text("half")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(study, "write_case_study", broken)
    code, stdout, err = cli("paper", "--no-dem", "--out", tmp_path / "fresh")
    assert code == 1 and err.startswith("error: out: ") and err.count("\n") == 1, err
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def read_only_dir(tmp_path):
    d = tmp_path / "ro"
    d.mkdir()
    d.chmod(0o555)
    yield d
    d.chmod(0o755)


@pytest.mark.parametrize("args", [
    [*_MAP, "--out", "{ro}/m.nc"],
    ["paper", "--no-dem", "--out", "{ro}/paper"],
], ids=["file", "directory"])
def test_read_only_directory_as_unprivileged_user(read_only_dir, args):
    prefix = unprivileged_prefix()
    if prefix is None:
        pytest.skip("no way to run as an unprivileged user here")
    p = subprocess.run([*prefix, *command(*[str(a).replace("{ro}", str(read_only_dir))
                                            for a in args])],
                       capture_output=True, text=True, env=env(), timeout=120)
    check_answer(p.returncode, p.stdout, p.stderr, field="vtk" if "--vtk" in args else "out")
    assert "not writable" in p.stderr or "ermission" in p.stderr
    assert list(read_only_dir.iterdir()) == []


@pytest.mark.parametrize("args", [["analytic", "--help"]], ids=["command-help"])
def test_help_text_on_a_broken_pipe_or_full_device(args):
    """The help text is written by click and rich, not by pdamper: the same answer."""
    p = subprocess.Popen(command(*args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=env(), text=True)
    p.stdout.close()
    err = p.stderr.read()
    assert p.wait(timeout=120) == 1 and err.startswith("error: stdout: ") and \
        err.count("\n") == 1, err
    with open("/dev/full", "w") as full:
        q = subprocess.run(command(*args), stdout=full, stderr=subprocess.PIPE, text=True,
                           env=env(), timeout=120)
    assert q.returncode == 1 and q.stderr.startswith("error: stdout: ") and \
        q.stderr.count("\n") == 1, q.stderr


def _plot_commands() -> list[str]:
    """Every registered command with a ``--plot`` option."""
    import inspect

    from pdamper.cli import _register, app

    _register()
    return sorted(c.name for c in app.registered_commands
                  if "plot" in inspect.signature(c.callback).parameters)


def test_every_plot_option_is_the_one_checked_option():
    """One ``--plot`` for all (``pdamper.cli._common.check_plot``): the same help and
    formats in every command that draws a figure."""
    import typer

    from pdamper.cli import app

    names = _plot_commands()
    assert {"simulate", "optimize", "cor", "cor-sensitivity"} <= set(names)
    group = typer.main.get_command(app)
    for name in names:
        (opt,) = [p for p in group.commands[name].params if p.name == "plot"]
        assert opt.opts == ["--plot"], name
        assert opt.help.endswith("its suffix names the format (.png, .pdf, .svg, .jpg, "
                                 ".jpeg)."), (name, opt.help)


@pytest.mark.parametrize("name", _plot_commands())
@pytest.mark.parametrize("suffix", [".gif", ".txt", ""])
def test_a_plot_suffix_without_a_format_is_refused_before_the_run(tmp_path, cli, name, suffix):
    """``--plot x.gif`` (or no suffix): one line naming ``plot`` and the allowed suffixes,
    before anything runs or is written, in every command that draws a figure."""
    t0 = time.perf_counter()
    code, out, err = cli(name, "--plot", tmp_path / f"figure{suffix}")
    check_answer(code, out, err, field="plot")
    assert "must end in .png, .pdf, .svg, .jpg, .jpeg" in err
    assert time.perf_counter() - t0 < 5.0 and not list(tmp_path.iterdir())


@pytest.mark.parametrize(("suffix", "magic"), [
    (".jpg", b"\xff\xd8\xff"), (".JPEG", b"\xff\xd8\xff"), (".pdf", b"%PDF"),
    (".svg", b"<?xml"), (".png", b"\x89PNG"),
])
def test_the_plot_suffix_names_the_format_written(tmp_path, cli, suffix, magic):
    """``simulate --plot x.jpg`` wrote PNG bytes under the .jpg name."""
    path = tmp_path / f"figure{suffix}"
    code, out, err = cli("simulate", "--duration", "0.5s", "--plot", path, "--json")
    assert code == 0, err
    assert path.read_bytes()[:len(magic)] == magic
    assert [p.name for p in tmp_path.iterdir()] == [path.name]
