"""Compile the pipeline's numba kernels once per test run instead of once per xdist worker.

The kernels are ``cache=True``: compiled once per machine, then loaded from ``__pycache__``.
In a clean clone nothing is cached, and each of the two xdist workers (and every CLI
subprocess a test started before the cache was written) compiled every signature it met on
its own: ~16 s CPU of compilation done about twice. Here the signatures listed in
`numba_signatures.txt` are compiled module by module, each module by one worker: when its
session starts, each worker walks the modules (most signatures first) and takes every one no
other worker holds (a non-blocking lock), compiling it (or loading it, if another worker
already did); a module held by another worker is loaded after collecting, before the first
test, waiting for that worker if it is still compiling. The modules so go to whichever worker
is free (one module, `pipeline.interference.lowrank`, takes about half of the compile time: a fixed
split by count left one worker idle for seconds). Every test, and every subprocess a test
starts, then finds the kernels compiled.

A module's signatures are compiled under a per-module file lock because numba keeps one
cache index per function and rewrites it without a lock (load, add, save): two processes
compiling one function at once can lose an entry or pair it with the other's data file. The
kernels of one module call only kernels of that module, so modules are disjoint units.

Only speed depends on the list: a signature the kernels no longer take is skipped, one the
tests compile that the list lacks is compiled where it is met (as without the warm-up); the
terminal summary names both. To rewrite the list, run the suite in a clean checkout with the
warm-up off (``TESTS_NUMBA_WARM=0``: the cache indexes then hold exactly what the tests and
their subprocesses compiled, not the list's own signatures) and then
``python -m tests.numba_warm``.
"""
from __future__ import annotations

import contextlib
import hashlib
import importlib
import os
import re
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

SIGNATURES = Path(__file__).with_name("numba_signatures.txt")
#: Environment variable: "0" turns the warm-up off (to record the list, see above).
SWITCH = "TESTS_NUMBA_WARM"
ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("pipeline", "radarsim", "metrics", "harness", "scenarios")


@dataclass
class Warmup:
    """What one process's warm-up did so far."""
    compiled: int = 0
    stale: list[str] = field(default_factory=list)
    cpu_s: float = 0.0
    wall_s: float = 0.0


def read_signatures(path: Path = SIGNATURES) -> dict[str, list[tuple[str, str]]]:
    """module -> [(function, signature repr)] from `path` (lines ``module function sig``)."""
    out: dict[str, list[tuple[str, str]]] = {}
    if not path.exists():
        return out
    for number, line in enumerate(path.read_text().splitlines(), 1):
        if line.strip() and not line.startswith("#"):
            fields = line.split(" ", 2)
            if len(fields) != 3:
                raise ValueError(f"{path}:{number}: {line!r} is not 'module function "
                                 "signature' (rewrite the list: python -m tests.numba_warm)")
            module, function, sig = fields
            out.setdefault(module, []).append((function, sig))
    return out


def claim_order(modules: dict[str, list]) -> list[str]:
    """The modules in the order every worker tries to take them: most signatures first (the
    heavy ones start early, the light ones fill in), then by name."""
    return sorted(modules, key=lambda m: (-len(modules[m]), m))


def _types_namespace() -> dict:
    from numba.core import types
    ns = dict(vars(types))
    ns["bool"] = types.boolean  # repr of types.boolean
    ns["omitted"] = lambda default: types.Omitted(default)  # an argument left at its default
    ns["_literal"] = types.literal
    return ns


def _parse(sig: str, ns: dict) -> tuple:
    """The argument types of a signature's repr (``Literal[int](0)``: a constant argument)."""
    return tuple(eval(re.sub(r"Literal\[\w+\]\(([^()]*)\)", r"_literal(\1)", sig), ns))


