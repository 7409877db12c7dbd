"""Nested frozen configs addressed by dotted keys, and the flat keys of the previous release.

A config made of sub-configs (`radarsim.RadarConfig`: ``waveform``, ``array``, ...) is changed
by keys that name a field of a sub-config by its path, ``"waveform.n_chirps"``; a sub-config's
name with a table of its fields (``waveform={"n_chirps": 256}``, a TOML table
``[base.radar.waveform]``) is the same as its dotted keys, and a sub-config's name with a
sub-config object replaces it whole. The flat keys of the previous release
(``"n_chirps"``) keep working for one release: `dotted_changes` translates them and warns
(`DeprecationWarning`) with the new key.

    >>> import dataclasses
    >>> @dataclasses.dataclass(frozen=True)
    ... class Inner:
    ...     pfa: float = 1e-6
    >>> @dataclasses.dataclass(frozen=True)
    ... class Outer:
    ...     inner: Inner = Inner()
    >>> replace_path(Outer(), "inner.pfa", 1e-5)
    Outer(inner=Inner(pfa=1e-05))
"""
from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Mapping
from typing import Any

from .errors import BadInput

__all__ = ["dotted_changes", "split_paths", "replace_path", "replace_paths"]


def dotted_changes(changes: Mapping[str, Any], groups: Mapping[str, type],
                   flat_keys: Mapping[str, str], owner: str, *,
                   warn: bool = True, stacklevel: int = 3) -> dict[str, Any]:
    """`changes` as dotted paths (``"group.field"``) or whole sub-configs (``"group"``).

    Parameters
    ----------
    changes : mapping
        Dotted paths, sub-config names (with a sub-config, or a table of its fields) and the
        deprecated flat keys.
    groups : mapping
        Sub-config name -> its dataclass.
    flat_keys : mapping
        Deprecated flat key -> its dotted path.
    owner : str
        The config's name, in the warning and in errors (``"RadarConfig"``).
    warn : bool
        Warn (`DeprecationWarning`) for every flat key; False for a bridge from a vocabulary
        that names the flat keys on purpose (a file format's own field names).
    stacklevel : int
        Of the warning: 3 names the caller of the function that calls this one.

    Raises
    ------
    BadInput
        A key that is no dotted path, sub-config or flat key, naming it and the sub-configs.
    """
    out: dict[str, Any] = {}
    for key, value in changes.items():
        if key in flat_keys:
            new = flat_keys[key]
            if warn:
                warnings.warn(f"{owner} key {key!r} is deprecated: use {new!r}",
                              DeprecationWarning, stacklevel=stacklevel)
            out[new] = value
        elif key in groups and isinstance(value, Mapping):
            for field, v in value.items():
                out[f"{key}.{field}"] = v
        elif key in groups or key.partition(".")[0] in groups:
            out[key] = value
        else:
            raise BadInput(f"unknown {owner} field(s) [{key!r}]; known: its sub-configs "
                           f"{sorted(groups)} and their fields as 'group.field'")
    return out


def split_paths(paths: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, dict[str, Any]]]:
    """(whole values by top-level name, {top-level name: {rest of the path: value}})."""
    top: dict[str, Any] = {}
    nested: dict[str, dict[str, Any]] = {}
    for path, value in paths.items():
        head, _, rest = path.partition(".")
        if rest:
            nested.setdefault(head, {})[rest] = value
        else:
            top[head] = value
    return top, nested


def replace_paths(obj: Any, paths: Mapping[str, Any]) -> Any:
    """Copy of the frozen dataclass `obj` with every dotted path of `paths` set (each
    sub-config copied by `dataclasses.replace`, so it validates itself again).

    Raises
    ------
    BadInput
        A path whose first part is no field of `obj` (naming the path and the known fields).
    """
    names = {f.name for f in dataclasses.fields(obj)}
    top, nested = split_paths(paths)
    for head in [*top, *nested]:
        if head not in names:
            raise BadInput(f"unknown {type(obj).__name__} field {head!r}; known: "
                           f"{sorted(names)}")
    for head, changes in nested.items():
        top[head] = replace_paths(top.get(head, getattr(obj, head)), changes)
    return dataclasses.replace(obj, **top) if top else obj


def replace_path(obj: Any, path: str, value: Any) -> Any:
    """Copy of the frozen dataclass `obj` with the field at dotted `path` set to `value`."""
    return replace_paths(obj, {path: value})
