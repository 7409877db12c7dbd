"""Tracking: radar point clouds to tracks (TI-style group tracker), one concept per module.

    tracks = pipeline.tracking.track_frames([(t0, pc0), (t1, pc1), ...], TrackerConfig())

Where to add what:

| module | holds | add here |
|---|---|---|
| `config` | `TrackerConfig` | a tracker setting |
| `models` | `MOTION_MODELS` (CV, CA: F, Q), `RangeAzimuthDoppler` (h, H) | a motion model |
| `association` | gating + `GatedMaximumLikelihood` associator | an associator |
| `update` | `KalmanPredictor`, `GroupEkfUpdater` | a predictor or updater |
| `clustering` | `leader_clusters`, `LeaderClusterAllocator` | an allocator |
| `ego_motion` | RANSAC ego velocity, static labels (`RansacEgoMotion`) | an ego-motion source |
| `tracker` | `GroupTracker` (wires the parts, maintenance), `track_frames` | nothing per part |
| `state` | typed data between parts: `Points`, `Tracks`, `Association`, `NewTracks` | |

A part is passed to `GroupTracker(cfg, associator=..., allocator=..., predictor=...,
updater=..., ego_motion=...)`; the tracker itself is not edited.
"""
from .association import Associator, GatedMaximumLikelihood
from .clustering import Allocator, LeaderClusterAllocator, leader_clusters, same_group
from .config import TrackerConfig
from .ego_motion import (EGO_MODELS, EgoFrame, EgoMotionConfig, EgoMotionEstimate,
                         EgoVelocity, RansacEgoMotion, estimate_ego_motion,
                         ground_radial_velocity, static_mask)
from .models import MOTION_MODELS, MotionModel, RangeAzimuthDoppler, measurement_model
from .state import Association, NewTracks, Points, Tracks
from .tracker import TRACK_COLUMNS, TRACK_STATES, GroupTracker, track_frames
from .update import GroupEkfUpdater, KalmanPredictor, UpdateResult

__all__ = ["TrackerConfig", "GroupTracker", "track_frames", "TRACK_COLUMNS", "TRACK_STATES",
           "MOTION_MODELS", "MotionModel", "RangeAzimuthDoppler", "measurement_model",
           "Associator", "GatedMaximumLikelihood", "Allocator", "LeaderClusterAllocator",
           "leader_clusters", "same_group", "KalmanPredictor", "GroupEkfUpdater",
           "UpdateResult", "Points", "Tracks", "Association", "NewTracks", "EGO_MODELS",
           "EgoMotionConfig", "EgoMotionEstimate", "EgoVelocity", "EgoFrame",
           "RansacEgoMotion", "estimate_ego_motion", "ground_radial_velocity", "static_mask"]
