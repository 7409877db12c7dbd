"""Scoring of one scheme of one run: from its point clouds, the truth and the scatterers to
the labelled detections, the actor tables and one summary row whose every number is a
`metrics.METRICS` entry.

The harness runs the scene and the chains and calls `label_detections` then `score_scheme`
per scheme; everything a number means is decided here and in the modules it calls.

References
----------
.. [1] design.md section 7.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

from . import detection as det
from . import r79
from .association import (
    CLUTTER,
    GHOST,
    STATIC_CLASSES,
    TRUE,
    VELOCITY_AMBIGUOUS,
    AssociationConfig,
    actor_frames,
    associate,
    detection_errors,
)
from .joins import with_columns
from .registry import METRICS, case_criteria
from .velocity import FAILURE, RIGHT, velocity_check

__all__ = ["CaseInfo", "SchemeScore", "CaseVerdict", "CASE_VERDICTS", "label_detections",
           "score_scheme", "case_info", "add_track_metrics", "add_snr_gains", "frame_counts"]


class CaseInfo(NamedTuple):
    """What scoring needs of a case (read by attribute from ``scenarios.Case``).

    Attributes
    ----------
    target_ids : list of int or None
        Actors that must be detected (None: every road user).
    criteria : tuple
        Pass criteria (objects with metric, op, value, actor_id).
    case_class : str
        Key of `CASE_VERDICTS` (``scenarios.catalog.CASE_CLASSES``).
    ego_speed_mps : float
        The ego's scripted speed, m/s (NaN for random traffic).
    approach_speed_mps : float
        The first target's scripted speed, m/s (the R79 approaching vehicle; NaN if none).
    """

    target_ids: list | None = None
    criteria: tuple = ()
    case_class: str = "ordinary"
    ego_speed_mps: float = float("nan")
    approach_speed_mps: float = float("nan")


def case_info(case) -> CaseInfo:
    """`CaseInfo` of a ``scenarios.Case`` (or any object with its attributes; None: the
    defaults)."""
    if case is None:
        return CaseInfo()
    must = tuple(getattr(case, "must_detect", ()) or ())
    actors = tuple(getattr(case, "actors", ()) or ())
    ego = getattr(case, "ego", None)
    approach = float(actors[must[0]].speed_mps) if must and must[0] < len(actors) \
        else float("nan")
    return CaseInfo(target_ids=list(must) if must else None,
                    criteria=tuple(getattr(case, "criteria", ()) or ()),
                    case_class=str(getattr(case, "case_class", "ordinary")),
                    ego_speed_mps=float(getattr(ego, "speed_mps", float("nan")))
                    if ego is not None else float("nan"),
                    approach_speed_mps=approach)


def _r79_verdict(actors: pd.DataFrame, case: CaseInfo) -> dict:
    """`r79.r79_verdict` of the first target's first detection range and the case's speeds."""
    first = actors.set_index("actor_id")["first_detection_range_m"] \
        .get(case.target_ids[0], np.nan) if case.target_ids and len(actors) else np.nan
    return r79.r79_verdict(first, case.ego_speed_mps, case.approach_speed_mps)


class CaseVerdict(NamedTuple):
    """What a case class adds to the scoring of its cases.

    Attributes
    ----------
    verdict : callable or None
        ``verdict(actors, case) -> dict`` of extra summary columns (METRICS keys).
    mitigation_reference : bool
        The harness also processes the frames with interference mitigation off, for the
        floor recovered by the mitigation and the ghosts it adds (`metrics.interference`).
    """

    verdict: object = None
    mitigation_reference: bool = False


#: Case class -> its verdict (the same keys as ``scenarios.catalog.CASE_CLASSES``).
CASE_VERDICTS: dict[str, CaseVerdict] = {
    "ordinary": CaseVerdict(),
    "interference": CaseVerdict(mitigation_reference=True),
    "r79": CaseVerdict(verdict=_r79_verdict),
}


def label_detections(points: pd.DataFrame, truth: pd.DataFrame, scatterers: pd.DataFrame,
                     *, velocity_span_mps: float, failure_step_mps: float,
                     config: AssociationConfig) -> pd.DataFrame:
    """Label one scheme's detections and check their velocities.

    `association.associate` (2D footprint and velocity gates) and
    `association.detection_errors`, then the velocity check (`velocity.velocity_check`,
    range and radial velocity only):

    - every detection not explained as clutter is checked against the road users' scatterers
      with the scheme's failure step; a GHOST found off by whole steps is relabelled
      VELOCITY_AMBIGUOUS of that road user: an aliased echo (its angle corrupted by the wrong
      Doppler compensation), not a ghost. A VELOCITY_AMBIGUOUS detection of the 2D association
      is a failure too;
    - the guard-rail CLUTTER of the 2D association and every remaining GHOST are checked
      against the scatterers of modelled static infrastructure (guard rails) with the
      scheme's unambiguous span 2 Vmax, the step by which a static world aliases: right or
      off by whole spans. A GHOST found either way is relabelled CLUTTER (design.md 7: modelled
      infrastructure is clutter; its angle may be off, as an aliased TDMA echo's is).

    CLUTTER is not checked against the road users: the association already explained it, and
    at a road user's range it would match by chance (one step in 13.6 m/s for DDMA). Ground
    cells are matched in range and velocity by construction and are not counted.

    Returns
    -------
    DataFrame
        ``points`` with the association's columns plus ``velocity_check`` ("right",
        "failure", ""), ``velocity_actor_id``, ``velocity_step_k`` (steps of the check that
        matched), ``velocity_truth_mps``, ``velocity_resolution_failure`` (bool) and
        ``velocity_on_infrastructure`` (bool: the verdict refers to modelled static
        infrastructure, a guard rail, not to a road user).
    """
    lab = associate(points, truth, velocity_span_mps=velocity_span_mps, config=config,
                    scatterers=scatterers)
    lab = detection_errors(lab, truth, scatterers)
    label = lab["label"].to_numpy()
    chk = velocity_check(points, scatterers, truth, failure_step_mps, config,
                         candidates=label != CLUTTER)
    verdict, actor = chk.verdict.copy(), chk.actor_id.copy()
    k, v_true = chk.alias_k.copy(), chk.truth_radial_velocity_mps.copy()
    # the 2D association already decided these: TRUE is right, VELOCITY_AMBIGUOUS a failure
    tru = label == TRUE
    verdict[tru] = RIGHT
    actor[tru] = lab["actor_id"].to_numpy()[tru]
    k[tru] = 0
    v_true[tru] = lab["truth_radial_velocity_mps"].to_numpy()[tru]
    amb = label == VELOCITY_AMBIGUOUS
    verdict[amb] = FAILURE
    actor[amb] = lab["actor_id"].to_numpy()[amb]
    v_true[amb] = lab["truth_radial_velocity_mps"].to_numpy()[amb]
    user_alias = (chk.verdict == FAILURE) & (label == GHOST)
    # modelled static infrastructure (guard rails; not the ground cells, which are matched in
    # range and velocity by construction): its 2D-gated clutter and the ghosts left over
    rail = (label == CLUTTER) & (lab["actor_class"].to_numpy() != "ground")
    static = velocity_check(points, scatterers, truth, velocity_span_mps, config,
                            classes=STATIC_CLASSES,
                            candidates=rail | ((label == GHOST) & (verdict == "")))
    found = static.verdict != ""
    static_ghost = found & (label == GHOST)
    verdict[found] = static.verdict[found]
    actor[found] = static.actor_id[found]
    k[found] = static.alias_k[found]
    v_true[found] = static.truth_radial_velocity_mps[found]
    cls = truth.drop_duplicates("actor_id").set_index("actor_id")["actor_class"]
    for sel, new in ((user_alias, VELOCITY_AMBIGUOUS), (static_ghost, CLUTTER)):
        if sel.any():
            lab.loc[sel, "label"] = new
            lab.loc[sel, "actor_id"] = actor[sel]
            lab.loc[sel, "actor_class"] = cls.reindex(actor[sel]).to_numpy()
            lab.loc[sel, "truth_radial_velocity_mps"] = v_true[sel]
    # velocity_on_infrastructure: which verdicts were checked against infrastructure (guard
    # rails), not road users: the road-user velocity metrics leave them out, the
    # infrastructure columns count them
    return with_columns(lab, {
        "velocity_check": verdict, "velocity_actor_id": actor, "velocity_step_k": k,
        "velocity_truth_mps": v_true, "velocity_resolution_failure": verdict == FAILURE,
        "velocity_on_infrastructure": found})


class SchemeScore(NamedTuple):
    """Scores of one scheme of one run."""

    row: dict
    """Summary row (every numeric value a `METRICS` key)."""
    actor_frames: pd.DataFrame
    """`association.actor_frames`."""
    actors: pd.DataFrame
    """`detection.actor_detection`."""


def score_scheme(labelled: pd.DataFrame, truth: pd.DataFrame, scatterers: pd.DataFrame,
                 n_frames: int, config: AssociationConfig, case: CaseInfo) -> SchemeScore:
    """Detection scores, case criteria and (R79 cases) the category C verdict of one scheme.

    Parameters
    ----------
    labelled : DataFrame
        `label_detections` output.
    truth, scatterers : DataFrame
        The run's truth and scatterer table.
    n_frames : int
        Frames processed.
    config : AssociationConfig
    case : CaseInfo

    Returns
    -------
    SchemeScore
        ``row`` holds `detection.summarize_scheme`, the case criteria
        (`registry.case_criteria`), ``case_class`` and its class's verdict (R79 cases:
        ``s_critical_m``, ``r79_required_range_m``, ``r79_pass``).
    """
    af = actor_frames(labelled, truth, scatterers=scatterers, config=config)
    actors = det.actor_detection(af)
    row = det.summarize_scheme(labelled, af, n_frames, config, target_ids=case.target_ids,
                               actors=actors)
    row.update(case_criteria(case.criteria, labelled, actors, row))
    row["case_class"] = case.case_class
    verdict = CASE_VERDICTS[case.case_class].verdict
    if verdict is not None:
        row.update(verdict(actors, case))
    for name, metric in METRICS.items():  # metrics a plugin added (`register_metric`)
        if metric.row_value is not None:
            # on copies: a metric that wrote into its tables would change the detections
            # this cell reports (`harness.testing.check_metric` names such a metric)
            row[name] = float(metric.row_value(labelled.copy(), af.copy()))
    return SchemeScore(row, af, actors)


def add_track_metrics(row: dict, tm: dict | None) -> None:
    """Add a scheme's numeric track metrics (`metrics.tracks.track_metrics`) to its summary
    row in place; a name the row already has (n_frames) gets the prefix ``track_``."""
    for k, v in dict(tm or {}).items():
        if isinstance(v, (int, float, np.integer, np.floating)):
            row[k if k not in row else f"track_{k}"] = v


def add_snr_gains(summary: pd.DataFrame, actors: pd.DataFrame, gain_schemes, base: str) -> None:
    """SNR-gain columns (`detection.snr_gain_stats`) of every scheme in `gain_schemes` over
    ``base`` on the same actor and frame, in place; rows of other schemes (the baseline, chain
    variants sharing an ADC frame) get NaN and count 0."""
    gains = {s: det.snr_gain_stats(_gain_pairs(actors, s, base)) for s in gain_schemes}
    for k in det.snr_gain_stats(pd.DataFrame({"snr_gain_db": pd.Series(dtype=float)})):
        count = k.endswith("_n")
        summary[k] = np.array([gains[s][k] if s in gains else (0 if count else np.nan)
                               for s in summary["scheme"]],
                              dtype=np.int64 if count else float)
    summary["case_pass"] = summary["case_pass"].astype(float)


def _gain_pairs(af: pd.DataFrame, a: str, b: str) -> pd.DataFrame:
    """The two columns of `detection.snr_gain_pairs` that `snr_gain_stats` reads
    (snr_gain_db, reference_snr_db), without the actor columns it does not."""
    ra, rb = det.snr_gain_rows(af, a, b)
    snr = af["max_snr_db"].to_numpy()
    return pd.DataFrame({"reference_snr_db": snr[rb], "snr_gain_db": snr[ra] - snr[rb]})


def frame_counts(labelled: pd.DataFrame, frames: np.ndarray) -> pd.DataFrame:
    """Per frame: detections and label counts (frames without detections give zeros)."""
    frames = np.asarray(frames, dtype=np.int64)
    # Row of `frames` of every detection (-1: a frame not listed, not counted).
    at = pd.Index(frames).get_indexer(labelled["frame"].to_numpy()) if len(labelled) \
        else np.zeros(0, dtype=np.intp)
    label = labelled["label"].to_numpy() if len(labelled) else np.zeros(0, dtype=object)
    out = pd.DataFrame({"frame": frames})
    names = {TRUE: "n_true", VELOCITY_AMBIGUOUS: "n_velocity_ambiguous", GHOST: "n_ghost",
             CLUTTER: "n_clutter"}
    for lab_name, col in names.items():
        out[col] = np.bincount(at[(label == lab_name) & (at >= 0)],
                               minlength=len(frames)).astype(np.int64)
    out.insert(1, "n_detections", out[list(names.values())].sum(axis=1))
    return out
