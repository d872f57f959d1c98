"""The shape of the code a reader meets: short functions, a short engine, a small engine
constructor, and a type check that passes.

- no function outside the numba kernels (``pdamper/dem/kernels``) over 80 lines, counted
  without its docstring;
- ``dem/simulation.py`` under 700 lines, ``io/scenario.py`` (the scenario's schema and its
  builders) under 600;
- ``reports/`` renders: no module there runs anything (no ``run_*`` function, no sweep
  engine, no dask); the runs live in ``runs/``;
- ``DEMEngine.__init__`` takes at most six parameters (the settings travel as objects);
- mypy, as CI runs it (``python3 -m mypy``, configured in pyproject.toml), passes.
"""

from __future__ import annotations

import ast
import importlib.util
import inspect
import subprocess
import sys
from pathlib import Path

import pytest

import pdamper

PACKAGE = Path(pdamper.__file__).parent
REPO = Path(__file__).resolve().parents[1]
#: Longest function body allowed [lines, without the docstring].
MAX_FUNCTION_LINES = 80


def function_lengths(path: Path) -> list[tuple[str, int]]:
    """``(name, lines)`` of every function and method in ``path``, nested ones included;
    lines from ``def`` to the last line of the body, less the docstring's."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            assert node.end_lineno is not None
            n = node.end_lineno - node.lineno + 1
            first = node.body[0]
            if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
                    and isinstance(first.value.value, str)):
                assert first.end_lineno is not None
                n -= first.end_lineno - first.lineno + 1
            out.append((node.name, n))
    return out


def long_functions(skip: tuple[str, ...] = ()) -> list[str]:
    """``file:function (lines)`` of every function over the limit outside the kernels and
    the files in ``skip`` (paths relative to the package)."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel.startswith("dem/kernels/") or rel in skip:
            continue
        found += [f"{rel}:{name} ({n} lines)" for name, n in function_lengths(path)
                  if n > MAX_FUNCTION_LINES]
    return found


def test_the_length_count_leaves_out_the_docstring(tmp_path):
    """The counting itself: a docstring does not count, the body does."""
    body = "\n".join(f"    x{i} = {i}" for i in range(3))
    src = f'def f():\n    """One.\n\n    Two.\n    """\n{body}\n\n\ndef g():\n{body}\n'
    (tmp_path / "m.py").write_text(src)
    assert function_lengths(tmp_path / "m.py") == [("f", 4), ("g", 4)]


def test_no_function_over_80_lines():
    assert long_functions() == []


def test_the_engine_module_is_under_700_lines():
    lines = (PACKAGE / "dem" / "simulation.py").read_text(encoding="utf-8").splitlines()
    assert len(lines) < 700


def test_the_scenario_module_is_under_600_lines():
    """The schema and its builders; the example text, the resource checks, the grids, the
    reading and the load-time checks live in modules of their own."""
    lines = (PACKAGE / "io" / "scenario.py").read_text(encoding="utf-8").splitlines()
    assert len(lines) < 600


#: What a module that runs things imports: the sweep engine and dask.
RUNNER_IMPORTS = ("pdamper.sweep", "dask", "distributed")


def runners_in(source: str) -> list[str]:
    """The runners in a module's ``source``: functions named ``run_*`` (anywhere, methods
    included) and imports of the sweep engine or dask (function-level ones included)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) \
                and node.name.startswith("run_"):
            found.append(f"def {node.name} (line {node.lineno})")
        names: list[str] = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            names = [node.module]
        found += [f"import {n} (line {node.lineno})" for n in names
                  if any(n == r or n.startswith(r + ".") for r in RUNNER_IMPORTS)]
    return found


def test_the_runner_check_finds_a_runner():
    """The check below can fail: a ``run_*`` function and a sweep import are found."""
    src = "def run_map():\n    from pdamper.sweep import run_sweep\n"
    assert runners_in(src) == ["def run_map (line 1)", "import pdamper.sweep (line 2)"]
    assert runners_in("import dask.array\n") == ["import dask.array (line 1)"]
    assert runners_in("def render(run):\n    return run\n") == []


def test_reports_hold_no_runner():
    """``reports/`` renders what ``runs/`` computed."""
    found = {path.name: runners_in(path.read_text(encoding="utf-8"))
             for path in sorted((PACKAGE / "reports").glob("*.py"))}
    assert {k: v for k, v in found.items() if v} == {}


def test_the_engine_takes_at_most_six_parameters():
    """Explicit parameters (settings objects), no ``**options``."""
    from pdamper.dem import DEMEngine

    params = [p for name, p in inspect.signature(DEMEngine.__init__).parameters.items()
              if name != "self"]
    assert len(params) <= 6, [p.name for p in params]
    assert not [p for p in params if p.kind in (p.VAR_KEYWORD, p.VAR_POSITIONAL)]


@pytest.mark.long  # a whole mypy run (tens of CPU seconds cold): in CI's long group
def test_the_type_check_passes():
    """``python3 -m mypy`` from the repository root, as CI runs it: no error."""
    if importlib.util.find_spec("mypy") is None:
        pytest.skip("mypy is not installed (pip install -e '.[test]')")
    if not (REPO / "pyproject.toml").is_file() or not (REPO / "src" / "pdamper").is_dir():
        pytest.skip("needs the source tree (pyproject.toml and src/pdamper)")
    p = subprocess.run([sys.executable, "-m", "mypy"], cwd=REPO, capture_output=True,
                       text=True, timeout=900)
    assert p.returncode == 0, p.stdout[-4000:] + p.stderr[-2000:]
