"""Plugins: a team's own schemes, chains, CFAR modes, boards, metrics ... without editing us.

A plugin is a Python module that, when imported, registers its parts through the same public
``register_*`` calls the built-ins use (`radarsim.register_scheme`, `pipeline.register_chain`,
`pipeline.CFAR_MODES.register`, `radarsim.register_board`, `metrics.register_metric`,
`harness.report.sections.register_report_section`, ...). It reaches the harness in three ways:

- an installed distribution declares an entry point in the group `ENTRY_POINT_GROUP`
  (``radar_harness.plugins``) naming the module: loaded by every command at start;
- ``--plugin MODULE_OR_FILE`` (repeatable) on the commands that build configs or run cells;
- ``plugins = ["my_radar.plugin", "local_chain.py"]`` at the top of a sweep file (a ``.py``
  path relative to the sweep file).

Loading is all or nothing per plugin: a plugin whose import raises is named with its error
(`PluginError`, a `core.errors.BadInput`: the CLI exits 2 with one line) and every registration
it made before failing is undone (`core.registry.restore_registry_state`). Every loaded plugin
is recorded (`PluginInfo`: module, distribution, version, SHA-256 of its source files) for the
manifest and for the code version that decides whether a cached cell is reused
(`harness.sweep.store.code_version`). Workers load the plugins the client loaded
(`ensure_plugins`, given the client's `PluginInfo` list): by module name from their own
environment, a file plugin from the source the client shipped; a worker that cannot load one,
or loads a different source, fails the cell with one line naming the plugin.
"""
from __future__ import annotations

import hashlib
import importlib
import importlib.util
import sys
from dataclasses import asdict, dataclass
from importlib import metadata
from pathlib import Path

from core.errors import BadInput
from core.registry import all_registries, registry_state, restore_registry_state

__all__ = ["ENTRY_POINT_GROUP", "PluginError", "PluginInfo", "load_plugins", "loaded_plugins",
           "ensure_plugins", "entry_point_modules", "origin_of", "registry_entries",
           "BUILTIN_PACKAGES", "plugins_fingerprint", "import_builtins",
           "plugin_entries"]

#: Entry-point group an installed plugin declares
#: (``[project.entry-points."radar_harness.plugins"]`` in its pyproject.toml).
ENTRY_POINT_GROUP = "radar_harness.plugins"
#: Top-level packages of this project: what they register is "built in".
BUILTIN_PACKAGES = ("core", "radarsim", "pipeline", "metrics", "scenarios", "harness")
#: Modules whose import registers every built-in entry (so a listing or a rollback sees them).
_BUILTIN_MODULES = ("radarsim", "pipeline", "pipeline.tracking", "metrics", "scenarios",
                    "harness.report.sections")
#: Prefix of the module name a ``.py`` file plugin is imported under.
FILE_MODULE_PREFIX = "radar_harness_file_plugin_"


class PluginError(BadInput):
    """A plugin that cannot be loaded (import error, missing file, a worker without it)."""


@dataclass(frozen=True)
class PluginInfo:
    """One loaded plugin, as the manifest records it and a worker reloads it.

    Attributes
    ----------
    name : str
        What the user gave: a module name, a ``.py`` path, or the entry point's name.
    how : str
        "entry point", "--plugin" or "sweep file".
    module : str
        Module name it is imported under (a file plugin:
        ``radar_harness_file_plugin_<stem>_<path hash>``).
    path : str or None
        The ``.py`` file of a file plugin (absolute).
    distribution, version : str or None
        The installed distribution that provides the module, and its version.
    sha256 : str
        SHA-256 (16 hex digits) over the plugin's source files (its package's ``.py`` files).
    source : str or None
        A file plugin's source text, shipped to Dask workers that do not see the file.
    """

    name: str
    how: str
    module: str
    path: str | None
    distribution: str | None
    version: str | None
    sha256: str
    source: str | None = None

    def record(self) -> dict:
        """The manifest's record (without the shipped source)."""
        d = asdict(self)
        d.pop("source")
        return d

    @property
    def label(self) -> str:
        """``module (distribution version)`` or ``module (file path)``."""
        if self.distribution:
            return f"{self.module} ({self.distribution} {self.version})"
        return f"{self.module} ({self.path or 'not installed'})"


#: Plugins loaded in this process, by module name (process state, like `sys.modules`).
_LOADED: dict[str, PluginInfo] = {}


