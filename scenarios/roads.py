"""Road layouts (scripted cases) and random-traffic environments, as registries.

A case names its road with ``road = "..."`` (a key of `ROAD_LAYOUTS`) or asks for random
traffic with ``traffic = "..."`` (a key of `TRAFFIC_ENVS`). A new road layout is one builder
function here and one `ROAD_LAYOUTS` entry; `scenarios.catalog` (which paths an actor may
follow) and `scenarios.traffic` (which network to drive on) only look the name up.

Paths of the shipped layouts; `s_m` runs along a path with s = 0 at the path's point nearest
the layout origin (the intersection centre; x = 0 on straight roads):

* ``highway``: ``lane_0`` .. ``lane_{lanes-1}``, 4 m apart, all driving +x; ``lane_0`` is the
  LEFTMOST lane (highway-env's order). Guard rails 1.5 m beyond both edges.
* ``two_way``: ``lane_0`` .. ``lane_{lanes-1}`` driving +x (``lane_0`` leftmost of them) and
  ``oncoming`` to the left of ``lane_0``, driving -x (s grows along its direction).
* ``urban``: a four-way intersection centred on the origin: ``main`` (+x, right-hand lane),
  ``oncoming`` (-x), ``from_left`` (crossing traffic coming from the ego's left),
  ``from_right``, and ``turn_left`` (``main`` then a 8 m radius left turn into the cross road).

Coordinates here are highway-env's (y to the driver's RIGHT); `scenarios.truth` converts.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from highway_env.road.lane import CircularLane, StraightLane
from highway_env.road.road import RoadNetwork

__all__ = ["Path", "Layout", "RoadLayout", "ROAD_LAYOUTS", "TrafficEnv", "TRAFFIC_ENVS",
           "LANE_WIDTH_M", "RAIL_SHOULDER_M", "MemoStraightLane", "memoise_lanes"]

LANE_WIDTH_M = StraightLane.DEFAULT_WIDTH  # 4 m
#: Guard rails stand this far beyond the outer lane edge, m.
RAIL_SHOULDER_M = 1.5
#: Half-length of the straight lanes, m (far beyond any radar's reach).
_FAR_M = 2000.0


class MemoStraightLane(StraightLane):
    """A highway-env `StraightLane` that remembers `local_coordinates` (and `on_lane`) of
    recent positions.

    highway-env's neighbour search projects every vehicle onto a lane once per (vehicle, lane)
    query: about 50 000 projections per 80-frame dense-highway run, most of them of a position
    already projected in the same decision step. The projection is a pure function of the
    position, so a memo keyed on the position's exact bytes returns the very floats the parent
    computes (traffic bit-identical) for a dictionary look-up. The memo is dropped when it
    reaches `MEMO_SIZE` entries (positions change every simulation step).
    """

    MEMO_SIZE = 4096

    def local_coordinates(self, position) -> tuple[float, float]:
        memo = self.__dict__.setdefault("_memo", {})
        key = np.asarray(position, dtype=np.float64).tobytes()
        hit = memo.get(key)
        if hit is None:
            if len(memo) >= self.MEMO_SIZE:
                memo.clear()
            hit = memo[key] = super().local_coordinates(position)
        return hit

    def on_lane(self, position, longitudinal=None, lateral=None, margin: float = 0):
        """The parent's test, remembered per (position bytes, margin) when the coordinates are
        not given (the neighbour search asks it ~45 000 times per dense-highway run)."""
        if longitudinal is not None and lateral is not None:
            return super().on_lane(position, longitudinal, lateral, margin)
        memo = self.__dict__.setdefault("_on_memo", {})
        key = (np.asarray(position, dtype=np.float64).tobytes(), margin)
        hit = memo.get(key)
        if hit is None:
            if len(memo) >= self.MEMO_SIZE:
                memo.clear()
            hit = memo[key] = super().on_lane(position, margin=margin)
        return hit


def memoise_lanes(network: RoadNetwork) -> None:
    """Turn every plain `StraightLane` of `network` (e.g. one a highway-env environment built)
    into a `MemoStraightLane` in place: same object, same geometry, so the vehicles that hold
    it and the network's graph keep working unchanged."""
    for ends in network.graph.values():
        for lanes in ends.values():
            for lane in lanes:
                if type(lane) is StraightLane:
                    lane.__class__ = MemoStraightLane


