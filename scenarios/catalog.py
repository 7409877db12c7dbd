"""The vocabulary of a corner-radar case (UN R79, Euro NCAP, ISO 17387): what a case file holds.

A `Case` says where the radar sits (`Mount`), which road layout and traffic the scene has
(`ActorSpec` per scripted actor, or a random highway-env traffic environment), how long it runs,
which actors must be detected and the physical pass criteria (`Criterion`) that the metrics
package evaluates. The shipped cases are TOML files in ``scenarios/cases/`` (`scenarios.registry`
loads them into `SCENARIOS`); road layouts and traffic environments are the registries of
`scenarios.roads`. Conventions: ISO 8855 vehicle frame (x forward, y LEFT, z up), SI units with
the unit in every name.

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

from core.checks import one_of, require
from core.errors import BadInput

from .equipment import RadarSpec
from .motion import Motion
from .roads import ROAD_LAYOUTS, TRAFFIC_ENVS

__all__ = ["ActorClass", "ACTOR_CLASSES", "GUARD_RAIL", "Mount", "MOUNTS", "ActorSpec",
           "Criterion", "CRITERION_OPS", "CaseClass", "CASE_CLASSES", "Case", "ROAD_LAYOUTS",
           "TRAFFIC_ENVS", "path_names", "KMH"]

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
    random_traffic : bool
        Drives in highway-env's random traffic (an IDM/MOBIL class, `traffic.IDM_CLASSES`).
    cruise_speed_cap_mps : float or None
        Random traffic: cap on the IDM target speed, m/s (None: highway-env's own).
    initial_speed_fractions : (float, float) or None
        highway-env's default initial speed range as fractions of `max_speed_mps` (None:
        highway-env's own, 23-25 m/s, far too fast for road users on foot or bicycle).
    """

    name: str
    length_m: float
    width_m: float
    height_m: float
    max_speed_mps: float
    random_traffic: bool = False
    cruise_speed_cap_mps: float | None = None
    initial_speed_fractions: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        require(self, ("length_m", "width_m", "height_m", "max_speed_mps"), gt=0)
        require(self, "random_traffic", "bool")
        require(self, "cruise_speed_cap_mps", gt=0, none_ok=True)


#: Road-user classes. Car 5 x 2 m is highway-env's default; motorcycle 2.2 x 0.8 m and truck
#: about 16 m (design.md 6); heights include a rider. Max speeds: motorcycles must reach the R79
#: 130 km/h (and 160 km/h for margin), pedestrians run at most ~4 m/s.
ACTOR_CLASSES: dict[str, ActorClass] = {
    "car": ActorClass(name="car", length_m=5.0, width_m=2.0, height_m=1.5, max_speed_mps=45.0,
                      random_traffic=True),
    "truck": ActorClass(name="truck", length_m=16.5, width_m=2.55, height_m=4.0,
                        max_speed_mps=36.0, random_traffic=True, cruise_speed_cap_mps=25.0),
    "motorcycle": ActorClass(name="motorcycle", length_m=2.2, width_m=0.8, height_m=1.4,
                             max_speed_mps=45.0, random_traffic=True),
    "bicycle": ActorClass(name="bicycle", length_m=1.8, width_m=0.6, height_m=1.8,
                          max_speed_mps=15.0, initial_speed_fractions=(0.5, 0.7)),
    "pedestrian": ActorClass(name="pedestrian", length_m=0.5, width_m=0.6, height_m=1.75,
                             max_speed_mps=4.0, initial_speed_fractions=(0.5, 0.7)),
}
#: Guard-rail segment box (steel W-beam on posts, top at 0.75 m); static infrastructure.
GUARD_RAIL = ActorClass(name="guard_rail", length_m=16.0, width_m=0.3, height_m=0.75,
                        max_speed_mps=1e-9)


_MOUNT_NAMES = ("front_left", "front_right", "rear_left", "rear_right")


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
        if self.name not in _MOUNT_NAMES:
            raise BadInput(f"mount name={self.name!r} unknown; known: "
                           f"{', '.join(_MOUNT_NAMES)}")
        require(self, "x_m", ge=-10, le=10, unit="m", where="mount ")
        require(self, "y_m", ge=-3, le=3, unit="m", where="mount ")
        require(self, "z_m", gt=0, le=3, unit="m", where="mount ")
        require(self, "yaw_deg", ge=-180, le=180, unit="deg", where="mount ")


