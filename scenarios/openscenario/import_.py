"""An OpenSCENARIO 1.x file as a case: `read_xosc`.

The file is read with lxml (each element knows its source line), its `$name` parameter
references are substituted, and every element is checked against the supported subset
(`scenarios.openscenario.subset`): anything else is refused naming the element, its line and
what is supported. The road comes from the referenced OpenDRIVE file (`road.read_xodr`); the
storyboard is played by `scenarios.openscenario.player` into one timed trajectory per entity,
and the case drives those in highway-env (`scenarios.motion`). The ego is the entity named
`ego` (default ``"Ego"``); the other entities are the actors, truth ids 0, 1, ... in the
file's entity order.

Harness fields the file does not hold (mount, criteria, must_detect, duration) come from the
arguments (a case TOML's keys), else from the ``harness_*`` parameters our export writes
(`export.HARNESS_PARAMETERS`), else the defaults: mount ``rear_left``, the storyboard's
stop time or `DEFAULT_DURATION_S`, no criteria.
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
from lxml import etree

from core.errors import BadInput
from core.fileio import read_input_bytes

from ..catalog import MOUNTS, ActorSpec, Case, Criterion, Mount
from ..equipment import RadarSpec
from ..motion import EntityMotion, Motion
from . import player
from .road import OdrRoad, read_xodr
from .subset import Unsupported, refuse

__all__ = ["read_xosc", "DEFAULT_EGO", "DEFAULT_MOUNT", "DEFAULT_DURATION_S", "CATEGORIES",
           "case_name_of"]

DEFAULT_EGO = "Ego"
DEFAULT_MOUNT = "rear_left"
#: Duration of a file whose storyboard has no simulation-time stop, s.
DEFAULT_DURATION_S = 10.0
#: OpenSCENARIO vehicle category -> actor class.
CATEGORIES = {"car": "car", "truck": "truck", "motorbike": "motorcycle",
              "bicycle": "bicycle"}
_PARAM = re.compile(r"^\$([A-Za-z_][A-Za-z0-9_]*)$")
#: Elements read past anywhere (descriptive, no behaviour).
_DESCRIPTIVE = {"FileHeader", "Properties", "Performance", "Axles", "ParameterDeclarations",
                "CatalogLocations", "SceneGraphFile", "License"}


def case_name_of(path: str | Path) -> str:
    """Case name of a bare .xosc file: its stem in lowercase letters, digits and _."""
    name = re.sub(r"[^a-z0-9_]+", "_", Path(path).stem.lower()).strip("_")
    return name or "xosc_case"


class _Doc:
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


def _position(doc: _Doc, pos, roads: dict[str, OdrRoad]):
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


def _point(where) -> tuple[float, float]:
    if where[0] == "world":
        return where[1], where[2]
    x, y, _ = where[1].point(where[2], where[3])
    return x, y


def _attach(mover: player.Mover, where, roads: dict[str, OdrRoad]) -> None:
    """Place a mover: on a lane (a LanePosition, or a WorldPosition on a lane heading along
    it) or free."""
    if where[0] == "lane":
        mover.place_on_road(where[1], where[2], where[3], where[4])
        return
    _, x, y, h = where
    mover.x_m, mover.y_m, mover.yaw_rad, mover.road = x, y, h, None
    for road in roads.values():
        out, s, t = road.project(x, y)
        edges = [(c - 0.5 * w, c + 0.5 * w) for c, w in road.lanes.values()]
        if out > 0 or not any(lo <= t <= hi for lo, hi in edges):
            continue
        _, _, hr = road.point(s, t)
        along = math.cos(h - hr)
        if abs(along) > 0.9:
            mover.place_on_road(road, s, t, 1 if along > 0 else -1)
            mover.yaw_rad = h
            return


def _entities(doc: _Doc, root) -> list[tuple[str, str, tuple, tuple]]:
    """(name, actor class, (L, W, H), (centre x, centre y)) per ScenarioObject, in order."""
    out = []
    ents = root.find("Entities")
    if ents is None:
        raise doc.refuse(root, "no Entities")
    for obj in doc.children(ents, {"ScenarioObject"}, "entity"):
        name = doc.get(obj, "name")
        kind = doc.one(obj, {"Vehicle", "Pedestrian"}, "entity kind")
        if kind.tag == "Vehicle":
            cat = doc.get(kind, "vehicleCategory")
            if cat not in CATEGORIES:
                raise doc.refuse(kind, f"entity {name}: unsupported vehicleCategory {cat}",
                                 ", ".join(CATEGORIES))
            cls = CATEGORIES[cat]
        else:
            cat = doc.get(kind, "pedestrianCategory", "pedestrian")
            if cat != "pedestrian":
                raise doc.refuse(kind, f"entity {name}: unsupported pedestrianCategory {cat}",
                                 "pedestrian")
            cls = "pedestrian"
        box = kind.find("BoundingBox")
        if box is None or box.find("Dimensions") is None or box.find("Center") is None:
            raise doc.refuse(kind, f"entity {name} has no BoundingBox with Center and "
                             "Dimensions")
        dims, centre = box.find("Dimensions"), box.find("Center")
        size = tuple(doc.num(dims, k) for k in ("length", "width", "height"))
        if min(size) <= 0:
            raise doc.refuse(dims, f"entity {name}: bounding box {size} must be > 0")
        out.append((name, cls, size, (doc.num(centre, "x"), doc.num(centre, "y"))))
    if not out:
        raise doc.refuse(ents, "the file has no entity")
    return out


def _dynamics(doc: _Doc, dyn, shapes: set[str], dimensions: set[str]) -> tuple[str, str, float]:
    shape, dim = doc.get(dyn, "dynamicsShape"), doc.get(dyn, "dynamicsDimension")
    if shape not in shapes:
        raise doc.refuse(dyn, f"unsupported dynamicsShape {shape}", ", ".join(sorted(shapes)))
    if dim not in dimensions:
        raise doc.refuse(dyn, f"unsupported dynamicsDimension {dim} for {shape}",
                         ", ".join(sorted(dimensions)))
    value = doc.num(dyn, "value")
    if value < 0 or (value == 0 and shape != "step"):
        raise doc.refuse(dyn, f"value={value:g} must be > 0 for a {shape} transition")
    return shape, dim, value


def _speed_action(doc: _Doc, elem, init: bool):
    """SpeedAction -> action(mover, movers, now)."""
    dyn = elem.find("SpeedActionDynamics")
    target = elem.find("SpeedActionTarget")
    if dyn is None or target is None:
        raise doc.refuse(elem, "a SpeedAction needs SpeedActionDynamics and SpeedActionTarget")
    kind = doc.one(target, {"AbsoluteTargetSpeed"}, "speed target")
    speed = doc.num(kind, "value")
    shape, dim, value = _dynamics(doc, dyn, {"step", "linear", "sinusoidal"},
                                  {"time", "distance", "rate"})
    if dim == "rate" and shape != "linear":
        raise doc.refuse(dyn, f"a rate for a {shape} speed change", "rate only with linear")
    if init and shape != "step":
        raise doc.refuse(dyn, f"a {shape} speed change in Init", "step")

    def act(m: player.Mover, movers: dict, now: float) -> None:
        if init:
            m.speed_mps = speed
        else:
            m.set_speed(now, speed, shape, dim, value)
    return act


def _lane_change(doc: _Doc, elem):
    dyn = elem.find("LaneChangeActionDynamics")
    target = elem.find("LaneChangeTarget")
    if dyn is None or target is None:
        raise doc.refuse(elem, "a LaneChangeAction needs LaneChangeActionDynamics and "
                         "LaneChangeTarget")
    shape, dim, value = _dynamics(doc, dyn, set(player.SHAPES), {"time", "distance"})
    kind = doc.one(target, {"RelativeTargetLane", "AbsoluteTargetLane"}, "lane target")
    offset = doc.num(elem, "targetLaneOffset", 0.0)
    lanes = int(doc.num(kind, "value"))
    ref = doc.get(kind, "entityRef") if kind.tag == "RelativeTargetLane" else None

    def act(m: player.Mover, movers: dict, now: float) -> None:
        if m.road is None:
            raise doc.refuse(elem, f"entity {m.name} is not on a lane of the road when its "
                             "lane change starts", "lane changes of entities on a lane")
        if ref is None:
            if lanes not in m.road.lanes:
                raise doc.refuse(kind, f"lane {lanes} is not a lane of the entity's road; "
                                 f"lanes: {sorted(m.road.lanes)}")
            centre = m.road.lanes[lanes][0]
        else:
            r = movers[ref]
            if r.road is not m.road:
                raise doc.refuse(kind, f"entity {ref} is not on {m.name}'s road")
            order = sorted(c for c, _ in m.road.lanes.values())
            k = order.index(r.lane_t()) + r.direction * lanes
            if not 0 <= k < len(order):
                raise doc.refuse(kind, f"{lanes} lanes beside {ref}'s lane is off the road")
            centre = order[k]
        m.change_lane(now, centre + m.direction * offset, shape, dim, value)
    return act


def _trajectory(doc: _Doc, elem):
    ref = elem.find("TrajectoryRef")
    traj = ref.find("Trajectory") if ref is not None else elem.find("Trajectory")
    if traj is None:
        cat = elem.find(".//CatalogReference")
        raise doc.refuse(cat if cat is not None else elem, "a FollowTrajectoryAction needs an "
                         "inline Trajectory", "Trajectory or TrajectoryRef > Trajectory")
    if doc.num(elem, "initialDistanceOffset", 0.0) != 0.0:
        raise doc.refuse(elem, "initialDistanceOffset", "0")
    shape = doc.one(traj.find("Shape") if traj.find("Shape") is not None else traj,
                    {"Polyline"}, "trajectory shape")
    verts = doc.children(shape, {"Vertex"}, "element")
    if len(verts) < 2:
        raise doc.refuse(shape, "a Polyline needs at least two vertices")
    if any(v.get("time") is None for v in verts):
        raise doc.refuse(shape, "an untimed Polyline", "vertices with a time")
    times = np.array([doc.num(v, "time") for v in verts])
    pts = []
    for v in verts:
        w = doc.one(v.find("Position") if v.find("Position") is not None else v,
                    {"WorldPosition"}, "vertex position")
        for name in ("z", "p", "r"):
            if doc.num(w, name, 0.0) != 0.0:
                raise doc.refuse(w, f"{name}={doc.get(w, name)}: the scene is flat",
                                 "z, p and r of 0")
        pts.append((doc.num(w, "x"), doc.num(w, "y"), w.get("h")))
    if not (np.diff(times) > 0).all():
        raise doc.refuse(shape, "vertex times must increase")
    timing = elem.find("TimeReference/Timing")
    if timing is None:
        raise doc.refuse(elem, "a trajectory without TimeReference/Timing",
                         "Timing absolute or relative")
    domain = doc.get(timing, "domainAbsoluteRelative")
    if domain not in ("absolute", "relative"):
        raise doc.refuse(timing, f"domainAbsoluteRelative={domain}", "absolute, relative")
    scale, offset = doc.num(timing, "scale", 1.0), doc.num(timing, "offset", 0.0)
    if scale <= 0:
        raise doc.refuse(timing, f"scale={scale:g} must be > 0")
    xs, ys = np.array([p[0] for p in pts]), np.array([p[1] for p in pts])
    given = [p[2] for p in pts]
    heading = np.arctan2(np.gradient(ys), np.gradient(xs))
    yaws = np.unwrap(np.array([doc.num(v.find(".//WorldPosition"), "h") if g is not None
                               else heading[i] for i, (v, g) in enumerate(zip(verts, given))]))

    def act(m: player.Mover, movers: dict, now: float) -> None:
        start = now if domain == "relative" else 0.0
        m.follow(start + offset + scale * times, xs, ys, yaws)
    return act


def _private_action(doc: _Doc, pa, init: bool):
    kind = doc.one(pa, {"TeleportAction", "LongitudinalAction"} if init else
                   {"LongitudinalAction", "LateralAction", "RoutingAction"}, "action")
    if kind.tag == "LongitudinalAction":
        return "speed", _speed_action(doc, doc.one(kind, {"SpeedAction"}, "action"), init)
    if kind.tag == "LateralAction":
        return "lateral", _lane_change(doc, doc.one(kind, {"LaneChangeAction"}, "action"))
    if kind.tag == "RoutingAction":
        return "path", _trajectory(doc, doc.one(kind, {"FollowTrajectoryAction"}, "action"))
    return "teleport", kind


def _rule(doc: _Doc, elem) -> str:
    rule = doc.get(elem, "rule")
    if rule not in player.RULES:
        raise doc.refuse(elem, f"rule={rule}", ", ".join(player.RULES))
    return rule


def _distance(a: player.Mover, b: player.Mover, kind: str, freespace: bool) -> float:
    """Distance of `b` from `a` in `a`'s frame: between reference points, or (freespace)
    between the bounding boxes (their centres less half their extents)."""
    (ax, ay), (bx, by) = ((a.box_centre(), b.box_centre()) if freespace else
                          ((a.x_m, a.y_m), (b.x_m, b.y_m)))
    dx, dy = bx - ax, by - ay
    c, s = math.cos(a.yaw_rad), math.sin(a.yaw_rad)
    lon, lat = abs(c * dx + s * dy), abs(-s * dx + c * dy)
    if kind == "longitudinal":
        return max(lon - 0.5 * (a.length_m + b.length_m), 0.0) if freespace else lon
    if kind == "lateral":
        return max(lat - 0.5 * (a.width_m + b.width_m), 0.0) if freespace else lat
    return math.hypot(dx, dy)


def _entity_condition(doc: _Doc, by, roads, names: set[str]):
    trig = by.find("TriggeringEntities")
    if trig is None:
        raise doc.refuse(by, "a ByEntityCondition needs TriggeringEntities")
    rule = doc.get(trig, "triggeringEntitiesRule")
    if rule not in ("any", "all"):
        raise doc.refuse(trig, f"triggeringEntitiesRule={rule}", "any, all")
    who = [doc.get(e, "entityRef") for e in doc.children(trig, {"EntityRef"}, "element")]
    for w in who:
        if w not in names:
            raise doc.refuse(trig, f"entityRef={w} is not an entity")
    doc.children(by, {"TriggeringEntities", "EntityCondition"}, "element")
    if by.find("EntityCondition") is None:
        raise doc.refuse(by, "a ByEntityCondition needs an EntityCondition")
    cond = doc.one(by.find("EntityCondition"),
                   {"ReachPositionCondition", "RelativeDistanceCondition"}, "condition")
    combine = any if rule == "any" else all
    if cond.tag == "ReachPositionCondition":
        tol = doc.num(cond, "tolerance")
        px, py = _point(_position(doc, doc.one(cond, {"Position"}, "element"), roads))
        return lambda ms, now: combine(math.hypot(ms[w].x_m - px, ms[w].y_m - py) <= tol
                                       for w in who)
    ref = doc.get(cond, "entityRef")
    if ref not in names:
        raise doc.refuse(cond, f"entityRef={ref} is not an entity")
    kind = doc.get(cond, "relativeDistanceType")
    kind = {"cartesianDistance": "euclidianDistance"}.get(kind, kind)
    if kind not in ("longitudinal", "lateral", "euclidianDistance"):
        raise doc.refuse(cond, f"relativeDistanceType={kind}",
                         "longitudinal, lateral, cartesianDistance, euclidianDistance")
    if doc.get(cond, "coordinateSystem", "entity") != "entity":
        raise doc.refuse(cond, f"coordinateSystem={doc.get(cond, 'coordinateSystem')}",
                         "entity")
    free = doc.get(cond, "freespace").lower() in ("true", "1")
    if free and kind == "euclidianDistance":
        raise doc.refuse(cond, "a freespace euclidian distance",
                         "freespace with longitudinal or lateral distances")
    op, value = player.RULES[_rule(doc, cond)], doc.num(cond, "value")
    return lambda ms, now: combine(op(_distance(ms[w], ms[ref], kind, free), value)
                                   for w in who)


def _trigger(doc: _Doc, trig, roads, names: set[str]) -> player.Trigger:
    groups = []
    for group in doc.children(trig, {"ConditionGroup"}, "element"):
        conds = []
        for c in doc.children(group, {"Condition"}, "element"):
            edge = doc.get(c, "conditionEdge")
            if edge not in ("none", "rising", "falling", "risingOrFalling"):
                raise doc.refuse(c, f"conditionEdge={edge}",
                                 "none, rising, falling, risingOrFalling")
            kind = doc.one(c, {"ByValueCondition", "ByEntityCondition"}, "condition")
            if kind.tag == "ByValueCondition":
                st = doc.one(kind, {"SimulationTimeCondition"}, "condition")
                op, value = player.RULES[_rule(doc, st)], doc.num(st, "value")
                fn = (lambda op, value: lambda ms, now: op(now, value))(op, value)
            else:
                fn = _entity_condition(doc, kind, roads, names)
            conds.append(player.Condition(fn, edge, doc.num(c, "delay", 0.0)))
        groups.append(conds)
    return player.Trigger(groups)


def _init(doc: _Doc, init, movers: dict, roads) -> dict[str, float]:
    """Apply `Init` (teleports, speeds); returns each entity's initial speed."""
    actions = doc.one(init, {"Actions"}, "element")
    for private in doc.children(actions, {"Private"}, "init action"):
        name = doc.get(private, "entityRef")
        if name not in movers:
            raise doc.refuse(private, f"entityRef={name} is not an entity")
        for pa in doc.children(private, {"PrivateAction"}, "element"):
            kind, act = _private_action(doc, pa, init=True)
            if kind == "teleport":
                where = _position(doc, doc.one(act, {"Position"}, "element"), roads)
                _attach(movers[name], where, roads)
            else:
                act(movers[name], movers, 0.0)
    return {n: m.speed_mps for n, m in movers.items()}


