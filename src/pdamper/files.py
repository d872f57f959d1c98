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
- **Only this module touches the device.** Third-party writers serialise into memory
  (:func:`atomic_write_netcdf`: the HDF5 library writes into a buffer, never into a file),
  and :func:`atomic_write_bytes` writes the bytes with plain system calls, checking every
  count and the size written before the rename. A full device thus ends with one line
  (an :class:`~pdamper.errors.OutputError`, status 1 at the command line) for every
  format: written by HDF5 itself, a file on a full device ended in a segmentation fault
  of the library after its own tracebacks.
  :func:`atomic_directory` does the same for a directory of results (``paper --out``): the
  files are written into a hidden staging directory beside the target, which becomes the
  target (a new directory appears complete or not at all) or whose files replace their
  namesakes in an existing target (other files there stay).
- **Usual permissions.** Files get 0666 and directories 0777, less the umask, whatever the
  temporary-file machinery would give (``mkstemp`` makes 0600).
- **Missing directories are refused, not created**: a command creates at most the output
  directory it is asked for, never its parents.
- **Standard output** (:func:`write_stdout`): written with the same checked system calls
  (Python's buffered stream took a short write on a nearly full device as complete: 4096
  of 7611 bytes and status 0); a closed pipe, a closed stream or a full device becomes an
  :class:`~pdamper.errors.OutputError` for ``stdout`` (one line, status 1 at the command
  line), with nothing more printed at exit.
- **One line.** Every message is one line (:func:`one_line`), whatever the operating
  system or a library put in it.

