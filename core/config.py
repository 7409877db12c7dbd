"""Nested frozen configs addressed by dotted keys, and the flat keys of the previous release.

A config made of sub-configs (`radarsim.RadarConfig`: ``waveform``, ``array``, ...) is changed
by keys that name a field of a sub-config by its path, ``"waveform.n_chirps"``; a sub-config's
name with a table of its fields (``waveform={"n_chirps": 256}``, a TOML table
``[base.radar.waveform]``) is the same as its dotted keys, and a sub-config's name with a
sub-config object replaces it whole. The flat keys of the previous release
(``"n_chirps"``, or a family of them by a prefix, ``"cfar_pfa"`` for ``"cfar.pfa"``) keep
working for one release: `dotted_changes` translates them and warns (`DeprecationWarning`) with
the new key, and `replace_paths` names a refused change by the flat key it was given by
(`flat_given`). A config with a rule of its own on top (an old switch folded into another
setting, a sub-config whose fields depend on each other) adds it around these functions.

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
import operator
import warnings
from collections.abc import Callable, Mapping
from typing import Any

from .errors import BadInput

__all__ = ["dotted_changes", "flat_key", "flat_given", "split_paths", "replace_path",
           "replace_paths", "add_flat_properties"]


def flat_key(key: str, flat_keys: Mapping[str, str],
             prefixes: Mapping[str, str] | None = None) -> str | None:
    """The dotted path of the flat key `key` (`flat_keys`, else the first of `prefixes`,
    ``{"cfar_": "cfar."}``, it starts with), or None when it is no flat key."""
    if key in flat_keys:
        return flat_keys[key]
    for old, new in (prefixes or {}).items():
        if key.startswith(old):
            return new + key[len(old):]
    return None


def flat_given(changes: Mapping[str, Any], flat_keys: Mapping[str, str],
               prefixes: Mapping[str, str] | None = None) -> dict[str, str]:
    """How the changes given by flat keys read in an error (``"cfar_pfa=2 (now cfar.pfa)"``)
    -> their dotted paths: `replace_paths`'s `given`."""
    news = {key: flat_key(key, flat_keys, prefixes) for key in changes}
    return {f"{key}={changes[key]!r} (now {new})": new for key, new in news.items() if new}


def dotted_changes(changes: Mapping[str, Any], groups: Mapping[str, type],
                   flat_keys: Mapping[str, str], owner: str, *,
                   prefixes: Mapping[str, str] | None = None, section: str | None = None,
                   check_fields: bool = False, warn: bool = True,
                   stacklevel: int = 3) -> dict[str, Any]:
    """`changes` as dotted paths (``"group.field"``) or whole sub-configs (``"group"``).

    Parameters
    ----------
    changes : mapping
        Dotted paths, sub-config names (with a sub-config, or a table of its fields) and the
        deprecated flat keys.
    groups : mapping
        Top-level field -> its type (a sub-config's dataclass, or the type of a plain field).
    flat_keys : mapping
        Deprecated flat key -> its dotted path.
    owner : str
        The config's name, in the warning and in errors (``"RadarConfig"``).
    prefixes : mapping, optional
        Deprecated flat-key prefix -> the start of its dotted path (``{"cfar_": "cfar."}``):
        a family of flat keys the table `flat_keys` does not list one by one.
    section : str, optional
        The section of a sweep file that holds these keys (``"processing"``), named in the
        warning with the new key.
    check_fields : bool
        Refuse here a dotted path to a field its sub-config does not have, naming the
        sub-config (``unknown CfarConfig field(s) ['bogus']``); False leaves that to the
        caller's own check or to `replace_paths`.
    warn : bool
        Warn (`DeprecationWarning`) for every flat key; False for a bridge from a vocabulary
        that names the flat keys on purpose (a file format's own field names).
    stacklevel : int
        Of the warning: 3 names the caller of the function that calls this one.

    Raises
    ------
    BadInput
        A key that is no dotted path, sub-config or flat key, naming it and the sub-configs;
        with `check_fields`, a dotted path into a sub-config that has no such field, naming the
        field (by the flat key when given by one) and the sub-config's fields.
    """
    out: dict[str, Any] = {}
    for key, value in changes.items():
        new = flat_key(key, flat_keys, prefixes)
        if new is not None and key in groups and isinstance(value, (Mapping, groups[key])):
            new = None  # a flat key that is a sub-config's name too, given a table or one
        if new is not None:
            if warn:
                where = f" (sweep files: '{section}.{new}')" if section else ""
                warnings.warn(f"{owner} key {key!r} is deprecated: use {new!r}{where}",
                              DeprecationWarning, stacklevel=stacklevel)
            _check_field(check_fields, new, groups, key)
            out[new] = value
        elif key in groups and isinstance(value, Mapping):
            for field, v in value.items():
                _check_field(check_fields, f"{key}.{field}", groups, field)
                out[f"{key}.{field}"] = v
        elif key in groups or key.partition(".")[0] in groups:
            _check_field(check_fields, key, groups, key.partition(".")[2])
            out[key] = value
        else:
            raise BadInput(f"unknown {owner} field(s) [{key!r}]; known: its sub-configs "
                           f"{sorted(groups)} and their fields as 'group.field'")
    return out


