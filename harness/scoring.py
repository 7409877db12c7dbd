"""Per-scheme scoring of one cell: labelled detections, per-actor frames, the summary row.

`score_scheme` is everything `metrics` says about one scheme's point clouds of a cell; the cell
(`harness.cell.run_cell`) only adds what it alone knows (tracks, saturation, noise floors) and
the SNR gains across schemes (`add_snr_gains`). Kept apart from the cell's frame loop so the
scoring can move into `metrics` without touching the loop.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

from metrics import detection as mdet
from metrics.association import (LABELS, actor_frames, associate, detection_errors)

__all__ = ["SchemeScore", "score_scheme", "concat_clouds", "add_track_metrics", "add_snr_gains",
           "frame_counts", "floor_summary"]

#: Columns of an empty point cloud (a scheme that detected nothing in any frame).
_CLOUD_COLUMNS = ("frame", "time_s", "range_m", "azimuth_deg", "elevation_deg",
                  "radial_velocity_mps", "snr_db", "x_m", "y_m", "z_m")


class SchemeScore(NamedTuple):
    """Scores of one result scheme of a cell."""

    labels: pd.DataFrame        # every detection with its label and errors
    actor_frames: pd.DataFrame  # per actor and frame: visible / detected / peak SNR
    per_actor: pd.DataFrame     # per actor: detection probability, first-detection range
    row: dict                   # summary columns of the scheme, in table order


def concat_clouds(clouds: list[pd.DataFrame]) -> pd.DataFrame:
    """One scheme's point clouds of every frame as one table (typed columns when empty)."""
    pcs = pd.concat(clouds, ignore_index=True) if clouds else pd.DataFrame()
    if pcs.empty:
        pcs = pd.DataFrame({c: pd.Series(dtype=float) for c in _CLOUD_COLUMNS})
        pcs["frame"] = pcs["frame"].astype(np.int64)
    return pcs


def score_scheme(pcs: pd.DataFrame, truth: pd.DataFrame, scat_df: pd.DataFrame, cfg, assoc,
                 n_frames: int, target_ids, criteria) -> SchemeScore:
    """Label one scheme's detections and summarise them (DESIGN section 7).

    Parameters
    ----------
    pcs : pandas.DataFrame
        The scheme's point clouds of every processed frame (`concat_clouds`).
    truth, scat_df : pandas.DataFrame
        Ground truth of the processed frames and their scatterers
        (`metrics.association.scatterer_table`).
    cfg : radarsim.RadarConfig
        The scheme's radar config (unambiguous span, velocity-failure step).
    assoc : metrics.association.AssociationConfig
    n_frames : int
        Processed frames.
    target_ids, criteria
        The case's must-detect actors and pass criteria.
    """
    span = 2 * cfg.max_unambiguous_velocity_mps
    lab = associate(pcs, truth, velocity_span_mps=span, config=assoc, scatterers=scat_df)
    lab = detection_errors(lab, truth, scat_df)
    lab["velocity_resolution_failure"] = mdet.velocity_resolution_failures(
        pcs, truth, cfg.scheme.velocity_failure_step_mps(cfg), config=assoc,
        scatterers=scat_df)
    af = actor_frames(lab, truth, scatterers=scat_df, config=assoc)
    row = mdet.summarize_scheme(lab, af, n_frames, assoc, target_ids=target_ids)
    per_actor = mdet.actor_detection(af)
    row.update(mdet.case_criteria(criteria, lab, per_actor, row))
    row.update(mdet.velocity_failure_stats(lab))
    return SchemeScore(lab, af, per_actor, row)


def add_track_metrics(row: dict, tm: dict | None) -> None:
    """Add a scheme's numeric track metrics to its summary row (in place)."""
    for k, v in dict(tm or {}).items():
        if isinstance(v, (int, float, np.integer, np.floating)):
            # Track metrics keep their names unless they collide (n_frames).
            row[k if k not in row else f"track_{k}"] = v


def add_snr_gains(summary: pd.DataFrame, actors: pd.DataFrame, schemes, base: str) -> None:
    """SNR-gain columns of every scheme over ``base`` on the same actor and frame (in place;
    NaN, count 0, for ``base`` itself, chain variants and when ``base`` did not run)."""
    names = [rs.name for rs in schemes]
    gains = {rs.name: mdet.snr_gain_stats(mdet.snr_gain_pairs(actors, rs.name, base))
             for rs in schemes if not rs.is_variant and rs.name != base and base in names}
    for k in mdet.snr_gain_stats(pd.DataFrame({"snr_gain_db": pd.Series(dtype=float)})):
        count = k.endswith("_n")
        summary[k] = np.array([gains[s][k] if s in gains else (0 if count else np.nan)
                               for s in summary["scheme"]],
                              dtype=np.int64 if count else float)
    summary["case_pass"] = summary["case_pass"].astype(float)


def frame_counts(lab: pd.DataFrame, frames: np.ndarray) -> pd.DataFrame:
    """Per frame: detections and label counts (frames without detections give zeros)."""
    ct = pd.crosstab(lab["frame"], lab["label"]) if len(lab) else pd.DataFrame()
    ct = ct.reindex(index=frames, columns=list(LABELS), fill_value=0)
    out = pd.DataFrame({"frame": np.asarray(frames, dtype=np.int64)})
    names = {"TRUE": "n_true", "VELOCITY_AMBIGUOUS": "n_velocity_ambiguous",
             "GHOST": "n_ghost", "CLUTTER": "n_clutter"}
    for lab_name, col in names.items():
        out[col] = ct[lab_name].to_numpy(dtype=np.int64)
    out.insert(1, "n_detections", out[list(names.values())].sum(axis=1))
    return out


def floor_summary(fl: pd.DataFrame) -> dict:
    """Summary columns of one scheme: medians over frames (INR over frames that have
    interferers; NaN when none has)."""
    inr = fl["interference_to_noise_db"].to_numpy(dtype=float)
    return {"noise_floor_rise_db": float(np.median(fl["noise_floor_rise_db"])),
            "noise_floor_rise_range_db": float(np.median(fl["noise_floor_rise_range_db"])),
            "interference_to_noise_db": float(np.nanmedian(inr)) if np.isfinite(inr).any()
            else float("nan")}
