"""Atomic file output: the one writer every result file goes through.

A result file is written to a temporary file beside its target and renamed over it only when
the writer has finished, so that an interrupted or failed run never leaves a half-written
file under the target's name. Files get the usual permissions (0644 less the umask) whatever
the temporary-file machinery would give.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable
from pathlib import Path

__all__ = ["atomic_write", "atomic_write_text"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write(path: str | os.PathLike[str], writer: Callable[[Path], object]) -> Path:
    """Call ``writer(tmp)`` on a temporary path beside ``path``, then rename it to ``path``.

    Parameters
    ----------
    path
        Target file; its directory must exist.
    writer
        Writes the complete file to the path it is given (e.g.
        ``lambda p: ds.to_netcdf(p, engine="h5netcdf")``).

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> atomic_write(d / "a.txt", lambda p: p.write_text("hello")).read_text()
    'hello'
    """
    path = Path(path)
    fd, tmp_name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        writer(tmp)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    return path


def atomic_write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8, ``\\n`` line ends) atomically to ``path``."""

    def write(p: Path) -> None:
        with open(p, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)

    return atomic_write(path, write)
