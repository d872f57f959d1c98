"""Output files and streams of the command line: every result file goes through
the one writer (:mod:`pdamper.files`), checked before any computation; stdout failures end
with one line and status 1; the same policy in every command."""

from __future__ import annotations

import errno
import json
import os
import shutil
import stat
import subprocess
import sys
import textwrap
import time

import pytest

from answers import check_answer
from proc import command, env, unprivileged_prefix

_MAP = ["map", "--frequency", "2Hz:4Hz:2", "--amplitude", "1mm:2mm:2"]
_DEM = ["dem", "--particles", 4, "--cycles", 2, "--skip-cycles", 1]


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@pytest.mark.parametrize("args", [
    ["analytic"],
    [*_MAP, "--json"],
    ["simulate", "--duration", "0.5s", "--json"],
], ids=["analytic", "map-json", "simulate-json"])
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
    import pdamper.runs.paper_case_study as runner
    from pdamper.files import atomic_write_text

    monkeypatch.setattr(runner, "run_case_study",
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


# -- full devices and closed streams: every writer ends with one line and status 1 ---------

#: Runs inside a private mount namespace (``unshare --mount``): mounts a small tmpfs on the
#: directory given, puts an earlier result there, runs the command and reports as JSON.
_ON_A_SMALL_TMPFS = textwrap.dedent("""
    import json, os, subprocess, sys
    directory, size, earlier, stdout, *args = sys.argv[1:]
    mount = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", directory],
                           capture_output=True, text=True)
    if mount.returncode:
        print(json.dumps({"skip": "cannot mount a tmpfs: " + mount.stderr.strip()}))
        sys.exit()
    if earlier:
        with open(os.path.join(directory, earlier), "w") as f:
            f.write("earlier")
    with open(os.path.join(directory, stdout), "wb") if stdout else open(os.devnull, "wb") as out:
        p = subprocess.run(args, stdout=out, stderr=subprocess.PIPE, text=True)
    found = {}
    for root, dirs, files in os.walk(directory):
        for name in files:
            path = os.path.join(root, name)
            found[os.path.relpath(path, directory)] = os.path.getsize(path)
    print(json.dumps({
        "status": p.returncode, "stderr": p.stderr, "files": found,
        "earlier": open(os.path.join(directory, earlier)).read() if earlier else None}))
""")


def on_a_small_tmpfs(tmp_path, size, args, earlier="", stdout=""):
    """Run ``pdamper ARGS`` (``{dir}`` is the tmpfs) with a tmpfs of ``size`` mounted on a
    directory (the mount is private to the command: nothing to clean up), or skip where
    this process may not mount one (not root, no user namespaces)."""
    if shutil.which("unshare") is None:
        pytest.skip("no unshare here to mount a tmpfs")
    if os.sysconf("SC_PAGE_SIZE") != 4096:  # the sizes below count 4 KiB pages
        pytest.skip("a tmpfs here is counted in pages other than 4 KiB")
    d = tmp_path / "small"
    d.mkdir()
    p = subprocess.run(["unshare", "--mount", "--propagation", "private", sys.executable,
                        "-c", _ON_A_SMALL_TMPFS, str(d), size, earlier, stdout,
                        *command(*[str(a).replace("{dir}", str(d)) for a in args])],
                       capture_output=True, text=True, env=env(), timeout=300)
    if p.returncode != 0 or not p.stdout.strip():
        pytest.skip(f"cannot mount a tmpfs here: {p.stderr.strip()[-200:]}")
    report = json.loads(p.stdout.strip().splitlines()[-1])
    if "skip" in report:
        pytest.skip(report["skip"])
    assert list(d.iterdir()) == [], "the tmpfs was not private to the command"
    return report


_DEM_MAP_SERIAL = ["map", "--model", "dem", "--serial", "--particles", 4, "--frequency",
                   "4Hz:6Hz:2", "--amplitude", "2mm:4mm:2"]


@pytest.mark.parametrize(("args", "size"), [
    ([*_MAP, "--out", "{dir}/r.nc"], "8k"),
    (["simulate", "--duration", "0.5s", "--out", "{dir}/r.nc"], "8k"),
    ([*_DEM, "--integrator", "verlet", "--out", "{dir}/r.nc"], "8k"),
    # room for the four per-point records of <out>.partial/ (a page each), not for the map
    ([*_DEM_MAP_SERIAL, "--out", "{dir}/r.nc"], "24k"),
    # no room for the per-point records either: the store fails the same way
    ([*_DEM_MAP_SERIAL, "--out", "{dir}/r.nc"], "8k"),
    (["simulate", "--duration", "0.5s", "--plot", "{dir}/r.png"], "8k"),
], ids=["map", "simulate", "dem", "map-dem", "map-dem-store", "simulate-plot"])
def test_a_full_device_is_one_line_and_status_1(tmp_path, args, size):
    """On a nearly full device the NetCDF writers printed HDF5's tracebacks, then an error
    line with HDF5's multi-line message, and died of a segmentation fault (status -11).
    Now: one line naming the option and the size that did not fit, status 1, the earlier
    result intact, no temporary file."""
    field = "plot" if "--plot" in args else "out"
    r = on_a_small_tmpfs(tmp_path, size, args, earlier="r.png" if field == "plot" else "r.nc")
    assert r["status"] == 1, r
    assert r["stderr"].count("\n") == 1 and r["stderr"].startswith(f"error: {field}: "), r
    assert "No space left on device" in r["stderr"], r
    assert r["earlier"] == "earlier"
    assert not [f for f in r["files"] if os.path.basename(f).startswith(".")], r["files"]


def test_stdout_cut_short_on_a_nearly_full_device(tmp_path):
    """``simulate --json > full/s.json`` ended with status 0 and 4096 of its 7611 bytes:
    Python's buffered stream took the short write for a complete one."""
    r = on_a_small_tmpfs(tmp_path, "4k", ["simulate", "--json"], stdout="s.json")
    assert r["status"] == 1, r
    assert r["stderr"] == "error: stdout: cannot write: No space left on device\n", r
    assert r["files"]["s.json"] == 4096  # what fitted; the status says it is incomplete


@pytest.mark.parametrize("args", [
    ["analytic", "--json"],
    ["analytic"],
    ["example-scenario"],
    ["--help"],
    [*_MAP, "--json"],
], ids=["analytic-json", "analytic", "example-scenario", "help", "map-json"])
def test_stdout_closed(args):
    """``pdamper analytic --json >&-`` ended in an AttributeError traceback (Python sets
    ``sys.stdout`` to None when descriptor 1 is closed at start-up)."""
    p = subprocess.run(command(*args), stderr=subprocess.PIPE, text=True, env=env(),
                       timeout=120, preexec_fn=lambda: os.close(1))
    assert p.returncode == 1, p.stderr
    assert p.stderr == "error: stdout: cannot write: the stream is closed\n", p.stderr


def test_stdout_closed_leaves_no_file_in_its_place(tmp_path):
    """With descriptor 1 closed, the next file opened would have become standard output
    (the result file, its temporary): descriptor 1 points at the null device instead, the
    result file is complete and only the summary line is missing (status 1)."""
    out = tmp_path / "m.nc"
    p = subprocess.run(command(*_MAP, "--out", out), stderr=subprocess.PIPE, text=True,
                       env=env(), timeout=120, preexec_fn=lambda: os.close(1))
    assert p.returncode == 1 and p.stderr.startswith("error: stdout: "), p.stderr
    assert out.read_bytes()[:4] == b"\x89HDF"
    assert sorted(q.name for q in tmp_path.iterdir()) == ["m.nc"]


def test_error_lines_are_one_line():
    """A library's message with line breaks (HDF5's) is printed as one line."""
    from pdamper.files import one_line

    assert one_line("write failed: time = Thu Nov 26\n, errno = 28\r\n") == \
        "write failed: time = Thu Nov 26 , errno = 28"


def test_short_writes_are_completed_or_raise(monkeypatch):
    """A write that returns less than it was given is followed by another; one that writes
    nothing is a full device, not a loop."""
    from pdamper import files

    calls = []

    def short(fd, view):
        calls.append(bytes(view))
        return min(3, len(view)) if len(calls) < 4 else 0

    monkeypatch.setattr(files.os, "write", short)
    with pytest.raises(OSError) as info:
        files._write_all(1, b"0123456789")
    assert calls[:3] == [b"0123456789", b"3456789", b"6789"]
    assert info.value.errno == errno.ENOSPC


def test_what_other_libraries_print_is_written_completely_or_raises(monkeypatch, tmp_path):
    """The console script rebuilds ``sys.stdout`` on checked writes (click's help text,
    rich): a short write is completed, a device that takes nothing more raises."""
    from pdamper import files

    real = os.write
    counts = []

    def short(fd, view):
        if len(counts) == 3:
            raise OSError(errno.ENOSPC, "No space left on device")
        counts.append(real(fd, bytes(view[:4])))
        return counts[-1]

    with open(tmp_path / "o", "w") as f:
        stream = files.checked_stdout(f)
        monkeypatch.setattr(files.os, "write", short)
        stream.write("0123456789")
        stream.flush()
        assert (tmp_path / "o").read_text() == "0123456789"
        stream.write("more")
        with pytest.raises(OSError):
            stream.flush()
