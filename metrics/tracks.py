"""Track metrics: how well the group tracker's output follows the ground truth of a run.

Pure functions over pandas frames. Confirmed tracks are matched to truth actors frame by frame
(optimal assignment, `scipy.optimize.linear_sum_assignment`, gated by the distance of the track
to the actor's footprint); from the matches follow the time and range at confirmation per
actor, continuity (identity switches, fragmentations), false tracks per minute, position and
velocity RMSE; GOSPA scores the track set against the truth set each frame independently.

Inputs
------
tracks : the tracker's table (`pipeline.tracking.TRACK_COLUMNS` plus `frame`): frame, time_s,
    track_id, state, x_m, y_m, vx_mps, vy_mps (vehicle frame; velocity RELATIVE to the ego).
truth : the scenario's per-frame, per-actor table (common brief): frame, time_s, actor_id,
    actor_class, x_m, y_m, vx_mps, vy_mps (vehicle frame, velocity RELATIVE to the ego),
    optionally length_m, width_m, yaw_deg (footprint) and range_m (radar frame).
Velocities are compared as they are given: both relative to the ego, vehicle frame.
Positions: the track reports the centroid of its detections, the truth the box centre, so the
position RMSE includes the centroid's offset from the centre (about half the visible depth).

References
----------
.. [1] A. S. Rahmathullah, A. F. Garcia-Fernandez, L. Svensson, "Generalized optimal
       sub-pattern assignment metric", FUSION 2017 (GOSPA, alpha = 2).
.. [2] K. Bernardin, R. Stiefelhagen, "Evaluating multiple object tracking performance: the
       CLEAR MOT metrics", EURASIP JIVP 2008 (identity switches, fragmentation).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from core.checks import require
from core.errors import BadInput

from .joins import first_valid_rows, pair_isin

__all__ = [
    "TrackMetricsConfig", "gospa", "match_tracks", "gospa_per_frame", "per_actor_track_metrics",
    "track_metrics", "track_metrics_long", "TRACK_METRIC_COLUMNS",
]

#: Columns of the one-row-per-run summary returned by `track_metrics`.
TRACK_METRIC_COLUMNS = (
    "n_frames", "duration_s", "n_actors", "n_actors_confirmed", "track_confirm_time_s_min",
    "track_confirm_latency_s_median", "track_confirm_latency_s_max",
    "track_confirm_range_m_max", "track_confirm_range_m_median", "track_id_switches",
    "track_fragmentations", "track_coverage_mean", "n_false_tracks", "false_tracks_per_min",
    "gospa_mean_m", "gospa_localization_mean_m", "gospa_missed_per_frame",
    "gospa_false_per_frame", "track_pos_rmse_m", "track_vel_rmse_mps",
)

_TRACK_NEEDS = ("frame", "time_s", "track_id", "state", "x_m", "y_m", "vx_mps", "vy_mps")
_TRUTH_NEEDS = ("frame", "time_s", "actor_id", "x_m", "y_m", "vx_mps", "vy_mps")
_BIG = 1e12


@dataclass(frozen=True, kw_only=True, slots=True)
class TrackMetricsConfig:
    """Settings of the track metrics.

    Parameters
    ----------
    match_gate_m : float
        A track may match an actor when its position lies within this distance of the
        actor's footprint (length_m x width_m box at yaw_deg; the centre when those columns are
        missing), m.
    gospa_c_m : float
        GOSPA cut-off distance c, m.
    gospa_p : float
        GOSPA order p, >= 1. (alpha is fixed at 2, the value that gives the
        localisation / missed / false decomposition [1].)
    confirmed_states : tuple of str
        Track states that count as confirmed tracks.
    exclude_classes : tuple of str
        Actor classes left out of the truth (static infrastructure: a track on a guard rail
        counts as a false track).
    false_track_max_match_fraction : float
        A confirmed track matched to an actor in fewer than this fraction of its confirmed
        frames is a false track, [0, 1].
    frame_period_s : float or None
        Frame period for the run duration when it cannot be read from the tables (single
        frame), s.
    fov_azimuth_deg, max_range_m : float or None
        The radar's field of view (|azimuth_deg| <= fov_azimuth_deg and range_m <=
        max_range_m, radar frame; applied when the truth has those columns). An actor outside
        it cannot be missed: per-actor rows, coverage, fragmentation and the GOSPA truth set
        use only rows inside it (plus, for GOSPA, rows a confirmed track matches), while a
        track on an actor just outside it still matches and is not false. Defaults: the
        AWR2944 corner-radar claims, +/-80 deg and 200 m (design.md 4.1). None: no limit.

    Raises
    ------
    ValueError
        On a value out of its domain; the message names the field, the value and the limit.
    """

    match_gate_m: float = 2.0
    gospa_c_m: float = 10.0
    gospa_p: float = 2.0
    confirmed_states: tuple[str, ...] = ("ACTIVE",)
    exclude_classes: tuple[str, ...] = ("guard_rail",)
    false_track_max_match_fraction: float = 0.5
    frame_period_s: float | None = None
    fov_azimuth_deg: float | None = 80.0
    max_range_m: float | None = 200.0

    def __post_init__(self) -> None:
        require(self, ("match_gate_m", "gospa_c_m"), gt=0)
        require(self, "gospa_p", ge=1)
        require(self, "false_track_max_match_fraction", ge=0, le=1)
        require(self, ("frame_period_s", "max_range_m"), gt=0, none_ok=True)
        require(self, "fov_azimuth_deg", gt=0, le=180, unit="deg", none_ok=True)
        if isinstance(self.confirmed_states, str) or not self.confirmed_states:
            raise BadInput(f"confirmed_states={self.confirmed_states!r} must be a non-empty "
                           "tuple of state names")


# ---------------------------------------------------------------------------------------------
# GOSPA


def gospa(truth_xy, track_xy, c_m: float = 10.0, p: float = 2.0) -> dict[str, float]:
    """GOSPA distance (alpha = 2) between a truth set and an estimate set in the plane.

    d = (min over assignments of sum_assigned min(d_ij, c)^p
         + c^p / 2 (n_missed + n_false))^(1/p)

    Parameters
    ----------
    truth_xy : (m, 2) float
        Truth positions, m.
    track_xy : (n, 2) float
        Estimated positions, m.
    c_m : float
        Cut-off distance, m (> 0).
    p : float
        Order (>= 1).

    Returns
    -------
    dict
        gospa_m, localization_m ((sum of d^p over assigned pairs)^(1/p)), n_missed, n_false,
        n_assigned. Pairs at distance >= c count as one miss plus one false track (for alpha = 2
        the two are equivalent, c^p either way).

    Raises
    ------
    ValueError
        On c_m <= 0, p < 1 or arrays not of shape (k, 2).
    """
    if not (math.isfinite(c_m) and c_m > 0):
        raise BadInput(f"c_m={c_m!r} must be a finite number > 0")
    if not (math.isfinite(p) and p >= 1):
        raise BadInput(f"p={p!r} must be a finite number >= 1")
    x = np.asarray(truth_xy, dtype=float).reshape(-1, 2)
    y = np.asarray(track_xy, dtype=float).reshape(-1, 2)
    m, n = len(x), len(y)
    loc_p, n_assigned = 0.0, 0
    if m and n:
        d = np.minimum(np.hypot(x[:, None, 0] - y[None, :, 0], x[:, None, 1] - y[None, :, 1]),
                       c_m)
        rows, cols = linear_sum_assignment(d ** p)
        dij = d[rows, cols]
        real = dij < c_m
        loc_p = float(np.sum(dij[real] ** p))
        n_assigned = int(real.sum())
    n_missed, n_false = m - n_assigned, n - n_assigned
    total = loc_p + c_m ** p / 2 * (n_missed + n_false)
    return {"gospa_m": total ** (1 / p), "localization_m": loc_p ** (1 / p),
            "n_missed": n_missed, "n_false": n_false, "n_assigned": n_assigned}


# ---------------------------------------------------------------------------------------------
# Helpers


def _check(df: pd.DataFrame, name: str, needs: tuple[str, ...]) -> None:
    if not isinstance(df, pd.DataFrame):
        raise BadInput(f"{name} must be a pandas DataFrame, got {type(df).__name__}")
    missing = [c for c in needs if c not in df.columns]
    if missing:
        raise BadInput(f"{name} is missing columns {missing}")


def _prepare(tracks: pd.DataFrame, truth: pd.DataFrame, cfg: TrackMetricsConfig
             ) -> tuple[pd.DataFrame, pd.DataFrame]:
    _check(tracks, "tracks", _TRACK_NEEDS)
    _check(truth, "truth", _TRUTH_NEEDS)
    conf = tracks[tracks["state"].isin(cfg.confirmed_states)]
    if "actor_class" in truth.columns and cfg.exclude_classes:
        truth = truth[~truth["actor_class"].isin(cfg.exclude_classes)]
    return (conf.sort_values(["frame", "track_id"], kind="stable").reset_index(drop=True),
            truth.sort_values(["frame", "actor_id"], kind="stable").reset_index(drop=True))


def _in_view(truth: pd.DataFrame, cfg: TrackMetricsConfig) -> np.ndarray:
    """(rows,) bool: truth rows inside the radar's field of view."""
    ok = np.ones(len(truth), dtype=bool)
    if cfg.fov_azimuth_deg is not None and "azimuth_deg" in truth.columns:
        ok &= truth["azimuth_deg"].abs().to_numpy() <= cfg.fov_azimuth_deg
    if cfg.max_range_m is not None and "range_m" in truth.columns:
        ok &= truth["range_m"].to_numpy() <= cfg.max_range_m
    return ok


