"""Output: the one writer every result goes through (files, directories, standard output).

Policy (the same for every command):

- **Checked first.** :func:`check_file_target` and :func:`check_directory_target` run before
  any computation: the name is not empty, a file target is not a directory (nor a name
  ending in ``/``), not a device or FIFO, the directory that will hold it exists and a file
  can really be created there (a probe, so that ``/proc`` or a read-only mount is caught
  too). Problems are one-line :class:`~pdamper.errors.InputError`\\ s naming the option.
- **Atomic.** :func:`atomic_write` writes a temporary file beside the target and renames it
  over the target only when the writer has finished, so that a failed or interrupted run
  never leaves a half-written file under the target's name, and an earlier complete result
  stays as it was. A symlinked target is written through (the link stays). A signal that
  arrives while the writer runs is held until the writer returns (:func:`signals_deferred`):
  raised inside the HDF5 library, an interrupt was sometimes swallowed (the command went on)
  or left the library's state broken; held, it deletes the temporary file and the target
  stays as it was.
  :func:`atomic_directory` does the same for a directory of results (``paper --out``): the
  files are written into a hidden staging directory beside the target, which becomes the
  target (a new directory appears complete or not at all) or whose files replace their
  namesakes in an existing target (other files there stay).
- **Usual permissions.** Files get 0666 and directories 0777, less the umask, whatever the
  temporary-file machinery would give (``mkstemp`` makes 0600).
- **Missing directories are refused, not created**: a command creates at most the output
  directory it is asked for, never its parents.
- **Standard output** (:func:`write_stdout`): a closed pipe or a full device becomes an
  :class:`~pdamper.errors.OutputError` for ``stdout`` (one line, status 1 at the command
  line), with nothing more printed at exit.

Problems while writing (a full device) are :class:`~pdamper.errors.OutputError`\\ s.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import signal
import stat
import sys
import tempfile
import threading
from collections.abc import Callable, Iterator
from pathlib import Path

from pdamper.errors import InputError, OutputError

__all__ = ["atomic_directory", "atomic_write", "atomic_write_text", "check_directory_target",
           "check_file_target", "signals_deferred", "stdout_error", "write_stdout"]

#: Signals whose Python handlers :func:`signals_deferred` holds back (those the command line
#: turns into :class:`~pdamper.errors.Interrupted`, where the platform has them).
DEFERRED_SIGNALS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP")
                         if hasattr(signal, name))


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """Hold back the Python handlers of :data:`DEFERRED_SIGNALS` while the block runs.

    A signal arriving inside the block is recorded; when the block ends, the handlers are
    restored and the first recorded signal is handed to its handler, so that an interrupt
    (``KeyboardInterrupt``, :class:`~pdamper.errors.Interrupted`) is raised *after* the
    block, never inside third-party code that is not safe against it (the HDF5 library,
    measured: 10 of 300 signals sent during ``to_netcdf`` were swallowed there, others broke
    its state). Signals with the default or ignore disposition are left alone, and so is
    every thread but the main one (where Python runs signal handlers).

    Examples
    --------
    >>> import os, signal
    >>> got = []
    >>> old = signal.signal(signal.SIGINT, lambda s, f: got.append(("handled", s)))
    >>> with signals_deferred():
    ...     os.kill(os.getpid(), signal.SIGINT)
    ...     got.append("block ends")
    >>> _ = signal.signal(signal.SIGINT, old)
    >>> got == ["block ends", ("handled", signal.SIGINT)]
    True
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []
    previous = {s: signal.getsignal(s) for s in DEFERRED_SIGNALS}
    held = {s: h for s, h in previous.items() if callable(h)}
    for s in held:
        signal.signal(s, lambda signum, _frame: pending.append(signum))
    try:
        yield
    finally:
        for s, h in held.items():
            signal.signal(s, h)
        if pending:
            held[pending[0]](pending[0], None)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _reason(exc: OSError) -> str:
    if isinstance(exc, BrokenPipeError) or exc.errno == errno.EPIPE:
        return "broken pipe (the reading end was closed)"
    return exc.strerror or str(exc)


