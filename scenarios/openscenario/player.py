"""Plays an OpenSCENARIO storyboard (the supported subset) into timed trajectories.

The import (`scenarios.openscenario.import_`) turns a file's entities, `Init` and storyboard
into `Mover`s, `Condition`s and `Event`s; `play` steps them together at `STEP_S` and returns
each entity's `scenarios.motion.TimedTrajectory`, which highway-env then drives
(`scenarios.motion.TrajectoryVehicle`). Conditions that look at other entities
(`ReachPosition`, `RelativeDistance`) are evaluated on the poses of the same step, so events
fire in the order the scene makes them true.

Kinematics: an entity placed on a lane moves along its road at its speed (right lanes along
the road's s, left lanes against it: right-hand traffic) and changes lane by moving its
lateral coordinate; an entity placed off every lane drives straight along its heading; a
`FollowTrajectoryAction` moves it along its timed polyline, vertex to vertex, and afterwards it
goes straight on at the last segment's velocity. A newer action replaces an older one of the
same kind (speed, lateral, trajectory); a speed or lane-change action ends a trajectory.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..motion import TIME_TOLERANCE_S, TimedTrajectory
from .road import OdrRoad

__all__ = ["STEP_S", "SHAPES", "RULES", "Mover", "Condition", "Trigger", "Event", "Act",
           "play"]

#: Time step of the player, s (speed and lane-change profiles are sampled at it; trajectories
#: keep their own vertices).
STEP_S = 0.01

#: Transition shapes: u in [0, 1] -> progress in [0, 1].
SHAPES: dict[str, Callable[[float], float]] = {
    "step": lambda u: 1.0,
    "linear": lambda u: u,
    "sinusoidal": lambda u: 0.5 * (1.0 - math.cos(math.pi * u)),
    "cubic": lambda u: u * u * (3.0 - 2.0 * u),
}
#: Comparison rules of conditions (equalTo within half a step's worth of tolerance).
RULES: dict[str, Callable[[float, float], bool]] = {
    "greaterThan": lambda a, b: a > b, "greaterOrEqual": lambda a, b: a >= b,
    "lessThan": lambda a, b: a < b, "lessOrEqual": lambda a, b: a <= b,
    "equalTo": lambda a, b: abs(a - b) <= 1e-6 * max(1.0, abs(b)),
    "notEqualTo": lambda a, b: abs(a - b) > 1e-6 * max(1.0, abs(b)),
}


@dataclass
class _Profile:
    """A transition from `v0` to `v1` starting at `start` over `span` (time or distance)."""

    start: float
    v0: float
    v1: float
    span: float
    shape: str
    by_distance: bool

    def value(self, now: float) -> float:
        if self.span <= 0:
            return self.v1
        u = min(max((now - self.start) / self.span, 0.0), 1.0)
        return self.v0 + (self.v1 - self.v0) * SHAPES[self.shape](u)

    def done(self, now: float) -> bool:
        return now - self.start >= self.span


@dataclass
class Mover:
    """One entity in play.

    Parameters
    ----------
    name : str
    length_m, width_m : float
        Bounding box (for freespace distances).
    x_m, y_m, yaw_rad : float
        Reference-point pose, ISO world.
    speed_mps : float
    road : OdrRoad or None
        The road it drives along (None: straight along its heading).
    s_m, t_m : float
        Road coordinates when on a road.
    direction : int
        +1 along the road's s, -1 against it.
    centre_x_m, centre_y_m : float
        Bounding-box centre from the reference point, vehicle frame, m.
    """

    name: str
    length_m: float
    width_m: float
    centre_x_m: float = 0.0
    centre_y_m: float = 0.0
    x_m: float = 0.0
    y_m: float = 0.0
    yaw_rad: float = 0.0
    speed_mps: float = 0.0
    road: OdrRoad | None = None
    s_m: float = 0.0
    t_m: float = 0.0
    direction: int = 1
    travelled_m: float = 0.0
    speed_profile: _Profile | None = None
    lateral_profile: _Profile | None = None
    path: tuple | None = None  # (times, x, y, yaw) in simulation time
    samples: list = field(default_factory=list)

    def place_on_road(self, road: OdrRoad, s: float, t: float, direction: int) -> None:
        self.road, self.s_m, self.t_m, self.direction = road, s, t, direction
        self.x_m, self.y_m, h = road.point(s, t)
        self.yaw_rad = h + (math.pi if direction < 0 else 0.0)

    def box_centre(self) -> tuple[float, float]:
        """World position of the bounding-box centre."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return (self.x_m + c * self.centre_x_m - s * self.centre_y_m,
                self.y_m + s * self.centre_x_m + c * self.centre_y_m)

    def lane_t(self) -> float:
        """Centre t of the lane the entity is on (nearest centre)."""
        return min((c for c, _ in self.road.lanes.values()), key=lambda c: abs(c - self.t_m))

    def set_speed(self, now: float, target: float, shape: str, dimension: str,
                  value: float) -> None:
        v0 = self.speed_mps
        span = value if dimension != "rate" else abs(target - v0) / value
        if dimension == "distance":
            mean = 0.5 * (abs(v0) + abs(target))
            span = value / mean if mean > 0 else 0.0
        self.speed_profile = _Profile(now, v0, target, 0.0 if shape == "step" else span,
                                      shape, False)
        self._leave_path()

    def change_lane(self, now: float, target_t: float, shape: str, dimension: str,
                    value: float) -> None:
        by_distance = dimension == "distance"
        start = self.travelled_m if by_distance else now
        self.lateral_profile = _Profile(start, self.t_m, target_t,
                                        0.0 if shape == "step" else value, shape, by_distance)
        self._leave_path()

    def follow(self, times: np.ndarray, xs: np.ndarray, ys: np.ndarray,
               yaws: np.ndarray) -> None:
        self.path = (times, xs, ys, yaws)
        self.speed_profile = self.lateral_profile = None

    def _leave_path(self) -> None:
        if self.path is not None:
            self.path = None
            self.road = None  # goes on straight from where the trajectory left it

    def record(self, now: float) -> None:
        if not self.samples or now > self.samples[-1][0] + TIME_TOLERANCE_S:
            self.samples.append((now, self.x_m, self.y_m, self.yaw_rad))

    def _step_path(self, now: float, dt: float) -> None:
        times, xs, ys, yaws = self.path
        end = now + dt
        inside = (times > now + TIME_TOLERANCE_S) & (times <= end + TIME_TOLERANCE_S)
        for k in np.flatnonzero(inside):
            self.samples.append((float(times[k]), float(xs[k]), float(ys[k]),
                                 float(yaws[k])))
        if end >= times[-1] - TIME_TOLERANCE_S or times.size < 2:
            k = times.size - 1
            self.x_m, self.y_m, self.yaw_rad = float(xs[k]), float(ys[k]), float(yaws[k])
            if times.size >= 2:
                dtk = times[k] - times[k - 1]
                self.speed_mps = math.hypot(xs[k] - xs[k - 1], ys[k] - ys[k - 1]) / dtk
            self.path, self.road = None, None
            return
        self.x_m = float(np.interp(end, times, xs))
        self.y_m = float(np.interp(end, times, ys))
        self.yaw_rad = float(np.interp(end, times, yaws))
        k = min(int(np.searchsorted(times, end, side="right")), times.size - 1)
        dtk = times[k] - times[k - 1]
        self.speed_mps = math.hypot(xs[k] - xs[k - 1], ys[k] - ys[k - 1]) / dtk

    def step(self, now: float, dt: float) -> None:
        """Advance from `now` to `now + dt`."""
        if self.path is not None:
            if now + dt >= self.path[0][0] - TIME_TOLERANCE_S:
                self._step_path(now, dt)
            else:
                self.record(now + dt)  # waits where it is for the trajectory's first time
            return
        v0 = self.speed_mps
        if self.speed_profile is not None:
            self.speed_mps = self.speed_profile.value(now + dt)
        ds = 0.5 * (v0 + self.speed_mps) * dt
        self.travelled_m += abs(ds)
        if self.road is None:
            self.x_m += ds * math.cos(self.yaw_rad)
            self.y_m += ds * math.sin(self.yaw_rad)
            self.record(now + dt)
            return
        t0 = self.t_m
        if self.lateral_profile is not None:
            lp = self.lateral_profile
            self.t_m = lp.value(self.travelled_m if lp.by_distance else now + dt)
        self.s_m += self.direction * ds
        self.x_m, self.y_m, h = self.road.point(self.s_m, self.t_m)
        heading = h + (math.pi if self.direction < 0 else 0.0)
        lateral = self.direction * (self.t_m - t0)
        self.yaw_rad = heading + (math.atan2(lateral, ds) if abs(ds) > 1e-9 and ds > 0
                                  else -math.atan2(lateral, -ds) if abs(ds) > 1e-9 else 0.0)
        self.record(now + dt)

    def trajectory(self) -> TimedTrajectory:
        a = np.array(self.samples, dtype=float)
        return TimedTrajectory(a[:, 0], a[:, 1], a[:, 2], a[:, 3])


