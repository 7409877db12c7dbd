"""Detection scores per scenario x scheme x seed, computed from labelled detections.

Every function takes the long tables produced by `metrics.association` (labelled detections
with errors, actor-frame table) and returns plain numbers or pandas frames whose column names
carry their unit (``_m``, ``_mps``, ``_db``; rates and probabilities are fractions in [0, 1]).
Each docstring states exactly how the number is computed, so a gate threshold has one meaning.

References
----------
.. [1] design.md section 7 (metrics) and section 8 (5.4 dB detection-SNR gain, Nt = 4).
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from .association import CLUTTER, GHOST, TRUE, VELOCITY_AMBIGUOUS, AssociationConfig
from .joins import first_valid_rows, pair_index
from .velocity import FAILURE, RIGHT

__all__ = [
    "error_stats", "velocity_stats", "ghost_stats", "actor_detection",
    "pd_vs_range", "max_range_pd90", "snr_gain_rows", "snr_gain_pairs", "snr_gain_stats",
    "summarize_scheme",
    "target_first_detection_range_m", "NOISE_LIMITED_SNR_DB", "NOISE_LIMITED_MIN_PAIRS",
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
    outlier that dominates an RMSE. ``azimuth_error_rmse_deg`` = sqrt(mean(e_az^2)) of the
    azimuth error against the same scatterer (TRUE detections with a scatterer reference).
    NaN when there is no TRUE detection. ``n_error_samples`` counts the detections used.
    """
    tru = labelled[labelled["label"] == TRUE]
    er = tru["range_error_m"].to_numpy(dtype=float) if "range_error_m" in tru else np.array([])
    ev = tru["radial_velocity_error_mps"].to_numpy(dtype=float) \
        if "radial_velocity_error_mps" in tru else np.array([])
    ea = tru["azimuth_error_deg"].to_numpy(dtype=float) if "azimuth_error_deg" in tru \
        else np.array([])
    return {"range_error_rmse_m": _rmse(er), "range_error_median_m": _median_abs(er),
            "range_error_p95_m": _p95_abs(er),
            "radial_velocity_error_rmse_mps": _rmse(ev),
            "radial_velocity_error_median_mps": _median_abs(ev),
            "radial_velocity_error_p95_mps": _p95_abs(ev),
            "azimuth_error_rmse_deg": _rmse(ea),
            "n_error_samples": int(np.isfinite(er).sum())}


