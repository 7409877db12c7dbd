"""Case files: a TOML file with the same fields as a `Case`; the shipped catalogue is made of them.

The cases in ``scenarios/cases/*.toml`` are the catalogue (`scenarios.registry.SCENARIOS`); a
user's case is the same kind of file, shown with ``radar-harness show my_case.toml`` or added
to that folder. ``scenarios/cases/r79_motorcycle_rear.toml`` is a complete example. Keys: the
fields of `scenarios.catalog.Case` (name, description, mount and duration_s are required;
``mount`` is a `MOUNTS` name or a ``[mount]`` table name, x_m, y_m, z_m, yaw_deg), an ``[ego]``
table and ``[[actors]]`` tables with the fields of `ActorSpec`, ``[[criteria]]`` tables with
the fields of `Criterion`, ``[[radars]]`` tables (radars on actors, `equipment.RadarSpec`).

A case may be an OpenSCENARIO file instead: ``xosc = "path/to/file.xosc"`` (relative to the
TOML) with only the harness fields beside it (`XOSC_KEYS`: ``ego`` the ego's entity name,
default ``"Ego"``; ``mount``; ``criteria``; ``must_detect``; ``duration_s``; ``name``;
``description``); a bare ``FILE.xosc`` is such a case with the defaults
(`scenarios.openscenario.import_`). `load_case_file` reads either kind, and `get_case`
(``scenarios.registry``) takes such paths as well as catalogue names.

Every error is a `ValueError` that names the offending key with its position
(e.g. ``actors[0].speed_kmh``): unknown keys, keys in a non-SI unit (``speed_kmh`` instead of
``speed_mps``), values written with units (``"130 km/h"``), wrong types and impossible values
(the dataclass checks of `scenarios.catalog`).
"""
from __future__ import annotations

import os
from pathlib import Path

from core.checks import UNIT_ALIASES, build_from_table, check_keys, check_types, read_toml
from core.errors import BadInput

from .catalog import MOUNTS, ActorSpec, Case, Criterion, Mount
from .equipment import RadarSpec
from .openscenario.import_ import read_xosc

__all__ = ["load_scenario_file", "load_case_directory", "parse_scenario", "UNIT_ALIASES",
           "load_case_file", "is_case_path", "CASE_FILE_SUFFIXES", "XOSC_KEYS"]

#: File suffixes of case files (TOML case, OpenSCENARIO).
CASE_FILE_SUFFIXES = (".toml", ".xosc")
#: Keys of a case TOML that names an OpenSCENARIO file.
XOSC_KEYS = ("xosc", "name", "description", "ego", "mount", "criteria", "must_detect",
             "duration_s")

#: Arrays of tables (``[[actors]]`` ...) and how one table, at position ``name[i]``, becomes
#: its object; ``[[radars]]`` holds actor_id, an optional family and RadarEquipment fields.
_ARRAYS = {
    "actors": lambda table, where: build_from_table(ActorSpec, table, f"{where}."),
    "criteria": lambda table, where: build_from_table(Criterion, table, f"{where}."),
    "radars": RadarSpec.from_table,
}
#: Keys holding tables rather than plain values.
_NESTED = {"ego", "mount", *_ARRAYS}


def _mount(value) -> Mount:
    if isinstance(value, str):
        if value not in MOUNTS:
            raise BadInput(f"mount: unknown mount {value!r}; known: {sorted(MOUNTS)}")
        return MOUNTS[value]
    return build_from_table(Mount, value, "mount.")


def _array(data: dict, name: str) -> tuple:
    items = data[name]
    if not isinstance(items, list):
        raise BadInput(f"{name}: must be an array of tables ([[{name}]])")
    return tuple(_ARRAYS[name](t, f"{name}[{i}]") for i, t in enumerate(items))