def _check_field(check: bool, path: str, groups: Mapping[str, type], shown: str) -> None:
    """Raise (if `check`) unless the field a dotted `path` names in its sub-config exists."""
    head, _, rest = path.partition(".")
    if not check or not rest:
        return
    kind = groups[head]
    names = {f.name for f in dataclasses.fields(kind)} if dataclasses.is_dataclass(kind) else set()
    if rest.partition(".")[0] not in names:
        raise BadInput(f"unknown {kind.__name__} field(s) [{shown!r}] ({path!r}); known: "
                       f"{sorted(names)}")


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


def replace_paths(obj: Any, paths: Mapping[str, Any],
                  replace_sub: Mapping[str, Callable[[Any, dict[str, Any]], Any]] | None = None,
                  *, given: Mapping[str, str] | None = None) -> Any:
    """Copy of the frozen dataclass `obj` with every dotted path of `paths` set (each
    sub-config copied by `dataclasses.replace`, so it validates itself again).

    Parameters
    ----------
    obj : dataclass
        Frozen dataclass, its fields sub-configs or plain values.
    paths : mapping
        Dotted path (or top-level field) -> value.
    replace_sub : mapping, optional
        Top-level field -> the function (its sub-config, {rest of the path: value}) -> the new
        sub-config, for a sub-config with a rule across its fields that a plain replace
        would miss.
    given : mapping, optional
        How a change was given when not by its path (`flat_given`): text -> dotted path. A
        sub-config (or `obj`) that refuses its new values raises naming the texts of its paths.

    Raises
    ------
    BadInput
        A path whose first part is no field of `obj` (naming the path and the known fields);
        a value a sub-config or `obj` refuses.
    """
    names = {f.name for f in dataclasses.fields(obj)}
    top, nested = split_paths(paths)
    for head in [*top, *nested]:
        if head not in names:
            raise BadInput(f"unknown {type(obj).__name__} field {head!r}; known: "
                           f"{sorted(names)}")
    for head, changes in nested.items():
        replace = (replace_sub or {}).get(head, replace_paths)
        try:
            top[head] = replace(top.get(head, getattr(obj, head)), changes)
        except BadInput as exc:
            raise _named(exc, given, head) from None
    try:
        return dataclasses.replace(obj, **top) if top else obj
    except BadInput as exc:
        raise _named(exc, given, None) from None


def _named(exc: BadInput, given: Mapping[str, str] | None, head: str | None) -> BadInput:
    """`exc` naming how the changes of sub-config `head` (None: all) were given."""
    texts = [t for t, path in (given or {}).items()
             if head is None or path.partition(".")[0] == head]
    return BadInput(f"{', '.join(texts)}: {exc}") if texts else exc


def replace_path(obj: Any, path: str, value: Any) -> Any:
    """Copy of the frozen dataclass `obj` with the field at dotted `path` set to `value`."""
    return replace_paths(obj, {path: value})


def add_flat_properties(cls: type, field_group: Mapping[str, str]) -> None:
    """Give the nested config `cls` a read-only property per field of the previous release's
    flat config: ``cfg.<name>`` reads ``cfg.<group>.<name>`` (`field_group`: name -> group).
    Setting goes through the config's ``replace`` (dotted keys)."""
    for name, group in field_group.items():
        setattr(cls, name, property(
            operator.attrgetter(f"{group}.{name}"),
            doc=f"``{group}.{name}`` (read-only; set it by `{cls.__name__}.replace`)."))