@contextlib.contextmanager
def _module_lock(module: str, wait: bool = True):
    """An exclusive flock shared by every process of this machine warming `module` of this
    checkout (released by the OS if the holder dies). Yields whether it is held: with
    ``wait=False`` False when another process holds it (nothing done then)."""
    try:
        import fcntl
    except ImportError:  # no flock: compile unlocked (the warm-up is an optimisation)
        yield True
        return
    key = hashlib.sha1(f"{ROOT}:{module}".encode()).hexdigest()[:16]
    with open(Path(tempfile.gettempdir()) / f"numba-warm-{key}.lock", "a") as f:
        try:
            fcntl.flock(f, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            yield False
            return
        try:
            yield True
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def warm(modules: list[str], table: dict[str, list[tuple[str, str]]], out: Warmup,
         wait: bool = True) -> list[str]:
    """Compile (or load from the disk cache) the signatures of `modules` listed in `table`,
    one module at a time under its lock; counts and failures added to `out`. With
    ``wait=False`` a module another process holds is skipped; returns the skipped modules."""
    if os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"):
        return []
    t0, c0 = time.perf_counter(), time.process_time()
    ns = _types_namespace()
    skipped = []
    for module in modules:
        with _module_lock(module, wait) as held:
            if not held:
                skipped.append(module)
                continue
            try:
                mod = importlib.import_module(module)
            except Exception as e:  # noqa: BLE001 - a module gone: its lines are stale
                out.stale += [f"{module} {fn}: {type(e).__name__}" for fn, _ in table[module]]
                continue
            for fn, sig in table[module]:
                try:
                    getattr(mod, fn).compile(_parse(sig, ns))
                    out.compiled += 1
                except Exception as e:  # noqa: BLE001 - the kernel changed: compiled lazily
                    out.stale.append(f"{module}.{fn}{sig[:60]}...: {type(e).__name__}")
    out.cpu_s += time.process_time() - c0
    out.wall_s += time.perf_counter() - t0
    return skipped


def _dispatchers():
    """(module, name, dispatcher) of every cached numba kernel in the project's packages
    (imported)."""
    import pkgutil

    from numba.core.registry import CPUDispatcher
    for pkg in PACKAGES:
        root = importlib.import_module(pkg)
        names = [pkg] + [m.name for m in pkgutil.walk_packages(root.__path__, pkg + ".")
                         if not m.name.endswith("__main__")]
        for name in names:
            mod = sys.modules.get(name) or importlib.import_module(name)
            for k, v in vars(mod).items():
                if (isinstance(v, CPUDispatcher) and v.py_func.__module__ == name
                        and v._cache.__class__.__name__ != "NullCache"):
                    yield name, k, v


def missing(table: dict[str, list[tuple[str, str]]]) -> list[str]:
    """Signatures this process compiled or loaded that `table` lacks (kernels of modules
    already imported only)."""
    from numba.core.registry import CPUDispatcher
    have = {(m, fn, sig) for m, rows in table.items() for fn, sig in rows}
    out = []
    for name, mod in list(sys.modules.items()):
        if not name.startswith(tuple(p + "." for p in PACKAGES)) or mod is None:
            continue
        for k, v in list(vars(mod).items()):
            if isinstance(v, CPUDispatcher) and v.py_func.__module__ == name:
                out += [f"{name}.{k}{s!r}" for s in v.signatures
                        if (name, k, repr(tuple(s))) not in have]
    return sorted(set(out))


def record(path: Path = SIGNATURES) -> int:
    """Rewrite `path` from the on-disk cache indexes of the current sources (run the suite
    first, in a clean checkout with the warm-up off, so that they hold what it compiles and
    nothing else). Returns the number of signatures."""
    ns = _types_namespace()
    lines = []
    for module, name, d in _dispatchers():
        index = d._cache._cache_file._load_index()  # {(signature, target), ...}: fresh only
        for sig in sorted({repr(tuple(key[0])) for key in index}):
            try:
                ok = repr(_parse(sig, ns)) == sig
            except Exception:  # noqa: BLE001 - a type this parser does not know
                ok = False
            if ok:
                lines.append(f"{module} {name} {sig}")
            else:  # compiled lazily where met
                print(f"skipped (no eval(repr()) round trip): {module}.{name}{sig}")
    path.write_text("# Signatures of the cached numba kernels the test suite compiles: "
                    "tests/numba_warm.py\n# (python -m tests.numba_warm rewrites it after a "
                    "suite run).\n" + "\n".join(lines) + "\n")
    return len(lines)


if __name__ == "__main__":
    print(f"{record()} signatures written to {SIGNATURES}")
