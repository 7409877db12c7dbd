"""Recorded motion: road users that follow timed trajectories (an imported OpenSCENARIO file).

A `Motion` is what a case read from an OpenSCENARIO file drives: one `TimedTrajectory` per
entity (the ego and the actors, in the file's entity order) and the lanes of its road. highway-env
still runs the traffic: each entity is a `TrajectoryVehicle` on a highway-env `Road` built from
those lanes, stepped by the same loop as every other case (`scenarios.traffic`), so its truth,
the bird's-eye view and the sweep's tables come out exactly as for a scripted case.

Coordinates are ISO 8855 world axes (x east, y north/left, yaw counter-clockwise), as in
OpenSCENARIO; the one flip to highway-env's axes is `scenarios.truth.iso_lateral_to_highway`'s
sign convention, applied here when a vehicle's pose is set.

A trajectory is piecewise linear in time between its samples (an OpenSCENARIO timed polyline).
Its velocity at time t is the slope of the segment that starts at or before t, so a trajectory
written with one extra sample a moment after each frame (`VELOCITY_PROBE_S`, as
`scenarios.openscenario.export` writes) carries each frame's instantaneous velocity too.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from highway_env.road.lane import CircularLane, StraightLane
from highway_env.road.road import Road, RoadNetwork
from highway_env.vehicle.kinematics import Vehicle

from core.errors import BadInput

__all__ = ["TimedTrajectory", "EntityMotion", "LaneGeometry", "Motion", "TrajectoryVehicle",
           "VELOCITY_PROBE_S", "TIME_TOLERANCE_S"]

#: Offset of the velocity-carrying sample after each frame's sample, s (1 ms: the position it
#: adds is the frame's own within a micrometre at any road user's acceleration).
VELOCITY_PROBE_S = 1e-3
#: Times closer than this are the same instant (a frame time summed in steps of 1/20 s differs
#: from the written one in the last bits), s.
TIME_TOLERANCE_S = 1e-7


@dataclass(frozen=True, eq=False, slots=True)
class TimedTrajectory:
    """Samples of one entity's pose, piecewise linear in time.

    Parameters
    ----------
    time_s : (N,) float
        Strictly increasing sample times, s (N >= 1).
    x_m, y_m : (N,) float
        Reference-point position (the bounding-box centre), ISO world, m.
    yaw_rad : (N,) float
        Heading, rad, counter-clockwise (unwrapped before interpolation).
    """

    time_s: np.ndarray
    x_m: np.ndarray
    y_m: np.ndarray
    yaw_rad: np.ndarray

    def __post_init__(self) -> None:
        arrays = [np.asarray(getattr(self, n), dtype=float).ravel()
                  for n in ("time_s", "x_m", "y_m", "yaw_rad")]
        n = arrays[0].size
        if n < 1 or any(a.size != n for a in arrays):
            raise BadInput(f"trajectory: time_s, x_m, y_m and yaw_rad need the same length "
                             f">= 1, got {[a.size for a in arrays]}")
        if not all(np.isfinite(a).all() for a in arrays):
            raise BadInput("trajectory: samples must be finite")
        if n > 1 and not (np.diff(arrays[0]) > 0).all():
            raise BadInput("trajectory: time_s must be strictly increasing")
        arrays[3] = np.unwrap(arrays[3])
        for name, a in zip(("time_s", "x_m", "y_m", "yaw_rad"), arrays):
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    def _segment(self, t: float) -> int:
        """Index of the sample that starts the segment holding t (clamped to the ends)."""
        k = int(np.searchsorted(self.time_s, t + TIME_TOLERANCE_S, side="right")) - 1
        return min(max(k, 0), max(self.time_s.size - 2, 0))

    def pose(self, t: float) -> tuple[float, float, float, float, float]:
        """(x, y, yaw, vx, vy) at time t, ISO world; before the first sample the entity waits
        at it, after the last it goes on at the last segment's velocity."""
        ts = self.time_s
        if ts.size == 1:
            return float(self.x_m[0]), float(self.y_m[0]), float(self.yaw_rad[0]), 0.0, 0.0
        k = self._segment(t)
        dt = ts[k + 1] - ts[k]
        vx = (self.x_m[k + 1] - self.x_m[k]) / dt
        vy = (self.y_m[k + 1] - self.y_m[k]) / dt
        wz = (self.yaw_rad[k + 1] - self.yaw_rad[k]) / dt
        u = max(t - ts[k], 0.0)
        if t < ts[0]:
            vx = vy = wz = 0.0
        return (float(self.x_m[k] + vx * u), float(self.y_m[k] + vy * u),
                float(self.yaw_rad[k] + wz * u), float(vx), float(vy))