Problems while writing (a full device) are :class:`~pdamper.errors.OutputError`\\ s.
"""

from __future__ import annotations

import contextlib
import errno
import io
import os
import re
import shutil
import signal
import stat
import sys
import tempfile
import threading
from collections.abc import Callable, Iterator
from pathlib import Path

from pdamper.errors import InputError, OutputError

__all__ = ["atomic_directory", "atomic_write", "atomic_write_bytes", "atomic_write_netcdf",
           "atomic_write_text", "check_directory_target", "check_file_target", "checked_stdout",
           "one_line", "signals_deferred", "stdout_error", "write_stdout"]

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


def one_line(text: str) -> str:
    r"""``text`` with its line breaks (and the blanks around them) replaced by one space:
    an error is one line, whatever a library or the system put in its message.

    >>> one_line("file write failed: time = Thu\n, errno = 28\r\n")
    'file write failed: time = Thu , errno = 28'
    """
    return re.sub(r"\s*[\r\n\v\f\x85\u2028\u2029]+\s*", " ", str(text)).strip()


def _reason(exc: OSError) -> str:
    if isinstance(exc, BrokenPipeError) or exc.errno == errno.EPIPE:
        return "broken pipe (the reading end was closed)"
    if exc.errno == errno.EBADF:
        return "the stream is closed"
    return one_line(exc.strerror or str(exc))


#: Errors of a write that did not fit (a full device, a quota, a file size limit).
_FULL = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG}


def _size(n: int) -> str:
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n} bytes"


def _write_all(fd: int, data: bytes | bytearray | memoryview) -> None:
    """Write every byte of ``data`` to ``fd`` with plain ``os.write`` calls.

    A short count is followed by another call, which then says why (``ENOSPC``); a call
    that writes nothing is taken as a full device rather than tried forever.
    """
    view = memoryview(data).cast("B")
    while view:
        n = os.write(fd, view)
        if n <= 0:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        view = view[n:]


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
        Writes the complete file to the path it is given, with Python's file objects
        (which raise on a full device). A library that writes in C (HDF5) serialises into
        memory instead: :func:`atomic_write_netcdf`, :func:`atomic_write_bytes`.
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


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes | bytearray | memoryview,
                       field: str = "out") -> Path:
    """Write ``data`` atomically to ``path`` with checked system calls.

    Every ``os.write`` count is checked (a short write on a nearly full device is followed
    by another call, which says why) and the size of the temporary file is compared with
    ``len(data)`` before the rename.

    Raises
    ------
    OutputError
        On a full device (or any other failed write): one line naming ``field``, the file
        and the size that did not fit; the target is as it was and no temporary is left.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> atomic_write_bytes(d / "a.bin", b"\\x00\\x01").read_bytes()
    b'\\x00\\x01'
    """
    size = memoryview(data).nbytes

    def write(p: Path) -> None:
        try:
            fd = os.open(p, os.O_WRONLY | os.O_TRUNC | getattr(os, "O_BINARY", 0))
            try:
                _write_all(fd, data)
                written = os.fstat(fd).st_size
            finally:
                os.close(fd)  # where the file system reports a failed write late (NFS)
        except OSError as exc:
            if exc.errno in _FULL:
                raise OSError(exc.errno, f"{_reason(exc)} (writing {_size(size)})") from None
            raise
        if written != size:  # pragma: no cover - a file system that lost bytes silently
            raise OSError(errno.EIO, f"{written} of {size} bytes reached the file")

    return atomic_write(path, write, field)


def atomic_write_text(path: str | os.PathLike[str], text: str, field: str = "out") -> Path:
    """Write ``text`` (UTF-8, ``\\n`` line ends) atomically to ``path``."""
    return atomic_write_bytes(path, text.encode("utf-8"), field)


def netcdf_bytes(ds) -> memoryview:
    """``ds`` (an ``xarray.Dataset``) as the bytes of a NetCDF-4 file (h5netcdf engine),
    made in memory: the HDF5 library never writes to a device (on a full one, it printed
    tracebacks and ended in a segmentation fault). Signals wait until it returns
    (:func:`signals_deferred`)."""
    buf = io.BytesIO()
    with signals_deferred():
        ds.to_netcdf(buf, engine="h5netcdf")
    return buf.getbuffer()


def atomic_write_netcdf(path: str | os.PathLike[str], ds, field: str = "out") -> Path:
    """Write ``ds`` (an ``xarray.Dataset``) as NetCDF-4 atomically to ``path``: serialised
    in memory (:func:`netcdf_bytes`, the file's size once more in memory for a moment),
    then written by :func:`atomic_write_bytes`.

    Examples
    --------
    >>> import tempfile, pathlib, xarray as xr
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> p = atomic_write_netcdf(d / "a.nc", xr.Dataset({"x": ("i", [1.0, 2.0])}))
    >>> xr.load_dataset(p, engine="h5netcdf")["x"].values.tolist()
    [1.0, 2.0]
    """
    return atomic_write_bytes(path, netcdf_bytes(ds), field)


@contextlib.contextmanager
def atomic_directory(path: str | os.PathLike[str], field: str = "out") -> Iterator[Path]:
    """A staging directory whose files become the directory ``path`` when the block ends.

    Write the results into the yielded directory (flat: files only). When the block ends
    normally, a missing ``path`` is created by renaming the staging directory (it appears
    complete, with mode 0777 less the umask), an existing one gets the new files, each
    replacing its namesake, other files staying. When the block raises (an error, an
    interrupt), the staging directory is removed and ``path`` is as it was: no empty
    directory, no partial files.

    The staging directory is made where its files are renamed to: inside an existing
    ``path`` (which may be a mount point, a device of its own: a rename across devices
    fails), beside a missing one (which then appears on its parent's device).

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
                home = target if target.is_dir() else target.absolute().parent
                stage = Path(tempfile.mkdtemp(dir=home, prefix=f".{target.name}.",
                                              suffix=".tmp"))
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


class _CompleteWrites(io.RawIOBase):
    """A raw stream on a file descriptor (not owned: never closed) whose every write is
    complete or raises (:func:`_write_all`)."""

    def __init__(self, fd: int):
        super().__init__()
        self._fd = fd

    def writable(self) -> bool:
        return True

    def fileno(self) -> int:
        return self._fd

    def isatty(self) -> bool:
        return os.isatty(self._fd)

    def write(self, b) -> int:
        view = memoryview(b)
        _write_all(self._fd, view)
        return view.nbytes


def checked_stdout(stream):
    """``stream`` (``sys.stdout``) rebuilt on :class:`_CompleteWrites`, so that what other
    libraries print there (click's help text, rich) is written completely or raises, as
    :func:`write_stdout` does; the same encoding, error handler and line buffering. A
    stream without a descriptor (a test's capture) is returned as it is."""
    try:
        fd = stream.fileno()
        stream.flush()
    except (AttributeError, OSError, ValueError, io.UnsupportedOperation):
        return stream
    return io.TextIOWrapper(io.BufferedWriter(_CompleteWrites(fd)),
                            encoding=getattr(stream, "encoding", None) or "utf-8",
                            errors=getattr(stream, "errors", None) or "strict",
                            line_buffering=bool(getattr(stream, "line_buffering", False)))


def write_stdout(text: str) -> None:
    """Write ``text`` to standard output, completely, or raise.

    What the stream holds is flushed first; then the encoded text goes to its file
    descriptor with checked ``os.write`` calls (:func:`_write_all`), since the buffered
    stream of Python took a short write on a nearly full device for a complete one. A
    stream without a descriptor (a test's capture) is written as a stream.

    Raises
    ------
    OutputError
        For ``stdout`` when the pipe was closed by its reader, standard output is closed
        (``>&-``) or the device is full.
    """
    stream = sys.stdout
    try:
        if stream is None:  # closed when Python started (``>&-``)
            raise OSError(errno.EBADF, "standard output is closed")
        try:
            fd = stream.fileno()
        except (AttributeError, ValueError, io.UnsupportedOperation):
            fd = None
        if fd is None:
            stream.write(text)
            stream.flush()
            return
        stream.flush()
        if os.linesep != "\n":  # pragma: no cover - the stream's newline translation
            text = text.replace("\n", os.linesep)
        _write_all(fd, text.encode(getattr(stream, "encoding", None) or "utf-8",
                                   getattr(stream, "errors", None) or "strict"))
    except OSError as exc:
        raise stdout_error(exc) from None
