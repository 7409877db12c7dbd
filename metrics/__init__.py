"""Scores over pandas frames: detection association, detection metrics and track metrics.

    span = 2 * cfg.max_unambiguous_velocity_mps
    lab = metrics.associate(point_cloud, truth, velocity_span_mps=span)
    row = metrics.summarize_scheme(lab, metrics.actor_frames(lab, truth), n_frames)

`metrics.association` labels detections TRUE / VELOCITY_AMBIGUOUS / CLUTTER / GHOST (DESIGN 7),
`metrics.detection` turns labelled detections into per-run scores, and `metrics.tracks` (the
tracker's metrics: confirmation, continuity, GOSPA) scores tracks. The package never imports
the simulator or the pipeline: it only reads tables.
"""
from . import association, detection, tracks
from .association import (CLUTTER, GHOST, LABELS, TRUE, VELOCITY_AMBIGUOUS, AssociationConfig,
                          actor_frames, associate, detection_errors, scatterer_table)
from .detection import (actor_detection, error_stats, ghost_stats, max_range_pd90, pd_vs_range,
                        snr_gain_pairs, snr_gain_stats, summarize_scheme,
                        target_first_detection_range_m, velocity_unambiguity_rate)

__all__ = [
    "association", "detection", "AssociationConfig", "LABELS", "TRUE", "VELOCITY_AMBIGUOUS",
    "GHOST", "CLUTTER", "associate", "detection_errors", "actor_frames", "scatterer_table",
    "error_stats", "velocity_unambiguity_rate", "ghost_stats", "actor_detection",
    "pd_vs_range", "max_range_pd90", "snr_gain_pairs", "snr_gain_stats", "summarize_scheme",
    "target_first_detection_range_m",
]

from .tracks import *  # noqa: E402,F401,F403 - re-export the track metrics' public names

__all__ += ["tracks", *tracks.__all__]
