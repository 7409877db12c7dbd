"""highway-env traffic for the catalogue: scripted road users and random traffic, headless.

Scripted cases build a highway-env `Road` on the case's layout and fill it with
`ScriptedVehicle`s (highway-env `Vehicle` subclasses that follow a path at a scripted speed,
with scripted lane changes and braking). Random-traffic cases use highway-env's own
environments (highway, merge, roundabout, intersection) with IDM/MOBIL drivers, the ego included
(it is re-created as an `IDMVehicle` so it drives itself and never needs an agent's action).
Trucks and motorcycles, which highway-env lacks, are `IDMVehicle` / `Vehicle` subclasses with
their own size and speed (`VEHICLE_CLASSES`, `IDM_CLASSES`).

Speed choices (the sweep steps every frame):
* no rendering: `render_mode=None` and no viewer; `env.step` is never called, the loop calls
  `road.act()` and `road.step(dt)` directly, so no observation or reward is computed per frame
  (the one observation at `reset` is a 1-vehicle, 1-feature Kinematics);
* the simulation runs at `substeps` x the frame rate (default 1: 20 Hz, finer than
  highway-env's 15 Hz default), sampled exactly at every radar frame;
* the drivers (IDM/MOBIL `road.act()`, the O(N^2) part) decide at `decision_rate_hz`
  (default 10 Hz, a 100 ms reaction step; highway-env's fast variant decides at 5 Hz) while
  the dynamics integrate at every step;
* collision physics is disabled (scripted cases drive deliberately on collision courses, and
  it saves an O(N^2) Python loop).
Determinism: random traffic draws only from the environment's generator seeded by
`env.reset(seed=seed)`; scripted cases use no randomness at all. highway-env's environments
may set driver constants on the vehicle classes themselves (`IntersectionEnv._make_vehicles`
sets `DISTANCE_WANTED`, `COMFORT_ACC_MAX` and `COMFORT_ACC_MIN` of `IDMVehicle`), which would
otherwise reach every later case simulated in the same process; each simulation restores them
(`vehicle_class_state_restored`), so a case gives the same traffic whatever ran before it.
"""
from __future__ import annotations

import contextlib
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
import pandas as pd
from highway_env.road.road import Road
from highway_env.vehicle.behavior import IDMVehicle
from highway_env.vehicle.kinematics import Vehicle
from scipy.spatial import cKDTree

from core.errors import BadInput

from .catalog import ACTOR_CLASSES, GUARD_RAIL, Case, Mount
from .motion import TrajectoryVehicle
from .registry import get_case
from .roads import LANE_WIDTH_M, ROAD_LAYOUTS, TRAFFIC_ENVS, Path, memoise_lanes
from .truth import (
    RAW_ACTOR_COLUMNS,
    RAW_EGO_COLUMNS,
    build_tables,
    ego_yaw_rate_rps,
    iso_lateral_to_highway,
    radar_velocity_mps,
)

__all__ = ["ScenarioRun", "FrameTruth", "run_scenario", "Path", "ScriptedVehicle",
           "VEHICLE_CLASSES", "IDM_CLASSES", "LANE_WIDTH_M", "RANDOM_ID_BASE",
           "RAIL_ID_BASE", "vehicle_class_state_restored"]

#: Actor ids: scripted actors 0..n-1, random traffic from 100, guard-rail segments from 10000.
RANDOM_ID_BASE = 100
RAIL_ID_BASE = 10_000
#: Guard-rail segments farther than this from the ego are left out of the truth, m.
RAIL_VIEW_M = 300.0


def _vehicle_class(name: str, base: type) -> type:
    spec = ACTOR_CLASSES[name]
    attrs = {"LENGTH": spec.length_m, "WIDTH": spec.width_m, "HEIGHT": spec.height_m,
             "MAX_SPEED": spec.max_speed_mps, "ACTOR_CLASS": name,
             "__doc__": f"highway-env {base.__name__} with {name} size "
                        f"{spec.length_m} x {spec.width_m} x {spec.height_m} m."}
    if spec.initial_speed_fractions is not None:
        attrs["DEFAULT_INITIAL_SPEEDS"] = [f * spec.max_speed_mps
                                           for f in spec.initial_speed_fractions]
    prefix = "IDM" if base is IDMVehicle else ""
    return type(f"{prefix}{name.title()}", (base,), attrs)


