"""A case as OpenSCENARIO 1.2 XML (+ its road as OpenDRIVE), written with ``scenariogeneration``.

`export_case` runs the case in highway-env (one seed) and writes what ran: the ego (entity
``Ego``) and every road user (entities named ``<class>_<truth id>``, in truth-id order, guard
rails left out: they are road furniture, kept as a parameter) with its category and bounding
box, an `Init` teleport and speed per entity, and one `FollowTrajectoryAction` per entity
with a timed `Polyline` of `WorldPosition`s at every frame of the run. Each frame's vertex is
followed by one `scenarios.motion.VELOCITY_PROBE_S` later along the entity's velocity, so the
polyline carries each frame's velocity as well as its position (a replay that moves linearly
between vertices reproduces both). The reference point of every entity is its bounding-box
centre (the box's `Center` is 0, 0, height / 2).

What the case means beyond the motion (the radar mount, duration, criteria, must_detect, case
class, radars, guard-rail lines) is kept as global `ParameterDeclarations` named
``harness_*`` (`HARNESS_PARAMETERS`), which `scenarios.openscenario.import_` reads back.
"""
from __future__ import annotations

import datetime
import json
from pathlib import Path

import numpy as np
from scenariogeneration import xosc

from core.fileio import check_output_dir

from ..catalog import ACTOR_CLASSES, Case
from ..motion import VELOCITY_PROBE_S
from ..traffic import RAIL_ID_BASE, ScenarioRun, run_scenario
from .opendrive import case_road, write_xodr

__all__ = ["OSC_MINOR_VERSION", "EGO_NAME", "CATEGORIES", "HARNESS_PARAMETERS", "export_case",
           "export_run", "world_states", "entity_name"]

#: OpenSCENARIO 1.x minor version written (1.2: the newest most players read).
OSC_MINOR_VERSION = 2
#: Entity name of the ego.
EGO_NAME = "Ego"
#: Actor class -> OpenSCENARIO vehicle category (None: a Pedestrian).
CATEGORIES: dict[str, xosc.VehicleCategory | None] = {
    "car": xosc.VehicleCategory.car, "truck": xosc.VehicleCategory.truck,
    "motorcycle": xosc.VehicleCategory.motorbike, "bicycle": xosc.VehicleCategory.bicycle,
    "pedestrian": None,
}
#: Global parameters that carry the case's harness fields (read back by the import).
HARNESS_PARAMETERS = ("harness_description", "harness_references", "harness_case_class",
                      "harness_mount", "harness_duration_s", "harness_must_detect",
                      "harness_criteria", "harness_radars", "harness_equipped_share",
                      "harness_rails_y_m")


#: FileHeader date of every export: a fixed one, so the same case and seed give the same file.
_FILE_DATE = datetime.datetime(2026, 1, 1)


def entity_name(actor_class: str, actor_id: int) -> str:
    """Exported entity name of a truth actor."""
    return f"{actor_class}_{actor_id}"


def world_states(run: ScenarioRun) -> dict:
    """World (ISO) states per entity of a run: ``{key: (class, (L, W, H), t, x, y, yaw, vx,
    vy)}`` with arrays over the frames; key ``None`` is the ego, else the truth actor id
    (guard rails left out). Inverts `scenarios.truth.build_tables`' ego-frame transform."""
    ego = run.ego
    t = ego["time_s"].to_numpy(float)
    ex, ey = ego["ego_x_m"].to_numpy(float), ego["ego_y_m"].to_numpy(float)
    eyaw = np.radians(ego["ego_yaw_deg"].to_numpy(float))
    ev = ego["ego_speed_mps"].to_numpy(float)
    car = ACTOR_CLASSES["car"]
    out = {None: ("car", (car.length_m, car.width_m, car.height_m), t, ex, ey, eyaw,
                  ev * np.cos(eyaw), ev * np.sin(eyaw))}
    truth = run.truth[run.truth["actor_id"] < RAIL_ID_BASE]
    for aid, g in truth.groupby("actor_id", sort=True):
        k = g["frame"].to_numpy(np.int64)
        c, s = np.cos(eyaw[k]), np.sin(eyaw[k])
        xv, yv = g["x_m"].to_numpy(float), g["y_m"].to_numpy(float)
        vxv, vyv = g["vx_mps"].to_numpy(float), g["vy_mps"].to_numpy(float)
        first = g.iloc[0]
        out[int(aid)] = (str(first["actor_class"]),
                         (float(first["length_m"]), float(first["width_m"]),
                          float(first["height_m"])),
                         t[k], ex[k] + c * xv - s * yv, ey[k] + s * xv + c * yv,
                         eyaw[k] + np.radians(g["yaw_deg"].to_numpy(float)),
                         ev[k] * c + c * vxv - s * vyv, ev[k] * s + s * vxv + c * vyv)
    return out


