"""Tracking: radar point clouds to tracks (TI-style group tracker), one concept per module.

    tracks = pipeline.tracking.track_frames([(t0, pc0), (t1, pc1), ...], TrackerConfig())

Where to add what:

| module | holds | add here |
|---|---|---|
| `config` | `TrackerConfig`: the parts' sub-configs, dotted keys | a sub-config |
| `models` | `MOTION_MODELS` (CV, CA: F, Q), `RangeAzimuthDoppler` (h, H) | a motion model |
| `hypothesis` | `GroupGateHypothesiser`: predictions, innovations, gates | a hypothesiser |
| `association` | `GatedMaximumLikelihood`, `GatedNearestNeighbour`: choose only | an associator |
| `update` | `KalmanPredictor`, `GroupEkfUpdater` | a predictor or updater |
| `clustering` | `leader_clusters`, `same_group`, `LeaderClusterAllocator` | an allocator |
| `parts` | registries of the parts by name; `PartNames` | its entry |
| `ego_motion` | RANSAC ego velocity, static labels (`RansacEgoMotion`) | an ego-motion source |
| `tracker` | `GroupTracker` (wires the parts), `track_frames` | nothing per part |
| `state` | data between parts: `Points`, `Tracks`, ...; maintenance (`maintain`) | |

Each module also declares the sub-config its part reads (`MotionConfig`, `MountConfig`,
`MeasurementNoise` in `models`; `GateConfig`; `AssociationRules`; `GroupUpdateConfig`;
`AllocationConfig`, `MergeConfig` in `clustering`; `PartNames`; `EgoMotionConfig`;
`MaintenanceConfig` in `state`).

A part is passed to `GroupTracker(cfg, hypothesiser=..., associator=..., allocator=...,
predictor=..., updater=..., ego_motion=...)` or registered in `parts` and named in
`TrackerConfig.parts` (so a sweep can vary it: ``"tracker.parts.associator"``); the tracker
itself is not edited. Each part declares the settings it reads as its own frozen dataclass,
next to it, and `TrackerConfig` is made of them (``cfg.gating`` is the hypothesiser's
`GateConfig`); a part built by its registry entry gets its own sub-config.
"""
from .associators import AssociationRules, Associator, GatedMaximumLikelihood, GatedNearestNeighbour
from .clustering import (
                          AllocationConfig,
                          Allocator,
                          LeaderClusterAllocator,
                          MergeConfig,
                          leader_clusters,
                          same_group,
)
from .config import TrackerConfig, tracker_paths
from .ego_motion import (
                          EGO_MODELS,
                          EgoFrame,
                          EgoMotionConfig,
                          EgoMotionEstimate,
                          EgoVelocity,
                          RansacEgoMotion,
                          estimate_ego_motion,
                          ground_radial_velocity,
                          static_mask,
)
from .hypothesis import GateConfig, GroupGateHypothesiser, Hypotheses, Hypothesiser
from .models import (
                          MOTION_MODELS,
                          MeasurementNoise,
                          MotionConfig,
                          MotionModel,
                          MountConfig,
                          RangeAzimuthDoppler,
                          measurement_model,
)
from .parts import (
                          ALLOCATORS,
                          ASSOCIATORS,
                          HYPOTHESISERS,
                          PART_REGISTRIES,
                          PREDICTORS,
                          UPDATERS,
                          PartNames,
                          TrackerPart,
)
from .track_state import Association, MaintenanceConfig, NewTracks, Points, Tracks
from .tracker import TRACK_COLUMNS, TRACK_STATES, GroupTracker, track_frames
from .update import GroupEkfUpdater, GroupUpdateConfig, KalmanPredictor, UpdateResult

__all__ = ["TrackerConfig", "GroupTracker", "track_frames", "TRACK_COLUMNS", "TRACK_STATES",
           "MOTION_MODELS", "MotionModel", "RangeAzimuthDoppler", "measurement_model",
           "Associator", "GatedMaximumLikelihood", "Allocator", "LeaderClusterAllocator",
           "leader_clusters", "same_group", "KalmanPredictor", "GroupEkfUpdater",
           "UpdateResult", "Points", "Tracks", "Association", "NewTracks", "EGO_MODELS",
           "EgoMotionConfig", "EgoMotionEstimate", "EgoVelocity", "EgoFrame",
           "RansacEgoMotion", "estimate_ego_motion", "ground_radial_velocity", "static_mask",
           "AssociationRules", "GatedNearestNeighbour", "AllocationConfig", "MergeConfig",
           "GateConfig", "GroupGateHypothesiser", "Hypotheses", "Hypothesiser",
           "GroupUpdateConfig", "TrackerPart", "HYPOTHESISERS", "ASSOCIATORS", "UPDATERS",
           "PREDICTORS", "ALLOCATORS", "PART_REGISTRIES", "PartNames", "MotionConfig",
           "MountConfig", "MeasurementNoise", "MaintenanceConfig", "tracker_paths"]