#: Kinematic highway-env vehicle classes per road-user class (sizes from `ACTOR_CLASSES`).
VEHICLE_CLASSES: dict[str, type] = {n: _vehicle_class(n, Vehicle) for n in ACTOR_CLASSES}
#: IDM-driven classes for random traffic.
IDM_CLASSES: dict[str, type] = {n: _vehicle_class(n, IDMVehicle)
                                for n, c in ACTOR_CLASSES.items() if c.random_traffic}


class ScriptedVehicle(Vehicle):
    """A highway-env vehicle that follows a `Path` on a script (speed, lane change, braking).

    Parameters
    ----------
    road : highway_env.road.road.Road
    path : Path
    spec : scenarios.catalog.ActorSpec
    s_m : float
        Initial path coordinate, m.
    """

    def __init__(self, road: Road, path: Path, spec, s_m: float) -> None:
        cls = ACTOR_CLASSES[spec.actor_class]
        # Instance sizes before Vehicle.__init__, which derives the diagonal from them.
        self.LENGTH, self.WIDTH = cls.length_m, cls.width_m
        self.HEIGHT = cls.height_m
        self.ACTOR_CLASS = spec.actor_class
        self.path, self.spec, self.s, self.t = path, spec, float(s_m), 0.0
        self._velocity = np.zeros(2)
        super().__init__(road, path.position(s_m), path.heading(s_m), spec.speed_mps)
        self.check_collisions = False
        self.collidable = False
        self._update_pose()

    def _lateral(self) -> tuple[float, float]:
        """Lateral offset (highway-env) and its rate at the current time."""
        sp = self.spec
        lat = iso_lateral_to_highway(sp.lateral_offset_m)
        if sp.lane_change_time_s is None or self.t <= sp.lane_change_time_s:
            return lat, 0.0
        u = min((self.t - sp.lane_change_time_s) / sp.lane_change_duration_s, 1.0)
        d = iso_lateral_to_highway(sp.lane_change_left_m)
        rate = 0.0 if u >= 1 else d * 0.5 * np.pi * np.sin(np.pi * u) / sp.lane_change_duration_s
        return lat + d * 0.5 * (1 - np.cos(np.pi * u)), rate

    def _update_pose(self) -> None:
        lat, lat_rate = self._lateral()
        self.position = self.path.position(self.s, lat)
        h = self.path.heading(self.s)
        tangent = np.array([np.cos(h), np.sin(h)])
        normal = np.array([-np.sin(h), np.cos(h)])
        self._velocity = self.speed * tangent + lat_rate * normal
        self.heading = h + (np.arctan2(lat_rate, self.speed) if self.speed > 0.5 else 0.0)

    @property
    def velocity(self) -> np.ndarray:
        return self._velocity

    def act(self, action=None) -> None:
        """Scripted: no decision to take."""

    def step(self, dt: float) -> None:
        sp = self.spec
        v0 = self.speed
        # 1e-9 s: the time accumulates dt, so 10 x 0.05 s falls just short of 0.5 s.
        if sp.brake_time_s is not None and self.t >= sp.brake_time_s - 1e-9 and v0 != 0.0:
            v1 = v0 - np.sign(v0) * sp.brake_decel_mps2 * dt
            v1 = 0.0 if np.sign(v1) != np.sign(v0) else v1
        else:
            v1 = v0
        self.s += 0.5 * (v0 + v1) * dt
        self.speed = v1
        self.t += dt
        self._update_pose()

    def on_state_update(self) -> None:
        """The path is known: skip highway-env's closest-lane search."""


@dataclass(frozen=True, slots=True)
class FrameTruth:
    """What the radar simulation needs at one frame."""

    frame: int
    time_s: float
    truth: pd.DataFrame
    radar_velocity_mps: np.ndarray
    mount_height_m: float


