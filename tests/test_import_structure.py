"""The rules of the house, read from the source with `ast` (docs/design.md section 2).

- Dependencies point one way inside every package, counting imports inside functions: an
  import placed inside a function to dodge a circle hides the circle, it does not remove it.
  Each package's import graph is built from EVERY import statement (module level, inside
  functions, under ``if TYPE_CHECKING``) and searched for a cycle (Tarjan's strongly connected
  components).
- Between packages the layer order holds: core < scenarios < radarsim < pipeline < metrics <
  harness, benchmarks on top (`test_layer_order`).
- No module imports another module's private name, and no library module reaches into a
  third-party private (`test_no_private_name_crosses_a_module`).
- Nothing patches a third-party module at import time (`test_nothing_patches_at_import`).
- Modules of one concept (< 600 lines) and functions under 100 lines, test helpers included.
- A compiled kernel takes fewer than a dozen positional arguments: more travel together as
  a small typed parameter object (`test_kernels_take_fewer_than_a_dozen_arguments`).
"""
from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Layer order, bottom up: a package may import only itself and the packages before it.
LAYERS = ("core", "scenarios", "radarsim", "pipeline", "metrics", "harness", "benchmarks")
PACKAGES = LAYERS + ("tests",)
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 100


def _parse(path: Path) -> ast.Module:
    """The syntax tree of a source file (read-only for the callers): every rule walks the same
    files, so each is parsed once per test process while it is unchanged."""
    st = path.stat()
    return _parsed(path, st.st_mtime_ns, st.st_size)


@functools.lru_cache(maxsize=None)
def _parsed(path: Path, mtime_ns: int, size: int) -> ast.Module:
    return ast.parse(path.read_text(), str(path))


def _nodes(path: Path) -> tuple[ast.AST, ...]:
    """Every node of a source file's tree in `ast.walk` order (read-only): the rules filter
    this list, walked once per test process while the file is unchanged, instead of walking
    the tree again each (the walks were most of this module's time)."""
    st = path.stat()
    return _walked(path, st.st_mtime_ns, st.st_size)


@functools.lru_cache(maxsize=None)
def _walked(path: Path, mtime_ns: int, size: int) -> tuple[ast.AST, ...]:
    return tuple(ast.walk(_parsed(path, mtime_ns, size)))


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
        for node in _nodes(path):
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
    for node in _nodes(path):
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


#: A numba kernel's positional arguments, at most: fewer than a dozen; operands that travel
#: together come as one small parameter object (docs/design.md section 3, compiled kernels).
MAX_KERNEL_ARGUMENTS = 11


def _long_kernels(path: Path) -> list[tuple[str, int]]:
    """(name, argument count) of every ``numba.njit`` function of a source file with more than
    `MAX_KERNEL_ARGUMENTS` arguments."""
    out = []
    for node in _nodes(path):
        if isinstance(node, ast.FunctionDef) and any(
                "njit" in ast.unparse(d) for d in node.decorator_list):
            n = len(node.args.posonlyargs) + len(node.args.args)
            if n > MAX_KERNEL_ARGUMENTS:
                out.append((node.name, n))
    return out


def test_the_kernel_checker_finds_a_long_signature(tmp_path):
    args = ", ".join(f"a{i}" for i in range(MAX_KERNEL_ARGUMENTS + 1))
    (tmp_path / "k.py").write_text(f"import numba\n\n@numba.njit(cache=True)\ndef wide({args}):\n"
                                   f"    return a0\n\n@numba.njit\ndef narrow(a, b):\n"
                                   f"    return a\n")
    assert _long_kernels(tmp_path / "k.py") == [("wide", MAX_KERNEL_ARGUMENTS + 1)]


@pytest.mark.parametrize("package", LAYERS)
def test_kernels_take_fewer_than_a_dozen_arguments(package):
    wide = [f"{mod}.{name} ({n} arguments)" for mod, path in _modules(package).items()
            for name, n in _long_kernels(path)]
    assert wide == []


