"""The test loop's own settings (tests/conftest.py): what keeps the default run short."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
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



def test_cpu_seconds_count_the_children_a_test_waited_for():
    """``--cpu-durations`` charges a test with its child processes' CPU: a child that
    computes for about 0.3 s adds at least 0.2 s once waited for, while this process
    only waited."""
    from cpu_durations import cpu_seconds

    before = cpu_seconds()
    subprocess.run([sys.executable, "-c",
                    "import time\nt = time.process_time()\n"
                    "while time.process_time() - t < 0.3: pass"], check=True)
    assert cpu_seconds() - before >= 0.2


def test_cpu_durations_reach_the_controller_from_the_workers(tmp_path):
    """The CPU seconds travel on the teardown report, which pytest-xdist sends from its
    workers to the controller: the summary lists each test there, with the total."""
    (tmp_path / "test_two.py").write_text("def test_a():\n    pass\n\n\ndef test_b():\n"
                                          "    pass\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(TESTS), *filter(None, [os.environ.get("PYTHONPATH")])]))
    run = subprocess.run([sys.executable, "-m", "pytest", "-p", "cpu_durations", "-p",
                          "no:cacheprovider", "-n", "1", "--cpu-durations=0", "-o", "addopts=",
                          "test_two.py"], cwd=tmp_path, env=env, capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    summary = run.stdout[run.stdout.index("CPU seconds of 2 tests"):]
    # (the node ids joined here: tests/test_docs.py reads "file::name" as a cited test)
    assert all("test_two.py" + "::" + name in summary for name in ("test_a", "test_b"))
