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


def candidates(environ: MutableMapping[str, str] = os.environ, kind: str = "numba") -> list[Path]:
    """Cache directories to try, in order (``kind``: what is cached, ``numba`` or ``pint``)."""
    out = []
    xdg = environ.get("XDG_CACHE_HOME")
    if xdg and os.path.isabs(xdg):
        out.append(Path(xdg) / "pdamper" / kind)
    home = environ.get("HOME")
    if home and os.path.isabs(home):
        out.append(Path(home) / ".cache" / "pdamper" / kind)
    uid = os.getuid() if hasattr(os, "getuid") else "user"
    out.append(Path(tempfile.gettempdir()) / f"pdamper-{kind}-cache-{uid}")
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
                numba_config.CACHE_DIR = str(directory)  # type: ignore[attr-defined]
            logger.debug("pdamper is installed read-only: numba caches in %s", directory)
            return directory
    logger.warning("no writable directory for numba's cache (package, %s); set %s",
                   ", ".join(map(str, candidates(environ))), VARIABLE)
    return None


#: The fingerprint of the kernel sources that the cached kernels were compiled from, kept
#: beside them (:func:`refresh`).
STAMP = "pdamper-kernel-sources.sha1"


def _cache_root(package: Path, environ: MutableMapping[str, str]) -> Path:
    """Where numba keeps the cache of ``package``: beside the sources, or, under a
    user-provided ``NUMBA_CACHE_DIR``, in the mirror of the package path that numba
    creates there."""
    user = environ.get(VARIABLE)
    if user:
        return Path(user) / package.resolve().as_posix().lstrip("/")
    return package


def fingerprint(package: Path) -> str:
    """SHA-1 of every module of ``package`` that compiles numba kernels (path and text)."""
    import hashlib

    h = hashlib.sha1()
    for path in sorted(package.rglob("*.py")):
        text = path.read_bytes()
        if b"njit" in text:
            h.update(path.relative_to(package).as_posix().encode())
            h.update(text)
    return h.hexdigest()


def refresh(environ: MutableMapping[str, str] = os.environ,
            package: Path | None = None) -> int:
    """Delete pdamper's cached kernels when a kernel source changed since they were cached;
    returns the number of files deleted.

    numba checks a cached kernel only against the timestamp of its own source file, not
    against the helpers it inlines from other files (``gear_advance`` inlines the contact
    law of :mod:`pdamper.dem.kernels.forces`, the free flights of
    :mod:`pdamper.dem.kernels.flights`, ...): after such a helper changes (a ``git pull``
    into an editable installation), numba would load the stale kernel. A fingerprint of all
    kernel sources, kept beside the cache, catches it; the next call compiles afresh. Cheap
    (reads about twenty files); failures to read or write are logged and ignored.
    """
    package = Path(__file__).resolve().parent if package is None else package
    root = _cache_root(package, environ)
    try:
        digest = fingerprint(package)
        stamp = (root / "__pycache__" / STAMP) if root == package else (root / STAMP)
        if stamp.is_file() and stamp.read_text().strip() == digest:
            return 0
        deleted = 0
        if root.is_dir():
            for pattern in ("*.nbi", "*.nbc"):
                for f in root.rglob(pattern):
                    f.unlink()
                    deleted += 1
        stamp.parent.mkdir(parents=True, exist_ok=True)
        stamp.write_text(digest + "\n")
    except OSError as exc:
        logger.debug("numba cache of pdamper not refreshed: %s", exc)
        return 0
    if deleted:
        logger.info("kernel sources changed: %d cached numba files of pdamper deleted", deleted)
    return deleted