@dataclass(frozen=True, slots=True)
class ScenarioRun:
    """Result of `run_scenario`.

    Attributes
    ----------
    case : scenarios.catalog.Case
    seed : int
    frame_rate_hz : float
    mount : scenarios.catalog.Mount
    truth : pandas.DataFrame
        `scenarios.truth.TRUTH_COLUMNS`, one row per frame and actor (guard rails included).
    ego : pandas.DataFrame
        `scenarios.truth.EGO_COLUMNS`, one row per frame.
    """

    case: Case
    seed: int
    frame_rate_hz: float
    mount: Mount
    truth: pd.DataFrame
    ego: pd.DataFrame

    @property
    def n_frames(self) -> int:
        return len(self.ego)

    def radar_velocity_mps(self) -> np.ndarray:
        """(F, 3) velocity of the radar over the ground, radar frame, m/s."""
        return radar_velocity_mps(self.ego["ego_speed_mps"].to_numpy(),
                                  ego_yaw_rate_rps(self.ego), self.mount)

    def frames(self) -> Iterator[FrameTruth]:
        """Per frame: the truth rows, the radar velocity and the mount height (for
        `radarsim.rcs.scene_scatterers`)."""
        vel = self.radar_velocity_mps()
        groups = dict(iter(self.truth.groupby("frame", sort=True)))
        empty = self.truth.iloc[0:0]
        for k, (frame, t) in enumerate(zip(self.ego["frame"], self.ego["time_s"])):
            yield FrameTruth(int(frame), float(t), groups.get(frame, empty), vel[k],
                             self.mount.z_m)

    def __iter__(self) -> Iterator[FrameTruth]:
        return self.frames()


def _meet_s(ego_path: Path, ego_s: float, ego_v: float, ego_lat: float, path: Path,
            v: float, lat: float) -> float:
    """Start s on `path` so that an actor at speed v meets the ego at the paths' crossing."""
    lo, hi = (ego_s, ego_s + 200.0) if ego_v >= 0 else (ego_s - 200.0, ego_s)
    se, pe = ego_path.sample(lo, hi, iso_lateral_to_highway(ego_lat), 0.25)
    sa, pa = path.sample(-400.0, 400.0, iso_lateral_to_highway(lat), 0.25)
    dist, j = cKDTree(pa).query(pe)
    i = int(np.argmin(dist))
    if dist[i] > 1.0 or ego_v == 0:
        raise BadInput("meet_ego: the actor's path does not cross the ego's path ahead of "
                       "the ego")
    t_meet = (se[i] - ego_s) / ego_v
    return float(sa[j[i]] - v * t_meet)


def _rail_rows(rails: list[float], ego_hw: pd.DataFrame) -> pd.DataFrame:
    """Static guard-rail segments along the rail lines near the ego (raw highway-env rows)."""
    if not rails:
        return pd.DataFrame(columns=RAW_ACTOR_COLUMNS)
    seg = GUARD_RAIL.length_m
    x_lo = ego_hw["x_hw"].min() - RAIL_VIEW_M - seg
    x_hi = ego_hw["x_hw"].max() + RAIL_VIEW_M + seg
    k = np.arange(np.floor(x_lo / seg), np.ceil(x_hi / seg))
    xs = (k + 0.5) * seg
    ids = RAIL_ID_BASE + np.concatenate([(k % 5000) + 5000 * side for side in range(len(rails))])
    xx = np.tile(xs, len(rails))
    yy = np.repeat(rails, xs.size)
    f = ego_hw["frame"].to_numpy()
    ex = ego_hw["x_hw"].to_numpy()
    near = np.abs(xx[None, :] - ex[:, None]) <= RAIL_VIEW_M
    fi, si = np.nonzero(near)
    n = fi.size
    return pd.DataFrame({"frame": f[fi], "actor_id": ids[si].astype(np.int64),
                         "actor_class": "guard_rail", "length_m": seg,
                         "width_m": GUARD_RAIL.width_m, "height_m": GUARD_RAIL.height_m,
                         "x_hw": xx[si], "y_hw": yy[si], "heading_hw": np.zeros(n),
                         "vx_hw": np.zeros(n), "vy_hw": np.zeros(n)})