def import_builtins() -> None:
    """Import every built-in registry, so their entries exist before a plugin adds its own
    (a rollback then never removes a built-in entry)."""
    for mod in _BUILTIN_MODULES:
        importlib.import_module(mod)


def entry_point_modules() -> list[tuple[str, str]]:
    """(entry point name, module) of every installed plugin (`ENTRY_POINT_GROUP`)."""
    return sorted((ep.name, ep.value.split(":", 1)[0].strip())
                  for ep in metadata.entry_points(group=ENTRY_POINT_GROUP))


def loaded_plugins() -> list[PluginInfo]:
    """Plugins loaded in this process, in load order."""
    return list(_LOADED.values())


def plugins_fingerprint(plugins: list[PluginInfo] | None = None) -> str:
    """``module=sha256`` of every plugin, sorted, one per line ("" without plugins): what the
    code version of a cell adds for its plugins."""
    plugins = loaded_plugins() if plugins is None else plugins
    return "".join(f"{p.module}={p.sha256}\n" for p in sorted(plugins, key=lambda p: p.module))


def _is_file(name: str) -> bool:
    return name.endswith(".py") or "/" in name or "\\" in name


def _file_module(path: Path) -> str:
    """``radar_harness_file_plugin_<stem>_<8 hex of the path>``: two files of one name in two
    folders are two plugins."""
    stem = "".join(c if c.isalnum() else "_" for c in path.stem)
    return f"{FILE_MODULE_PREFIX}{stem}_{hashlib.sha256(str(path).encode()).hexdigest()[:8]}"


def _distribution(module: str) -> tuple[str | None, str | None]:
    top = module.split(".", 1)[0]
    dists = metadata.packages_distributions().get(top) or []
    if not dists:
        return None, None
    try:
        return dists[0], metadata.version(dists[0])
    except metadata.PackageNotFoundError:
        return dists[0], None


def _source_files(mod) -> list[Path]:
    """The plugin's source: its package's ``.py`` files (a module: its own file)."""
    f = getattr(mod, "__file__", None)
    if f is None:
        return []
    f = Path(f)
    if f.name == "__init__.py":
        return sorted(p for p in f.parent.rglob("*.py") if "__pycache__" not in p.parts)
    return [f]


