"""Where numba caches the compiled kernels when pdamper is installed read-only.

The kernels are compiled with ``cache=True``; numba writes the cache beside the sources
(``__pycache__``) or, where that is not writable, in ``~/.cache/numba``. In a read-only
installation run by a user without a writable home (a service account, ``nobody``) both
fail and numba refuses to load the kernels ("cannot cache function ...: no locator
available"). :func:`configure` therefore points ``NUMBA_CACHE_DIR`` at a writable per-user
directory, before numba is first imported, when the package directory is not writable and
the user has not chosen a cache directory: ``$XDG_CACHE_HOME/pdamper/numba``,
``~/.cache/pdamper/numba``, or a private directory in the system's temporary directory.
This module imports neither numba nor anything heavy: ``import pdamper`` stays fast.
"""

from __future__ import annotations

import logging
import os
import stat
import sys
import tempfile
from collections.abc import MutableMapping
from pathlib import Path

logger = logging.getLogger("pdamper")

#: The environment variable numba reads for a user-provided cache directory.
VARIABLE = "NUMBA_CACHE_DIR"


def _writable(directory: Path) -> bool:
    """A file can be created in ``directory`` (mode bits, read-only mounts, ownership)."""
    try:
        fd, name = tempfile.mkstemp(dir=directory, prefix=".pdamper-probe-")
    except OSError:
        return False
    os.close(fd)
    try:
        os.unlink(name)
    except OSError:
        pass
    return True


def _in_tree_writable(package: Path) -> bool:
    """numba can write its cache beside the sources: the package directory and every
    ``__pycache__`` in it are writable (``os.access``: no file is created on import)."""
    flags = os.W_OK | os.X_OK
    if not os.access(package, flags):
        return False
    return all(os.access(d, flags) for d in package.rglob("__pycache__"))


def _private(directory: Path) -> bool:
    """``directory`` exists (created if needed, mode 0700), is ours, no symlink, writable."""
    try:
        directory.mkdir(mode=0o700, parents=True, exist_ok=True)
        st = os.lstat(directory)
    except OSError:
        return False
    if not stat.S_ISDIR(st.st_mode) or (hasattr(os, "getuid") and st.st_uid != os.getuid()):
        return False
    return _writable(directory)


def candidates(environ: MutableMapping[str, str] = os.environ) -> list[Path]:
    """Cache directories to try, in order."""
    out = []
    xdg = environ.get("XDG_CACHE_HOME")
    if xdg and os.path.isabs(xdg):
        out.append(Path(xdg) / "pdamper" / "numba")
    home = environ.get("HOME")
    if home and os.path.isabs(home):
        out.append(Path(home) / ".cache" / "pdamper" / "numba")
    uid = os.getuid() if hasattr(os, "getuid") else "user"
    out.append(Path(tempfile.gettempdir()) / f"pdamper-numba-cache-{uid}")
    return out


def configure(environ: MutableMapping[str, str] = os.environ,
              package: Path | None = None) -> Path | None:
    """Set ``NUMBA_CACHE_DIR`` if needed; returns the directory set, or None.

    Nothing changes when the user has set ``NUMBA_CACHE_DIR`` or the package directory is
    writable (numba's own choice then works). When no candidate is writable either, numba
    is left to say so when a kernel is first compiled.
    """
    if environ.get(VARIABLE):
        return None
    package = Path(__file__).resolve().parent if package is None else package
    if _in_tree_writable(package):
        return None
    for directory in candidates(environ):
        if _private(directory):
            environ[VARIABLE] = str(directory)
            numba_config = sys.modules.get("numba.core.config")
            if numba_config is not None:  # numba already loaded: its setting too
                numba_config.CACHE_DIR = str(directory)
            logger.debug("pdamper is installed read-only: numba caches in %s", directory)
            return directory
    logger.warning("no writable directory for numba's cache (package, %s); set %s",
                   ", ".join(map(str, candidates(environ))), VARIABLE)
    return None