class Path:
    """A chain of highway-env lanes followed by a scripted actor.

    s = 0 sits at the path's point nearest the layout origin; positions beyond either end
    extrapolate along the end lanes.
    """

    def __init__(self, lanes: list) -> None:
        self.lanes = list(lanes)
        self.lengths = np.array([ln.length for ln in self.lanes], dtype=float)
        self.starts = np.concatenate([[0.0], np.cumsum(self.lengths)[:-1]])
        # s = 0 at the point nearest the origin: project the origin on every lane.
        best = (np.inf, 0.0)
        for start, lane in zip(self.starts, self.lanes):
            s_loc = float(np.clip(lane.local_coordinates(np.zeros(2))[0], 0.0, lane.length))
            d = float(np.hypot(*lane.position(s_loc, 0.0)))
            best = min(best, (d, start + s_loc))
        self.s0 = best[1]

    def _locate(self, s_raw: float):
        k = int(np.clip(np.searchsorted(self.starts, s_raw, side="right") - 1, 0,
                        len(self.lanes) - 1))
        return self.lanes[k], s_raw - self.starts[k]

    def _raw_position(self, s_raw: float, lat_hw: float) -> np.ndarray:
        lane, s_loc = self._locate(s_raw)
        return np.asarray(lane.position(s_loc, lat_hw), dtype=float)

    def position(self, s_m: float, lat_hw: float = 0.0) -> np.ndarray:
        """(2,) highway-env position at path coordinate s and lateral lat (highway-env, m)."""
        return self._raw_position(s_m + self.s0, lat_hw)

    def heading(self, s_m: float) -> float:
        """highway-env heading of the path at s, rad."""
        lane, s_loc = self._locate(s_m + self.s0)
        return float(lane.heading_at(s_loc))

    def sample(self, s_lo: float, s_hi: float, lat_hw: float = 0.0, step_m: float = 0.1):
        """Points of the path between s_lo and s_hi: (s (N,), xy (N, 2))."""
        s = np.arange(s_lo, s_hi, step_m)
        return s, np.array([self.position(v, lat_hw) for v in s]).reshape(-1, 2)


class Layout(NamedTuple):
    """A built road: the highway-env network, the named paths, the guard-rail lines.

    Attributes
    ----------
    network : highway_env.road.road.RoadNetwork
    paths : dict of str to Path
        In the order a user reads them (forward lanes first).
    rails_y_hw : list of float
        highway-env y of each guard-rail line, m (empty: no rails on this layout).
    """

    network: RoadNetwork
    paths: dict[str, Path]
    rails_y_hw: list[float]


def _straight(lanes: int, oncoming: bool) -> Layout:
    """Forward lanes at y = 0, 4, 8 ... m (highway-env y), plus one oncoming lane at y = -4 m."""
    net = RoadNetwork()
    paths: dict[str, Path] = {}
    w = LANE_WIDTH_M
    for i in range(lanes):
        lane = StraightLane([-_FAR_M, i * w], [_FAR_M, i * w], speed_limit=40.0)
        net.add_lane("w", "e", lane)
        paths[f"lane_{i}"] = Path([lane])
    left_edge = -0.5 * w
    if oncoming:
        lane = StraightLane([_FAR_M, -w], [-_FAR_M, -w], speed_limit=40.0)
        net.add_lane("e", "w", lane)
        paths["oncoming"] = Path([lane])
        left_edge -= w
    rails = [left_edge - RAIL_SHOULDER_M, (lanes - 0.5) * w + RAIL_SHOULDER_M]
    return Layout(net, paths, rails)


def _highway(lanes: int) -> Layout:
    return _straight(lanes, oncoming=False)


def _two_way(lanes: int) -> Layout:
    return _straight(lanes, oncoming=True)