def _events(doc: _Doc, maneuver, actors: list[str], roads, names) -> list[player.Event]:
    out = []
    for ev in doc.children(maneuver, {"Event"}, "element"):
        if doc.num(ev, "maximumExecutionCount", 1) != 1:
            raise doc.refuse(ev, "maximumExecutionCount above 1", "1")
        acts = []
        for a in doc.children(ev, {"Action", "StartTrigger"}, "element"):
            if a.tag == "Action":
                acts.append(_private_action(doc, doc.one(a, {"PrivateAction"}, "action"),
                                            init=False)[1])
        start = ev.find("StartTrigger")
        trig = _trigger(doc, start, roads, names) if start is not None else player.Trigger([])
        out.append(player.Event(trig, actors, acts))
    return out


def _acts(doc: _Doc, board, roads, names: set[str]) -> list[player.Act]:
    acts = []
    for story in doc.children(board, {"Init", "Story", "StopTrigger"}, "element"):
        if story.tag != "Story":
            continue
        for act in doc.children(story, {"Act"}, "element"):
            events = []
            for mg in doc.children(act, {"ManeuverGroup", "StartTrigger", "StopTrigger"},
                                   "element"):
                if mg.tag == "StopTrigger" and len(mg):
                    raise doc.refuse(mg, "an Act StopTrigger with conditions",
                                     "acts that run to the end")
                if mg.tag != "ManeuverGroup":
                    continue
                if doc.num(mg, "maximumExecutionCount", 1) != 1:
                    raise doc.refuse(mg, "maximumExecutionCount above 1", "1")
                parts = doc.children(mg, {"Actors", "Maneuver"}, "element")
                who = [doc.get(e, "entityRef") for p in parts if p.tag == "Actors"
                       for e in doc.children(p, {"EntityRef"}, "actor")]
                for w in who:
                    if w not in names:
                        raise doc.refuse(mg, f"actor {w} is not an entity")
                for man in (p for p in parts if p.tag == "Maneuver"):
                    events += _events(doc, man, who, roads, names)
            start = act.find("StartTrigger")
            trig = _trigger(doc, start, roads, names) if start is not None else \
                player.Trigger([])
            acts.append(player.Act(trig, events))
    return acts