def velocity_stats(labelled: pd.DataFrame, window_mps: float) -> dict[str, float]:
    """Velocity resolution of the run's detections (`metrics.velocity`), road users and
    infrastructure apart.

    From the columns ``velocity_check`` (`velocity.RIGHT` / `velocity.FAILURE` / ""),
    ``velocity_truth_mps`` (radial velocity of the matching scatterer) and
    ``velocity_on_infrastructure`` (the match is a guard rail, not a road user) that
    `metrics.scoring.label_detections` adds. Over the detections matched to a road user
    (whatever their 2D label): ``velocity_unambiguity_rate`` = n_right / (n_right +
    n_failures); ``velocity_unambiguity_rate_in_span`` the same over detections whose truth
    |radial velocity| <= ``window_mps`` (what a scheme promises to report unaliased);
    ``n_velocity_right`` = n_right and ``n_velocity_resolution_failures`` = n_failures (the
    weights that pool the rate over runs). Over the detections matched to modelled
    infrastructure (a guard rail, checked with the unambiguous span): the same rate and counts
    as ``infrastructure_velocity_unambiguity_rate``, ``n_infrastructure_velocity_right`` and
    ``n_infrastructure_velocity_failures``; a static world inside the span is always right,
    so pooling it with the road users hides their aliasing. Rates are NaN without either kind.
    A table without ``velocity_on_infrastructure`` counts every verdict as a road user's.

    Examples
    --------
    >>> import pandas as pd
    >>> lab = pd.DataFrame({"velocity_check": ["right", "right", "failure", "", "right"],
    ...                     "velocity_truth_mps": [-5.0, 12.0, 50.0, float("nan"), -25.0],
    ...                     "velocity_on_infrastructure": [False] * 4 + [True]})
    >>> s = velocity_stats(lab, window_mps=40.9)
    >>> round(s["velocity_unambiguity_rate"], 3), s["velocity_unambiguity_rate_in_span"]
    (0.667, 1.0)
    >>> s["infrastructure_velocity_unambiguity_rate"], s["n_infrastructure_velocity_right"]
    (1.0, 1)
    """
    chk = labelled["velocity_check"].to_numpy() if "velocity_check" in labelled \
        else np.zeros(0, dtype=object)
    vt = labelled["velocity_truth_mps"].to_numpy(dtype=float) if "velocity_truth_mps" in \
        labelled else np.zeros(0)
    infra = labelled["velocity_on_infrastructure"].to_numpy(dtype=bool) \
        if "velocity_on_infrastructure" in labelled else np.zeros(len(chk), dtype=bool)
    right, fail = chk == RIGHT, chk == FAILURE

    def rate(sel: np.ndarray) -> float:
        n_r, n_f = int(np.sum(sel & right)), int(np.sum(sel & fail))
        return n_r / (n_r + n_f) if n_r + n_f else float("nan")

    road = ~infra
    return {"velocity_unambiguity_rate": rate(road),
            "velocity_unambiguity_rate_in_span": rate(road & (np.abs(vt) <= window_mps)),
            "n_velocity_right": int(np.sum(road & right)),
            "n_velocity_resolution_failures": int(np.sum(road & fail)),
            "infrastructure_velocity_unambiguity_rate": rate(infra),
            "n_infrastructure_velocity_right": int(np.sum(infra & right)),
            "n_infrastructure_velocity_failures": int(np.sum(infra & fail))}


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
    {'ghost_rate': 0.25, 'ghosts_per_frame': 0.5, 'clutter_per_frame': 0.5, 'detections_per_frame':
    2.0}
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
    detected (NaN if never); ``max_visible_range_m`` = largest visible range. "Detected"
    means a TRUE detection (footprint and velocity right) assigned to the actor: the first
    detection range has this one definition in criteria, columns, headline and gates.
    """
    cols = ["actor_id", "actor_class", "n_visible_frames", "n_detected_frames",
            "detection_probability", "first_detection_range_m", "first_detection_time_s",
            "max_visible_range_m"]
    if af.empty:
        return pd.DataFrame(columns=cols)
    # By integer group codes (actor ids in increasing order, as groupby sorts them) instead of
    # five groupbys and reindexes: the same counts, rows and maxima.
    ids, grp = np.unique(af["actor_id"].to_numpy(), return_inverse=True)
    n = ids.size
    vis = af["visible"].to_numpy(dtype=bool)
    det = af["detected"].to_numpy(dtype=bool)
    frame = af["frame"].to_numpy()
    n_vis = np.bincount(grp[vis], minlength=n).astype(np.int64)
    n_det = np.bincount(grp[vis & det], minlength=n).astype(np.int64)
    with np.errstate(invalid="ignore", divide="ignore"):
        p_det = np.where(n_vis > 0, n_det / n_vis, np.nan)
    # Each actor's class: its first non-null class (groupby's first()), else its first row.
    cls = af["actor_class"]
    rows = first_valid_rows(grp, cls.notna().to_numpy())
    # First detection: the detected row of the lowest frame per actor.
    d_rows = np.flatnonzero(det)
    d_rows = d_rows[np.lexsort((frame[d_rows], grp[d_rows]))]
    d_grp, at = np.unique(grp[d_rows], return_index=True)
    first = np.full(n, -1, dtype=np.int64)
    first[d_grp] = d_rows[at]

    def _float(col: str) -> np.ndarray:
        """The column, and a NaN-filled (n,) array of the float dtype a reindex gives it."""
        v = af[col].to_numpy()
        return v, np.full(n, np.nan, dtype=v.dtype if v.dtype.kind == "f" else float)

    def at_first(col: str) -> np.ndarray:
        v, out = _float(col)
        out[d_grp] = v[first[d_grp]]
        return out
    r, max_vis = _float("range_m")
    np.fmax.at(max_vis, grp[vis], r[vis])
    return pd.DataFrame({
        "actor_id": ids, "actor_class": cls.array.take(rows), "n_visible_frames": n_vis,
        "n_detected_frames": n_det, "detection_probability": p_det,
        "first_detection_range_m": at_first("range_m"),
        "first_detection_time_s": at_first("time_s") if "time_s" in af else np.full(n, np.nan),
        "max_visible_range_m": max_vis}, columns=cols)


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


def _max_range_pd90_of(af: pd.DataFrame, bin_m: float, min_count: int,
                       pd_min: float = 0.9) -> dict[str, float]:
    """``max_range_pd90(pd_vs_range(af, bin_m), min_count, pd_min)`` without building the
    table: the same (class, range bin) groups of the visible actor-frames, counted with
    bincount; the same ratios, comparisons and upper bin edges."""
    vis = af["visible"].to_numpy(dtype=bool)
    out: dict[str, float] = {}
    if not vis.any():
        return out
    cls = af["actor_class"].to_numpy()[vis]
    k = np.floor(af["range_m"].to_numpy()[vis] / bin_m).astype(np.int64)
    det = af["detected"].to_numpy(dtype=bool)[vis]
    for c in pd.unique(cls):
        if pd.isna(c):
            continue  # groupby drops a null class
        m = cls == c
        bins, inv = np.unique(k[m], return_inverse=True)
        n_frames = np.bincount(inv, minlength=bins.size)
        n_det = np.bincount(inv[det[m]], minlength=bins.size)
        ok = (n_frames >= min_count) & (n_det / n_frames >= pd_min)
        out[c] = float(((bins[ok] + 1) * bin_m).max()) if ok.any() else float("nan")
    return out


def snr_gain_rows(af: pd.DataFrame, a: str, b: str) -> tuple[np.ndarray, np.ndarray]:
    """(P,) rows of ``af`` of scheme ``a`` and of scheme ``b`` on the same actor and frame,
    both detected: ``a``'s detected actor-frames in table order that ``b`` detected too (the
    row order of an inner join on (frame, actor_id)), each with ``b``'s row (its first, should
    the table repeat one)."""
    scheme, hit = af["scheme"].to_numpy(), af["detected"].to_numpy(dtype=bool)
    ra, rb = np.flatnonzero((scheme == a) & hit), np.flatnonzero((scheme == b) & hit)
    frame, actor = af["frame"].to_numpy(), af["actor_id"].to_numpy()
    at = pair_index(frame[rb], actor[rb], frame[ra], actor[ra])
    return ra[at >= 0], rb[at[at >= 0]]


def snr_gain_pairs(af: pd.DataFrame, a: str, b: str) -> pd.DataFrame:
    """SNR gain of scheme ``a`` over ``b`` on the same actor and frame.

    ``af`` is the actor-frame table of both schemes with a ``scheme`` column. For every
    (frame, actor_id) detected by both (`snr_gain_rows`), ``snr_gain_db`` = max snr_db of the
    actor's TRUE detections in ``a`` minus the same in ``b`` (the actor's strongest echo in
    each scheme). Returns columns frame, actor_id, actor_class, range_m (scheme ``a``'s rows),
    reference_snr_db (scheme ``b``'s peak SNR), snr_gain_db.
    """
    ra, rb = snr_gain_rows(af, a, b)
    out = af[["frame", "actor_id", "actor_class", "range_m"]].iloc[ra].reset_index(drop=True)
    snr = af["max_snr_db"].to_numpy()
    out["reference_snr_db"] = snr[rb]
    out["snr_gain_db"] = snr[ra] - snr[rb]
    return out


#: Pairs whose TDMA peak SNR is at most this are noise-limited, dB. DDMA's dynamic range is
#: capped by the 6-bit shifter spurs (about -34.5 dBc in the empty sub-bands, design.md 8) and
#: by the leakage of strong echoes into the demodulated noise estimate; 25 dB of TDMA SNR
#: (about 30 dB in DDMA) keeps those spurs >= 5 dB under the thermal noise, where the 5.4 dB
#: detection-SNR gain of design.md 8 is defined.
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
                                                   "pedestrian"),
                     actors: pd.DataFrame | None = None) -> dict[str, float]:
    """All detection scores of one scheme of one run as one summary row (dict).

    Counts ``n_frames``, ``n_detections``, ``n_true``, ``n_velocity_ambiguous``, ``n_ghost``,
    ``n_clutter``; `error_stats`; `velocity_stats` (window ``config.unambiguity_window_mps``);
    `ghost_stats`; ``detection_probability_mean`` /
    ``detection_probability_min`` = mean / min of the per-actor Pd of actors visible in at
    least ``config.pd_min_count`` frames; ``target_first_detection_range_m``; and
    ``pd90_max_range_<class>_m`` (`max_range_pd90`) for each class in ``classes``.
    ``actors``: `actor_detection` of ``af`` when the caller has it already (computed if
    None).
    """
    cfg = config or AssociationConfig()
    row: dict[str, float] = {"n_frames": int(n_frames), "n_detections": int(len(labelled))}
    counts = labelled["label"].value_counts()
    for name, lab in (("n_true", TRUE), ("n_velocity_ambiguous", VELOCITY_AMBIGUOUS),
                      ("n_ghost", GHOST), ("n_clutter", CLUTTER)):
        row[name] = int(counts.get(lab, 0))
    row.update(error_stats(labelled))
    row.update(velocity_stats(labelled, cfg.unambiguity_window_mps))
    row.update(ghost_stats(labelled, n_frames))
    actors = actor_detection(af) if actors is None else actors
    good = actors[actors["n_visible_frames"] >= cfg.pd_min_count]
    pdv = good["detection_probability"].to_numpy(dtype=float)
    row["detection_probability_mean"] = float(pdv.mean()) if len(pdv) else float("nan")
    row["detection_probability_min"] = float(pdv.min()) if len(pdv) else float("nan")
    row["target_first_detection_range_m"] = target_first_detection_range_m(
        actors, target_ids, target_classes)
    pr = _max_range_pd90_of(af, cfg.pd_range_bin_m, cfg.pd_min_count)
    for c in classes:
        row[f"pd90_max_range_{c}_m"] = pr.get(c, float("nan"))
    return row
