"""Injected tracker parts: a user's part replaces the default without editing the tracker, and
the default parts leave their inputs untouched."""
from __future__ import annotations

import copy
import dataclasses

import numpy as np
import pytest

from pipeline.tracking import (MOTION_MODELS, Association, GatedMaximumLikelihood,
                               GroupTracker, KalmanPredictor, LeaderClusterAllocator, Points,
                               Tracks, TrackerConfig)

from .test_tracker import _cfg, synth_points

CAR = (30.0, 5.0, -4.0, 0.0, 4.5, 1.8)


class NoAssociation:
    """An associator that never associates: every frame's points are unassociated."""

    def __init__(self):
        self.calls = 0

    def associate(self, tracks: Tracks, points: Points, static: np.ndarray) -> Association:
        self.calls += 1
        n = points.size
        return Association(np.full(n, -1), np.zeros((n, 3)),
                           np.zeros((tracks.size, 3, tracks.x.shape[1])))


def test_swapped_associator_is_used(rng):
    cfg = _cfg(merge_tracks=False)
    part = NoAssociation()
    tracker = GroupTracker(cfg, associator=part)
    for i in range(4):
        tab = tracker.step(synth_points(rng, [CAR]), 0.05 * i, 0.0)
    assert part.calls == 4
    # without association no track is ever hit twice: all stay DETECT, one new per frame
    assert set(tab.state) == {"DETECT"} and tab.age_frames.min() == 1


def test_swapped_motion_model_through_the_predictor(rng):
    """A predictor with a different process-noise intensity changes the covariance only."""
    cfg = _cfg()
    loose = GroupTracker(cfg, predictor=KalmanPredictor(MOTION_MODELS["cv"], 30.0))
    tight = GroupTracker(cfg)
    for i in range(6):
        pc = synth_points(rng, [CAR])
        a, b = loose.step(pc, 0.05 * i, 0.0), tight.step(pc, 0.05 * i, 0.0)
    assert (a.var_vx_m2ps2 > b.var_vx_m2ps2).all()


@pytest.mark.parametrize("part", ["associator", "allocator"])
def test_default_parts_do_not_edit_their_inputs(rng, part):
    cfg = TrackerConfig()
    tracker = GroupTracker(cfg)
    for i in range(3):
        tracker.step(synth_points(rng, [CAR]), 0.05 * i, 0.0)
    tracks = tracker.tracks
    pts = Points.from_frame(synth_points(rng, [CAR, (50.0, -10.0, 5.0, 0.0, 4.5, 1.8)]))
    static = np.zeros(pts.size, bool)
    before = copy.deepcopy((tracks, pts, static))
    if part == "associator":
        GatedMaximumLikelihood(cfg, tracker.sensor).associate(tracks, pts, static)
    else:
        new = LeaderClusterAllocator(cfg, tracker.sensor).allocate(pts, ~static, None, tracks,
                                                                   10)
        assert new.size >= 1 and new.members.size == new.member_track.size
    for x, y in zip(_arrays(tracks, pts, static), _arrays(*before)):
        np.testing.assert_array_equal(x, y)


def _arrays(tracks: Tracks, pts: Points, static: np.ndarray) -> list[np.ndarray]:
    return [*(getattr(tracks, f.name) for f in dataclasses.fields(tracks)), *pts, static]
