"""Recorded motion: timed trajectories, lane geometry for highway-env, their checks."""
from __future__ import annotations

import numpy as np
import pytest

from core.errors import BadInput
from scenarios.motion import EntityMotion, LaneGeometry, Motion, TimedTrajectory


def test_pose_is_linear_between_samples_and_velocity_is_the_segment_slope():
    tr = TimedTrajectory([0.0, 1.0, 1.001], [0.0, 10.0, 10.02], [0.0, 0.0, 0.0], [0, 0, 0])
    x, _, _, vx, _ = tr.pose(0.25)
    assert x == pytest.approx(2.5) and vx == pytest.approx(10.0)
    x, _, _, vx, _ = tr.pose(1.0 - 1e-9)   # within the time tolerance: the next segment
    assert x == pytest.approx(10.0) and vx == pytest.approx(20.0)
    x, _, _, vx, _ = tr.pose(2.001)        # after the end: straight on
    assert x == pytest.approx(10.02 + 20.0) and vx == pytest.approx(20.0)


def test_yaw_is_unwrapped_before_interpolation():
    tr = TimedTrajectory([0.0, 1.0], [0, 0], [0, 0], [np.pi - 0.1, -np.pi + 0.1])
    assert tr.pose(0.5)[2] == pytest.approx(np.pi)


@pytest.mark.parametrize("args,match", [
    (([0.0, 1.0], [0.0], [0.0, 0.0], [0.0, 0.0]), "the same length"),
    (([], [], [], []), "the same length >= 1"),
    (([0.0, 0.0], [0, 1], [0, 0], [0, 0]), "strictly increasing"),
    (([0.0, np.nan], [0, 1], [0, 0], [0, 0]), "finite"),
])
def test_bad_trajectory_is_refused(args, match):
    with pytest.raises(BadInput, match=match):
        TimedTrajectory(*args)


def test_bad_entity_box_and_empty_road_are_refused():
    tr = TimedTrajectory([0.0], [0.0], [0.0], [0.0])
    with pytest.raises(BadInput, match="width_m=0.0 must be a finite number > 0"):
        EntityMotion(name="a", actor_class="car", length_m=5.0, width_m=0.0, height_m=1.5,
                     trajectory=tr)
    ent = EntityMotion(name="a", actor_class="car", length_m=5.0, width_m=2.0, height_m=1.5,
                       trajectory=tr)
    with pytest.raises(BadInput, match="the road has no lane"):
        Motion(ego=ent, actors=(), lanes=())


@pytest.mark.parametrize("k", [0.0, 0.01, -0.02])
def test_lane_geometry_as_highway_env_lane_keeps_its_centre_line(k):
    g = LaneGeometry(x_m=3.0, y_m=-2.0, yaw_rad=0.4, length_m=50.0, curvature_per_m=k,
                     width_m=3.5)
    lane = g.highway_lane()
    for s in (0.0, 20.0, 50.0):
        # ISO: integrate the constant-curvature centre line; highway-env's y is flipped
        h = 0.4 + k * s
        x = 3.0 + (s * np.cos(0.4) if k == 0 else (np.sin(h) - np.sin(0.4)) / k)
        y = -2.0 + (s * np.sin(0.4) if k == 0 else -(np.cos(h) - np.cos(0.4)) / k)
        assert lane.position(s, 0.0) == pytest.approx([x, -y], abs=1e-9)
        assert lane.heading_at(s) == pytest.approx(-h)
