"""Shared field checks and the one TOML file policy of the project.

Every config dataclass validates its fields in ``__post_init__`` with `require` (type, finiteness
and bounds, one message shape: ``name=value must be <what>``) and `one_of` (registry keys), and
every TOML file (case files, sweeps, gates) is read by `read_toml` and checked by `check_keys` /
`build_from_table`, so a bad file always reports the same kind of message: the file, the key with
its position (``actors[0].speed_kmh``), and what is wrong (unknown key with the known ones,
wrong unit with the SI key to use, wrong type, impossible value).

It lives in `core` (standard library only), below every package, so `radarsim` and `pipeline`
validate with it without importing traffic simulation.
"""
from __future__ import annotations

import dataclasses
import math
import numbers
import tomllib
from collections.abc import Iterable, Mapping
from pathlib import Path

from .errors import BadInput
from .fileio import read_input_text
from .registry import unknown_name_message

__all__ = ["require", "one_of", "read_toml", "check_keys", "check_types", "build_from_table",
           "UNIT_ALIASES"]

_KINDS = {"number": "a finite number", "integer": "an integer", "bool": "true or false",
          "str": "a string"}


def _is_kind(value, kind: str) -> bool:
    # numpy.bool_ by name: this module imports nothing beyond the standard library
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return kind == "bool"
    if kind == "number":
        return isinstance(value, numbers.Real) and math.isfinite(value)
    if kind == "integer":
        return isinstance(value, numbers.Integral)
    return kind == "str" and isinstance(value, str)


def _requirement(kind: str, finite: bool, gt, ge, lt, le, unit: str) -> str:
    """What a value must be, e.g. "a finite positive number", "in (0, 5] deg", "an integer in
    1..4", ">= 0" (`finite`: the value is a finite number) or "finite and >= 0" (it is not)."""
    unit = f" {unit}" if unit else ""
    low = f"({gt:g}" if gt is not None else f"[{ge:g}" if ge is not None else None
    high = f"{lt:g})" if lt is not None else f"{le:g}]" if le is not None else None
    ops = " and ".join(f"{op} {v:g}" for op, v in ((">", gt), (">=", ge), ("<", lt),
                                                    ("<=", le)) if v is not None)
    if kind == "integer":
        if ge is not None and le is not None and gt is None and lt is None:
            return f"an integer in {ge}..{le}{unit}"
        return f"an integer {f'in {low}, {high}' if low and high else ops}{unit}".rstrip()
    if kind != "number":
        return _KINDS[kind]
    if gt == 0 and ge is None and lt is None and le is None:
        return f"a finite positive number{unit}"
    if low and high:
        return f"in {low}, {high}{unit}"
    if not finite:
        return f"finite and {ops}{unit}" if ops else "finite"
    return f"{ops}{unit}"


def require(obj, names: str | Iterable[str], kind: str = "number", *, gt=None, ge=None,
            lt=None, le=None, unit: str = "", none_ok: bool = False, where: str = "") -> None:
    """Check attributes of `obj` (a dataclass being validated): type, finiteness, bounds.

    Parameters
    ----------
    obj : object
        Holder of the attributes (usually ``self`` in ``__post_init__``).
    names : str or iterable of str
        Attribute names, each checked the same way.
    kind : {"number", "integer", "bool", "str"}
        "number": a finite real (not a bool); "integer": an integral value (Python or numpy
        integer, not a bool).
    gt, ge, lt, le : float, optional
        Bounds (greater than, greater or equal, less than, less or equal).
    unit : str
        Unit named in the message (e.g. "deg").
    none_ok : bool
        None is accepted (an optional field).
    where : str
        Prefix of the message (e.g. ``"gate 'x': "``).

    Raises
    ------
    ValueError
        ``{where}{name}={value!r} must be {a finite positive number | an integer in 1..4 |
        in (0, 5] deg | >= 0 | finite and >= 0 | finite | true or false}``.
    """
    if kind not in _KINDS:
        raise BadInput(f"kind={kind!r} is not one of {sorted(_KINDS)}")
    for name in (names,) if isinstance(names, str) else names:
        value = getattr(obj, name)
        if value is None and none_ok:
            continue
        ok = _is_kind(value, kind) and (
            (gt is None or value > gt) and (ge is None or value >= ge)
            and (lt is None or value < lt) and (le is None or value <= le))
        if not ok:
            what = _requirement(kind, _is_kind(value, "number"), gt, ge, lt, le, unit)
            raise BadInput(f"{where}{name}={value!r} must be {what}"
                           + (" or None" if none_ok else ""))


def one_of(name: str, value, known: Iterable, what: str = "") -> None:
    """Raise ``ValueError("{name}={value!r} is not one of [...]")`` unless `value` is a key of
    `known` (a registry); `what` prefixes the field name (e.g. "cfar ")."""
    known = list(known)  # a list: an unhashable value is simply not found
    if value not in known:
        raise BadInput(unknown_name_message(f"{what}{name}", value, known))