def _text(path: str | os.PathLike[str], field: str, what: str) -> str:
    try:
        text = os.fspath(path)
    except TypeError:
        raise InputError(field, f"must be a path naming a {what}, got {path!r}") from None
    if not isinstance(text, str) or not text.strip():
        raise InputError(field, f"must name a {what}, got {text!r}")
    if "\0" in text:
        raise InputError(field, f"must name a {what}, got a name with a NUL character")
    return text


def _missing_ancestor(directory: Path) -> str:
    """Why ``directory`` (which does not exist) cannot be used."""
    for parent in [directory, *directory.parents]:
        if parent.exists() or parent.is_symlink():
            if not parent.is_dir():
                return f"{parent} is not a directory"
            break
    return f"directory does not exist: {directory}"


def _probe(directory: Path, field: str) -> None:
    """Create and remove a file in ``directory``: the one sure test that writing works."""
    try:
        fd, name = tempfile.mkstemp(dir=directory, prefix=".pdamper-probe-", suffix=".tmp")
    except OSError as exc:
        raise InputError(field, f"cannot write in directory {directory}: {_reason(exc)} "
                         f"(not writable)") from None
    try:
        os.close(fd)
    finally:  # also when a signal lands here: no probe is left behind
        with contextlib.suppress(OSError):
            os.unlink(name)


def _existing_directory(directory: Path, field: str) -> None:
    if not directory.exists():
        raise InputError(field, _missing_ancestor(directory))
    if not directory.is_dir():
        raise InputError(field, f"{directory} is not a directory")
    _probe(directory, field)


def check_file_target(path: str | os.PathLike[str], field: str = "out") -> Path:
    """Check, before any computation, that a result file can be written at ``path``.

    Returns the path to write (a symlink resolved, so that the link stays a link).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> check_file_target(d / "map.nc") == d / "map.nc"
    True
    >>> check_file_target(str(d) + "/")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    pdamper.errors.InputError: out: '.../' names a directory; give a file name, e.g. .../result.nc
    """
    text = _text(path, field, "file")
    if text.endswith(("/", os.sep)) or text.endswith(("/.", "/..")) or text in (".", ".."):
        raise InputError(field, f"{text!r} names a directory; give a file name, e.g. "
                         f"{text.rstrip('/')}/result.nc")
    target = Path(text)
    if target.is_symlink():
        target = Path(os.path.realpath(target))
    if target.exists():
        mode = target.stat().st_mode
        if stat.S_ISDIR(mode):
            raise InputError(field, f"{target} is a directory; give a file name, e.g. "
                             f"{target}/result.nc")
        if not stat.S_ISREG(mode):
            raise InputError(field, f"{target} is not a regular file (a device, FIFO or "
                             f"socket); give a file name")
        if not os.access(target, os.W_OK):
            raise InputError(field, f"{target} is read-only (not writable)")
    _existing_directory(target.parent, field)
    return target


def check_directory_target(path: str | os.PathLike[str], field: str = "out") -> Path:
    """Check, before any computation, that a directory of results can be written at
    ``path``: an existing writable directory, or a new one in an existing writable
    directory (created when the results are complete, see :func:`atomic_directory`)."""
    text = _text(path, field, "directory")
    target = Path(text)
    if target.exists():
        if not target.is_dir():
            raise InputError(field, f"{target} is a file; give a directory")
        _probe(target, field)
    else:
        _existing_directory(target.absolute().parent, field)
    return target