def _entity(name: str, actor_class: str, size) -> xosc.Vehicle | xosc.Pedestrian:
    length, width, height = size
    box = xosc.BoundingBox(width, length, height, 0.0, 0.0, 0.5 * height)
    category = CATEGORIES[actor_class]
    if category is None:
        return xosc.Pedestrian(name, 75.0, xosc.PedestrianCategory.pedestrian, box,
                               model="pedestrian")
    wheel = 0.7 if actor_class in ("car", "truck") else 0.6
    track = 0.8 * width
    front = xosc.Axle(0.5, wheel, track, 0.3 * length, 0.5 * wheel)
    rear = xosc.Axle(0.0, wheel, track, -0.3 * length, 0.5 * wheel)
    cls = ACTOR_CLASSES[actor_class]
    veh = xosc.Vehicle(name, category, box, front, rear, cls.max_speed_mps, 10.0, 10.0)
    veh.add_property("actor_class", actor_class)
    return veh


def _polyline(t, x, y, yaw, vx, vy) -> xosc.Polyline:
    """Vertices at the frames and one `VELOCITY_PROBE_S` after each along its velocity."""
    d = VELOCITY_PROBE_S
    times = np.column_stack([t, t + d]).ravel()
    xs = np.column_stack([x, x + vx * d]).ravel()
    ys = np.column_stack([y, y + vy * d]).ravel()
    hs = np.repeat(yaw, 2)
    return xosc.Polyline([float(v) for v in times],
                         [xosc.WorldPosition(float(a), float(b), 0.0, float(h))
                          for a, b, h in zip(xs, ys, hs)])


def _parameters(case: Case, run: ScenarioRun, ids: dict[int, int],
                rails_y_m: list[float]) -> xosc.ParameterDeclarations:
    m = case.mount
    crit = [dict(c.to_dict(), actor_id=None if c.actor_id is None else ids[c.actor_id])
            for c in case.criteria]
    radars = [{"actor_id": ids[r.actor_id], "family": r.family,
               "overrides": dict(r.overrides)} for r in case.radars if r.actor_id in ids]
    values = {
        "harness_description": case.description, "harness_references": case.references,
        "harness_case_class": case.case_class,
        "harness_mount": json.dumps({"name": m.name, "x_m": m.x_m, "y_m": m.y_m,
                                     "z_m": m.z_m, "yaw_deg": m.yaw_deg}),
        "harness_duration_s": repr(run.n_frames / run.frame_rate_hz),
        "harness_must_detect": json.dumps([ids[i] for i in case.must_detect if i in ids]),
        "harness_criteria": json.dumps(crit), "harness_radars": json.dumps(radars),
        "harness_equipped_share": repr(case.equipped_share),
        "harness_rails_y_m": json.dumps(rails_y_m),
    }
    decl = xosc.ParameterDeclarations()
    for name in HARNESS_PARAMETERS:
        kind = xosc.ParameterType.double if name in ("harness_duration_s",
                                                     "harness_equipped_share") \
            else xosc.ParameterType.string
        decl.add_parameter(xosc.Parameter(name, kind, values[name]))
    return decl