def _matched_rows(truth: pd.DataFrame, matches: pd.DataFrame) -> np.ndarray:
    """(rows,) bool: truth rows (frame, actor) that a track matches (pairs compared as
    int64, by integer keys instead of two MultiIndexes)."""
    def pair(df: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
        return (df["frame"].to_numpy().astype(np.int64),
                df["actor_id"].to_numpy().astype(np.int64))
    return pair_isin(*pair(truth), *pair(matches))


def _footprint_distance(trk_xy: np.ndarray, tru: pd.DataFrame) -> np.ndarray:
    """(n_tracks, n_actors) distance of each track position to each actor's box, m."""
    return _box_distance(trk_xy, _Boxes.of(tru))


class _Boxes(NamedTuple):
    """Actors' boxes as arrays (length, width and yaw None when the table lacks them)."""

    x: np.ndarray
    y: np.ndarray
    yaw_deg: np.ndarray | None
    length: np.ndarray | None
    width: np.ndarray | None

    @classmethod
    def of(cls, tru: pd.DataFrame) -> "_Boxes":
        has_box = "length_m" in tru.columns and "width_m" in tru.columns
        return cls(tru["x_m"].to_numpy(), tru["y_m"].to_numpy(),
                   tru["yaw_deg"].to_numpy() if "yaw_deg" in tru.columns else None,
                   tru["length_m"].to_numpy() if has_box else None,
                   tru["width_m"].to_numpy() if has_box else None)

    def rows(self, a: int, b: int) -> "_Boxes":
        return _Boxes(*(None if v is None else v[a:b] for v in self))


def _box_distance(trk_xy: np.ndarray, box: _Boxes) -> np.ndarray:
    """`_footprint_distance` on `_Boxes`."""
    dx = trk_xy[:, None, 0] - box.x[None, :]
    dy = trk_xy[:, None, 1] - box.y[None, :]
    if box.length is None:
        return np.hypot(dx, dy)
    yaw = np.radians(box.yaw_deg) if box.yaw_deg is not None else 0.0
    c, s = np.cos(yaw), np.sin(yaw)
    along, across = c * dx + s * dy, -s * dx + c * dy
    ex = np.maximum(np.abs(along) - box.length / 2, 0)
    ey = np.maximum(np.abs(across) - box.width / 2, 0)
    return np.hypot(ex, ey)


def _frame_slices(frames: np.ndarray, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.searchsorted(frames, keys, "left"), np.searchsorted(frames, keys, "right")


def _duration_s(tracks: pd.DataFrame, truth: pd.DataFrame, cfg: TrackMetricsConfig) -> float:
    times = np.unique(np.concatenate([tracks["time_s"].to_numpy(float),
                                      truth["time_s"].to_numpy(float)]))
    if times.size >= 2:
        return float(times[-1] - times[0] + np.median(np.diff(times)))
    if times.size == 1 and cfg.frame_period_s is not None:
        return cfg.frame_period_s
    return math.nan


# ---------------------------------------------------------------------------------------------
# Matching and per-frame scores


def match_tracks(tracks: pd.DataFrame, truth: pd.DataFrame,
                 cfg: TrackMetricsConfig | None = None) -> pd.DataFrame:
    """Match confirmed tracks to truth actors in every frame.

    Per frame, `linear_sum_assignment` minimises the summed centre distance over the pairs
    whose footprint distance is within `match_gate_m` (other pairs are forbidden).

    Returns
    -------
    pandas.DataFrame
        One row per matched pair: frame, time_s, track_id, actor_id, dx_m, dy_m, dvx_mps,
        dvy_mps (track minus truth), range_m (truth range: `range_m` column if present,
        else the vehicle-frame distance).
    """
    cfg = TrackMetricsConfig() if cfg is None else cfg
    return _match(*_prepare(tracks, truth, cfg), cfg)


def _match(trk: pd.DataFrame, tru: pd.DataFrame, cfg: TrackMetricsConfig) -> pd.DataFrame:
    """`match_tracks` of the `_prepare`d tables."""
    cols = ["frame", "time_s", "track_id", "actor_id", "dx_m", "dy_m", "dvx_mps", "dvy_mps",
            "range_m"]
    if trk.empty or tru.empty:
        return pd.DataFrame({c: pd.Series(dtype=float) for c in cols})
    t_fr, u_fr = trk["frame"].to_numpy(), tru["frame"].to_numpy()
    common = np.intersect1d(t_fr, u_fr)
    t_lo, t_hi = _frame_slices(t_fr, common)
    u_lo, u_hi = _frame_slices(u_fr, common)
    t_xy = trk[["x_m", "y_m"]].to_numpy(float)
    u_xy = tru[["x_m", "y_m"]].to_numpy(float)
    boxes = _Boxes.of(tru)
    ti_all, ui_all = [], []
    # One small assignment problem per frame (frames are independent).
    for a, b, c, d in zip(t_lo, t_hi, u_lo, u_hi):
        gate = _box_distance(t_xy[a:b], boxes.rows(c, d))
        cost = np.hypot(t_xy[a:b, None, 0] - u_xy[None, c:d, 0],
                        t_xy[a:b, None, 1] - u_xy[None, c:d, 1])
        allowed = gate <= cfg.match_gate_m
        if not allowed.any():
            continue
        rows, cols_ = linear_sum_assignment(np.where(allowed, cost, _BIG))
        ok = allowed[rows, cols_]
        ti_all.append(a + rows[ok])
        ui_all.append(c + cols_[ok])
    if not ti_all:
        return pd.DataFrame({c: pd.Series(dtype=float) for c in cols})
    ti, ui = np.concatenate(ti_all), np.concatenate(ui_all)
    tr, tu = trk.iloc[ti], tru.iloc[ui]
    rng_m = (tu["range_m"].to_numpy(float) if "range_m" in tu.columns
             else np.hypot(tu["x_m"].to_numpy(float), tu["y_m"].to_numpy(float)))
    return pd.DataFrame({
        "frame": tu["frame"].to_numpy(), "time_s": tu["time_s"].to_numpy(float),
        "track_id": tr["track_id"].to_numpy(), "actor_id": tu["actor_id"].to_numpy(),
        "dx_m": tr["x_m"].to_numpy(float) - tu["x_m"].to_numpy(float),
        "dy_m": tr["y_m"].to_numpy(float) - tu["y_m"].to_numpy(float),
        "dvx_mps": tr["vx_mps"].to_numpy(float) - tu["vx_mps"].to_numpy(float),
        "dvy_mps": tr["vy_mps"].to_numpy(float) - tu["vy_mps"].to_numpy(float),
        "range_m": rng_m,
    })


def gospa_per_frame(tracks: pd.DataFrame, truth: pd.DataFrame,
                    cfg: TrackMetricsConfig | None = None,
                    matches: pd.DataFrame | None = None) -> pd.DataFrame:
    """GOSPA of the confirmed tracks' positions against the actors' centres, per frame.

    Frames are the union of the frames of both tables (a frame with tracks but no truth, or
    the reverse, is scored too). The truth set of a frame holds the actors in the field of
    view and those a confirmed track matches (`match_tracks`, computed unless given).

    Returns
    -------
    pandas.DataFrame
        frame, gospa_m, localization_m, n_missed, n_false, n_assigned.
    """
    cfg = TrackMetricsConfig() if cfg is None else cfg
    _check(tracks, "tracks", _TRACK_NEEDS)
    _check(truth, "truth", _TRUTH_NEEDS)
    frames = np.union1d(tracks["frame"].to_numpy(), truth["frame"].to_numpy())
    trk, tru = _prepare(tracks, truth, cfg)
    if matches is None:
        matches = _match(trk, tru, cfg)
    return _gospa(frames, trk, tru, cfg, _matched_rows(tru, matches))


def _gospa(frames: np.ndarray, trk: pd.DataFrame, tru: pd.DataFrame, cfg: TrackMetricsConfig,
           matched: np.ndarray) -> pd.DataFrame:
    """`gospa_per_frame` of the `_prepare`d tables, `matched` = `_matched_rows` of tru."""
    tru = tru[_in_view(tru, cfg) | matched]
    t_fr, u_fr = trk["frame"].to_numpy(), tru["frame"].to_numpy()
    t_lo, t_hi = _frame_slices(t_fr, frames)
    u_lo, u_hi = _frame_slices(u_fr, frames)
    t_xy = trk[["x_m", "y_m"]].to_numpy(float)
    u_xy = tru[["x_m", "y_m"]].to_numpy(float)
    rows = [gospa(u_xy[c:d], t_xy[a:b], cfg.gospa_c_m, cfg.gospa_p)
            for a, b, c, d in zip(t_lo, t_hi, u_lo, u_hi)]
    out = pd.DataFrame(rows, columns=["gospa_m", "localization_m", "n_missed", "n_false",
                                      "n_assigned"])
    out.insert(0, "frame", frames)
    return out


# ---------------------------------------------------------------------------------------------
# Per actor and per run


def per_actor_track_metrics(tracks: pd.DataFrame, truth: pd.DataFrame,
                            cfg: TrackMetricsConfig | None = None,
                            matches: pd.DataFrame | None = None) -> pd.DataFrame:
    """Confirmation, continuity and coverage of every truth actor.

    Returns
    -------
    pandas.DataFrame
        One row per actor seen in the field of view: actor_id, actor_class (if given),
        n_frames (truth rows in the field of view), first_time_s (first such row),
        track_confirm_time_s (time of the first frame a confirmed track matches the actor;
        NaN if never), track_confirm_latency_s (that minus first_time_s; negative when the
        track came before the actor entered the nominal field of view),
        track_confirm_range_m (truth range then), n_track_ids (distinct matched tracks),
        track_id_switches (changes of the matched track id between consecutive matched
        frames [2]), track_fragmentations (times the match resumes after an interruption in
        view), track_coverage (matched frames / truth frames in view).
    """
    cfg = TrackMetricsConfig() if cfg is None else cfg
    trk, tru = _prepare(tracks, truth, cfg)
    if matches is None:
        matches = _match(trk, tru, cfg)
    return _per_actor(tru, cfg, matches, _matched_rows(tru, matches))


def _per_actor(tru: pd.DataFrame, cfg: TrackMetricsConfig, matches: pd.DataFrame,
               matched: np.ndarray) -> pd.DataFrame:
    """`per_actor_track_metrics` of the `_prepare`d truth, `matched` = its
    `_matched_rows`."""
    # The groupby / shift / reindex formulation by integer group codes: rows in (actor,
    # frame) order (a stable lexsort, as the stable sort_values), actors in increasing id
    # order (as groupby sorts them).
    view = _in_view(tru, cfg)
    t_rows = np.flatnonzero(view)
    t_aid, t_frame = tru["actor_id"].to_numpy()[t_rows], tru["frame"].to_numpy()[t_rows]
    order = np.lexsort((t_frame, t_aid))
    t_rows, t_aid = t_rows[order], t_aid[order]
    ids, grp = np.unique(t_aid, return_inverse=True)
    n = ids.size
    n_frames = np.bincount(grp, minlength=n).astype(np.int64)
    first_time = np.full(n, np.nan)
    np.fmin.at(first_time, grp, tru["time_s"].to_numpy(dtype=float)[t_rows])
    cols: dict[str, np.ndarray] = {"actor_id": ids}
    if "actor_class" in tru.columns:
        cls = tru["actor_class"]
        rows = first_valid_rows(grp, cls.notna().to_numpy()[t_rows])
        cols["actor_class"] = cls.array.take(t_rows[rows])
    cols.update(n_frames=n_frames, first_time_s=first_time)
    # Confirmation and identity from every match (also just outside the field of view).
    m_aid, m_frame = matches["actor_id"].to_numpy(), matches["frame"].to_numpy()
    m_order = np.lexsort((m_frame, m_aid))
    m_aid = m_aid[m_order]
    m_tid = matches["track_id"].to_numpy()[m_order]
    m_ids, m_grp = np.unique(m_aid, return_inverse=True)
    pos = np.minimum(np.searchsorted(ids, m_ids), max(n - 1, 0))
    known = (ids[pos] == m_ids) if n else np.zeros(m_ids.size, dtype=bool)

    def first_valid(col: str) -> np.ndarray:
        """Per actor, the column's first non-null value over its matches (NaN if none)."""
        v = matches[col].to_numpy(dtype=float)[m_order]
        ok = ~np.isnan(v)
        g, at = np.unique(m_grp[ok], return_index=True)
        per_m = np.full(m_ids.size, np.nan)
        per_m[g] = v[ok][at]
        out = np.full(n, np.nan)
        out[pos[known]] = per_m[known]
        return out

    def per_actor(counts: np.ndarray) -> np.ndarray:
        """(n,) int64 of per-match-actor counts, 0 for actors without a match."""
        out = np.zeros(n, dtype=np.int64)
        out[pos[known]] = counts[known]
        return out
    confirm = first_valid("time_s")
    cols.update(track_confirm_time_s=confirm, track_confirm_latency_s=confirm - first_time,
                track_confirm_range_m=first_valid("range_m"))
    u_order = np.lexsort((m_tid, m_grp))
    g_s, t_s = m_grp[u_order], m_tid[u_order]
    new_id = np.r_[True, (g_s[1:] != g_s[:-1]) | (t_s[1:] != t_s[:-1])] if g_s.size else \
        np.zeros(0, dtype=bool)
    cols["n_track_ids"] = per_actor(np.bincount(g_s[new_id], minlength=m_ids.size))
    switch = np.r_[False, (m_tid[1:] != m_tid[:-1]) & (m_aid[1:] == m_aid[:-1])] \
        if m_aid.size else np.zeros(0, dtype=bool)
    cols["track_id_switches"] = per_actor(np.bincount(m_grp[switch], minlength=m_ids.size))
    # Fragmentation: an unmatched -> matched transition (in view) after the first match.
    hit = np.asarray(matched, dtype=bool)[t_rows]
    start = np.r_[True, grp[1:] != grp[:-1]] if n else np.zeros(0, dtype=bool)
    prev = np.r_[False, hit[:-1]]  # across an actor boundary seen_before is False
    before = np.cumsum(hit) - hit  # matches before each row, whole table
    seen_before = before - before[start][grp] > 0 if n else np.zeros(0, dtype=bool)
    resume = hit & ~prev & seen_before
    cols["track_fragmentations"] = np.bincount(grp[resume], minlength=n).astype(np.int64)
    cols["track_coverage"] = np.bincount(grp[hit], minlength=n) / n_frames
    return pd.DataFrame(cols)


def track_metrics(tracks: pd.DataFrame, truth: pd.DataFrame,
                  cfg: TrackMetricsConfig | None = None) -> dict[str, float]:
    """All track metrics of one run as one row of named columns (`TRACK_METRIC_COLUMNS`).

    Returns
    -------
    dict
        n_frames, duration_s, n_actors, n_actors_confirmed; track_confirm_time_s_min,
        track_confirm_latency_s_median / _max, track_confirm_range_m_max / _median (over
        confirmed actors); track_id_switches, track_fragmentations (sums over actors);
        track_coverage_mean; n_false_tracks and false_tracks_per_min (confirmed tracks matched
        in fewer than `false_track_max_match_fraction` of their confirmed frames, per minute
        of run); gospa_mean_m, gospa_localization_mean_m, gospa_missed_per_frame,
        gospa_false_per_frame; track_pos_rmse_m, track_vel_rmse_mps (over matched pairs,
        velocity relative to the ego). NaN where undefined (e.g. no match).
    """
    cfg = TrackMetricsConfig() if cfg is None else cfg
    # The confirmed tracks and the sorted truth once, for the matching and every score.
    trk, tru = _prepare(tracks, truth, cfg)
    matches = _match(trk, tru, cfg)
    matched = _matched_rows(tru, matches)
    actors = _per_actor(tru, cfg, matches, matched)
    gos = _gospa(np.union1d(tracks["frame"].to_numpy(), truth["frame"].to_numpy()), trk, tru,
                 cfg, matched)
    duration = _duration_s(tracks, truth, cfg)

    # Per confirmed track: confirmed frames and matched frames (bincount over its id).
    ids, n_conf = np.unique(trk["track_id"].to_numpy(), return_counts=True)
    at = np.searchsorted(ids, matches["track_id"].to_numpy())
    mine = at < ids.size
    mine[mine] = ids[at[mine]] == matches["track_id"].to_numpy()[mine]
    n_match = np.bincount(at[mine], minlength=ids.size)
    n_false = int((n_match / n_conf < cfg.false_track_max_match_fraction).sum())
    conf = actors.dropna(subset=["track_confirm_time_s"])

    def stat(series: pd.Series, how: str) -> float:
        return float(getattr(series, how)()) if len(series) else math.nan

    def rmse(a: str, b: str) -> float:
        if matches.empty:
            return math.nan
        return float(np.sqrt(np.mean(matches[a].to_numpy(float) ** 2
                                     + matches[b].to_numpy(float) ** 2)))

    row = {
        "n_frames": int(len(gos)),
        "duration_s": duration,
        "n_actors": int(len(actors)),
        "n_actors_confirmed": int(len(conf)),
        "track_confirm_time_s_min": stat(conf["track_confirm_time_s"], "min"),
        "track_confirm_latency_s_median": stat(conf["track_confirm_latency_s"], "median"),
        "track_confirm_latency_s_max": stat(conf["track_confirm_latency_s"], "max"),
        "track_confirm_range_m_max": stat(conf["track_confirm_range_m"], "max"),
        "track_confirm_range_m_median": stat(conf["track_confirm_range_m"], "median"),
        "track_id_switches": int(actors["track_id_switches"].sum()),
        "track_fragmentations": int(actors["track_fragmentations"].sum()),
        "track_coverage_mean": stat(actors["track_coverage"], "mean"),
        "n_false_tracks": n_false,
        "false_tracks_per_min": n_false / (duration / 60) if duration > 0 else math.nan,
        "gospa_mean_m": stat(gos["gospa_m"], "mean"),
        "gospa_localization_mean_m": stat(gos["localization_m"], "mean"),
        "gospa_missed_per_frame": stat(gos["n_missed"], "mean"),
        "gospa_false_per_frame": stat(gos["n_false"], "mean"),
        "track_pos_rmse_m": rmse("dx_m", "dy_m"),
        "track_vel_rmse_mps": rmse("dvx_mps", "dvy_mps"),
    }
    return {k: row[k] for k in TRACK_METRIC_COLUMNS}


def track_metrics_long(tracks: pd.DataFrame, truth: pd.DataFrame, *, scenario: str,
                       seed: int, scheme: str,
                       cfg: TrackMetricsConfig | None = None) -> pd.DataFrame:
    """`track_metrics` in long form: columns scenario, seed, scheme, metric, value."""
    row = track_metrics(tracks, truth, cfg)
    return pd.DataFrame({"scenario": scenario, "seed": seed, "scheme": scheme,
                         "metric": list(row), "value": [float(v) for v in row.values()]})
