"""Roads both ways: a case's highway-env road as OpenDRIVE, and an OpenDRIVE file as lanes.

Export: every lane of the case's highway-env network (a scripted layout of
`scenarios.roads.ROAD_LAYOUTS`, or the road a random-traffic environment builds) becomes one
OpenDRIVE road whose reference line is the lane's centre line (one right lane, shifted by a
`laneOffset` of half its width): straight lanes as `line`s, circular ones as `arc`s, any
other shape (highway-env's sine ramps) as 1 m chords. Written with ``scenariogeneration``.

Import: `read_xodr` reads roads of `line` and `arc` geometries with one lane section, constant
lane widths and a constant lane offset (the subset of `scenarios.openscenario.subset`); an
`OdrRoad` maps road coordinates (s, t) to the ISO world and back and lists its lanes' centre
lines as `scenarios.motion.LaneGeometry` for highway-env.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from highway_env.road.lane import CircularLane, StraightLane
from lxml import etree
from scenariogeneration import xodr

from ..catalog import Case
from core.fileio import read_input_bytes
from ..motion import LaneGeometry
from ..roads import ROAD_LAYOUTS, TRAFFIC_ENVS
from .subset import refuse

__all__ = ["CHORD_M", "network_lanes", "case_road", "write_xodr", "OdrPiece", "OdrRoad",
           "read_xodr", "parse_xodr"]

#: Chord length of lanes that are neither straight nor circular, m (a highway-env sine ramp
#: of 5 m amplitude over 80 m stays within 2 cm of its chords).
CHORD_M = 1.0


def _iso_pose(lane, s: float) -> tuple[float, float, float]:
    x, y = lane.position(s, 0.0)
    return float(x), float(-y), float(-lane.heading_at(s))


def _lane_pieces(lane) -> list[LaneGeometry]:
    """One highway-env lane as ISO centre-line pieces."""
    w = float(lane.width_at(0.0))
    if isinstance(lane, StraightLane):
        x, y, h = _iso_pose(lane, 0.0)
        return [LaneGeometry(x_m=x, y_m=y, yaw_rad=h, length_m=float(lane.length),
                             curvature_per_m=0.0, width_m=w)]
    if isinstance(lane, CircularLane):
        x, y, h = _iso_pose(lane, 0.0)
        # highway-env's direction +1 (clockwise on its y-down axes) is a right turn on ISO
        # axes: negative curvature
        return [LaneGeometry(x_m=x, y_m=y, yaw_rad=h, length_m=float(lane.length),
                             curvature_per_m=-lane.direction / lane.radius, width_m=w)]
    n = max(int(math.ceil(lane.length / CHORD_M)), 1)
    s = np.linspace(0.0, float(lane.length), n + 1)
    pts = np.array([_iso_pose(lane, v)[:2] for v in s])
    d = np.diff(pts, axis=0)
    return [LaneGeometry(x_m=float(p[0]), y_m=float(p[1]), yaw_rad=float(math.atan2(dy, dx)),
                         length_m=float(math.hypot(dx, dy)), curvature_per_m=0.0, width_m=w)
            for p, (dx, dy) in zip(pts[:-1], d)]


def network_lanes(network) -> list[list[LaneGeometry]]:
    """Every lane of a highway-env `RoadNetwork` as ISO pieces (one list per lane, in the
    network's edge order)."""
    return [_lane_pieces(lane) for ends in network.graph.values() for lanes in ends.values()
            for lane in lanes]


def case_road(case: Case) -> tuple[list[list[LaneGeometry]], list[float]]:
    """The road a case drives on: its lanes (ISO pieces per lane) and its guard-rail lines
    (ISO y, m; empty when the case has none).

    A random-traffic case drives on the road its highway-env environment builds (highway,
    merge, roundabout, intersection): it is built here the same way, without vehicles (the
    road does not depend on the seed).
    """
    if case.motion is not None:
        return [[g] for g in case.motion.lanes], list(case.motion.rails_y_m)
    if case.traffic is None:
        layout = ROAD_LAYOUTS[case.road].build(case.lanes)
        rails = [-y for y in layout.rails_y_hw] if case.guard_rails else []
        return network_lanes(layout.network), rails
    env = TRAFFIC_ENVS[case.traffic]
    sim = env.env_class()(config={"offscreen_rendering": True} |
                          env.env_config(case.lanes, 0, 1.0), render_mode=None)
    sim.reset(seed=0)
    rails = [-y for y in env.rails_y_hw(case.lanes)] if case.guard_rails else []
    return network_lanes(sim.road.network), rails


def write_xodr(roads: list[list[LaneGeometry]], path: str | Path, name: str) -> Path:
    """Write lanes as an OpenDRIVE 1.x file: one road per lane, reference line on the lane's
    centre line (one right lane and a `laneOffset` of half its width)."""
    odr = xodr.OpenDrive(name)
    for rid, pieces in enumerate(roads, start=1):
        w = pieces[0].width_m
        plan = xodr.PlanView()
        for p in pieces:
            geom = xodr.Line(p.length_m) if p.curvature_per_m == 0.0 else \
                xodr.Arc(p.curvature_per_m, length=p.length_m)
            plan.add_fixed_geometry(geom, p.x_m, p.y_m, p.yaw_rad)
        centre = xodr.Lane(a=0)
        centre.add_roadmark(xodr.std_roadmark_solid())
        section = xodr.LaneSection(0, centre)
        lane = xodr.Lane(a=w)
        lane.add_roadmark(xodr.std_roadmark_solid())
        section.add_right_lane(lane)
        lanes = xodr.Lanes()
        lanes.add_lanesection(section)
        lanes.add_laneoffset(xodr.LaneOffset(a=0.5 * w))
        odr.add_road(xodr.Road(rid, plan, lanes))
    odr.adjust_startpoints()
    path = Path(path)
    odr.write_xml(str(path))
    return path


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