# ----------------------------------------------------------------------------- TOML files
#: Non-SI unit suffixes users tend to write, and the SI suffix this project uses instead.
UNIT_ALIASES: dict[str, str] = {
    "_kmh": "_mps", "_kph": "_mps", "_mph": "_mps", "_kmph": "_mps", "_knots": "_mps",
    "_km": "_m", "_cm": "_m", "_mm": "_m", "_ft": "_m", "_mi": "_m",
    "_rad": "_deg", "_ms": "_s", "_min": "_s", "_h": "_s",
    "_g": "_mps2", "_kmh_per_s": "_mps2",
}


def read_toml(path: str | Path, what: str = "TOML file") -> dict:
    """Parse a TOML file, checked first to be a regular file of bounded size
    (`core.fileio.read_input_text`).

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    ValueError
        ``{path}: malformed TOML: {parser message}``; ``{what} '{path}': is a FIFO ...`` (or a
        directory, a device, a symbolic link loop, a file over the size limit, not UTF-8 text).
    """
    p = Path(path)
    text = read_input_text(p, what)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise BadInput(f"{p}: malformed TOML: {exc}") from None


def _unit_hint(key: str, known: set[str]) -> str | None:
    for bad, good in sorted(UNIT_ALIASES.items(), key=lambda kv: -len(kv[0])):
        if key.endswith(bad):
            stem = key[: -len(bad)]
            for cand in (stem + good, stem + "_mps2" if good == "_mps" else None):
                if cand in known:
                    return cand
    return None


def check_keys(table, known: Iterable[str], where: str = "") -> dict:
    """Check that `table` is a TOML table holding only `known` keys; return it.

    `where` is the table's position, ending in "." for nested tables (``"actors[0]."``).

    Raises
    ------
    ValueError
        ``{where}: must be a table``; ``{where}{key}: wrong unit; give {where}{si_key} in SI
        units (...)`` for a known key written in another unit; ``{where}{key}: unknown key;
        known: [...]``.
    """
    if not isinstance(table, Mapping):
        raise BadInput(f"{where.rstrip('.') or 'file'}: must be a table, got {table!r}")
    known = set(known)
    for key in table:
        if key in known:
            continue
        hint = _unit_hint(key, known)
        if hint is not None:
            raise BadInput(f"{where}{key}: wrong unit; give {where}{hint} in SI units "
                           f"({hint.rsplit('_', 1)[-1]})")
        raise BadInput(f"{where}{key}: unknown key; known: {sorted(known)}")
    return dict(table)


def _field_kind(annotation) -> tuple[str | None, bool]:
    """(kind for `_is_kind`, None allowed) of a dataclass field annotation (str or type)."""
    text = annotation if isinstance(annotation, str) else getattr(annotation, "__name__",
                                                                   str(annotation))
    parts = {p.strip() for p in text.split("|")}
    none_ok = "None" in parts or "Optional" in text
    parts.discard("None")
    if parts <= {"float", "int"} and "float" in parts:
        return "number", none_ok
    if parts == {"int"}:
        return "integer", none_ok
    if parts == {"bool"}:
        return "bool", none_ok
    if parts == {"str"}:
        return "str", none_ok
    return None, none_ok


def check_types(table: Mapping, cls: type, where: str = "") -> None:
    """Check the values of `table` against the field types of dataclass `cls`, naming the unit.

    A number field must hold a number, not ``"130 km/h"``; a bool field true or false; a str
    field a string. Other fields (tables, lists) are left to `cls` itself.

    Raises
    ------
    ValueError
        ``{where}{key}: must be a number in {unit} (wrong unit or type), got ...``,
        ``{where}{key}: must be true or false, got ...``, ``{where}{key}: must be a string``.
    """
    types = {f.name: f.type for f in dataclasses.fields(cls)}
    for key, value in table.items():
        kind, none_ok = _field_kind(types.get(key, ""))
        if kind is None or (value is None and none_ok):
            continue
        if kind in ("number", "integer"):
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                unit = key.rsplit("_", 1)[-1] if "_" in key else ""
                raise BadInput(f"{where}{key}: must be a number in {unit or 'SI units'} "
                               f"(wrong unit or type), got {value!r}")
        elif not _is_kind(value, kind):
            raise BadInput(f"{where}{key}: must be {_KINDS[kind]}, got {value!r}")


def build_from_table(cls: type, table, where: str = "", **extra):
    """Construct dataclass `cls` from a TOML table under the file policy.

    Checks keys (`check_keys` against the fields of `cls`) and value types (`check_types`),
    then calls ``cls(**table, **extra)``; `extra` holds fields already converted by the caller
    (nested tables). A ValueError of the dataclass's own checks, or a missing required field,
    comes back prefixed with `where`.
    """
    known = {f.name for f in dataclasses.fields(cls)}
    table = check_keys(table, known, where)
    check_types(table, cls, where)
    required = [f.name for f in dataclasses.fields(cls) if f.init
                and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    for name in required:
        if name not in table and name not in extra:
            raise BadInput(f"{where}{name}: required key missing")
    try:
        return cls(**{**table, **extra})
    except ValueError as exc:
        raise BadInput(f"{where}{exc}") from None

