"""The package's version, and a digest of the code that computes its results."""

from __future__ import annotations

import functools
import hashlib
from pathlib import Path

__version__ = "0.1.0"

#: Subpackages that only present results (figures, command-line parsing and formatting):
#: a change there leaves every number the same, so it does not invalidate cached results.
_PRESENTATION = ("cli", "plots")


@functools.cache
def source_digest() -> str:
    """16 hex digits identifying the source of every module that computes results.

    Part of the keys of cached maps and sweep points beside :data:`__version__`: the version
    changes only at releases, so without the digest a map cached by an older engine would
    be reused after a change of the physics between two releases.

    >>> len(source_digest()) == 16 and source_digest() == source_digest()
    True
    """
    return tree_digest(Path(__file__).resolve().parent)


def tree_digest(root: Path) -> str:
    """16 hex digits of the names and bytes of the ``*.py`` files under ``root``, less
    those of the presentation subpackages (:data:`_PRESENTATION`)."""
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        if rel.parts[0] in _PRESENTATION:
            continue
        h.update(rel.as_posix().encode())
        h.update(b"\0")
        h.update(path.read_bytes())
        h.update(b"\0")
    return h.hexdigest()[:16]