def _digest(files: list[Path], extra: str = "") -> str:
    h = hashlib.sha256(extra.encode())
    for f in files:
        h.update(f.name.encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()[:16]


def _import_file(module: str, path: Path, source: str | None = None):
    """Import a ``.py`` file (or its shipped `source`) as `module`."""
    if source is not None:
        spec = importlib.util.spec_from_loader(module, loader=None, origin=str(path))
        mod = importlib.util.module_from_spec(spec)
        mod.__file__ = str(path)
        sys.modules[module] = mod
        exec(compile(source, str(path), "exec"), mod.__dict__)  # noqa: S102 - the user's plugin
        return mod
    spec = importlib.util.spec_from_file_location(module, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[module] = mod
    spec.loader.exec_module(mod)
    return mod


def _fail(what: str, exc: BaseException) -> PluginError:
    text = " | ".join(line.strip() for line in str(exc).splitlines() if line.strip())
    return PluginError(f"plugin {what} failed to load: {type(exc).__name__}: {text}")


def _load_one(name: str, how: str, base_dir: Path | None, source: str | None = None,
              module: str | None = None) -> PluginInfo:
    """Import one plugin, all or nothing; returns its record."""
    path = None
    if _is_file(name):
        path = Path(name).expanduser()
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        path = path.resolve()
        if source is None and not path.is_file():
            raise PluginError(f"plugin {name!r} ({how}): {str(path)!r} is not a .py file")
        module = module or _file_module(path)
    else:
        module = module or name
    if module in _LOADED:
        return _LOADED[module]
    state = registry_state()
    before = set(sys.modules)
    try:
        mod = _import_file(module, path, source) if path is not None \
            else importlib.import_module(module)
    except BaseException as exc:  # noqa: BLE001 - a plugin may raise anything; named, undone
        restore_registry_state(state)
        for m in set(sys.modules) - before:  # never half-loaded: its modules go too
            del sys.modules[m]
        if isinstance(exc, KeyboardInterrupt):
            raise
        raise _fail(f"{name!r} ({how})", exc) from None
    files = [path] if path is not None else _source_files(mod)
    dist, version = (None, None) if path is not None else _distribution(module)
    text = path.read_text() if path is not None and source is None and path.is_file() \
        else source
    info = PluginInfo(name=name, how=how, module=module,
                      path=str(path) if path is not None else None, distribution=dist,
                      version=version,
                      sha256=_digest([], text) if path is not None else _digest(files),
                      source=text if path is not None else None)
    _LOADED[module] = info
    return info


def load_plugins(names=(), *, how: str = "--plugin", base_dir: str | Path | None = None,
                 entry_points: bool = True) -> list[PluginInfo]:
    """Load the installed plugins (`ENTRY_POINT_GROUP`) and the named ones; idempotent.

    Parameters
    ----------
    names : sequence of str
        Module names or ``.py`` paths (relative to `base_dir`, default the working folder).
    how : str
        Where the names come from, for messages and the manifest ("--plugin", "sweep file").
    entry_points : bool
        Also load every installed plugin.

    Returns
    -------
    list of PluginInfo
        Every plugin loaded in this process.

    Raises
    ------
    PluginError
        Naming the plugin (and how it was given) and its error; its registrations undone.
    """
    if isinstance(names, str) or not all(isinstance(n, str) and n for n in names):
        raise PluginError(f"plugins={names!r} must be a list of module names or .py paths")
    installed = entry_point_modules() if entry_points else []
    if not installed and not names:
        return loaded_plugins()  # nothing to load: no need to import the registries
    import_builtins()
    for _, module in installed:
        _load_one(module, "entry point", None)
    base = Path(base_dir) if base_dir is not None else None
    for name in names:
        _load_one(name, how, base)
    return loaded_plugins()


def ensure_plugins(plugins) -> None:
    """Load, in a worker, the plugins the client loaded (`PluginInfo` list): module plugins
    by name from this environment, file plugins from their path or the shipped source.

    Raises
    ------
    PluginError
        One line naming the plugin: not importable here, or a source that differs from the
        client's (another version installed on this worker).
    """
    if not plugins:
        return
    import_builtins()
    for p in plugins:
        if p.module in _LOADED:
            here = _LOADED[p.module]
        elif p.path is not None:
            src = p.source
            try:
                here = _load_one(p.path, p.how, None, source=src, module=p.module)
            except PluginError as exc:
                raise PluginError(f"this worker cannot load {exc}") from None
        else:
            try:
                here = _load_one(p.module, p.how, None)
            except PluginError as exc:
                raise PluginError(f"this worker lacks the plugin: {exc} (install "
                                  f"{p.distribution or p.module} in the workers' environment)"
                                  ) from None
        if here.sha256 != p.sha256:
            raise PluginError(f"plugin {p.module!r} on this worker ({here.label}, source "
                              f"{here.sha256}) differs from the client's ({p.label}, source "
                              f"{p.sha256}): install the same version on every worker")


def origin_of(module: str) -> str:
    """Who registered an entry whose registering module is `module`: "built in", the plugin
    (``plugin <module> (<distribution> <version>)``), or ``module <name>`` (a script's own
    registration)."""
    top = module.split(".", 1)[0]
    if top in BUILTIN_PACKAGES:
        return "built in"
    for p in _LOADED.values():
        if module == p.module or module.startswith(p.module + "."):
            return f"plugin {p.label}"
    dists = metadata.packages_distributions().get(top, []) if _LOADED else []
    for p in _LOADED.values():  # a helper module of a plugin's distribution
        if p.distribution and p.distribution in dists:
            return f"plugin {p.label}"
    return f"module {module}"


def registry_entries() -> list[dict]:
    """Every registry's entries: ``registry``, ``name``, ``origin`` (`origin_of`), ``module``
    (the registering module), sorted by registry then name."""
    rows = []
    for reg in all_registries():
        for name in reg:
            module = reg.origin(name)
            rows.append({"registry": reg.what, "name": name, "origin": origin_of(module),
                         "module": module})
    return rows


def plugin_entries(plugin: PluginInfo) -> dict[str, list[str]]:
    """Registry -> names the plugin registered (for the manifest: which plugin made what)."""
    label = f"plugin {plugin.label}"
    out: dict[str, list[str]] = {}
    for row in registry_entries():
        if row["origin"] == label:
            out.setdefault(row["registry"], []).append(row["name"])
    return out
