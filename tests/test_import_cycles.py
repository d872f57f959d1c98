"""No import circles inside a package of ``pdamper``.

The import graph of ``src/pdamper`` from plain AST parsing of every module: module-level and
deferred imports (inside functions) both count, those under ``if TYPE_CHECKING:`` do not
(they never run). ``from pkg import name`` is an edge to the submodule ``pkg.name`` where
there is one, to the module a package's lazy ``_EXPORTS`` table names for ``name`` (the
package's ``__getattr__`` imports it on first access: :mod:`pdamper.dem`), else to ``pkg``
(its ``__init__``). A circle among the modules of one package
(``pdamper.coupling`` with its subpackages; the top-level modules are the package
``pdamper``) fails: a shared piece belongs a level down, where both sides import it. The
levels between packages are :mod:`tests.test_layering`'s.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pdamper

ROOT = Path(pdamper.__file__).parent


def _is_type_checking(node: ast.If) -> bool:
    t = node.test
    return (isinstance(t, ast.Name) and t.id == "TYPE_CHECKING") or (
        isinstance(t, ast.Attribute) and t.attr == "TYPE_CHECKING")


def _nodes(tree: ast.AST):
    """Every node of ``tree`` except the bodies of ``if TYPE_CHECKING:`` blocks."""
    for child in ast.iter_child_nodes(tree):
        if isinstance(child, ast.If) and _is_type_checking(child):
            for other in child.orelse:
                yield other
                yield from _nodes(other)
            continue
        yield child
        yield from _nodes(child)


def lazy_exports(source: str) -> dict[str, str]:
    """A package's ``_EXPORTS = {name: module}`` (names its ``__getattr__`` imports)."""
    for node in ast.parse(source).body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "_EXPORTS" for t in node.targets) \
                and isinstance(node.value, ast.Dict):
            return {k.value: v.value for k, v in zip(node.value.keys, node.value.values,
                                                      strict=True)
                    if isinstance(k, ast.Constant) and isinstance(v, ast.Constant)}
    return {}


def edges(source: str, module: str, modules: set[str], is_package: bool = False,
          lazy: dict[str, dict[str, str]] | None = None) -> set[str]:
    """The modules of ``modules`` that ``module`` (whose code is ``source``) imports;
    ``lazy`` the packages' lazy exports (:func:`lazy_exports`) by package."""
    lazy = lazy or {}
    pkg = module if is_package else module.rpartition(".")[0]
    out = set()
    for node in _nodes(ast.parse(source)):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name in modules)
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative
                parts = pkg.split(".")
                base = parts[: len(parts) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            for a in node.names:
                if f"{name}.{a.name}" in modules:
                    out.add(f"{name}.{a.name}")
                elif lazy.get(name, {}).get(a.name) in modules:
                    out.add(lazy[name][a.name])
                elif name in modules:
                    out.add(name)
    out.discard(module)
    return out


def package_of(module: str) -> str:
    """``pdamper.dem.kernels.gear`` -> ``pdamper.dem``; ``pdamper.units`` -> ``pdamper``."""
    parts = module.split(".")
    return ".".join(parts[:2]) if len(parts) > 2 or (ROOT / parts[-1]).is_dir() else "pdamper"


def graph() -> dict[str, set[str]]:
    paths = {}
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT.parent).with_suffix("")
        paths[".".join(rel.parts).removesuffix(".__init__")] = path
    names = set(paths)
    lazy = {m: lazy_exports(p.read_text()) for m, p in paths.items() if p.name == "__init__.py"}
    return {m: edges(p.read_text(), m, names, p.name == "__init__.py", lazy)
            for m, p in paths.items()}


def circles(g: dict[str, set[str]], same=lambda a, b: True) -> list[list[str]]:
    """The strongly connected components of more than one module of ``g``, following only
    edges ``a -> b`` with ``same(a, b)`` (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(g.get(v, ())):
            if not same(v, w):
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(g):
        if v not in index:
            visit(v)
    return out


def test_no_import_circle_inside_a_package():
    found = circles(graph(), lambda a, b: package_of(a) == package_of(b))
    assert not found, "import circles:\n" + "\n".join(" <-> ".join(c) for c in found)


def test_the_checker_finds_a_deferred_circle_and_skips_type_checking():
    """The test above can fail: a circle through an import inside a function is found;
    one through a TYPE_CHECKING import is not; a relative import resolves."""
    names = {"pdamper.coupling.a", "pdamper.coupling.b", "pdamper.coupling"}
    a = "from pdamper.coupling.b import f\n"
    b_deferred = "def g():\n    from pdamper.coupling.a import h\n"
    b_typing = ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                "    from pdamper.coupling.a import h\n")
    b_relative = "def g():\n    from .a import h\n"
    for b, circle in ((b_deferred, True), (b_typing, False), (b_relative, True)):
        g = {"pdamper.coupling.a": edges(a, "pdamper.coupling.a", names),
             "pdamper.coupling.b": edges(b, "pdamper.coupling.b", names)}
        assert bool(circles(g)) is circle, b
    # through a package's __init__: ``from pdamper.coupling import x`` is an edge to it
    init = edges("from pdamper.coupling.a import f\n", "pdamper.coupling", names, True)
    assert init == {"pdamper.coupling.a"}
    assert edges("from pdamper.coupling import f\n", "pdamper.coupling.a", names) \
        == {"pdamper.coupling"}
    # through a lazy export: the module the package's _EXPORTS names
    lazy = {"pdamper.coupling": lazy_exports('_EXPORTS = {"h": "pdamper.coupling.a"}\n')}
    assert edges("def g():\n    from pdamper.coupling import h\n", "pdamper.coupling.b",
                 names, lazy=lazy) == {"pdamper.coupling.a"}


def test_packages_group_subpackages_and_top_level_modules():
    assert package_of("pdamper.dem.kernels.gear") == "pdamper.dem"
    assert package_of("pdamper.dem") == "pdamper.dem"
    assert package_of("pdamper.units") == "pdamper"
