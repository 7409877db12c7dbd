"""Scores over pandas frames: detection association, detection metrics and track metrics.

    lab = metrics.label_detections(points, truth, scatterers, velocity_span_mps=span,
                                   failure_step_mps=step, config=assoc)
    score = metrics.score_scheme(lab, truth, scatterers, n_frames, assoc,
                                 metrics.case_info(case))
    metrics.METRICS["ghost_rate"].unit, metrics.METRICS["ghost_rate"].description

`metrics.association` labels detections TRUE / VELOCITY_AMBIGUOUS / CLUTTER / GHOST (design.md 7),
`metrics.velocity` checks every velocity against the road users at the detection's range,
`metrics.detection` turns labelled detections into per-run scores, `metrics.interference` and
`metrics.r79` add the interference and UN R79 verdicts, `metrics.scoring` puts them together
per scheme, and `metrics.tracks` (the tracker's metrics: confirmation, continuity, GOSPA)
scores tracks. `metrics.METRICS` (`metrics.registry`) defines every reported number once. The
package never imports
the simulator or the pipeline: it only reads tables.
"""
from . import association, detection, interference, r79, registry, scoring, tracks, velocity
from .association import (
                          CLUTTER,
                          GHOST,
                          LABELS,
                          TRUE,
                          VELOCITY_AMBIGUOUS,
                          AssociationConfig,
                          actor_frames,
                          associate,
                          detection_errors,
                          scatterer_table,
)
from .detection import (
                          actor_detection,
                          error_stats,
                          ghost_stats,
                          max_range_pd90,
                          pd_vs_range,
                          snr_gain_pairs,
                          snr_gain_stats,
                          summarize_scheme,
                          target_first_detection_range_m,
                          velocity_stats,
)
from .registry import METRICS, Metric, case_criteria, check_criterion, get_metric, register_metric
from .scoring import CASE_VERDICTS, CaseInfo, case_info, label_detections, score_scheme
from .velocity import velocity_check

__all__ = [
    "association", "detection", "interference", "r79", "registry", "scoring", "velocity",
    "AssociationConfig", "LABELS", "TRUE", "VELOCITY_AMBIGUOUS",
    "GHOST", "CLUTTER", "associate", "detection_errors", "actor_frames", "scatterer_table",
    "error_stats", "velocity_stats", "ghost_stats", "actor_detection",
    "pd_vs_range", "max_range_pd90", "snr_gain_pairs", "snr_gain_stats", "summarize_scheme",
    "target_first_detection_range_m", "METRICS", "Metric", "get_metric", "register_metric",
    "check_criterion",
    "case_criteria", "CASE_VERDICTS", "CaseInfo", "case_info", "label_detections",
    "score_scheme", "velocity_check",
]

from .tracks import *  # noqa: E402,F401,F403 - re-export the track metrics' public names

__all__ += ["tracks", *tracks.__all__]
