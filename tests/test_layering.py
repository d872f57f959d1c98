"""Import layering of the package: the toolchain's levels import downwards only.

Plain AST parsing of every module (function-level and TYPE_CHECKING imports included): a
module of one level may import pdamper modules of its own or a lower level, never of a
higher one. The levels follow the paper's toolchain (Level I contact, Level II analysis and
DEM, the damper models, Level III structure, coupling, design), then the edges.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

import pdamper

ROOT = Path(pdamper.__file__).parent

#: Level of each top-level module or package of ``pdamper``.
LEVELS = {
    "__init__": 0, "_version": 0, "_numba_cache": 0, "errors": 0, "units": 0, "constants": 0,
    "files": 0, "settings": 0,                     # the one declaration mechanism
    "sweep": 0,                                       # generic resumable sweeps (dask)
    "materials": 1, "contact": 1, "damper": 1,        # Level I and the design object
    "resources": 1,                                   # what a run of the design implies
    "analysis": 2, "dem": 2,                          # Level II
    "models": 3,                                      # one interface, several fidelities
    "structure": 4, "coupling": 5, "design": 6,       # Level III
    "parameters": 7, "io": 8, "plots": 8,             # the scenario parsed and built; figures
    "runs": 9,                                        # a scenario's runs and their cost
    "reports": 10,                                    # rendering of the runs' results
    "cli": 11, "__main__": 11,
    "explore": 11,                                    # the local web page (beside cli)
}


def _unit(module: str) -> str:
    """``pdamper.dem.kernels`` -> ``dem``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def imports_of(source: str, module: str) -> set[str]:
    """Absolute names of the pdamper modules imported anywhere in ``source``."""
    out = set()
    pkg = module.rsplit(".", 1)[0]
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.startswith("pdamper"))
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative
                base = pkg.split(".")[: len(pkg.split(".")) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            if name.startswith("pdamper"):
                out.add(name)
                out.update(f"{name}.{a.name}" for a in node.names)
    return out


def violations(source: str, module: str) -> list[str]:
    """Upward imports of ``module`` (its pdamper name) whose code is ``source``."""
    own = LEVELS[_unit(module)]
    bad = []
    for name in sorted(imports_of(source, module)):
        unit = _unit(name)
        if unit in LEVELS and LEVELS[unit] > own:
            bad.append(f"{module} (level {own}) imports {name} (level {LEVELS[unit]})")
    return bad


def _modules():
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT.parent).with_suffix("")
        yield ".".join(rel.parts).removesuffix(".__init__"), path


def test_every_top_level_unit_has_a_level():
    units = {p.stem if p.is_file() else p.name for p in ROOT.iterdir()
             if p.suffix == ".py" or (p.is_dir() and (p / "__init__.py").exists())}
    assert units <= set(LEVELS), units - set(LEVELS)


def test_no_lower_level_imports_a_higher_one():
    bad = [v for module, path in _modules() for v in violations(path.read_text(), module)]
    assert not bad, "\n".join(bad)


def test_the_checker_catches_an_upward_import():
    """The test above can fail: a Level II module importing the coupling is reported."""
    src = "def f():\n    from pdamper.coupling import Simulation\n"
    assert violations(src, "pdamper.analysis.fields")
    assert violations("from ..coupling import Simulation\n", "pdamper.models.base")
    assert not violations("from pdamper.dem import DEMEngine\n", "pdamper.models.dem")


@pytest.mark.parametrize(("module", "absent"), [
    ("pdamper.models", "pdamper.coupling"),
    ("pdamper.models", "numba"),
    ("pdamper", "numba"),
    ("pdamper.io.scenario", "numba"),
    ("pdamper.runs.resources", "numba"),
    ("pdamper.sweep", "distributed"),
    ("pdamper.models", "distributed"),
])
def test_import_does_not_pull_in(module, absent):
    """``import pdamper.models`` does not import the coupling; the package, the models,
    the scenario reader and the resource checks of its runs load no numba (fast CLI
    start-up)."""
    code = f"import sys, {module}; print({absent!r} in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "False"