# ----------------------------------------------------------------------------- between packages
def _imports(path: Path, module: str) -> list[tuple[int, str, list[str]]]:
    """(line, imported module, names) of every import statement of a module, relative ones
    resolved (``names`` empty for ``import x``)."""
    is_init = path.name == "__init__.py"
    out = []
    for node in _nodes(path):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name, []) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            src = node.module or ""
            if node.level:
                base = module.split(".") if is_init else module.split(".")[:-1]
                base = base[:len(base) - node.level + 1]
                src = ".".join(base + ([node.module] if node.module else []))
            out.append((node.lineno, src, [a.name for a in node.names]))
    return out


def layer_violations(root: Path = ROOT, layers=LAYERS) -> list[str]:
    """Imports of a package later in `layers` than the importing one."""
    rank = {p: i for i, p in enumerate(layers)}
    bad = []
    for package in layers:
        for mod, path in _modules(package, root).items():
            for line, src, _ in _imports(path, mod):
                top = src.split(".")[0]
                if top in rank and rank[top] > rank[package]:
                    bad.append(f"{mod}:{line} imports {src} ({package} is below {top})")
    return bad


def test_the_layer_checker_finds_an_upward_import(tmp_path):
    for pkg, text in (("low", "def f():\n    from high import x\n"), ("high", "import low\n")):
        (tmp_path / pkg).mkdir()
        (tmp_path / pkg / "__init__.py").write_text("")
        (tmp_path / pkg / "m.py").write_text(text)
    assert layer_violations(tmp_path, ("low", "high")) == [
        "low.m:2 imports high (low is below high)"]


def test_layer_order():
    assert layer_violations() == []


def _third_party_aliases(nodes) -> dict[str, str]:
    """Local name -> dotted third-party module or object of every import among a module's
    `nodes` (`_nodes`)."""
    out = {}
    for node in nodes:
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] not in PACKAGES:
                    out[a.asname or a.name.split(".")[0]] = a.name
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            if node.module.split(".")[0] not in PACKAGES and node.module != "__future__":
                for a in node.names:
                    out[a.asname or a.name] = f"{node.module}.{a.name}"
    return out


def _root_name(node: ast.AST) -> str | None:
    while isinstance(node, ast.Attribute):
        node = node.value
    return node.id if isinstance(node, ast.Name) else None


def _is_private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


#: Underscore names that are public API of their module.
PUBLIC_UNDERSCORE = {"os._exit", "sys._getframe"}
#: The third-party privates the project reads, and why: a process pool's worker processes
#: (`concurrent.futures.ProcessPoolExecutor._processes`, stable since Python 3.2) are the only
#: handle to terminate them at a stop signal (`harness.runtime.stop_pool`); numba's cache
#: index path is what `core.numba_cache.install_cache_lock` (an explicit, documented call,
#: never made at import) locks while numba writes it.
KNOWN_PRIVATE = {"harness.runtime": {"_processes"}, "core.numba_cache": {"_index_path"}}


def private_crossings(package: str, root: Path = ROOT) -> list[str]:
    """``from x import _y`` of another module, ``thirdparty._y`` and ``getattr(x, "_y")``.

    Test modules (``test_*.py``) may test the private helpers of the module they test; test
    helper modules may not reach into other modules either."""
    bad = []
    for mod, path in _modules(package, root).items():
        white_box = package == "tests" and path.name.startswith("test_")
        for line, src, names in _imports(path, mod):
            if src.split(".")[0] in PACKAGES and not (white_box and not src.startswith("tests")):
                bad += [f"{mod}:{line} imports {src}.{n}" for n in names if _is_private(n)]
        if white_box:
            continue
        third = _third_party_aliases(_nodes(path))
        for node in _nodes(path):
            if isinstance(node, ast.Attribute) and _is_private(node.attr):
                base = _root_name(node)
                if base in third and f"{third[base]}.{node.attr}" not in PUBLIC_UNDERSCORE:
                    bad.append(f"{mod}:{node.lineno} uses {third[base]}...{node.attr}")
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and \
                    node.func.id in ("getattr", "hasattr") and len(node.args) >= 2 and \
                    isinstance(node.args[1], ast.Constant) and \
                    isinstance(node.args[1].value, str) and _is_private(node.args[1].value) \
                    and node.args[1].value not in KNOWN_PRIVATE.get(mod, ()):
                bad.append(f"{mod}:{node.lineno} {node.func.id}(..., {node.args[1].value!r})")
    return bad


