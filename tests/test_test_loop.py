"""The test loop's own settings (tests/conftest.py): what keeps the default run short."""

from __future__ import annotations

import ast
import os
from pathlib import Path

TESTS = Path(__file__).resolve().parent


def _root_conftest(config):
    """tests/conftest.py as pytest loaded it (``import conftest`` may find tests/fuzz's)."""
    (module,) = [p for p in config.pluginmanager.get_plugins()
                 if Path(getattr(p, "__file__", "") or "").resolve() == TESTS / "conftest.py"]
    return module


def test_every_test_run_first_exists(request):
    """A renamed or removed test in ``conftest.FIRST`` would silently stop being run
    first: each names a test function of its file."""
    for nodeid in _root_conftest(request.config).FIRST:
        path, name = nodeid.split("::")
        file = TESTS.parent / path
        assert file.is_file(), nodeid
        functions = {n.name for n in ast.walk(ast.parse(file.read_text(encoding="utf-8")))
                     if isinstance(n, ast.FunctionDef)}
        assert name.split("[")[0] in functions, nodeid


def test_one_blas_thread_per_process():
    """The suite runs a process per core: each one's BLAS keeps to one thread (unless the
    environment chose otherwise before the run)."""
    for variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        assert os.environ.get(variable), variable