#: Corner mounts on the 5 x 2 m ego: 0.2 m inside its corners, 0.5 m high, yaw +/-45 and
#: +/-135 deg (typical corner-radar installation).
MOUNTS: dict[str, Mount] = {
    "front_left": Mount(name="front_left", x_m=2.3, y_m=0.8, z_m=0.5, yaw_deg=45.0),
    "front_right": Mount(name="front_right", x_m=2.3, y_m=-0.8, z_m=0.5, yaw_deg=-45.0),
    "rear_left": Mount(name="rear_left", x_m=-2.3, y_m=0.8, z_m=0.5, yaw_deg=135.0),
    "rear_right": Mount(name="rear_right", x_m=-2.3, y_m=-0.8, z_m=0.5, yaw_deg=-135.0),
}

def path_names(road: str, lanes: int) -> tuple[str, ...]:
    """Paths an actor of a `road` layout (key of `ROAD_LAYOUTS`) with `lanes` forward lanes
    may follow."""
    one_of("road", road, ROAD_LAYOUTS)
    return ROAD_LAYOUTS[road].path_names(lanes)


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
        one_of("actor_class", self.actor_class, ACTOR_CLASSES)
        require(self, ("s_m", "speed_mps", "lateral_offset_m", "lane_change_left_m",
                       "lane_change_duration_s", "brake_decel_mps2"))
        vmax = ACTOR_CLASSES[self.actor_class].max_speed_mps
        if self.speed_mps > vmax:
            raise BadInput(f"speed_mps={self.speed_mps!r} exceeds the {self.actor_class} "
                           f"limit {vmax:g} m/s")
        if self.speed_mps < -5.0:
            raise BadInput(f"speed_mps={self.speed_mps!r}: reversing is limited to -5 m/s")
        if abs(self.lateral_offset_m) > 10:
            raise BadInput(f"lateral_offset_m={self.lateral_offset_m!r} must be within "
                           "+/-10 m")
        if abs(self.lane_change_left_m) > 12:
            raise BadInput(f"lane_change_left_m={self.lane_change_left_m!r} must be within "
                           "+/-12 m")
        require(self, ("lane_change_time_s", "brake_time_s"), ge=0, lt=1e4, unit="s",
                none_ok=True)
        if not self.lane_change_duration_s > 0:
            raise BadInput(f"lane_change_duration_s={self.lane_change_duration_s!r} must "
                           "be > 0")
        if not 0 <= self.brake_decel_mps2 <= 12:
            raise BadInput(f"brake_decel_mps2={self.brake_decel_mps2!r} must be in [0, 12] "
                           "m/s^2")


#: Comparison operators of a criterion.
CRITERION_OPS: dict[str, str] = {">=": "at least", "<=": "at most", ">": "above",
                                 "<": "below"}