def _storyboard(states: dict, names: dict, duration_s: float) -> xosc.StoryBoard:
    init = xosc.Init()
    act = xosc.Act("replay", xosc.ValueTrigger(
        "replay_start", 0, xosc.ConditionEdge.none,
        xosc.SimulationTimeCondition(0, xosc.Rule.greaterOrEqual)))
    for key, (_, _, t, x, y, yaw, vx, vy) in states.items():
        name = names[key]
        init.add_init_action(name, xosc.TeleportAction(
            xosc.WorldPosition(float(x[0]), float(y[0]), 0.0, float(yaw[0]))))
        speed = float(vx[0] * np.cos(yaw[0]) + vy[0] * np.sin(yaw[0]))
        init.add_init_action(name, xosc.AbsoluteSpeedAction(speed, xosc.TransitionDynamics(
            xosc.DynamicsShapes.step, xosc.DynamicsDimension.time, 0)))
        traj = xosc.Trajectory(f"{name}_path", False)
        traj.add_shape(_polyline(t, x, y, yaw, vx, vy))
        event = xosc.Event(f"{name}_follows", xosc.Priority.override)
        event.add_action(f"{name}_trajectory", xosc.FollowTrajectoryAction(
            traj, xosc.FollowingMode.position, xosc.ReferenceContext.absolute, 1, 0))
        event.add_trigger(xosc.ValueTrigger(
            f"{name}_start", 0, xosc.ConditionEdge.none,
            xosc.SimulationTimeCondition(0, xosc.Rule.greaterOrEqual)))
        man = xosc.Maneuver(f"{name}_maneuver")
        man.add_event(event)
        group = xosc.ManeuverGroup(f"{name}_group")
        group.add_actor(name)
        group.add_maneuver(man)
        act.add_maneuver_group(group)
    story = xosc.Story("recorded")
    story.add_act(act)
    stop = xosc.ValueTrigger("end", 0, xosc.ConditionEdge.none,
                             xosc.SimulationTimeCondition(duration_s, xosc.Rule.greaterThan),
                             "stop")
    board = xosc.StoryBoard(init, stop)
    board.add_story(story)
    return board


def export_run(run: ScenarioRun, out_dir: str | Path, name: str | None = None
               ) -> tuple[Path, Path]:
    """Write a run as ``out_dir/<name>.xosc`` and ``out_dir/<name>.xodr`` (name: the case's).

    Returns
    -------
    (xosc_path, xodr_path)
    """
    case = run.case
    name = name or case.name
    out = check_output_dir(out_dir, "--out")
    roads, rails = case_road(case)
    xodr_path = write_xodr(roads, out / f"{name}.xodr", name)
    states = world_states(run)
    actor_ids = [k for k in states if k is not None]
    ids = {aid: i for i, aid in enumerate(actor_ids)}
    names = {None: EGO_NAME} | {a: entity_name(states[a][0], a) for a in actor_ids}
    entities = xosc.Entities()
    for key, (cls, size, *_rest) in states.items():
        entities.add_scenario_object(names[key], _entity(names[key], cls, size))
    duration = run.n_frames / run.frame_rate_hz
    scenario = xosc.Scenario(
        name, "corner-radar-harness", _parameters(case, run, ids, rails), entities,
        _storyboard(states, names, duration), xosc.RoadNetwork(roadfile=xodr_path.name),
        xosc.Catalog(), osc_minor_version=OSC_MINOR_VERSION,
        creation_date=_FILE_DATE)
    xosc_path = out / f"{name}.xosc"
    scenario.write_xml(str(xosc_path))
    return xosc_path, xodr_path


def export_case(case, out_dir: str | Path, seed: int = 0) -> tuple[Path, Path]:
    """Run `case` (a `Case` or catalogue name) with `seed` and write it (see `export_run`)."""
    check_output_dir(out_dir, "--out")  # before the run
    return export_run(run_scenario(case, seed=seed), out_dir)