def _stop_time(doc: _Doc, board) -> float | None:
    stop = board.find("StopTrigger")
    if stop is None or not len(doc.children(stop)):
        return None
    conds = [c for g in doc.children(stop, {"ConditionGroup"}, "element")
             for c in doc.children(g, {"Condition"}, "element")]
    sims = [c.find("ByValueCondition/SimulationTimeCondition") for c in conds]
    if len(conds) != 1 or sims[0] is None:
        raise doc.refuse(stop, "a storyboard StopTrigger other than one "
                         "SimulationTimeCondition", "SimulationTimeCondition")
    return doc.num(sims[0], "value")


def _harness(doc: _Doc, name: str, default):
    """A ``harness_*`` parameter (our export's), JSON-decoded; `default` when absent."""
    if name not in doc.params:
        return default
    try:
        return json.loads(doc.params[name])
    except ValueError:
        raise doc.refuse(None, f"parameter {name}={doc.params[name]!r} is not valid JSON") \
            from None


def _road(doc: _Doc, root, path: Path) -> dict[str, OdrRoad]:
    net = root.find("RoadNetwork")
    logic = net.find("LogicFile") if net is not None else None
    if logic is None:
        raise doc.refuse(net if net is not None else root, "no RoadNetwork/LogicFile",
                         "a LogicFile naming an OpenDRIVE (.xodr) file")
    if net is not None:
        doc.children(net, {"LogicFile"}, "road network element")
    return read_xodr(path.parent / doc.get(logic, "filepath"))