def _scripted(case: Case):
    net, paths, rails = ROAD_LAYOUTS[case.road].build(case.lanes)
    road = Road(network=net, np_random=np.random.RandomState(0), record_history=False)
    ego_path = paths[case.ego.path]
    ego = ScriptedVehicle(road, ego_path, case.ego, case.ego.s_m)
    road.vehicles.append(ego)
    actors = []
    for spec in case.actors:
        s0 = spec.s_m
        if spec.meet_ego:
            s0 = _meet_s(ego_path, case.ego.s_m, case.ego.speed_mps, case.ego.lateral_offset_m,
                         paths[spec.path], spec.speed_mps, spec.lateral_offset_m)
        v = ScriptedVehicle(road, paths[spec.path], spec, s0)
        road.vehicles.append(v)
        actors.append(v)
    ids = {id(v): i for i, v in enumerate(actors)}
    return road, ego, ids, rails, None


def _recorded(case: Case, dt_s: float):
    """The ego and actors of a recorded case (`Case.motion`) on its road."""
    motion = case.motion
    road = Road(network=motion.network(), np_random=np.random.RandomState(0),
                record_history=False)
    ego = TrajectoryVehicle(road, motion.ego, dt_s)
    road.vehicles.append(ego)
    actors = [TrajectoryVehicle(road, m, dt_s) for m in motion.actors]
    road.vehicles.extend(actors)
    rails = [float(iso_lateral_to_highway(y)) for y in motion.rails_y_m]
    return road, ego, {id(v): i for i, v in enumerate(actors)}, rails, None


def _random_traffic(case: Case, seed: int, frame_rate_hz: float, substeps: int):
    traffic = TRAFFIC_ENVS[case.traffic]
    if abs(frame_rate_hz - round(frame_rate_hz)) > 1e-9:
        raise BadInput(f"frame_rate_hz={frame_rate_hz!r} must be a whole number of Hz for "
                       "highway-env traffic environments")
    config = {"simulation_frequency": int(round(frame_rate_hz)) * substeps,
              "policy_frequency": int(round(frame_rate_hz)),
              "observation": {"type": "Kinematics", "vehicles_count": 1,
                              "features": ["presence"]},
              "duration": case.duration_s + 1.0, "offscreen_rendering": True}
    config.update(traffic.env_config(case.lanes, case.vehicles_count, case.vehicles_density))
    env = traffic.env_class()(config=config, render_mode=None)
    env.reset(seed=seed)
    road = env.road
    memoise_lanes(road.network)   # bit-identical, ~6x cheaper neighbour projections
    old_ego = env.vehicle
    ego = IDM_CLASSES["car"].create_from(old_ego)
    road.vehicles[road.vehicles.index(old_ego)] = ego
    env.controlled_vehicles = [ego]
    gen = env.np_random
    for i, v in enumerate(road.vehicles):
        v.check_collisions = False
        if v is ego or not isinstance(v, IDMVehicle):
            continue
        u = gen.uniform()
        name = ("truck" if u < case.truck_fraction else "motorcycle"
                if u < case.truck_fraction + case.motorcycle_fraction else None)
        if name is not None:
            new = IDM_CLASSES[name].create_from(v)
            cap = ACTOR_CLASSES[name].cruise_speed_cap_mps
            if cap is not None:
                new.target_speed = min(new.target_speed, cap)
            new.check_collisions = False
            road.vehicles[i] = new
    return road, ego, {}, traffic.rails_y_hw(case.lanes), env


def _vehicle_classes() -> list[type]:
    """highway-env's `Vehicle` and every subclass defined so far (its own drivers, ours)."""
    out, todo = [], [Vehicle]
    while todo:
        cls = todo.pop()
        out.append(cls)
        todo.extend(cls.__subclasses__())
    return out


@contextlib.contextmanager
def vehicle_class_state_restored() -> Iterator[None]:
    """Restore the class-level constants (upper-case attributes) of every highway-env vehicle
    class on exit, as they were on entry: an environment that sets them for its own traffic
    (highway-env 1.x `IntersectionEnv._make_vehicles`: `DISTANCE_WANTED = 7`,
    `COMFORT_ACC_MAX = 6`, `COMFORT_ACC_MIN = -3` on `IDMVehicle`) keeps them for its own
    simulation only, not for the next case a sweep worker simulates."""
    saved = {cls: {k: v for k, v in vars(cls).items() if k.isupper()}
             for cls in _vehicle_classes()}
    try:
        yield
    finally:
        # Only the classes that existed on entry: a class first defined inside the block (a
        # module imported there) has nothing to restore, and its own constants stay.
        for cls, before in saved.items():
            for k in [k for k in vars(cls) if k.isupper() and k not in before]:
                delattr(cls, k)
            for k, v in before.items():
                if vars(cls).get(k, object()) is not v:
                    setattr(cls, k, v)


