"""One OpenSCENARIO document being read: parameters, checked attributes, positions.

`Document` substitutes ``$name`` parameter references, reads attributes as numbers with the
element's line in every error, and lists an element's children refusing any outside an allowed
set (`scenarios.openscenario.subset`); `position` reads a `Position` element.
"""
from __future__ import annotations

import math
import re

from .road import OdrRoad
from .subset import Unsupported, refuse

__all__ = ["Document", "position", "point"]

_PARAM = re.compile(r"^\$([A-Za-z_][A-Za-z0-9_]*)$")
#: Elements read past anywhere (descriptive, no behaviour).
_DESCRIPTIVE = {"FileHeader", "Properties", "Performance", "Axles", "ParameterDeclarations",
                "CatalogLocations", "SceneGraphFile", "License"}


class Document:
    """One parsed file: parameter substitution and checked attribute reads."""

    def __init__(self, source: str, root) -> None:
        self.source = source
        self.params: dict[str, str] = {}
        for decl in root.iter("ParameterDeclaration"):
            name, value = decl.get("name"), decl.get("value")
            if name is None or value is None:
                raise refuse(source, decl, "a ParameterDeclaration needs name and value")
            if name in self.params and self.params[name] != value:
                raise refuse(source, decl, f"parameter {name} declared twice with different "
                             "values", "one value per parameter name")
            self.params[name] = value

    def refuse(self, elem, what: str, supported: str = "") -> Unsupported:
        return refuse(self.source, elem, what, supported)

    def get(self, elem, name: str, default: str | None = None) -> str:
        raw = elem.get(name)
        if raw is None:
            if default is None:
                raise self.refuse(elem, f"missing attribute {name}")
            return default
        if raw.startswith("${"):
            raise self.refuse(elem, f"{name}={raw!r}: expressions are not supported",
                              "plain values and $name references")
        m = _PARAM.match(raw)
        if m:
            if m.group(1) not in self.params:
                raise self.refuse(elem, f"{name}={raw!r}: parameter {m.group(1)} is not "
                                  "declared")
            return self.params[m.group(1)]
        return raw

    def num(self, elem, name: str, default: float | None = None) -> float:
        raw = self.get(elem, name, None if default is None else repr(default))
        try:
            v = float(raw)
        except ValueError:
            raise self.refuse(elem, f"{name}={raw!r} is not a number") from None
        if not math.isfinite(v):
            raise self.refuse(elem, f"{name}={raw!r} is not finite")
        return v

    def children(self, elem, allowed: set[str] | None = None, what: str = "element") -> list:
        """Element children, refusing any outside `allowed` (descriptive ones skipped)."""
        out = []
        for c in elem:
            if not isinstance(c.tag, str) or c.tag in _DESCRIPTIVE:
                continue
            if allowed is not None and c.tag not in allowed:
                raise self.refuse(c, f"unsupported {what} {c.tag} in {elem.tag}",
                                  ", ".join(sorted(allowed)))
            out.append(c)
        return out

    def one(self, elem, allowed: set[str], what: str = "element"):
        kids = self.children(elem, allowed, what)
        if len(kids) != 1:
            raise self.refuse(elem, f"{elem.tag} needs exactly one of "
                              f"{', '.join(sorted(allowed))}")
        return kids[0]


def position(doc: Document, pos, roads: dict[str, OdrRoad]):
    """A `Position` element -> ('world', x, y, h) or ('lane', road, s, t, direction)."""
    p = doc.one(pos, {"WorldPosition", "LanePosition"}, "position")
    if p.tag == "WorldPosition":
        for name in ("z", "p", "r"):
            if doc.num(p, name, 0.0) != 0.0:
                raise doc.refuse(p, f"{name}={doc.get(p, name)}: the scene is flat",
                                 "z, p and r of 0")
        return ("world", doc.num(p, "x"), doc.num(p, "y"), doc.num(p, "h", 0.0))
    for o in doc.children(p, {"Orientation"}, "element"):
        if doc.num(o, "h", 0.0) != 0.0 or doc.get(o, "type", "relative") != "relative":
            raise doc.refuse(o, "a turned Orientation on a lane", "relative h = 0")
    rid, lane = doc.get(p, "roadId"), int(doc.num(p, "laneId"))
    if rid not in roads:
        raise doc.refuse(p, f"roadId={rid} is not a road of the OpenDRIVE file; roads: "
                         f"{sorted(roads)}")
    road = roads[rid]
    if lane not in road.lanes:
        raise doc.refuse(p, f"laneId={lane} is not a lane of road {rid}; lanes: "
                         f"{sorted(road.lanes)}")
    t = road.lanes[lane][0] + doc.num(p, "offset", 0.0)
    return ("lane", road, doc.num(p, "s"), t, 1 if lane < 0 else -1)


def point(where) -> tuple[float, float]:
    if where[0] == "world":
        return where[1], where[2]
    x, y, _ = where[1].point(where[2], where[3])
    return x, y


