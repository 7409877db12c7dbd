"""A case's road as OpenDRIVE, written with ``scenariogeneration`` (the export's side).

Every lane of the case's highway-env network (a scripted layout of
`scenarios.roads.ROAD_LAYOUTS`, or the road a random-traffic environment builds: highway,
merge, roundabout, intersection) becomes one OpenDRIVE road whose reference line is the lane's
centre line (one right lane, shifted by a `laneOffset` of half its width): straight lanes as
`line`s, circular ones as `arc`s, any other shape (highway-env's sine ramps) as `CHORD_M`
chords. `scenarios.openscenario.road` reads such files back.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from highway_env.road.lane import CircularLane, StraightLane
from scenariogeneration import xodr

from ..catalog import Case
from ..motion import LaneGeometry
from ..roads import ROAD_LAYOUTS, TRAFFIC_ENVS

__all__ = ["CHORD_M", "network_lanes", "case_road", "write_xodr"]

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