def _motion(doc, ents, trajectories, ego: str, roads, rails) -> Motion:
    lanes = tuple(g for r in roads.values() for g in r.lane_geometries())
    motions = {}
    for name, cls, (length, width, height), (cx, cy) in ents:
        tr = trajectories[name]
        if cx or cy:  # the truth is the box centre; the file moves the reference point
            c, s = np.cos(tr.yaw_rad), np.sin(tr.yaw_rad)
            tr = type(tr)(tr.time_s, tr.x_m + c * cx - s * cy, tr.y_m + s * cx + c * cy,
                          tr.yaw_rad)
        motions[name] = EntityMotion(name=name, actor_class=cls, length_m=length,
                                     width_m=width, height_m=height, trajectory=tr)
    return Motion(ego=motions[ego], actors=tuple(m for n, m in motions.items() if n != ego),
                  lanes=lanes, rails_y_m=tuple(float(v) for v in rails))


def read_xosc(path: str | Path, *, name: str | None = None, description: str | None = None,
              ego: str = DEFAULT_EGO, mount: Mount | None = None,
              criteria: tuple[Criterion, ...] | None = None,
              must_detect: tuple[int, ...] | None = None,
              duration_s: float | None = None) -> Case:
    """A `Case` from an OpenSCENARIO 1.x file (see the module docstring).

    Parameters
    ----------
    path : str or Path
    name, description : str, optional
        Default: from the file's name / our export's parameters.
    ego : str
        Entity name of the ego (a car).
    mount, criteria, must_detect, duration_s : optional
        Harness fields; None takes the file's ``harness_*`` parameters, else the defaults.

    Raises
    ------
    scenarios.openscenario.subset.Unsupported
        An element outside the supported subset, or invalid (naming it and its line).
    core.errors.BadInput
        A harness field the case refuses (naming it).
    """
    path = Path(path)
    source = str(path)
    try:
        root = etree.fromstring(read_input_bytes(path, "OpenSCENARIO file"))
    except etree.XMLSyntaxError as exc:
        raise refuse(source, None, f"not well-formed XML: {exc}") from None
    if root.tag != "OpenSCENARIO":
        raise refuse(source, root, "the root element is not OpenSCENARIO")
    doc = _Doc(source, root)
    doc.children(root, {"Entities", "Storyboard", "RoadNetwork"}, "element")
    header = root.find("FileHeader")
    if header is not None and doc.get(header, "revMajor", "1") != "1":
        raise doc.refuse(header, f"OpenSCENARIO {doc.get(header, 'revMajor')}.x", "1.x")
    roads = _road(doc, root, path)
    ents = _entities(doc, root)
    names = {e[0] for e in ents}
    if ego not in names:
        raise doc.refuse(root.find("Entities"), f"no entity named {ego!r} (the ego); "
                         f"entities: {sorted(names)}")
    movers = {n: player.Mover(n, size[0], size[1], centre[0], centre[1])
              for n, _, size, centre in ents}
    board = root.find("Storyboard")
    if board is None or board.find("Init") is None:
        raise doc.refuse(root, "no Storyboard with an Init")
    speeds = _init(doc, board.find("Init"), movers, roads)
    acts = _acts(doc, board, roads, names)
    duration = duration_s if duration_s is not None else _stop_time(doc, board)
    if duration is None:
        duration = float(_harness(doc, "harness_duration_s", DEFAULT_DURATION_S))
    if not 0 < duration <= 120:
        raise BadInput(f"{source}: duration_s={duration:g} must be in (0, 120] s")
    trajectories = player.play(movers, acts, duration)
    motion = _motion(doc, ents, trajectories, ego, roads, _harness(doc, "harness_rails_y_m",
                                                                    []))
    if mount is None:
        m = _harness(doc, "harness_mount", None)
        mount = Mount(**m) if m is not None else MOUNTS[DEFAULT_MOUNT]
    if criteria is None:
        criteria = tuple(Criterion(**c) for c in _harness(doc, "harness_criteria", []))
    if must_detect is None:
        must_detect = tuple(_harness(doc, "harness_must_detect", []))
    radars = tuple(RadarSpec(actor_id=r["actor_id"], family=r["family"],
                             overrides=tuple(r["overrides"].items()))
                   for r in _harness(doc, "harness_radars", []))
    try:
        specs = {n: ActorSpec(actor_class=cls, path="lane_0", speed_mps=speeds[n])
                 for n, cls, _, _ in ents}
    except BadInput as exc:
        raise BadInput(f"{source}: {exc}") from None
    return Case(name=name or case_name_of(path),
                description=description or doc.params.get(
                    "harness_description", f"OpenSCENARIO file {path.name}"),
                mount=mount, duration_s=duration, road="highway", lanes=1,
                guard_rails=bool(motion.rails_y_m),
                ego=specs[ego], actors=tuple(s for n, s in specs.items() if n != ego),
                must_detect=must_detect, criteria=criteria,
                references=doc.params.get("harness_references", f"OpenSCENARIO {path.name}"),
                case_class=doc.params.get("harness_case_class", "ordinary"),
                equipped_share=float(doc.params.get("harness_equipped_share", 0.0)),
                radars=radars, motion=motion)