def test_the_private_name_checker_finds_each_kind(tmp_path):
    pkg = tmp_path / "pipeline"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .b import _k\nimport pandas as pd\nx = pd.DataFrame._m\n"
                              "y = getattr(pd, '_z', None)\nimport os\nos._exit\n")
    assert private_crossings("pipeline", tmp_path) == [
        "pipeline.a:1 imports pipeline.b._k", "pipeline.a:3 uses pandas..._m",
        "pipeline.a:4 getattr(..., '_z')"]


@pytest.mark.parametrize("package", PACKAGES)
def test_no_private_name_crosses_a_module(package):
    assert private_crossings(package) == []


def _patches(tree: ast.AST, third: dict[str, str]) -> list[tuple[int, str]]:
    """Statements of `tree` that assign to an attribute of a third-party module or object
    (`third`: the module's imports), or setattr one: (line, what)."""
    out = []
    for node in ast.walk(tree):
        targets = node.targets if isinstance(node, ast.Assign) else \
            [node.target] if isinstance(node, (ast.AugAssign, ast.AnnAssign)) else []
        for tgt in targets:
            if isinstance(tgt, ast.Attribute) and _root_name(tgt) in third:
                out.append((node.lineno, f"{third[_root_name(tgt)]}...{tgt.attr} = ..."))
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and \
                node.func.id == "setattr" and node.args and _root_name(node.args[0]) in third:
            out.append((node.lineno, f"setattr({third[_root_name(node.args[0])]}, ...)"))
    return out


def import_time_patches(package: str, root: Path = ROOT) -> list[str]:
    """Third-party patches that run when a module is imported: at module level, or in a
    function of the package that module-level code calls."""
    mods = _modules(package, root)
    trees = {m: _parse(p) for m, p in mods.items()}
    patchers = set()  # (module, function) whose body patches a third-party module
    third = {m: _third_party_aliases(_nodes(p)) for m, p in mods.items()}
    for mod, tree in trees.items():
        for node in tree.body:
            if isinstance(node, ast.FunctionDef) and _patches(node, third[mod]):
                patchers.add((mod, node.name))
    bad = []
    for mod, tree in trees.items():
        imported = {}
        for line, src, names in _imports(mods[mod], mod):
            imported.update({n: (src, n) for n in names})
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                continue
            bad += [f"{mod}:{line} {what}" for line, what in _patches(node, third[mod])]
            for call in ast.walk(node):
                if isinstance(call, ast.Call) and isinstance(call.func, ast.Name):
                    f = call.func.id
                    if (mod, f) in patchers or imported.get(f) in patchers:
                        bad.append(f"{mod}:{call.lineno} calls {f}(), which patches a "
                                   "third-party module, at import")
    return bad


def test_the_patch_checker_finds_an_import_time_patch(tmp_path):
    pkg = tmp_path / "pipeline"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("from .c import install\ninstall()\n")
    (pkg / "c.py").write_text("import numba\n\ndef install():\n    numba.core.x = 1\n")
    (pkg / "d.py").write_text("import numba\nnumba.config.Y = 2\n")
    assert import_time_patches("pipeline", tmp_path) == [
        "pipeline:2 calls install(), which patches a third-party module, at import",
        "pipeline.d:2 numba...Y = ..."]


@pytest.mark.parametrize("package", LAYERS)
def test_nothing_patches_at_import(package):
    assert import_time_patches(package) == []
