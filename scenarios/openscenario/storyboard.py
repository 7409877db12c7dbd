"""The storyboard of an OpenSCENARIO document as player objects (`scenarios.openscenario.player`).

`apply_init` places the entities and sets their speeds; `acts` turns every `Act` into
`player.Act`s of `player.Event`s whose triggers are `player.Condition`s and whose actions change
a `player.Mover` (speed, lane change, trajectory); `stop_time` reads the storyboard's stop. Every
element outside the supported subset is refused with its line.
"""
from __future__ import annotations

import math

import numpy as np

from . import player
from .document import Document, point, position
from .road import OdrRoad

__all__ = ["apply_init", "acts", "stop_time"]


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


def _dynamics(doc: Document, dyn, shapes: set[str], dimensions: set[str]) -> tuple[str, str, float]:
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


def _speed_action(doc: Document, elem, init: bool):
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


def _lane_change(doc: Document, elem):
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


def _trajectory(doc: Document, elem):
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


def _private_action(doc: Document, pa, init: bool):
    kind = doc.one(pa, {"TeleportAction", "LongitudinalAction"} if init else
                   {"LongitudinalAction", "LateralAction", "RoutingAction"}, "action")
    if kind.tag == "LongitudinalAction":
        return "speed", _speed_action(doc, doc.one(kind, {"SpeedAction"}, "action"), init)
    if kind.tag == "LateralAction":
        return "lateral", _lane_change(doc, doc.one(kind, {"LaneChangeAction"}, "action"))
    if kind.tag == "RoutingAction":
        return "path", _trajectory(doc, doc.one(kind, {"FollowTrajectoryAction"}, "action"))
    return "teleport", kind


def _rule(doc: Document, elem) -> str:
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


def _entity_condition(doc: Document, by, roads, names: set[str]):
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
        px, py = point(position(doc, doc.one(cond, {"Position"}, "element"), roads))
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


def _trigger(doc: Document, trig, roads, names: set[str]) -> player.Trigger:
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


def apply_init(doc: Document, init, movers: dict, roads) -> dict[str, float]:
    """Apply `Init` (teleports, speeds); returns each entity's initial speed."""
    actions = doc.one(init, {"Actions"}, "element")
    for private in doc.children(actions, {"Private"}, "init action"):
        name = doc.get(private, "entityRef")
        if name not in movers:
            raise doc.refuse(private, f"entityRef={name} is not an entity")
        for pa in doc.children(private, {"PrivateAction"}, "element"):
            kind, act = _private_action(doc, pa, init=True)
            if kind == "teleport":
                where = position(doc, doc.one(act, {"Position"}, "element"), roads)
                _attach(movers[name], where, roads)
            else:
                act(movers[name], movers, 0.0)
    return {n: m.speed_mps for n, m in movers.items()}


def _events(doc: Document, maneuver, actors: list[str], roads, names) -> list[player.Event]:
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


def acts(doc: Document, board, roads, names: set[str]) -> list[player.Act]:
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


def stop_time(doc: Document, board) -> float | None:
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