@dataclass(frozen=True, kw_only=True, slots=True)
class EntityMotion:
    """One entity of a recorded scene.

    Parameters
    ----------
    name : str
        The entity's name in its file.
    actor_class : str
        Key of `scenarios.catalog.ACTOR_CLASSES`.
    length_m, width_m, height_m : float
        Bounding box, m (> 0).
    trajectory : TimedTrajectory
    """

    name: str
    actor_class: str
    length_m: float
    width_m: float
    height_m: float
    trajectory: TimedTrajectory

    def __post_init__(self) -> None:
        for n in ("length_m", "width_m", "height_m"):
            v = getattr(self, n)
            if not (isinstance(v, (int, float)) and np.isfinite(v) and v > 0):
                raise BadInput(f"entity {self.name!r}: {n}={v!r} must be a finite number > 0")


@dataclass(frozen=True, kw_only=True, slots=True)
class LaneGeometry:
    """One lane's centre line, ISO world: a straight piece or a circular arc.

    Parameters
    ----------
    x_m, y_m, yaw_rad : float
        Start point and heading of the centre line.
    length_m : float
        Length along the centre line, m (> 0).
    curvature_per_m : float
        Signed curvature, 1/m (0: straight; positive turns left).
    width_m : float
        Lane width, m (> 0).
    """

    x_m: float
    y_m: float
    yaw_rad: float
    length_m: float
    curvature_per_m: float
    width_m: float

    def highway_lane(self):
        """The lane as a highway-env `StraightLane` or `CircularLane` (its axes: y flipped)."""
        x0, y0, h = self.x_m, -self.y_m, -self.yaw_rad
        k = -self.curvature_per_m  # a left turn (ISO) is clockwise on highway-env's screen axes
        if abs(k) < 1e-12:
            end = [x0 + self.length_m * np.cos(h), y0 + self.length_m * np.sin(h)]
            return StraightLane([x0, y0], end, width=self.width_m)
        r = 1.0 / abs(k)
        # Centre to the side the lane turns to; highway-env's phase runs clockwise when
        # `clockwise` (its direction +1) on its own axes.
        side = np.sign(k)
        cx, cy = x0 - side * r * np.sin(h), y0 + side * r * np.cos(h)
        phase0 = np.arctan2(y0 - cy, x0 - cx)
        sweep = self.length_m / r
        clockwise = k > 0
        phase1 = phase0 + sweep if clockwise else phase0 - sweep
        return CircularLane([cx, cy], r, phase0, phase1, clockwise=clockwise,
                            width=self.width_m)


@dataclass(frozen=True, kw_only=True, slots=True)
class Motion:
    """A recorded scene: the ego, the actors (truth ids 0, 1, ... in this order), the road.

    Parameters
    ----------
    ego : EntityMotion
    actors : tuple of EntityMotion
    lanes : tuple of LaneGeometry
        The road's lanes (at least one: highway-env places every vehicle on a lane).
    rails_y_m : tuple of float
        ISO y of straight guard-rail lines along x (empty: none).
    """

    ego: EntityMotion
    actors: tuple[EntityMotion, ...]
    lanes: tuple[LaneGeometry, ...]
    rails_y_m: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        if not self.lanes:
            raise BadInput("motion: the road has no lane")

    def network(self) -> RoadNetwork:
        """The road as a highway-env network, one edge per lane."""
        net = RoadNetwork()
        for i, lane in enumerate(self.lanes):
            net.add_lane(f"a{i}", f"b{i}", lane.highway_lane())
        return net


class TrajectoryVehicle(Vehicle):
    """A highway-env vehicle that follows an `EntityMotion` (its pose at every step).

    Parameters
    ----------
    road : highway_env.road.road.Road
    motion : EntityMotion
    dt_s : float
        Integration step of the loop that steps it, s: its time is the step count times this,
        not a running sum, so it lands on the samples' times.
    """

    def __init__(self, road: Road, motion: EntityMotion, dt_s: float) -> None:
        self.LENGTH, self.WIDTH = motion.length_m, motion.width_m
        self.HEIGHT = motion.height_m
        self.ACTOR_CLASS = motion.actor_class
        self.motion, self.dt_s, self.n_steps = motion, float(dt_s), 0
        self._velocity = np.zeros(2)
        x, y, yaw, vx, vy = motion.trajectory.pose(0.0)
        super().__init__(road, np.array([x, -y]), -yaw, float(np.hypot(vx, vy)))
        self.check_collisions = False
        self.collidable = False
        self._update_pose()

    def _update_pose(self) -> None:
        x, y, yaw, vx, vy = self.motion.trajectory.pose(self.n_steps * self.dt_s)
        self.position = np.array([x, -y])
        self.heading = -yaw
        self._velocity = np.array([vx, -vy])
        # signed: negative when the entity moves against its heading (reversing)
        along = vx * np.cos(yaw) + vy * np.sin(yaw)
        self.speed = float(np.copysign(np.hypot(vx, vy), along if along != 0 else 1.0))

    @property
    def velocity(self) -> np.ndarray:
        return self._velocity

    def act(self, action=None) -> None:
        """Recorded: no decision to take."""

    def step(self, dt: float) -> None:
        self.n_steps += int(round(dt / self.dt_s))
        self._update_pose()

    def on_state_update(self) -> None:
        """The pose is recorded: skip highway-env's closest-lane search."""