def _urban(lanes: int) -> Layout:
    """Four-way intersection of two one-lane-per-direction roads (`lanes` is not used)."""
    net = RoadNetwork()
    h = 0.5 * LANE_WIDTH_M
    r = 8.0
    main = StraightLane([-_FAR_M, h], [_FAR_M, h], speed_limit=20.0)
    onc = StraightLane([_FAR_M, -h], [-_FAR_M, -h], speed_limit=20.0)
    f_left = StraightLane([-h, -_FAR_M], [-h, _FAR_M], speed_limit=20.0)
    f_right = StraightLane([h, _FAR_M], [h, -_FAR_M], speed_limit=20.0)
    # Left turn: main until x = h - r, then a radius-r arc into the cross road's lane that
    # leaves to the ego's left (highway-env -y), at x = +h.
    lead = StraightLane([-_FAR_M, h], [h - r, h], speed_limit=20.0)
    arc = CircularLane([h - r, h - r], r, np.pi / 2, 0.0, clockwise=False, speed_limit=10.0)
    out = StraightLane([h, h - r], [h, -_FAR_M], speed_limit=20.0)
    for a, b, lane in (("w", "e", main), ("e", "w", onc), ("n", "s", f_left),
                       ("s", "n", f_right), ("w", "c", lead), ("c", "t", arc),
                       ("t", "n", out)):
        net.add_lane(a, b, lane)
    paths = {"main": Path([main]), "oncoming": Path([onc]), "from_left": Path([f_left]),
             "from_right": Path([f_right]), "turn_left": Path([lead, arc, out])}
    return Layout(net, paths, [])


@dataclass(frozen=True, kw_only=True, slots=True)
class RoadLayout:
    """One road layout for scripted cases.

    Parameters
    ----------
    name : str
        Registry key (what a case file writes as ``road``).
    description : str
    build : callable
        ``build(lanes) -> Layout`` for ``lanes`` forward lanes (1..6).
    """

    name: str
    description: str
    build: Callable[[int], Layout]

    def path_names(self, lanes: int) -> tuple[str, ...]:
        """Paths an actor may follow on this layout with `lanes` forward lanes."""
        return tuple(self.build(lanes).paths)


#: Road layouts of scripted cases, keyed by the name a case file uses.
ROAD_LAYOUTS: dict[str, RoadLayout] = {r.name: r for r in (
    RoadLayout(name="highway", build=_highway,
               description="straight multi-lane motorway, all lanes +x, guard rails at both "
                           "edges"),
    RoadLayout(name="two_way", build=_two_way,
               description="straight rural road: forward lanes plus one oncoming lane on the "
                           "left"),
    RoadLayout(name="urban", build=_urban,
               description="four-way intersection: main, oncoming, from_left, from_right, "
                           "turn_left"),
)}


def _highway_env() -> type:
    from highway_env.envs import HighwayEnv
    return HighwayEnv


def _merge_env() -> type:
    from highway_env.envs import MergeEnv
    return MergeEnv


def _roundabout_env() -> type:
    from highway_env.envs import RoundaboutEnv
    return RoundaboutEnv


def _intersection_env() -> type:
    from highway_env.envs import IntersectionEnv
    return IntersectionEnv


@dataclass(frozen=True, kw_only=True, slots=True)
class TrafficEnv:
    """One highway-env random-traffic environment (the ego drives itself, IDM/MOBIL).

    Parameters
    ----------
    name : str
        Registry key (what a case file writes as ``traffic``).
    description : str
    env_class : callable
        Returns the highway-env environment class (imported on first use: highway_env.envs
        pulls in gymnasium and pygame).
    road : str or None
        Key of `ROAD_LAYOUTS` whose geometry the environment shares: the case's ``lanes``,
        ``vehicles_count`` and ``vehicles_density`` configure it and its guard rails are that
        layout's. None: the environment keeps its own road and has no guard rails.
    """

    name: str
    description: str
    env_class: Callable[[], type]
    road: str | None = None

    def env_config(self, lanes: int, vehicles_count: int, vehicles_density: float) -> dict:
        """Environment settings a case controls (only for environments with a `road`)."""
        if self.road is None:
            return {}
        return {"lanes_count": lanes, "vehicles_count": vehicles_count,
                "vehicles_density": vehicles_density}

    def rails_y_hw(self, lanes: int) -> list[float]:
        """Guard-rail lines (highway-env y, m) of the shared road layout, if any."""
        return [] if self.road is None else ROAD_LAYOUTS[self.road].build(lanes).rails_y_hw


#: Random-traffic environments, keyed by the name a case file uses.
TRAFFIC_ENVS: dict[str, TrafficEnv] = {t.name: t for t in (
    TrafficEnv(name="highway", env_class=_highway_env, road="highway",
               description="highway-env highway-v0: multi-lane motorway"),
    TrafficEnv(name="merge", env_class=_merge_env,
               description="highway-env merge-v0: on-ramp merge"),
    TrafficEnv(name="roundabout", env_class=_roundabout_env,
               description="highway-env roundabout-v0"),
    TrafficEnv(name="intersection", env_class=_intersection_env,
               description="highway-env intersection-v0: unsignalised crossing"),
)}
