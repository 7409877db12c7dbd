"""Detection scores per scenario x scheme x seed, computed from labelled detections.

Every function takes the long tables produced by `metrics.association` (labelled detections
with errors, actor-frame table) and returns plain numbers or pandas frames whose column names
carry their unit (``_m``, ``_mps``, ``_db``; rates and probabilities are fractions in [0, 1]).
Each docstring states exactly how the number is computed, so a gate threshold has one meaning.

References
----------
.. [1] DESIGN.md section 7 (metrics) and section 8 (5.4 dB detection-SNR gain, Nt = 4).
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from .association import CLUTTER, GHOST, TRUE, VELOCITY_AMBIGUOUS, AssociationConfig

__all__ = [
    "error_stats", "velocity_unambiguity_rate", "ghost_stats", "actor_detection",
    "pd_vs_range", "max_range_pd90", "snr_gain_pairs", "snr_gain_stats", "summarize_scheme",
    "target_first_detection_range_m", "case_criteria", "CRITERION_MEASURES",
    "NOISE_LIMITED_SNR_DB", "NOISE_LIMITED_MIN_PAIRS", "velocity_resolution_failures",
    "velocity_failure_stats",
]


def _rmse(x: np.ndarray) -> float:
    x = x[np.isfinite(x)]
    return float(np.sqrt(np.mean(x ** 2))) if len(x) else float("nan")


def _median_abs(x: np.ndarray) -> float:
    x = x[np.isfinite(x)]
    return float(np.median(np.abs(x))) if len(x) else float("nan")


def _p95_abs(x: np.ndarray) -> float:
    x = x[np.isfinite(x)]
    return float(np.percentile(np.abs(x), 95)) if len(x) else float("nan")


def error_stats(labelled: pd.DataFrame) -> dict[str, float]:
    """Range and radial-speed accuracy of TRUE detections.

    ``range_error_rmse_m`` = sqrt(mean(e_R^2)) and ``range_error_p95_m`` = 95th percentile of
    |e_R| over TRUE detections, e_R = detection slant range minus the slant range of the nearest
    scatterer of its actor (`association.detection_errors`); the same for the radial velocity
    (``radial_velocity_error_rmse_mps``, ``radial_velocity_error_p95_mps``). The medians of
    |e| (``range_error_median_m``, ``radial_velocity_error_median_mps``) are robust to the odd
    outlier that dominates an RMSE. NaN when there is no TRUE detection. ``n_error_samples``
    counts the detections used.
    """
    tru = labelled[labelled["label"] == TRUE]
    er = tru["range_error_m"].to_numpy(dtype=float) if "range_error_m" in tru else np.array([])
    ev = tru["radial_velocity_error_mps"].to_numpy(dtype=float) \
        if "radial_velocity_error_mps" in tru else np.array([])
    return {"range_error_rmse_m": _rmse(er), "range_error_median_m": _median_abs(er),
            "range_error_p95_m": _p95_abs(er),
            "radial_velocity_error_rmse_mps": _rmse(ev),
            "radial_velocity_error_median_mps": _median_abs(ev),
            "radial_velocity_error_p95_mps": _p95_abs(ev),
            "n_error_samples": int(np.isfinite(er).sum())}


def velocity_unambiguity_rate(labelled: pd.DataFrame, window_mps: float) -> float:
    """Fraction of footprint-associated detections whose velocity is not aliased.

    n_TRUE / (n_TRUE + n_VELOCITY_AMBIGUOUS), counting only detections whose truth radial
    velocity (at the nearest box point) satisfies |v| <= ``window_mps``. NaN if none.
    A wrong velocity that is not a multiple of 2 Vmax is a GHOST and does not enter this rate
    (it enters the ghost rate).

    Examples
    --------
    >>> import pandas as pd
    >>> from metrics.detection import velocity_unambiguity_rate
    >>> lab = pd.DataFrame({"label": ["TRUE", "TRUE", "TRUE", "VELOCITY_AMBIGUOUS", "GHOST"],
    ...                     "truth_radial_velocity_mps": [-5.0, 12.0, 30.0, 35.0, 0.0]})
    >>> velocity_unambiguity_rate(lab, window_mps=40.9)   # 3 of the 4 footprint detections
    0.75
    """
    lab = labelled[labelled["label"].isin([TRUE, VELOCITY_AMBIGUOUS])]
    lab = lab[np.abs(lab["truth_radial_velocity_mps"]) <= window_mps]
    if lab.empty:
        return float("nan")
    return float((lab["label"] == TRUE).mean())


def velocity_resolution_failures(detections: pd.DataFrame, truth: pd.DataFrame,
                                 step_mps: float, *, config: AssociationConfig | None = None,
                                 scatterers: pd.DataFrame | None = None) -> np.ndarray:
    """Detections whose velocity resolution failed: inside an actor's footprint gate with the
    radial velocity off by a non-zero multiple of ``step_mps`` (within the velocity gate).

    ``step_mps`` is the scheme's own failure step (`radarsim.mimo.MimoScheme.
    velocity_failure_step_mps`): one sub-band for DDMA (a demodulation or assignment error
    moves the velocity by whole sub-bands), the unambiguous span 2 Vmax of one Tx's slow time
    for TDMA and BPM (a wrong disambiguation hypothesis), so DDMA demodulation errors,
    classic-DDMA assignment errors and TDMA/BPM disambiguation errors count on one scale. It is
    `association.associate` with ``velocity_span_mps = step_mps``: its VELOCITY_AMBIGUOUS
    detections.

    Returns
    -------
    (n,) bool, in the row order of ``detections``.
    """
    from .association import associate
    if len(detections) == 0:
        return np.zeros(0, dtype=bool)
    lab = associate(detections, truth, velocity_span_mps=step_mps, config=config,
                    scatterers=scatterers)
    return (lab["label"] == VELOCITY_AMBIGUOUS).to_numpy()


def velocity_failure_stats(labelled: pd.DataFrame) -> dict[str, float]:
    """``n_velocity_resolution_failures`` (column ``velocity_resolution_failure`` of the
    detections) and ``velocity_resolution_failure_rate`` = failures / (TRUE + failures), NaN
    without either."""
    fail = labelled["velocity_resolution_failure"].to_numpy(dtype=bool) \
        if "velocity_resolution_failure" in labelled else np.zeros(len(labelled), dtype=bool)
    n_fail = int(fail.sum())
    n_true = int((labelled["label"] == TRUE).sum()) if len(labelled) else 0
    return {"n_velocity_resolution_failures": n_fail,
            "velocity_resolution_failure_rate": n_fail / (n_true + n_fail)
            if n_true + n_fail else float("nan")}


def ghost_stats(labelled: pd.DataFrame, n_frames: int) -> dict[str, float]:
    """Ghost and clutter counts.

    ``ghost_rate`` = n_GHOST / n_detections (NaN without detections); ``ghosts_per_frame`` =
    n_GHOST / n_frames processed; ``clutter_per_frame`` = n_CLUTTER / n_frames;
    ``detections_per_frame`` = n_detections / n_frames.

    Examples
    --------
    >>> import pandas as pd
    >>> from metrics.detection import ghost_stats
    >>> lab = pd.DataFrame({"label": ["TRUE", "TRUE", "GHOST", "CLUTTER"]})
    >>> ghost_stats(lab, n_frames=2)
    {'ghost_rate': 0.25, 'ghosts_per_frame': 0.5, 'clutter_per_frame': 0.5, 'detections_per_frame': 2.0}
    """
    n = len(labelled)
    n_g = int((labelled["label"] == GHOST).sum())
    n_c = int((labelled["label"] == CLUTTER).sum())
    nf = max(int(n_frames), 1)
    return {"ghost_rate": n_g / n if n else float("nan"), "ghosts_per_frame": n_g / nf,
            "clutter_per_frame": n_c / nf, "detections_per_frame": n / nf}


def actor_detection(af: pd.DataFrame) -> pd.DataFrame:
    """Per-actor detection probability and first-detection range.

    From the actor-frame table (`association.actor_frames`): ``n_visible_frames`` = visible
    actor-frames, ``n_detected_frames`` = visible and detected, ``detection_probability`` =
    their ratio (NaN if never visible); ``first_detection_range_m`` / ``first_detection_time_s``
    = truth centre range / time at the first frame (lowest frame number) in which the actor is
    detected (NaN if never); ``max_visible_range_m`` = largest visible range;
    ``first_association_range_m`` = range at the first frame with a TRUE or a
    VELOCITY_AMBIGUOUS detection of the actor (seen at its position, velocity possibly aliased).
    """
    cols = ["actor_id", "actor_class", "n_visible_frames", "n_detected_frames",
            "detection_probability", "first_detection_range_m", "first_detection_time_s",
            "max_visible_range_m"]
    if af.empty:
        return pd.DataFrame(columns=cols)
    vis = af[af["visible"]]
    g = af.groupby("actor_id", sort=True)
    out = pd.DataFrame({"actor_class": g["actor_class"].first()})
    out["n_visible_frames"] = vis.groupby("actor_id").size().reindex(out.index).fillna(0) \
        .astype(np.int64)
    det = vis[vis["detected"]]
    out["n_detected_frames"] = det.groupby("actor_id").size().reindex(out.index).fillna(0) \
        .astype(np.int64)
    with np.errstate(invalid="ignore", divide="ignore"):
        out["detection_probability"] = np.where(
            out["n_visible_frames"] > 0, out["n_detected_frames"] / out["n_visible_frames"],
            np.nan)
    first = af[af["detected"]].sort_values("frame").drop_duplicates("actor_id") \
        .set_index("actor_id")
    out["first_detection_range_m"] = first["range_m"].reindex(out.index)
    out["first_detection_time_s"] = (first["time_s"].reindex(out.index)
                                     if "time_s" in first else np.nan)
    out["max_visible_range_m"] = vis.groupby("actor_id")["range_m"].max().reindex(out.index)
    seen = af["detected"].to_numpy(dtype=bool)
    if "n_ambiguous" in af:
        seen = seen | (af["n_ambiguous"].to_numpy() > 0)
    first_a = af[seen].sort_values("frame").drop_duplicates("actor_id").set_index("actor_id")
    out["first_association_range_m"] = first_a["range_m"].reindex(out.index)
    return out.reset_index()[cols + ["first_association_range_m"]]


def pd_vs_range(af: pd.DataFrame, bin_m: float = 10.0) -> pd.DataFrame:
    """Detection probability versus range per actor class.

    Visible actor-frames are binned by truth centre range into [k bin_m, (k+1) bin_m);
    ``detection_probability`` = detected / visible per (class, bin). Columns actor_class,
    range_lo_m, range_hi_m, n_frames, n_detected, detection_probability.
    """
    vis = af[af["visible"]]
    if vis.empty:
        return pd.DataFrame(columns=["actor_class", "range_lo_m", "range_hi_m", "n_frames",
                                     "n_detected", "detection_probability"])
    k = np.floor(vis["range_m"].to_numpy() / bin_m).astype(np.int64)
    t = vis.assign(_k=k).groupby(["actor_class", "_k"]).agg(
        n_frames=("detected", "size"), n_detected=("detected", "sum")).reset_index()
    t["range_lo_m"] = t["_k"] * bin_m
    t["range_hi_m"] = (t["_k"] + 1) * bin_m
    t["n_detected"] = t["n_detected"].astype(np.int64)
    t["detection_probability"] = t["n_detected"] / t["n_frames"]
    return t[["actor_class", "range_lo_m", "range_hi_m", "n_frames", "n_detected",
              "detection_probability"]]


def max_range_pd90(pd_table: pd.DataFrame, min_count: int = 5,
                   pd_min: float = 0.9) -> dict[str, float]:
    """Largest range at which each class is still detected with Pd >= ``pd_min``.

    The upper edge ``range_hi_m`` of the farthest range bin of `pd_vs_range` that holds at
    least ``min_count`` visible actor-frames and has detection_probability >= ``pd_min``; NaN
    for a class with no such bin. Returns {class: metres}.
    """
    ok = pd_table[(pd_table["n_frames"] >= min_count) &
                  (pd_table["detection_probability"] >= pd_min)]
    out = {c: float("nan") for c in pd_table["actor_class"].unique()}
    out.update(ok.groupby("actor_class")["range_hi_m"].max().astype(float).to_dict())
    return out


def snr_gain_pairs(af: pd.DataFrame, a: str, b: str) -> pd.DataFrame:
    """SNR gain of scheme ``a`` over ``b`` on the same actor and frame.

    ``af`` is the actor-frame table of both schemes with a ``scheme`` column. For every
    (frame, actor_id) detected by both, ``snr_gain_db`` = max snr_db of the actor's TRUE
    detections in ``a`` minus the same in ``b`` (the actor's strongest echo in each scheme).
    Returns columns frame, actor_id, actor_class, range_m, reference_snr_db (scheme ``b``'s
    peak SNR), snr_gain_db.
    """
    key = ["frame", "actor_id"]
    da = af[(af["scheme"] == a) & af["detected"]].set_index(key)
    db = af[(af["scheme"] == b) & af["detected"]].set_index(key)
    j = da[["actor_class", "range_m", "max_snr_db"]].join(
        db[["max_snr_db"]].rename(columns={"max_snr_db": "max_snr_db_b"}), how="inner")
    j["snr_gain_db"] = j["max_snr_db"] - j["max_snr_db_b"]
    j = j.rename(columns={"max_snr_db_b": "reference_snr_db"})
    return j.reset_index()[["frame", "actor_id", "actor_class", "range_m", "reference_snr_db",
                            "snr_gain_db"]]


#: Pairs whose TDMA peak SNR is at most this are noise-limited, dB. DDMA's dynamic range is
#: capped by the 6-bit shifter spurs (about -34.5 dBc in the empty sub-bands, DESIGN 8) and
#: by the leakage of strong echoes into the demodulated noise estimate; 25 dB of TDMA SNR
#: (about 30 dB in DDMA) keeps those spurs >= 5 dB under the thermal noise, where the 5.4 dB
#: detection-SNR gain of DESIGN 8 is defined.
NOISE_LIMITED_SNR_DB = 25.0


#: Fewest noise-limited pairs for a per-run median (with ~1.6 dB spread per pair, the median
#: of 10 pairs is known to about +/-0.6 dB).
NOISE_LIMITED_MIN_PAIRS = 10


def snr_gain_stats(pairs: pd.DataFrame, noise_limited_snr_db: float = NOISE_LIMITED_SNR_DB,
                   min_pairs: int = NOISE_LIMITED_MIN_PAIRS) -> dict[str, float]:
    """Median and spread of `snr_gain_pairs`, over all pairs and over noise-limited pairs.

    ``snr_gain_median_db``, ``snr_gain_p25_db``, ``snr_gain_p75_db`` (quartiles),
    ``snr_gain_std_db`` (sample standard deviation) and ``snr_gain_n`` (pairs) over all
    pairs; ``snr_gain_noise_limited_median_db`` and ``snr_gain_noise_limited_n`` over the pairs
    whose reference (TDMA) peak SNR is <= ``noise_limited_snr_db`` (the median is NaN with
    fewer than ``min_pairs`` such pairs). NaN if none.
    """
    nan = float("nan")
    g = pairs["snr_gain_db"].to_numpy(dtype=float)
    ok = np.isfinite(g)
    ref = pairs["reference_snr_db"].to_numpy(dtype=float) if "reference_snr_db" in pairs \
        else np.full(len(g), np.nan)
    low = g[ok & (ref <= noise_limited_snr_db)]
    g = g[ok]
    out = {"snr_gain_median_db": nan, "snr_gain_p25_db": nan, "snr_gain_p75_db": nan,
           "snr_gain_std_db": nan, "snr_gain_n": int(len(g)),
           "snr_gain_noise_limited_median_db": float(np.median(low))
           if len(low) >= max(min_pairs, 1) else nan,
           "snr_gain_noise_limited_n": int(len(low))}
    if len(g):
        out.update({"snr_gain_median_db": float(np.median(g)),
                    "snr_gain_p25_db": float(np.percentile(g, 25)),
                    "snr_gain_p75_db": float(np.percentile(g, 75)),
                    "snr_gain_std_db": float(np.std(g, ddof=1)) if len(g) > 1 else 0.0})
    return out


def target_first_detection_range_m(actors: pd.DataFrame, target_ids=None,
                                   target_classes=None) -> float:
    """First-detection range of the case's target actors, m.

    The minimum over target actors (``target_ids`` if given, else actors whose class is in
    ``target_classes``, else all road users) of `actor_detection`'s
    ``first_detection_range_m``, so every target must be seen by that range; NaN if a target
    is never detected or there is no target.
    """
    sel = actors
    if target_ids is not None:
        sel = actors[actors["actor_id"].isin(list(target_ids))]
    elif target_classes:
        sel = actors[actors["actor_class"].isin(list(target_classes))]
    sel = sel[sel["n_visible_frames"] > 0]
    if sel.empty:
        return float("nan")
    v = sel["first_detection_range_m"].to_numpy(dtype=float)
    return float("nan") if np.isnan(v).any() else float(v.min())


def summarize_scheme(labelled: pd.DataFrame, af: pd.DataFrame, n_frames: int,
                     config: AssociationConfig | None = None, *, target_ids=None,
                     target_classes=None, classes=("car", "truck", "motorcycle", "bicycle",
                                                   "pedestrian")) -> dict[str, float]:
    """All detection scores of one scheme of one run as one summary row (dict).

    Counts ``n_frames``, ``n_detections``, ``n_true``, ``n_velocity_ambiguous``, ``n_ghost``,
    ``n_clutter``; `error_stats`; ``velocity_unambiguity_rate`` (window
    ``config.unambiguity_window_mps``); `ghost_stats`; ``detection_probability_mean`` /
    ``detection_probability_min`` = mean / min of the per-actor Pd of actors visible in at
    least ``config.pd_min_count`` frames; ``target_first_detection_range_m``; and
    ``pd90_max_range_<class>_m`` (`max_range_pd90`) for each class in ``classes``.
    """
    cfg = config or AssociationConfig()
    row: dict[str, float] = {"n_frames": int(n_frames), "n_detections": int(len(labelled))}
    counts = labelled["label"].value_counts()
    for name, lab in (("n_true", TRUE), ("n_velocity_ambiguous", VELOCITY_AMBIGUOUS),
                      ("n_ghost", GHOST), ("n_clutter", CLUTTER)):
        row[name] = int(counts.get(lab, 0))
    row.update(error_stats(labelled))
    row["velocity_unambiguity_rate"] = velocity_unambiguity_rate(labelled,
                                                                 cfg.unambiguity_window_mps)
    row.update(ghost_stats(labelled, n_frames))
    actors = actor_detection(af)
    good = actors[actors["n_visible_frames"] >= cfg.pd_min_count]
    pdv = good["detection_probability"].to_numpy(dtype=float)
    row["detection_probability_mean"] = float(pdv.mean()) if len(pdv) else float("nan")
    row["detection_probability_min"] = float(pdv.min()) if len(pdv) else float("nan")
    row["target_first_detection_range_m"] = target_first_detection_range_m(
        actors, target_ids, target_classes)
    pr = max_range_pd90(pd_vs_range(af, cfg.pd_range_bin_m), cfg.pd_min_count)
    for c in classes:
        row[f"pd90_max_range_{c}_m"] = pr.get(c, float("nan"))
    return row


#: Criterion metric name -> how `case_criteria` measures it.
CRITERION_MEASURES = {
    "first_detection_range_m": "actor_detection first_association_range_m of the actor: the "
                               "first frame with a detection in its footprint gate whose "
                               "velocity is right or off by k 2 Vmax (the object is seen in "
                               "time; velocity correctness is velocity_unambiguous_rate)",
    "detection_probability": "actor_detection detection_probability of the actor",
    "velocity_unambiguous_rate": "TRUE / (TRUE + VELOCITY_AMBIGUOUS) detections of the actor "
                                 "(no velocity window)",
    "ghost_rate": "ghost_stats ghost_rate (whole run)",
    "range_rmse_m": "error_stats range_error_rmse_m (whole run)",
}

_OPS = {">=": np.greater_equal, "<=": np.less_equal, ">": np.greater, "<": np.less}


def case_criteria(criteria, labelled: pd.DataFrame, actors: pd.DataFrame,
                  row: dict) -> dict[str, object]:
    """Evaluate a case's pass criteria (``metric op value`` for an actor or the whole run).

    ``criteria`` are objects with ``metric``, ``op``, ``value`` and ``actor_id`` (the
    catalogue's ``scenarios.Criterion``; read by attribute, so this package does not import
    the scenarios). Metrics are measured as `CRITERION_MEASURES` says; a NaN measurement
    fails (an actor never detected has no first-detection range).

    Returns
    -------
    dict
        ``case_pass`` (1.0 all criteria met, 0.0 otherwise, NaN without criteria),
        ``case_criteria_n``, ``case_criteria_failed`` (";"-joined descriptions, "" if none)
        and ``case_<metric>`` (the measured value of the first criterion on each metric).
    """
    out: dict[str, object] = {"case_pass": float("nan"), "case_criteria_n": 0,
                              "case_criteria_failed": ""}
    crits = list(criteria or ())
    if not crits:
        return out
    a = actors.set_index("actor_id") if len(actors) else actors
    failed = []
    for c in crits:
        aid = getattr(c, "actor_id", None)
        m = c.metric
        if m in ("first_detection_range_m", "detection_probability"):
            col = "first_association_range_m" if m == "first_detection_range_m" else m
            v = float(a.loc[aid, col]) if aid is not None and aid in a.index else float("nan")
        elif m == "velocity_unambiguous_rate":
            lab = labelled[labelled["label"].isin([TRUE, VELOCITY_AMBIGUOUS])]
            if aid is not None:
                lab = lab[lab["actor_id"] == aid]
            v = float((lab["label"] == TRUE).mean()) if len(lab) else float("nan")
        elif m == "ghost_rate":
            v = float(row.get("ghost_rate", float("nan")))
        elif m == "range_rmse_m":
            v = float(row.get("range_error_rmse_m", float("nan")))
        else:
            raise ValueError(f"criterion metric {m!r} is not one of "
                             f"{sorted(CRITERION_MEASURES)}")
        if c.op not in _OPS:
            raise ValueError(f"criterion op {c.op!r} is not one of {sorted(_OPS)}")
        ok = bool(np.isfinite(v) and _OPS[c.op](v, c.value))
        out.setdefault(f"case_{m}", v)
        if not ok:
            who = f" actor {aid}" if aid is not None else ""
            failed.append(f"{m}{who} = {v:.4g} not {c.op} {c.value:g}")
    out["case_pass"] = float(not failed)
    out["case_criteria_n"] = len(crits)
    out["case_criteria_failed"] = "; ".join(failed)
    return out