def _xosc_case(data: dict, source: str) -> Case:
    """The case of a TOML table with an ``xosc`` key (path relative to `source`)."""
    data = check_keys(data, XOSC_KEYS, "")
    kw = {}
    for key, kind in (("xosc", str), ("name", str), ("description", str), ("ego", str),
                      ("duration_s", (int, float))):
        if key in data:
            if isinstance(data[key], bool) or not isinstance(data[key], kind):
                raise BadInput(f"{key}={data[key]!r} must be "
                                 f"{'a string' if kind is str else 'a number'}")
            kw[key] = data[key]
    if "mount" in data:
        kw["mount"] = _mount(data["mount"])
    if "criteria" in data:
        kw["criteria"] = _array(data, "criteria")
    if "must_detect" in data:
        md = data["must_detect"]
        if not isinstance(md, list) or not all(isinstance(i, int) and not isinstance(i, bool)
                                               for i in md):
            raise BadInput(f"must_detect={md!r} must be a list of actor ids")
        kw["must_detect"] = tuple(md)
    xosc = Path(kw.pop("xosc"))
    path = xosc if xosc.is_absolute() else Path(source).parent / xosc
    if path.suffix != ".xosc":
        raise BadInput(f"xosc={str(xosc)!r} must name an .xosc file")
    return read_xosc(path, **kw)


def parse_scenario(data: dict, source: str = "<scenario>") -> Case:
    """A `Case` from a parsed TOML table (one with an ``xosc`` key: from that file).

    Raises
    ------
    ValueError
        ``{source}: {key}: ...`` naming the key (with its position) on any unknown key, non-SI
        unit, wrong type or impossible value (the file policy of `core.checks`).
    """
    try:
        if "xosc" in data:
            return _xosc_case(data, source)
        data = check_keys(data, {f for f in Case.__dataclass_fields__} - {"motion"}, "")
        nested = {}
        if "mount" in data:
            nested["mount"] = _mount(data["mount"])
        if "ego" in data:
            nested["ego"] = build_from_table(ActorSpec, data["ego"], "ego.")
        for name in _ARRAYS:
            if name in data:
                nested[name] = _array(data, name)
        flat = {k: v for k, v in data.items() if k not in _NESTED}
        check_types(flat, Case)
        if "must_detect" in flat:
            flat["must_detect"] = tuple(flat["must_detect"])
        return build_from_table(Case, flat, "", **nested)
    except ValueError as exc:
        raise BadInput(f"{source}: {exc}") from None


def load_scenario_file(path) -> Case:
    """Read a TOML case file into a `Case` (see the module docstring for the format).

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        On a malformed file or any bad key (named).
    """
    return parse_scenario(read_toml(path, "case file"), source=str(path))


def is_case_path(ref) -> bool:
    """Whether a case reference names a file (a case-file suffix, or a folder in it) rather
    than a catalogue case."""
    text = os.fspath(ref)
    return text.endswith(CASE_FILE_SUFFIXES) or "/" in text or os.sep in text


def load_case_file(path) -> Case:
    """A case from a file: a TOML case file (`load_scenario_file`) or a bare OpenSCENARIO
    file (``.xosc``, the import's defaults).

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        A suffix other than .toml / .xosc, or any bad content (named).
    """
    p = Path(path)
    if p.suffix == ".xosc":
        return read_xosc(p)
    if p.suffix != ".toml":
        raise BadInput(f"case file {str(path)!r}: a case file ends in "
                         f"{' or '.join(CASE_FILE_SUFFIXES)}")
    return load_scenario_file(p)


def load_case_directory(directory) -> dict[str, Case]:
    """Every ``*.toml`` case file of `directory`, keyed by case name, in file-name order.

    Each file is named after its case (``<name>.toml``), so a case is found by its name.

    Raises
    ------
    ValueError
        A bad file (named), or a file not named after its case.
    """
    cases: dict[str, Case] = {}
    for path in sorted(Path(directory).glob("*.toml")):
        case = load_scenario_file(path)
        if path.stem != case.name:
            raise BadInput(f"{path}: holds case {case.name!r}; name the file "
                           f"{case.name}.toml")
        cases[case.name] = case
    return cases
