"""Suite-wide scores per scheme: the answer a report leads with.

Per-run scores (one summary row per scenario, variant, seed and scheme) are pooled over the
whole suite with their own weights: detection probability by actor-frames, RMSE by error
samples (sqrt of the sample-weighted mean square), velocity-unambiguity and ghost rates by
detection counts (right and failed velocities, ghosts and detections), the SNR gain as the
median of every noise-limited pair. Nothing here
re-associates detections: it only reads the tables the sweep wrote.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from .detection import NOISE_LIMITED_SNR_DB, snr_gain_pairs

__all__ = ["headline_table", "suite_snr_gain_db", "aliased_runs"]

#: A run whose road users' velocity-unambiguity rate is below this shows aliasing (most of
#: its road-user detections are off by whole steps: a road user beyond the scheme's span).
ALIASED_BELOW = 0.5

#: Static infrastructure is clutter, not an actor to detect (design.md 7).
_NOT_ACTORS = ("guard_rail",)


def _ratio(num: pd.Series, den: pd.Series) -> float:
    d = float(den.sum())
    return float(num.sum()) / d if d > 0 else float("nan")


def _pooled_rmse(rmse: pd.Series, n: pd.Series) -> float:
    ok = np.isfinite(rmse.to_numpy(float)) & (n.to_numpy(float) > 0)
    w = n.to_numpy(float)[ok]
    return float(np.sqrt(np.sum(w * rmse.to_numpy(float)[ok] ** 2) / w.sum())) if w.sum() else \
        float("nan")


def suite_snr_gain_db(actors: pd.DataFrame, scheme: str, baseline: str,
                      noise_limited_snr_db: float = NOISE_LIMITED_SNR_DB) -> np.ndarray:
    """SNR gains (dB) of `scheme` over `baseline` on the same actor and frame, every run of
    the suite pooled; only noise-limited pairs (baseline peak SNR <= `noise_limited_snr_db`,
    where design.md 8's 5.4 dB is defined)."""
    parts = [snr_gain_pairs(g, scheme, baseline)
             for _, g in actors.groupby(["scenario", "variant", "seed"], sort=False)]
    if not parts:
        return np.zeros(0)
    pairs = pd.concat(parts)
    return pairs.loc[pairs["reference_snr_db"] <= noise_limited_snr_db,
                     "snr_gain_db"].to_numpy(float)


def headline_table(summary: pd.DataFrame, actor_summary: pd.DataFrame,
                   actors: pd.DataFrame | None = None, *, baseline: str,
                   verdicts: dict[str, str] | None = None) -> pd.DataFrame:
    """One row per scheme (run order) with the suite-wide answer.

    Parameters
    ----------
    summary : DataFrame
        The sweep's summary (rows with an ``error`` are left out).
    actor_summary : DataFrame
        Per actor and run: actor_class, n_visible_frames, n_detected_frames,
        first_detection_range_m.
    actors : DataFrame, optional
        Actor-frame table, for the SNR gain over `baseline` (left out without it).
    baseline : str
        Scheme the SNR gain is measured against.
    verdicts : dict, optional
        Gate verdict per scheme (e.g. "PASS", "FAIL: ddma_snr_gain").

    Returns
    -------
    DataFrame
        Columns scheme; ``pd_<class>`` (detected / visible actor-frames) and
        ``first_detection_range_<class>_m`` (median over the actors detected at all) per actor
        class present; range_rmse_m, radial_velocity_rmse_mps (pooled by error samples);
        velocity_unambiguity_rate (right / (right + failures) road-user velocities over every
        run, `metrics.velocity`); infrastructure_velocity_unambiguity_rate (the same over
        guard-rail detections, when the summary has its counts); ghost_rate (ghosts /
        detections); snr_gain_over_<baseline>_db (median of noise-limited pairs) and
        snr_gain_pairs; gates.
    """
    ok = summary[summary["error"].fillna("") == ""] if "error" in summary else summary
    schemes = [s for s in dict.fromkeys(ok["scheme"]) if s]
    act = actor_summary[~actor_summary["actor_class"].isin(_NOT_ACTORS)] \
        if len(actor_summary) else actor_summary
    classes = sorted(set(act["actor_class"])) if len(act) else []
    rows = []
    for s in schemes:
        sm = ok[ok["scheme"] == s]
        row: dict = {"scheme": s}
        a = act[act["scheme"] == s] if len(act) else act
        for c in classes:
            ac = a[a["actor_class"] == c]
            row[f"pd_{c}"] = _ratio(ac["n_detected_frames"], ac["n_visible_frames"])
            row[f"first_detection_range_{c}_m"] = float(ac["first_detection_range_m"].median())
        row["range_rmse_m"] = _pooled_rmse(sm["range_error_rmse_m"], sm["n_error_samples"])
        row["radial_velocity_rmse_mps"] = _pooled_rmse(sm["radial_velocity_error_rmse_mps"],
                                                       sm["n_error_samples"])
        row["velocity_unambiguity_rate"] = _ratio(
            sm["n_velocity_right"], sm["n_velocity_right"] + sm["n_velocity_resolution_failures"])
        if "n_infrastructure_velocity_right" in sm:
            row["infrastructure_velocity_unambiguity_rate"] = _ratio(
                sm["n_infrastructure_velocity_right"],
                sm["n_infrastructure_velocity_right"] + sm["n_infrastructure_velocity_failures"])
        row["ghost_rate"] = _ratio(sm["n_ghost"], sm["n_detections"])
        if actors is not None and len(actors):
            gains = (suite_snr_gain_db(actors, s, baseline) if s != baseline
                     else np.zeros(0))
            row[f"snr_gain_over_{baseline}_db"] = float(np.median(gains)) if gains.size \
                else float("nan")
            row["snr_gain_pairs"] = int(gains.size)
        if verdicts is not None:
            row["gates"] = verdicts.get(s, "-")
        rows.append(row)
    return pd.DataFrame(rows)


def aliased_runs(summary: pd.DataFrame, below: float = ALIASED_BELOW) -> pd.DataFrame:
    """Runs whose road users alias: velocity_unambiguity_rate below `below`.

    Parameters
    ----------
    summary : DataFrame
        The sweep's summary (rows with an ``error`` are left out).
    below : float
        Rate under which a run counts as aliased (default `ALIASED_BELOW`).

    Returns
    -------
    DataFrame
        Columns scenario, variant, seed, scheme, velocity_unambiguity_rate,
        n_velocity_resolution_failures, in summary order.

    Examples
    --------
    >>> import pandas as pd
    >>> s = pd.DataFrame({"scenario": ["head_on", "head_on"], "variant": ["", ""],
    ...                   "seed": [0, 0], "scheme": ["ddma", "tdma"],
    ...                   "velocity_unambiguity_rate": [0.0, 0.9],
    ...                   "n_velocity_resolution_failures": [52, 3]})
    >>> aliased_runs(s)["scheme"].tolist()
    ['ddma']
    """
    cols = ["scenario", "variant", "seed", "scheme", "velocity_unambiguity_rate",
            "n_velocity_resolution_failures"]
    ok = summary[summary["error"].fillna("") == ""] if "error" in summary else summary
    if "velocity_unambiguity_rate" not in ok:
        return pd.DataFrame(columns=cols)
    rate = ok["velocity_unambiguity_rate"].to_numpy(float)
    return ok.loc[rate < below, [c for c in cols if c in ok]].reset_index(drop=True)
