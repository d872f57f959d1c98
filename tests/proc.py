"""Run ``pdamper`` in a child process (signals, pipes, devices, other users), for tests."""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pdamper

#: ``src`` directory of the pdamper under test (editable install or PYTHONPATH).
SRC = Path(pdamper.__file__).resolve().parents[1]


def env(**extra: str) -> dict[str, str]:
    """The environment of a child: this pdamper first on the path, no colour, no pager."""
    e = dict(os.environ)
    e["PYTHONPATH"] = os.pathsep.join([str(SRC), *filter(None, [e.get("PYTHONPATH")])])
    e.setdefault("MPLBACKEND", "Agg")
    e["NO_COLOR"] = "1"
    e.update(extra)
    return e


def command(*args: object) -> list[str]:
    """``python -m pdamper ARGS``."""
    return [sys.executable, "-m", "pdamper", *map(str, args)]


def _works(prefix: list[str]) -> bool:
    """``prefix`` runs this Python, with numpy, as a user other than root."""
    try:
        probe = subprocess.run([*prefix, sys.executable, "-c",
                                "import os, numpy; print(os.geteuid())"],
                               capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return probe.returncode == 0 and probe.stdout.strip() not in ("", "0")


@functools.cache
def unprivileged_prefix() -> list[str] | None:
    """A command prefix that runs a program as an unprivileged user who can still read this
    Python installation, or None when there is no such way here.

    Not root: nothing to do. Root: a user namespace in which root's files belong to an
    unprivileged user (``unshare --user --map-user=65534``: permission bits then hold as for
    any user, so that a read-only directory is really read-only), else ``setpriv`` or
    ``runuser`` to ``nobody`` where that user can read this Python.
    """
    if os.geteuid() != 0:
        return []
    candidates = []
    if shutil.which("unshare"):
        candidates.append(["unshare", "--user", "--map-user=65534", "--map-group=65534"])
    if shutil.which("setpriv"):
        candidates.append(["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"])
    if shutil.which("runuser"):
        candidates.append(["runuser", "-u", "nobody", "--"])
    return next((c for c in candidates if _works(c)), None)
