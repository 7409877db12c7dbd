"""The scenario catalogue: named corner-radar cases (UN R79, Euro NCAP, ISO 17387) as data.

A `Case` says where the radar sits (`Mount`), which road layout and traffic the scene has
(`ActorSpec` per scripted actor, or a random highway-env traffic environment), how long it runs,
which actors must be detected and the physical pass criteria (`Criterion`) that the metrics
package evaluates. `SCENARIOS` is the registry users type names from. Conventions: ISO 8855
vehicle frame (x forward, y LEFT, z up), SI units with the unit in every name.

Paths of the road layouts (`ROAD_LAYOUTS`); `s_m` runs along the path with s = 0 at the path's
point nearest the layout origin (the intersection centre; x = 0 on straight roads):

* ``highway``: ``lane_0`` .. ``lane_{lanes-1}``, 4 m apart, all driving +x; ``lane_0`` is the
  LEFTMOST lane (highway-env's order). Guard rails 1.5 m beyond both edges.
* ``two_way``: ``lane_0`` .. ``lane_{lanes-1}`` driving +x (``lane_0`` leftmost of them) and
  ``oncoming`` to the left of ``lane_0``, driving -x (s grows along its direction).
* ``urban``: a four-way intersection centred on the origin: ``main`` (+x, right-hand lane),
  ``oncoming`` (-x), ``from_left`` (crossing traffic coming from the ego's left),
  ``from_right``, and ``turn_left`` (``main`` then a 8 m radius left turn into the cross road).

References
----------
.. [1] UN Regulation No. 79, rev. 4, para. 5.6.4 (ACSF category C: S_rear >= 55 m, critical
       distance S_crit, v_app = 130 km/h, a = 3 m/s^2, t_B = 0.4 s, t_G = 1 s).
.. [2] Euro NCAP AEB Car-to-Car test protocol v4.3 (CCCscp, CCFtap, CCFhos), AEB/LSS VRU
       protocol (dooring with cyclist, backover pedestrian).
.. [3] ISO 17387:2008, Lane change decision aid systems (closing speeds 10/15/20 m/s).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = ["ActorClass", "ACTOR_CLASSES", "GUARD_RAIL", "Mount", "MOUNTS", "ActorSpec",
           "Criterion", "CRITERION_METRICS", "CRITERION_OPS", "Case", "SCENARIOS",
           "ROAD_LAYOUTS", "TRAFFIC_ENVS", "path_names", "get_case", "s_crit_m", "KMH"]

KMH = 1 / 3.6  # m/s per km/h


@dataclass(frozen=True, kw_only=True, slots=True)
class ActorClass:
    """Size and speed limit of one road-user class (box used by the RCS model).

    Parameters
    ----------
    name : str
    length_m, width_m, height_m : float
        Box size, m (> 0).
    max_speed_mps : float
        Highest speed a scenario may give this class, m/s (> 0).
    """

    name: str
    length_m: float
    width_m: float
    height_m: float
    max_speed_mps: float

    def __post_init__(self) -> None:
        for f in ("length_m", "width_m", "height_m", "max_speed_mps"):
            if not getattr(self, f) > 0:
                raise ValueError(f"{f}={getattr(self, f)!r} must be > 0")


#: Road-user classes. Car 5 x 2 m is highway-env's default; motorcycle 2.2 x 0.8 m and truck
#: about 16 m (DESIGN 6); heights include a rider. Max speeds: motorcycles must reach the R79
#: 130 km/h (and 160 km/h for margin), pedestrians run at most ~4 m/s.
ACTOR_CLASSES: dict[str, ActorClass] = {
    "car": ActorClass(name="car", length_m=5.0, width_m=2.0, height_m=1.5, max_speed_mps=45.0),
    "truck": ActorClass(name="truck", length_m=16.5, width_m=2.55, height_m=4.0,
                        max_speed_mps=36.0),
    "motorcycle": ActorClass(name="motorcycle", length_m=2.2, width_m=0.8, height_m=1.4,
                             max_speed_mps=45.0),
    "bicycle": ActorClass(name="bicycle", length_m=1.8, width_m=0.6, height_m=1.8,
                          max_speed_mps=15.0),
    "pedestrian": ActorClass(name="pedestrian", length_m=0.5, width_m=0.6, height_m=1.75,
                             max_speed_mps=4.0),
}
#: Guard-rail segment box (steel W-beam on posts, top at 0.75 m); static infrastructure.
GUARD_RAIL = ActorClass(name="guard_rail", length_m=16.0, width_m=0.3, height_m=0.75,
                        max_speed_mps=1e-9)


@dataclass(frozen=True, kw_only=True, slots=True)
class Mount:
    """Where a corner radar sits on the ego (vehicle frame, ISO 8855).

    p_vehicle = Rz(yaw) p_radar + (x_m, y_m, z_m); the radar x axis is its boresight.

    Parameters
    ----------
    name : str
        One of front_left, front_right, rear_left, rear_right.
    x_m, y_m : float
        Position on the ego, m (|x| <= 10, |y| <= 3).
    z_m : float
        Height above the ground, m, in (0, 3].
    yaw_deg : float
        Boresight yaw from the ego's x axis, deg, in [-180, 180] (positive to the left).
    """

    name: str
    x_m: float
    y_m: float
    z_m: float
    yaw_deg: float

    def __post_init__(self) -> None:
        if self.name not in ("front_left", "front_right", "rear_left", "rear_right"):
            raise ValueError(f"mount name={self.name!r} unknown; known: front_left, "
                             "front_right, rear_left, rear_right")
        if not abs(self.x_m) <= 10:
            raise ValueError(f"mount x_m={self.x_m!r} must be within +/-10 m of the ego centre")
        if not abs(self.y_m) <= 3:
            raise ValueError(f"mount y_m={self.y_m!r} must be within +/-3 m of the ego centre")
        if not 0 < self.z_m <= 3:
            raise ValueError(f"mount z_m={self.z_m!r} must be in (0, 3] m")
        if not -180 <= self.yaw_deg <= 180:
            raise ValueError(f"mount yaw_deg={self.yaw_deg!r} must be in [-180, 180] deg")


#: Corner mounts on the 5 x 2 m ego: 0.2 m inside its corners, 0.5 m high, yaw +/-45 and
#: +/-135 deg (typical corner-radar installation).
MOUNTS: dict[str, Mount] = {
    "front_left": Mount(name="front_left", x_m=2.3, y_m=0.8, z_m=0.5, yaw_deg=45.0),
    "front_right": Mount(name="front_right", x_m=2.3, y_m=-0.8, z_m=0.5, yaw_deg=-45.0),
    "rear_left": Mount(name="rear_left", x_m=-2.3, y_m=0.8, z_m=0.5, yaw_deg=135.0),
    "rear_right": Mount(name="rear_right", x_m=-2.3, y_m=-0.8, z_m=0.5, yaw_deg=-135.0),
}

#: Road layouts and how many forward lanes they accept.
ROAD_LAYOUTS: dict[str, str] = {
    "highway": "straight multi-lane motorway, all lanes +x, guard rails at both edges",
    "two_way": "straight rural road: forward lanes plus one oncoming lane on the left",
    "urban": "four-way intersection: main, oncoming, from_left, from_right, turn_left",
}
#: Random-traffic environments of highway-env (the ego drives itself, IDM).
TRAFFIC_ENVS: dict[str, str] = {
    "highway": "highway_env.envs.HighwayEnv",
    "merge": "highway_env.envs.MergeEnv",
    "roundabout": "highway_env.envs.RoundaboutEnv",
    "intersection": "highway_env.envs.IntersectionEnv",
}


def path_names(road: str, lanes: int) -> tuple[str, ...]:
    """Paths an actor of a `road` layout with `lanes` forward lanes may follow."""
    if road == "highway":
        return tuple(f"lane_{i}" for i in range(lanes))
    if road == "two_way":
        return tuple(f"lane_{i}" for i in range(lanes)) + ("oncoming",)
    if road == "urban":
        return ("main", "oncoming", "from_left", "from_right", "turn_left")
    raise ValueError(f"road={road!r} unknown; known: {sorted(ROAD_LAYOUTS)}")


@dataclass(frozen=True, kw_only=True, slots=True)
class ActorSpec:
    """One scripted road user (or the ego).

    Parameters
    ----------
    actor_class : str
        Key of `ACTOR_CLASSES`.
    path : str
        Path of the road layout it follows (see module docstring).
    s_m : float
        Position along the path at t = 0, m (ignored if `meet_ego` is set).
    speed_mps : float
        Initial speed along the path, m/s; negative = reversing (at most 5 m/s).
    lateral_offset_m : float
        Offset from the path centre line, m, positive to the LEFT (|offset| <= 10).
    meet_ego : bool
        Place the actor so that, at constant speeds, it reaches the crossing point of its path
        and the ego's path at the same time as the ego (a collision course, as in NCAP).
    lane_change_time_s : float or None
        Start of a scripted lane change, s (>= 0).
    lane_change_left_m : float
        Lateral displacement of the lane change, m, positive to the left.
    lane_change_duration_s : float
        Duration of the (half-cosine) lane change, s (> 0).
    brake_time_s : float or None
        Start of scripted braking, s (>= 0).
    brake_decel_mps2 : float
        Deceleration while braking, m/s^2, in [0, 12] (12: beyond any tyre on asphalt).
    """

    actor_class: str = "car"
    path: str = "lane_1"
    s_m: float = 0.0
    speed_mps: float = 0.0
    lateral_offset_m: float = 0.0
    meet_ego: bool = False
    lane_change_time_s: float | None = None
    lane_change_left_m: float = 0.0
    lane_change_duration_s: float = 3.0
    brake_time_s: float | None = None
    brake_decel_mps2: float = 0.0

    def __post_init__(self) -> None:
        if self.actor_class not in ACTOR_CLASSES:
            raise ValueError(f"actor_class={self.actor_class!r} unknown; known: "
                             f"{sorted(ACTOR_CLASSES)}")
        for f in ("s_m", "speed_mps", "lateral_offset_m", "lane_change_left_m",
                  "lane_change_duration_s", "brake_decel_mps2"):
            v = getattr(self, f)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"{f}={v!r} must be a finite number")
        vmax = ACTOR_CLASSES[self.actor_class].max_speed_mps
        if self.speed_mps > vmax:
            raise ValueError(f"speed_mps={self.speed_mps!r} exceeds the {self.actor_class} "
                             f"limit {vmax:g} m/s")
        if self.speed_mps < -5.0:
            raise ValueError(f"speed_mps={self.speed_mps!r}: reversing is limited to -5 m/s")
        if abs(self.lateral_offset_m) > 10:
            raise ValueError(f"lateral_offset_m={self.lateral_offset_m!r} must be within "
                             "+/-10 m")
        if abs(self.lane_change_left_m) > 12:
            raise ValueError(f"lane_change_left_m={self.lane_change_left_m!r} must be within "
                             "+/-12 m")
        for f in ("lane_change_time_s", "brake_time_s"):
            v = getattr(self, f)
            if v is not None and not (isinstance(v, (int, float)) and 0 <= v < 1e4):
                raise ValueError(f"{f}={v!r} must be a time >= 0 s")
        if not self.lane_change_duration_s > 0:
            raise ValueError(f"lane_change_duration_s={self.lane_change_duration_s!r} must "
                             "be > 0")
        if not 0 <= self.brake_decel_mps2 <= 12:
            raise ValueError(f"brake_decel_mps2={self.brake_decel_mps2!r} must be in [0, 12] "
                             "m/s^2")


#: Metrics a criterion may name (computed per actor, scenario, scheme and seed by `metrics`).
CRITERION_METRICS: dict[str, str] = {
    "first_detection_range_m": "range of the actor at its first TRUE detection, m",
    "detection_probability": "fraction of frames (actor in the FOV) with a TRUE detection",
    "velocity_unambiguous_rate": "TRUE / (TRUE + VELOCITY-AMBIGUOUS) detections of the actor",
    "ghost_rate": "ghost detections / all detections (scenario-wide)",
    "range_rmse_m": "RMS range error of TRUE detections, m",
}
#: Comparison operators of a criterion.
CRITERION_OPS: dict[str, str] = {">=": "at least", "<=": "at most", ">": "above",
                                 "<": "below"}


@dataclass(frozen=True, kw_only=True, slots=True)
class Criterion:
    """A physical pass criterion: `metric op value` for one actor (or the whole case).

    Parameters
    ----------
    metric : str
        Key of `CRITERION_METRICS`.
    op : str
        Key of `CRITERION_OPS`.
    value : float
        Threshold in the metric's unit.
    actor_id : int or None
        Truth actor the metric is computed for (scripted actors have ids 0, 1, ...); None for a
        scenario-wide metric.
    note : str
        Where the number comes from.
    """

    metric: str
    op: str
    value: float
    actor_id: int | None = None
    note: str = ""

    def __post_init__(self) -> None:
        if self.metric not in CRITERION_METRICS:
            raise ValueError(f"metric={self.metric!r} unknown; known: "
                             f"{sorted(CRITERION_METRICS)}")
        if self.op not in CRITERION_OPS:
            raise ValueError(f"op={self.op!r} unknown; known: {sorted(CRITERION_OPS)}")
        if isinstance(self.value, bool) or not isinstance(self.value, (int, float)) \
                or not math.isfinite(self.value):
            raise ValueError(f"value={self.value!r} must be a finite number")
        if self.actor_id is not None and (isinstance(self.actor_id, bool)
                                          or not isinstance(self.actor_id, int)
                                          or self.actor_id < 0):
            raise ValueError(f"actor_id={self.actor_id!r} must be an integer >= 0")

    def to_dict(self) -> dict:
        """Plain dict (metric, op, value, actor_id, note) for tables and gates."""
        return {"metric": self.metric, "op": self.op, "value": float(self.value),
                "actor_id": self.actor_id, "note": self.note}

    def passed(self, measured: float) -> bool:
        """Whether `measured` meets the criterion (NaN never passes)."""
        if measured is None or not math.isfinite(measured):
            return False
        return {">=": measured >= self.value, "<=": measured <= self.value,
                ">": measured > self.value, "<": measured < self.value}[self.op]


@dataclass(frozen=True, kw_only=True, slots=True)
class Case:
    """One named corner-radar scenario.

    Parameters
    ----------
    name : str
        Registry key (lowercase, digits, underscores).
    description : str
        One line: what happens and why it matters.
    mount : Mount
        The radar under test.
    duration_s : float
        Simulated time, s, in (0, 120].
    road : str
        Key of `ROAD_LAYOUTS` (scripted cases).
    lanes : int
        Forward lanes, 1..6.
    ego : ActorSpec
        The ego's script (a car).
    actors : tuple of ActorSpec
        Scripted road users; their truth actor_id is their index.
    guard_rails : bool
        Static guard rails along both road edges (highway and two_way roads, or the highway
        traffic env).
    traffic : str or None
        Key of `TRAFFIC_ENVS`: random traffic instead of scripted actors (the ego drives itself).
    vehicles_count : int
        Random vehicles (traffic cases), 0..60.
    vehicles_density : float
        highway-env density factor, in (0, 5].
    truck_fraction, motorcycle_fraction : float
        Share of random vehicles of those classes, each in [0, 1], sum <= 1.
    must_detect : tuple of int
        Actor ids that the radar must detect.
    criteria : tuple of Criterion
        Physical pass criteria.
    references : str
        Regulation / protocol the case comes from.
    """

    name: str
    description: str
    mount: Mount
    duration_s: float
    road: str = "highway"
    lanes: int = 3
    ego: ActorSpec = field(default_factory=lambda: ActorSpec(path="lane_1"))
    actors: tuple[ActorSpec, ...] = ()
    guard_rails: bool = False
    traffic: str | None = None
    vehicles_count: int = 0
    vehicles_density: float = 1.0
    truck_fraction: float = 0.0
    motorcycle_fraction: float = 0.0
    must_detect: tuple[int, ...] = ()
    criteria: tuple[Criterion, ...] = ()
    references: str = ""

    def __post_init__(self) -> None:
        if not self.name or not all(ch.islower() or ch.isdigit() or ch == "_"
                                    for ch in self.name):
            raise ValueError(f"name={self.name!r} must be lowercase letters, digits and _")
        if not isinstance(self.mount, Mount):
            raise ValueError(f"mount must be a Mount, got {self.mount!r}")
        if isinstance(self.duration_s, bool) or not isinstance(self.duration_s, (int, float)) \
                or not 0 < self.duration_s <= 120:
            raise ValueError(f"duration_s={self.duration_s!r} must be in (0, 120] s")
        if self.road not in ROAD_LAYOUTS:
            raise ValueError(f"road={self.road!r} unknown; known: {sorted(ROAD_LAYOUTS)}")
        if isinstance(self.lanes, bool) or not isinstance(self.lanes, int) \
                or not 1 <= self.lanes <= 6:
            raise ValueError(f"lanes={self.lanes!r} must be an integer in [1, 6]")
        if self.traffic is not None and self.traffic not in TRAFFIC_ENVS:
            raise ValueError(f"traffic={self.traffic!r} unknown; known: {sorted(TRAFFIC_ENVS)}")
        if self.ego.actor_class != "car":
            raise ValueError(f"ego.actor_class={self.ego.actor_class!r}: the ego is a car")
        if self.ego.meet_ego:
            raise ValueError("ego.meet_ego must be false (it is the reference)")
        paths = path_names(self.road, self.lanes)
        if self.traffic is None:
            for label, spec in [("ego", self.ego)] + [(f"actors[{i}]", a)
                                                      for i, a in enumerate(self.actors)]:
                if spec.path not in paths:
                    raise ValueError(f"{label}.path={spec.path!r} unknown for road "
                                     f"{self.road!r}; known: {list(paths)}")
        if isinstance(self.vehicles_count, bool) or not isinstance(self.vehicles_count, int) \
                or not 0 <= self.vehicles_count <= 60:
            raise ValueError(f"vehicles_count={self.vehicles_count!r} must be an integer in "
                             "[0, 60]")
        if not 0 < self.vehicles_density <= 5:
            raise ValueError(f"vehicles_density={self.vehicles_density!r} must be in (0, 5]")
        for f in ("truck_fraction", "motorcycle_fraction"):
            if not 0 <= getattr(self, f) <= 1:
                raise ValueError(f"{f}={getattr(self, f)!r} must be in [0, 1]")
        if self.truck_fraction + self.motorcycle_fraction > 1:
            raise ValueError("truck_fraction + motorcycle_fraction must be <= 1")
        n = len(self.actors)
        for i in self.must_detect:
            if not isinstance(i, int) or not 0 <= i < n:
                raise ValueError(f"must_detect id {i!r} is not a scripted actor (0..{n - 1})")
        for c in self.criteria:
            if not isinstance(c, Criterion):
                raise ValueError(f"criteria must hold Criterion objects, got {c!r}")
            if c.actor_id is not None and c.actor_id >= n:
                raise ValueError(f"criterion actor_id={c.actor_id} is not a scripted actor "
                                 f"(0..{n - 1})")

    def summary(self) -> str:
        """One catalogue line: name, mount, duration, description."""
        return f"{self.name:<28s} {self.mount.name:<11s} {self.duration_s:4.1f} s  " \
               f"{self.description}"


def s_crit_m(ego_speed_mps: float, v_app_mps: float = 130 * KMH, a_mps2: float = 3.0,
             t_b_s: float = 0.4, t_g_s: float = 1.0) -> float:
    """UN R79 critical distance S_crit = (v_app - v) t_B + (v_app - v)^2 / (2 a) + v t_G, m.

    87.5 m at 60 km/h, 59.9 m at 80 km/h, 42.7 m at 100 km/h (DESIGN 6).
    """
    dv = v_app_mps - ego_speed_mps
    return dv * t_b_s + dv * dv / (2 * a_mps2) + ego_speed_mps * t_g_s


def _fdr(actor_id: int, value: float, note: str) -> Criterion:
    return Criterion(metric="first_detection_range_m", op=">=", value=round(value, 1),
                     actor_id=actor_id, note=note)


def _pd(actor_id: int, value: float, note: str) -> Criterion:
    return Criterion(metric="detection_probability", op=">=", value=value, actor_id=actor_id,
                     note=note)


def _build() -> dict[str, Case]:
    m = MOUNTS
    cases = [
        Case(name="r79_motorcycle_rear", mount=m["rear_left"], duration_s=5.0, lanes=3,
             description="R79 ACSF-C: L3 motorcycle at 130 km/h approaching in the left "
                         "adjacent lane, ego 80 km/h; must be seen at S_rear >= 55 m",
             ego=ActorSpec(path="lane_1", speed_mps=80 * KMH),
             actors=(ActorSpec(actor_class="motorcycle", path="lane_0", s_m=-120.0,
                               speed_mps=130 * KMH),),
             guard_rails=True, must_detect=(0,),
             criteria=(_fdr(0, 55.0, "UN R79 5.6.4.8.1: S_rear >= 55 m"),),
             references="UN R79 rev. 4, 5.6.4"),
        Case(name="r79_critical_distance_60", mount=m["rear_left"], duration_s=3.0,
             description="R79 critical distance at ego 60 km/h: vehicle at 130 km/h in the "
                         "left lane must be seen at S_crit = 87.5 m",
             ego=ActorSpec(path="lane_1", speed_mps=60 * KMH),
             actors=(ActorSpec(actor_class="car", path="lane_0", s_m=-135.0,
                               speed_mps=130 * KMH),),
             guard_rails=True, must_detect=(0,),
             criteria=(_fdr(0, s_crit_m(60 * KMH), "UN R79 S_crit at 60 km/h"),),
             references="UN R79 rev. 4, 5.6.4.7"),
        Case(name="r79_critical_distance_100", mount=m["rear_left"], duration_s=4.0,
             description="R79 critical distance at ego 100 km/h: vehicle at 130 km/h in the "
                         "left lane must be seen at S_crit = 42.7 m",
             ego=ActorSpec(path="lane_1", speed_mps=100 * KMH),
             actors=(ActorSpec(actor_class="car", path="lane_0", s_m=-75.0,
                               speed_mps=130 * KMH),),
             guard_rails=True, must_detect=(0,),
             criteria=(_fdr(0, s_crit_m(100 * KMH), "UN R79 S_crit at 100 km/h"),),
             references="UN R79 rev. 4, 5.6.4.7"),
        Case(name="blind_spot_overtaking", mount=m["rear_left"], duration_s=6.0,
             description="ELK overtaking: car at 80 km/h passes the ego (72 km/h) through the "
                         "left blind spot",
             ego=ActorSpec(path="lane_1", speed_mps=72 * KMH),
             actors=(ActorSpec(actor_class="car", path="lane_0", s_m=-18.0,
                               speed_mps=80 * KMH),),
             guard_rails=True, must_detect=(0,),
             criteria=(_pd(0, 0.9, "blind-spot warning needs continuous detection"),),
             references="Euro NCAP LSS ELK overtaking; ISO 17387"),
        Case(name="truck_high_closing", mount=m["rear_left"], duration_s=3.0,
             description="Truck closing at 20 m/s (ISO 17387 maximum) in the left lane on a "
                         "slow ego (36 km/h)",
             ego=ActorSpec(path="lane_1", speed_mps=10.0),
             actors=(ActorSpec(actor_class="truck", path="lane_0", s_m=-110.0,
                               speed_mps=30.0),),
             guard_rails=True, must_detect=(0,),
             criteria=(_fdr(0, 70.0, "ISO 17387 type III: 3.5 s at 20 m/s"),),
             references="ISO 17387 closing speed 20 m/s"),
        Case(name="zero_relative_follower", mount=m["rear_left"], duration_s=3.0,
             description="Car holding the ego's speed (90 km/h) 8 m behind in the left lane: "
                         "zero Doppler, must not be lost",
             ego=ActorSpec(path="lane_1", speed_mps=25.0),
             actors=(ActorSpec(actor_class="car", path="lane_0", s_m=-8.0, speed_mps=25.0),),
             guard_rails=True, must_detect=(0,),
             criteria=(_pd(0, 0.9, "static relative target in the blind spot"),),
             references="ISO 17387 blind-spot zone"),
        Case(name="dooring_cyclist", road="two_way", lanes=1, mount=m["rear_left"],
             duration_s=6.0,
             description="Parked ego; cyclist at 20 km/h passes close on the left where a "
                         "door would open",
             ego=ActorSpec(path="lane_0", speed_mps=0.0, lateral_offset_m=-1.0),
             actors=(ActorSpec(actor_class="bicycle", path="lane_0", s_m=-40.0,
                               speed_mps=20 * KMH, lateral_offset_m=1.0),),
             must_detect=(0,),
             criteria=(_fdr(0, 20.0, "about 3.5 s warning before the door opens"),),
             references="Euro NCAP AEB/LSS VRU: dooring 15-25 km/h"),
        Case(name="reversing_pedestrian", road="urban", lanes=1, mount=m["rear_left"],
             duration_s=3.0,
             description="Ego reversing at 1.5 m/s; pedestrian walks at 5 km/h across its path "
                         "from the left",
             ego=ActorSpec(path="main", s_m=6.0, speed_mps=-1.5),
             actors=(ActorSpec(actor_class="pedestrian", path="from_left", speed_mps=5 * KMH,
                               meet_ego=True),),
             must_detect=(0,),
             criteria=(_pd(0, 0.8, "backover: pedestrian behind the car"),),
             references="Euro NCAP AEB backover, pedestrian 5 km/h"),
        Case(name="cccscp_crossing", road="urban", lanes=1, mount=m["front_left"],
             duration_s=3.5,
             description="CCCscp: ego at 30 km/h, target at 70 km/h crossing from the left on a "
                         "collision course",
             ego=ActorSpec(path="main", s_m=-35.0, speed_mps=30 * KMH),
             actors=(ActorSpec(actor_class="car", path="from_left", speed_mps=70 * KMH,
                               meet_ego=True),),
             must_detect=(0,),
             criteria=(_fdr(0, 50.0, "about 2.5 s before the conflict at 70 km/h"),),
             references="Euro NCAP AEB C2C CCCscp"),
        Case(name="ccftap_turn_across", road="urban", lanes=1, mount=m["front_right"],
             duration_s=4.0,
             description="CCFtap: ego turns left at 15 km/h across an oncoming car at 50 km/h",
             ego=ActorSpec(path="turn_left", s_m=-17.0, speed_mps=15 * KMH),
             actors=(ActorSpec(actor_class="car", path="oncoming", speed_mps=50 * KMH,
                               meet_ego=True),),
             must_detect=(0,),
             criteria=(_fdr(0, 40.0, "about 2.5 s before the conflict at 50 km/h"),),
             references="Euro NCAP AEB C2C CCFtap"),
        Case(name="head_on_aliasing", road="two_way", lanes=1, mount=m["front_left"],
             duration_s=3.0,
             description="CCFhos: oncoming car, 90 + 90 km/h = 50 m/s closing, beyond the "
                         "+/-40.8 m/s DDMA span: aliasing must show",
             ego=ActorSpec(path="lane_0", speed_mps=25.0),
             actors=(ActorSpec(actor_class="car", path="oncoming", s_m=-200.0,
                               speed_mps=25.0),),
             guard_rails=True, must_detect=(0,),
             criteria=(_fdr(0, 100.0, "2 s before the encounter at 50 m/s"),
                       Criterion(metric="velocity_unambiguous_rate", op="<", value=1.0,
                                 actor_id=0, note="|v_r| > 40.8 m/s: expected to alias "
                                                  "(DESIGN 6)")),
             references="Euro NCAP AEB C2C CCFhos"),
        Case(name="dense_highway", traffic="highway", lanes=4, mount=m["front_left"],
             duration_s=4.0, vehicles_count=30, vehicles_density=2.0, truck_fraction=0.15,
             motorcycle_fraction=0.1, guard_rails=True,
             description="Dense random 4-lane highway traffic with trucks and motorcycles",
             criteria=(Criterion(metric="ghost_rate", op="<=", value=0.1,
                                 note="ghost budget in clutter-rich traffic"),),
             references="highway-env highway-v0"),
        Case(name="merge_random", traffic="merge", mount=m["front_right"], duration_s=4.0,
             description="Random traffic at a highway on-ramp merge",
             criteria=(Criterion(metric="ghost_rate", op="<=", value=0.1),),
             references="highway-env merge-v0"),
        Case(name="roundabout_random", traffic="roundabout", mount=m["front_left"],
             duration_s=4.0, description="Random traffic entering a roundabout",
             criteria=(Criterion(metric="ghost_rate", op="<=", value=0.1),),
             references="highway-env roundabout-v0"),
        Case(name="intersection_random", traffic="intersection", mount=m["front_left"],
             duration_s=4.0, description="Random traffic at an unsignalised intersection",
             criteria=(Criterion(metric="ghost_rate", op="<=", value=0.1),),
             references="highway-env intersection-v0"),
    ]
    return {c.name: c for c in cases}


#: The catalogue, keyed by case name.
SCENARIOS: dict[str, Case] = _build()


def get_case(name_or_case) -> Case:
    """The `Case` itself, or the catalogue entry of that name.

    Raises
    ------
    ValueError
        Naming the unknown case and the known names.
    """
    if isinstance(name_or_case, Case):
        return name_or_case
    if name_or_case not in SCENARIOS:
        raise ValueError(f"unknown scenario {name_or_case!r}; known: {', '.join(SCENARIOS)}")
    return SCENARIOS[name_or_case]
