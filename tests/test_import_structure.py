"""Dependencies point one way inside every package, counting imports inside functions.

An import placed inside a function to dodge a circle hides the circle; it does not remove it
(STYLE, "Dependencies inside a package"). This test reads every module with `ast` and builds
each package's import graph from EVERY import statement (module level, inside functions, under
``if TYPE_CHECKING``), then looks for a cycle (Tarjan's strongly connected components). It also
holds the size rules of the house: modules of one concept (< 600 lines) and functions under 100
lines.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("scenarios", "radarsim", "pipeline", "metrics", "harness", "benchmarks")
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 100


def _modules(package: str, root: Path = ROOT) -> dict[str, Path]:
    out = {}
    for path in sorted((root / package).rglob("*.py")):
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def import_graph(package: str, root: Path = ROOT) -> dict[str, set[str]]:
    """Module -> modules of the same package it imports (every import statement counts).

    ``from . import x`` counts as importing ``package.x`` (not the package's ``__init__``,
    which Python runs first for every submodule anyway)."""
    mods = _modules(package, root)
    graph: dict[str, set[str]] = {m: set() for m in mods}
    for mod, path in mods.items():
        is_init = path.name == "__init__.py"
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = mod.split(".") if is_init else mod.split(".")[:-1]
                    base = base[:len(base) - node.level + 1]
                    src = ".".join(base + ([node.module] if node.module else []))
                else:
                    src = node.module or ""
                targets = [f"{src}.{a.name}" if f"{src}.{a.name}" in mods else src
                           for a in node.names]
            else:
                continue
            for t in targets:
                # A module importing its own parent package is the import system's order.
                if t in mods and t != mod and not mod.startswith(t + "."):
                    graph[mod].add(t)
    return graph


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, 1972)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_the_checker_finds_a_circle_hidden_inside_a_function(tmp_path):
    """The detector itself: a circle closed by an import inside a function is found."""
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from . import b\n")
    (pkg / "b.py").write_text("def f():\n    from .a import g\n")
    (pkg / "c.py").write_text("from pkg import a\n")
    graph = import_graph("pkg", tmp_path)
    assert graph["pkg.b"] == {"pkg.a"} and graph["pkg.c"] == {"pkg.a"}
    assert strongly_connected(graph) == [["pkg.a", "pkg.b"]]


@pytest.mark.parametrize("package", PACKAGES)
def test_no_import_circle_inside_a_package(package):
    assert strongly_connected(import_graph(package)) == []


def _function_lengths(path: Path):
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node.name, node.lineno, node.end_lineno - node.lineno + 1


@pytest.mark.parametrize("package", PACKAGES)
def test_modules_and_functions_stay_small(package):
    long_modules, long_functions = [], []
    for mod, path in _modules(package).items():
        n = len(path.read_text().splitlines())
        if n > MAX_MODULE_LINES:
            long_modules.append(f"{mod} ({n} lines)")
        long_functions += [f"{mod}.{name} (line {line}, {n} lines)"
                           for name, line, n in _function_lengths(path)
                           if n > MAX_FUNCTION_LINES]
    assert long_modules == [] and long_functions == []