@dataclass(frozen=True, kw_only=True, slots=True)
class Criterion:
    """A physical pass criterion: `metric op value` for one actor (or the whole case).

    Parameters
    ----------
    metric : str
        Name of a criterion metric of ``metrics.METRICS`` (checked there: this package knows
        nothing of the metrics downstream of it; a sweep checks every case's criteria before
        it starts).
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
        require(self, "metric", "str")
        if not self.metric:
            raise BadInput("metric='' must name a metric")
        one_of("op", self.op, CRITERION_OPS)
        require(self, "value")
        require(self, "actor_id", "integer", ge=0, none_ok=True)

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
class CaseClass:
    """What a kind of case exists to show.

    Parameters
    ----------
    name : str
    description : str
    needs_approaching_target : bool
        The verdict compares an approaching target with the ego (scripted speeds, a first
        ``must_detect`` actor faster than the ego): UN R79's critical distance.
    """

    name: str
    description: str
    needs_approaching_target: bool = False


#: Case classes; gates address cases by them, and ``metrics`` adds each class's verdict
#: (``metrics.scoring.CASE_VERDICTS``, same keys).
CASE_CLASSES: dict[str, CaseClass] = {c.name: c for c in (
    CaseClass(name="ordinary", description="detection range, accuracy, ghosts and velocity "
              "resolution of a corner case"),
    CaseClass(name="interference", description="other radars in the band: floor rise, "
              "recovery by mitigation, no ghosts added by it"),
    CaseClass(name="r79", description="UN R79 ACSF category C: the approaching vehicle seen "
              "at the critical distance", needs_approaching_target=True),
)}


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
    equipped_share : float
        Share of the vehicles (car, truck, motorcycle) without an explicit radar that carry one
        radar drawn with the seed from `equipment.WAVEFORM_FAMILIES`, in [0, 1] (default 0).
    radars : tuple of equipment.RadarSpec
        Radars on given actors (``[[radars]]`` tables: actor_id, optional family, and
        `equipment.RadarEquipment` fields).
    case_class : str
        Key of `CASE_CLASSES` (default "ordinary"). An "r79" case is judged on UN R79's
        critical distance from its ego speed and its first target's speed, so it needs
        scripted speeds and a target (``must_detect``) approaching faster than the ego.
    motion : scenarios.motion.Motion or None
        Recorded motion (a case read from an OpenSCENARIO file): the ego and the actors follow
        it instead of their scripts; `ego` and `actors` then hold each entity's class and
        initial speed (what the metrics read), one `actors` entry per `motion.actors` entry.
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
    equipped_share: float = 0.0
    radars: tuple[RadarSpec, ...] = ()
    case_class: str = "ordinary"
    motion: Motion | None = None

    def __post_init__(self) -> None:
        if not self.name or not all(ch.islower() or ch.isdigit() or ch == "_"
                                    for ch in self.name):
            raise BadInput(f"name={self.name!r} must be lowercase letters, digits and _")
        if not isinstance(self.mount, Mount):
            raise BadInput(f"mount must be a Mount, got {self.mount!r}")
        require(self, "duration_s", gt=0, le=120, unit="s")
        one_of("road", self.road, ROAD_LAYOUTS)
        require(self, "lanes", "integer", ge=1, le=6)
        if self.traffic is not None:
            one_of("traffic", self.traffic, TRAFFIC_ENVS)
        if self.ego.actor_class != "car":
            raise BadInput(f"ego.actor_class={self.ego.actor_class!r}: the ego is a car")
        if self.ego.meet_ego:
            raise BadInput("ego.meet_ego must be false (it is the reference)")
        paths = path_names(self.road, self.lanes)
        if self.traffic is None:
            for label, spec in [("ego", self.ego)] + [(f"actors[{i}]", a)
                                                      for i, a in enumerate(self.actors)]:
                if spec.path not in paths:
                    raise BadInput(f"{label}.path={spec.path!r} unknown for road "
                                   f"{self.road!r}; known: {list(paths)}")
        require(self, "vehicles_count", "integer", ge=0, le=60)
        require(self, "vehicles_density", gt=0, le=5)
        require(self, ("truck_fraction", "motorcycle_fraction"), ge=0, le=1)
        if self.truck_fraction + self.motorcycle_fraction > 1:
            raise BadInput("truck_fraction + motorcycle_fraction must be <= 1")
        n = len(self.actors)
        require(self, "equipped_share", ge=0, le=1)
        for r in self.radars:
            if not isinstance(r, RadarSpec):
                raise BadInput(f"radars must hold RadarSpec objects, got {r!r}")
            if self.traffic is None and r.actor_id >= n:
                raise BadInput(f"radars: actor_id={r.actor_id} is not a scripted actor "
                               f"(0..{n - 1})")
        for i in self.must_detect:
            if not isinstance(i, int) or not 0 <= i < n:
                raise BadInput(f"must_detect id {i!r} is not a scripted actor (0..{n - 1})")
        one_of("case_class", self.case_class, CASE_CLASSES)
        if self.motion is not None and (self.traffic is not None or
                                        len(self.motion.actors) != n):
            raise BadInput("motion: a recorded case has no random traffic and one actor "
                             f"per recorded entity ({len(self.motion.actors)}), got {n}")
        if CASE_CLASSES[self.case_class].needs_approaching_target and (
                self.traffic is not None or not self.must_detect or
                self.actors[self.must_detect[0]].speed_mps <= self.ego.speed_mps):
            raise BadInput(f"case_class={self.case_class!r} needs scripted actors and a "
                           "first must_detect actor approaching faster than the ego")
        for c in self.criteria:
            if not isinstance(c, Criterion):
                raise BadInput(f"criteria must hold Criterion objects, got {c!r}")
            if c.actor_id is not None and c.actor_id >= n:
                raise BadInput(f"criterion actor_id={c.actor_id} is not a scripted actor "
                               f"(0..{n - 1})")

    def summary(self) -> str:
        """One catalogue line: name, mount, duration, description."""
        return f"{self.name:<28s} {self.mount.name:<11s} {self.duration_s:4.1f} s  " \
               f"{self.description}"