def run_scenario(name_or_case, seed: int = 0, duration_s: float | None = None,
                 frame_rate_hz: float = 20.0, substeps: int = 1,
                 decision_rate_hz: float = 10.0) -> ScenarioRun:
    """Simulate a catalogue case (or a `Case`) and return its ground truth.

    Parameters
    ----------
    name_or_case : str or scenarios.catalog.Case
    seed : int
        Seed of the random traffic (scripted cases are deterministic anyway).
    duration_s : float, optional
        Override the case's duration, s (> 0).
    frame_rate_hz : float
        Radar frame rate, Hz, in (0, 100]; one truth sample per frame.
    substeps : int
        highway-env integration steps per frame (>= 1).
    decision_rate_hz : float
        Rate of the drivers' decisions (`road.act()`), Hz, in (0, frame_rate x substeps];
        rounded to a whole number of integration steps.

    Returns
    -------
    ScenarioRun

    Raises
    ------
    ValueError
        Unknown case (naming the known ones) or a bad argument.
    """
    case = get_case(name_or_case)
    if not 0 < frame_rate_hz <= 100:
        raise BadInput(f"frame_rate_hz={frame_rate_hz!r} must be in (0, 100] Hz")
    if isinstance(substeps, bool) or not isinstance(substeps, int) or substeps < 1:
        raise BadInput(f"substeps={substeps!r} must be an integer >= 1")
    sim_rate = frame_rate_hz * substeps
    if not 0 < decision_rate_hz <= sim_rate:
        raise BadInput(f"decision_rate_hz={decision_rate_hz!r} must be in (0, {sim_rate:g}] "
                       "Hz")
    stride = max(int(round(sim_rate / decision_rate_hz)), 1)
    duration = case.duration_s if duration_s is None else duration_s
    if not duration > 0:
        raise BadInput(f"duration_s={duration!r} must be > 0")
    n_frames = max(int(round(duration * frame_rate_hz)), 1)
    with vehicle_class_state_restored():
        if case.motion is not None:
            road, ego, ids, rails, _env = _recorded(case, 1.0 / sim_rate)
        elif case.traffic is None:
            road, ego, ids, rails, _env = _scripted(case)
        else:
            road, ego, ids, rails, _env = _random_traffic(case, seed, frame_rate_hz, substeps)
        dt = 1.0 / (frame_rate_hz * substeps)
        actor_rows: list[tuple] = []
        ego_rows: list[tuple] = []
        for frame in range(n_frames):
            ego_rows.append((frame, ego.position[0], ego.position[1], ego.heading, ego.speed))
            for v in road.vehicles:
                if v is ego:
                    continue
                key = id(v)
                if key not in ids:
                    ids[key] = RANDOM_ID_BASE + len(ids)
                cls = getattr(v, "ACTOR_CLASS", "car")
                vel = v.velocity
                height = getattr(v, "HEIGHT", ACTOR_CLASSES[cls].height_m)
                actor_rows.append((frame, ids[key], cls, v.LENGTH, v.WIDTH, height,
                                   v.position[0], v.position[1],
                                   v.heading, vel[0], vel[1]))
            if frame < n_frames - 1:
                for sub in range(substeps):
                    if (frame * substeps + sub) % stride == 0:
                        road.act()
                    road.step(dt)
    raw_ego = pd.DataFrame(ego_rows, columns=RAW_EGO_COLUMNS)
    raw = pd.DataFrame(actor_rows, columns=RAW_ACTOR_COLUMNS)
    rail = _rail_rows(rails, raw_ego) if case.guard_rails else None
    if rail is not None and len(rail):
        raw = pd.concat([raw, rail], ignore_index=True) if len(raw) else rail
    truth, ego_table = build_tables(raw, raw_ego, case.mount, frame_rate_hz)
    return ScenarioRun(case=case, seed=int(seed), frame_rate_hz=float(frame_rate_hz),
                       mount=case.mount, truth=truth, ego=ego_table)
