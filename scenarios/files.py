"""User scenario files: a TOML file with the same fields as a catalogue `Case`.

Example (every key is optional except name, description, mount and duration_s)::

    name = "my_r79_case"
    description = "motorcycle overtaking at 130 km/h"
    mount = "rear_left"            # or a table: [mount] name, x_m, y_m, z_m, yaw_deg
    duration_s = 5.0
    road = "highway"
    lanes = 3
    guard_rails = true

    [ego]
    path = "lane_1"
    speed_mps = 22.2

    [[actors]]
    actor_class = "motorcycle"
    path = "lane_0"
    s_m = -120.0
    speed_mps = 36.1

    [[criteria]]
    metric = "first_detection_range_m"
    op = ">="
    value = 55.0
    actor_id = 0

Every error is a `ValueError` that names the offending key with its position
(e.g. ``actors[0].speed_kmh``): unknown keys, keys in a non-SI unit (``speed_kmh`` instead of
``speed_mps``), values written with units (``"130 km/h"``), wrong types and impossible values
(the dataclass checks of `scenarios.catalog`).
"""
from __future__ import annotations

import dataclasses
import tomllib
from pathlib import Path as FsPath

from .catalog import MOUNTS, ActorSpec, Case, Criterion, Mount

__all__ = ["load_scenario_file", "parse_scenario", "UNIT_ALIASES"]

#: Non-SI unit suffixes users tend to write, and the SI suffix this project uses instead.
UNIT_ALIASES: dict[str, str] = {
    "_kmh": "_mps", "_kph": "_mps", "_mph": "_mps", "_kmph": "_mps", "_knots": "_mps",
    "_km": "_m", "_cm": "_m", "_mm": "_m", "_ft": "_m", "_mi": "_m",
    "_rad": "_deg", "_ms": "_s", "_min": "_s", "_h": "_s",
    "_g": "_mps2", "_kmh_per_s": "_mps2",
}

_TOP_KEYS = {f.name for f in dataclasses.fields(Case)}
_NESTED = {"ego": ActorSpec, "actors": ActorSpec, "criteria": Criterion, "mount": Mount}


def _unit_hint(key: str, known: set[str]) -> str | None:
    for bad, good in sorted(UNIT_ALIASES.items(), key=lambda kv: -len(kv[0])):
        if key.endswith(bad):
            stem = key[: -len(bad)]
            for cand in (stem + good, stem + "_mps2" if good == "_mps" else None):
                if cand in known:
                    return cand
    return None


def _check_keys(table: dict, known: set[str], where: str) -> None:
    for key in table:
        if key in known:
            continue
        hint = _unit_hint(key, known)
        if hint is not None:
            raise ValueError(f"{where}{key}: wrong unit; give {where}{hint} in SI units "
                             f"({hint.rsplit('_', 1)[-1]})")
        raise ValueError(f"{where}{key}: unknown key; known: {sorted(known)}")


def _check_values(table: dict, cls: type, where: str) -> None:
    """Type checks with the unit named: a number field must hold a number, not '130 km/h'."""
    types = {f.name: f.type for f in dataclasses.fields(cls)}
    for key, value in table.items():
        t = str(types.get(key, ""))
        unit = key.rsplit("_", 1)[-1] if "_" in key else ""
        if "float" in t or t == "int":
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                if value is None and "None" in t:
                    continue
                raise ValueError(f"{where}{key}: must be a number in {unit or 'SI units'} "
                                 f"(wrong unit or type), got {value!r}")
        elif t == "bool" and not isinstance(value, bool):
            raise ValueError(f"{where}{key}: must be true or false, got {value!r}")
        elif t == "str" and not isinstance(value, str):
            raise ValueError(f"{where}{key}: must be a string, got {value!r}")


def _build(cls: type, table, where: str):
    if not isinstance(table, dict):
        raise ValueError(f"{where.rstrip('.')}: must be a table, got {table!r}")
    known = {f.name for f in dataclasses.fields(cls)}
    _check_keys(table, known, where)
    _check_values(table, cls, where)
    try:
        return cls(**table)
    except ValueError as exc:
        raise ValueError(f"{where}{exc}") from None
    except TypeError as exc:  # a missing required key
        raise ValueError(f"{where.rstrip('.') or 'scenario'}: {exc}") from None


def parse_scenario(data: dict, source: str = "<scenario>") -> Case:
    """A `Case` from a parsed TOML table.

    Raises
    ------
    ValueError
        Naming the key (with its position) on any unknown key, non-SI unit, wrong type or
        impossible value.
    """
    prefix = f"{source}: "
    if not isinstance(data, dict):
        raise ValueError(f"{prefix}a scenario must be a table")
    try:
        _check_keys(data, _TOP_KEYS, "")
        kw = {k: v for k, v in data.items() if k not in _NESTED}
        _check_values(kw, Case, "")
        if "mount" in data:
            m = data["mount"]
            if isinstance(m, str):
                if m not in MOUNTS:
                    raise ValueError(f"mount: unknown mount {m!r}; known: {sorted(MOUNTS)}")
                kw["mount"] = MOUNTS[m]
            else:
                kw["mount"] = _build(Mount, m, "mount.")
        if "ego" in data:
            kw["ego"] = _build(ActorSpec, data["ego"], "ego.")
        for name, cls in (("actors", ActorSpec), ("criteria", Criterion)):
            if name in data:
                items = data[name]
                if not isinstance(items, list):
                    raise ValueError(f"{name}: must be an array of tables ([[{name}]])")
                kw[name] = tuple(_build(cls, t, f"{name}[{i}].") for i, t in enumerate(items))
        if "must_detect" in kw:
            kw["must_detect"] = tuple(kw["must_detect"])
        for req in ("name", "description", "mount", "duration_s"):
            if req not in kw:
                raise ValueError(f"{req}: required key missing")
        try:
            return Case(**kw)
        except ValueError as exc:
            raise ValueError(f"{exc}") from None
    except ValueError as exc:
        raise ValueError(f"{prefix}{exc}") from None


def load_scenario_file(path) -> Case:
    """Read a TOML scenario file into a `Case` (see the module docstring for the format).

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        On a malformed file or any bad key (named).
    """
    p = FsPath(path)
    text = p.read_text(encoding="utf-8")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{p}: not valid TOML: {exc}") from None
    return parse_scenario(data, source=str(p))