class Condition:
    """A condition of a trigger: `value(movers, now)` gives its state; `edge` and `delay` as
    in OpenSCENARIO (the delayed state is the one `delay` seconds ago)."""

    def __init__(self, value: Callable[[dict, float], bool], edge: str = "none",
                 delay_s: float = 0.0) -> None:
        self.value, self.edge, self.delay_s = value, edge, delay_s
        self.prev: bool | None = None
        self.history: list[tuple[float, bool]] = []

    def __call__(self, movers: dict, now: float) -> bool:
        v = bool(self.value(movers, now))
        prev, self.prev = self.prev, v
        hit = {"none": v, "rising": prev is False and v, "falling": prev is True and not v,
               "risingOrFalling": prev is not None and v != prev}[self.edge]
        if self.delay_s <= 0:
            return hit
        self.history.append((now, hit))
        return any(h and now >= t + self.delay_s - TIME_TOLERANCE_S
                   for t, h in self.history)


@dataclass
class Trigger:
    """Condition groups: the trigger fires when every condition of any group holds (no
    groups: fires at once)."""

    groups: list[list[Condition]]

    def __call__(self, movers: dict, now: float) -> bool:
        if not self.groups:
            return True
        results = [all([c(movers, now) for c in g]) for g in self.groups]
        return any(results)


@dataclass
class Event:
    """Actions (``action(mover, movers, now)``) for every actor, once its trigger fires."""

    trigger: Trigger
    actors: list[str]
    actions: list[Callable]
    fired: bool = False


@dataclass
class Act:
    trigger: Trigger
    events: list[Event]
    started: bool = False


def play(movers: dict[str, Mover], acts: list[Act], duration_s: float
         ) -> dict[str, TimedTrajectory]:
    """Step the scene from 0 to `duration_s` (+ one step) and return each entity's
    trajectory (by name)."""
    n = int(math.ceil(duration_s / STEP_S)) + 1
    for m in movers.values():
        m.record(0.0)
    for i in range(n + 1):
        now = i * STEP_S
        for act in acts:
            if not act.started and act.trigger(movers, now):
                act.started = True
            if not act.started:
                continue
            for ev in act.events:
                if not ev.fired and ev.trigger(movers, now):
                    ev.fired = True
                    for name in ev.actors:
                        for action in ev.actions:
                            action(movers[name], movers, now)
        if i == n:
            break
        for m in movers.values():
            m.step(now, STEP_S)
    return {name: m.trajectory() for name, m in movers.items()}