def atomic_write(path: str | os.PathLike[str], writer: Callable[[Path], object],
                 field: str = "out") -> Path:
    """Call ``writer(tmp)`` on a temporary path beside ``path``, then rename it to ``path``.

    Parameters
    ----------
    path
        Target file; its directory must exist. A symlink is written through.
    writer
        Writes the complete file to the path it is given (e.g.
        ``lambda p: ds.to_netcdf(p, engine="h5netcdf")``).
    field
        The option that named ``path``, for error messages.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    OutputError
        When the file cannot be written (no such directory, no permission, a full device);
        the target then is as it was and no temporary file is left.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> atomic_write(d / "a.txt", lambda p: p.write_text("hello")).read_text()
    'hello'
    """
    path = Path(path)
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    try:
        fd, tmp_name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.",
                                        suffix=".tmp")
    except OSError as exc:
        raise OutputError(field, f"cannot write {target}: {_reason(exc)}") from None
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        try:
            with signals_deferred():
                writer(tmp)
            os.chmod(tmp, 0o666 & ~_umask())
            os.replace(tmp, target)
        except OSError as exc:
            raise OutputError(field, f"cannot write {target}: {_reason(exc)}") from None
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    return path


def atomic_write_text(path: str | os.PathLike[str], text: str, field: str = "out") -> Path:
    """Write ``text`` (UTF-8, ``\\n`` line ends) atomically to ``path``."""

    def write(p: Path) -> None:
        with open(p, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)

    return atomic_write(path, write, field)


@contextlib.contextmanager
def atomic_directory(path: str | os.PathLike[str], field: str = "out") -> Iterator[Path]:
    """A staging directory whose files become the directory ``path`` when the block ends.

    Write the results into the yielded directory (flat: files only). When the block ends
    normally, a missing ``path`` is created by renaming the staging directory (it appears
    complete, with mode 0777 less the umask), an existing one gets the new files, each
    replacing its namesake, other files staying. When the block raises (an error, an
    interrupt), the staging directory is removed and ``path`` is as it was: no empty
    directory, no partial files.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_directory(d / "results") as tmp:
    ...     _ = atomic_write_text(tmp / "table.md", "| a |")
    >>> sorted(p.name for p in d.iterdir()), (d / "results" / "table.md").read_text()
    (['results'], '| a |')
    """
    target = Path(path)
    stage = None
    try:
        try:
            # an interrupt between the directory's creation and ``stage`` being set would
            # leave it behind: it is held until ``stage`` is known, then raised in here
            with signals_deferred():
                stage = Path(tempfile.mkdtemp(dir=target.absolute().parent,
                                              prefix=f".{target.name}.", suffix=".tmp"))
        except OSError as exc:
            raise OutputError(field, f"cannot write {target}: {_reason(exc)}") from None
        try:
            yield stage
            os.chmod(stage, 0o777 & ~_umask())
            if not target.exists():
                os.rename(stage, target)
                return
            for entry in sorted(stage.iterdir()):
                os.replace(entry, target / entry.name)
        except OSError as exc:
            raise OutputError(field, f"cannot write {target}: {_reason(exc)}") from None
    finally:
        if stage is not None:
            shutil.rmtree(stage, ignore_errors=True)


def _quiet_stdout() -> None:
    """Point the file descriptor of stdout at /dev/null, so that the interpreter's final
    flush of what could not be written raises nothing more."""
    try:
        fd = sys.stdout.fileno()
    except (OSError, ValueError, AttributeError):
        return  # not a real file (a test's capture)
    with contextlib.suppress(OSError):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, fd)
        os.close(null)


def stdout_error(exc: OSError) -> OutputError:
    """The :class:`OutputError` for a failed write to stdout (stdout then points at
    /dev/null, so that the interpreter's final flush raises nothing more)."""
    _quiet_stdout()
    return OutputError("stdout", f"cannot write: {_reason(exc)}")


def write_stdout(text: str) -> None:
    """Write ``text`` to standard output and flush it.

    Raises
    ------
    OutputError
        For ``stdout`` when the pipe was closed by its reader or the device is full.
    """
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except OSError as exc:
        raise stdout_error(exc) from None
