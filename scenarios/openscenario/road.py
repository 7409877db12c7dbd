"""An OpenDRIVE file as roads and lanes (the import's side; `opendrive` writes them).

`read_xodr` reads roads of `line` and `arc` geometries with one lane section, constant
lane widths and a constant lane offset (the subset of `scenarios.openscenario.subset`); an
`OdrRoad` maps road coordinates (s, t) to the ISO world and back and lists its lanes' centre
lines as `scenarios.motion.LaneGeometry` for highway-env.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from lxml import etree

from core.fileio import read_input_bytes

from ..motion import LaneGeometry
from .subset import refuse

__all__ = ["OdrPiece", "OdrRoad", "read_xodr", "parse_xodr"]


@dataclass(frozen=True, slots=True)
class OdrPiece:
    """One planView geometry: start s, pose, length and curvature (0: a line), ISO world."""

    s_m: float
    x_m: float
    y_m: float
    hdg_rad: float
    length_m: float
    curvature_per_m: float

    def point(self, ds: float) -> tuple[float, float, float]:
        """(x, y, heading) at ds along the piece."""
        k, h = self.curvature_per_m, self.hdg_rad
        if abs(k) < 1e-12:
            return self.x_m + ds * math.cos(h), self.y_m + ds * math.sin(h), h
        return (self.x_m + (math.sin(h + k * ds) - math.sin(h)) / k,
                self.y_m - (math.cos(h + k * ds) - math.cos(h)) / k, h + k * ds)

    def project(self, x: float, y: float) -> tuple[float, float]:
        """(ds, t) of a point: along the piece (unclamped) and to its left."""
        k, h = self.curvature_per_m, self.hdg_rad
        if abs(k) < 1e-12:
            dx, dy = x - self.x_m, y - self.y_m
            return dx * math.cos(h) + dy * math.sin(h), -dx * math.sin(h) + dy * math.cos(h)
        r = 1.0 / k  # signed: the centre is r to the left of the start
        cx, cy = self.x_m - r * math.sin(h), self.y_m + r * math.cos(h)
        ang = math.atan2(y - cy, x - cx) - math.atan2(self.y_m - cy, self.x_m - cx)
        ang = (ang + math.pi) % (2 * math.pi) - math.pi
        return ang * r, r - math.copysign(math.hypot(x - cx, y - cy), r)


@dataclass(frozen=True, slots=True)
class OdrRoad:
    """An OpenDRIVE road of the supported subset.

    Attributes
    ----------
    road_id : str
    pieces : tuple of OdrPiece
    lanes : dict of int to (float, float)
        Lane id -> (centre t, width), m; t positive to the left of the reference line.
    """

    road_id: str
    pieces: tuple[OdrPiece, ...]
    lanes: dict

    @property
    def length_m(self) -> float:
        return self.pieces[-1].s_m + self.pieces[-1].length_m

    def _piece(self, s: float) -> OdrPiece:
        starts = [p.s_m for p in self.pieces]
        return self.pieces[max(int(np.searchsorted(starts, s, side="right")) - 1, 0)]

    def point(self, s: float, t: float) -> tuple[float, float, float]:
        """(x, y, heading of the reference line) at road coordinates (s, t)."""
        p = self._piece(s)
        x, y, h = p.point(s - p.s_m)
        return x - t * math.sin(h), y + t * math.cos(h), h

    def project(self, x: float, y: float) -> tuple[float, float, float]:
        """(distance outside the road's length, s, t) of a point on its nearest piece."""
        best = (math.inf, 0.0, 0.0)
        for p in self.pieces:
            ds, t = p.project(x, y)
            out = max(-ds, ds - p.length_m, 0.0)
            best = min(best, (out, p.s_m + min(max(ds, 0.0), p.length_m), t))
        return best

    def lane_geometries(self) -> list[LaneGeometry]:
        """Each lane's centre line, piece by piece (curvature of the offset curve)."""
        out = []
        for t, w in self.lanes.values():
            for p in self.pieces:
                x, y, h = self.point(p.s_m, t)
                k = p.curvature_per_m
                scale = 1.0 - k * t
                if scale <= 0:
                    continue  # the lane would pass the arc's centre: not a drivable lane
                out.append(LaneGeometry(x_m=x, y_m=y, yaw_rad=h, length_m=p.length_m * scale,
                                        curvature_per_m=k / scale, width_m=w))
        return out


def _num(source: str, elem, name: str, default: float | None = None) -> float:
    raw = elem.get(name)
    if raw is None:
        if default is None:
            raise refuse(source, elem, f"missing attribute {name}")
        return default
    try:
        v = float(raw)
    except ValueError:
        raise refuse(source, elem, f"{name}={raw!r} is not a number") from None
    if not math.isfinite(v):
        raise refuse(source, elem, f"{name}={raw!r} is not finite")
    return v


def _constant_poly(source: str, elem, what: str) -> float:
    """The `a` of an OpenDRIVE cubic whose b, c, d are 0 (constant along the road)."""
    if any(_num(source, elem, c, 0.0) != 0.0 for c in ("b", "c", "d")):
        raise refuse(source, elem, f"{what} varies along the road",
                     "constant widths and offsets (b = c = d = 0)")
    return _num(source, elem, "a")


def _pieces(source: str, road) -> tuple[OdrPiece, ...]:
    out = []
    for g in road.findall("planView/geometry"):
        shape = [c for c in g if isinstance(c.tag, str)]
        if len(shape) != 1 or shape[0].tag not in ("line", "arc"):
            bad = shape[0] if shape else g
            raise refuse(source, bad, f"road {road.get('id')}: unsupported geometry "
                         f"{bad.tag}", "line, arc (straight or constant-curvature lanes)")
        k = _num(source, shape[0], "curvature") if shape[0].tag == "arc" else 0.0
        out.append(OdrPiece(_num(source, g, "s"), _num(source, g, "x"), _num(source, g, "y"),
                            _num(source, g, "hdg"), _num(source, g, "length"), k))
    if not out:
        raise refuse(source, road, f"road {road.get('id')} has no planView geometry")
    return tuple(out)


def _lanes(source: str, road) -> dict:
    sections = road.findall("lanes/laneSection")
    if len(sections) != 1:
        raise refuse(source, sections[1] if len(sections) > 1 else road,
                     f"road {road.get('id')}: {len(sections)} lane sections",
                     "one laneSection per road")
    offsets = road.findall("lanes/laneOffset")
    if len(offsets) > 1:
        raise refuse(source, offsets[1], "more than one laneOffset", "one constant laneOffset")
    offset = _constant_poly(source, offsets[0], "laneOffset") if offsets else 0.0
    lanes: dict = {}
    for side, sign in (("left", 1.0), ("right", -1.0)):
        edge = offset
        found = sorted(sections[0].findall(f"{side}/lane"),
                       key=lambda e: abs(int(_num(source, e, "id"))))
        for lane in found:
            widths = lane.findall("width")
            if len(widths) != 1:
                raise refuse(source, lane, f"lane {lane.get('id')}: {len(widths)} width "
                             "records", "one constant width per lane")
            w = _constant_poly(source, widths[0], "lane width")
            lanes[int(_num(source, lane, "id"))] = (edge + sign * 0.5 * w, w)
            edge += sign * w
    if not lanes:
        raise refuse(source, road, f"road {road.get('id')} has no lane")
    return lanes


def parse_xodr(text: bytes, source: str) -> dict[str, OdrRoad]:
    """Roads of an OpenDRIVE document, keyed by road id (see `read_xodr`)."""
    try:
        root = etree.fromstring(text)
    except etree.XMLSyntaxError as exc:
        raise refuse(source, None, f"not well-formed XML: {exc}") from None
    if root.tag != "OpenDRIVE":
        raise refuse(source, root, "the root element is not OpenDRIVE")
    roads = {}
    for road in root.findall("road"):
        r = OdrRoad(str(road.get("id")), _pieces(source, road), _lanes(source, road))
        roads[r.road_id] = r
    if not roads:
        raise refuse(source, root, "the file has no road")
    return roads


def read_xodr(path: str | Path) -> dict[str, OdrRoad]:
    """Roads of an OpenDRIVE file of the supported subset, keyed by road id.

    Raises
    ------
    scenarios.openscenario.subset.Unsupported
        A geometry other than line or arc, varying widths or offsets, several lane sections
        (naming the element and its line).
    """
    return parse_xodr(read_input_bytes(path, "OpenDRIVE file"), str(path))
