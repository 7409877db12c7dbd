"""Association of detections with ground-truth actors (design.md section 7).

Every detection of a point cloud gets one label:

TRUE
    inside the footprint gate of a road user (car, truck, motorcycle, bicycle, pedestrian),
    its radial velocity within the velocity gate of that actor's truth and, when the run's
    scatterers are given, within the same position gate of at least one scatterer of that actor
    in that frame (``require_scatterer``): a point inside a truck's box but 14 m from everything
    the truck reflects is not a detection of the truck;
VELOCITY_AMBIGUOUS
    inside the footprint gate of a road user, velocity off by a non-zero multiple k of the
    scheme's unambiguous span 2 Vmax (and within the velocity gate after removing k 2 Vmax);
CLUTTER
    not TRUE / ambiguous but inside the footprint gate of static infrastructure the scene models
    (``actor_class == "guard_rail"``), whatever its velocity;
GHOST
    anything else (sidelobes, DDMA leakage into the empty sub-bands, multipath, noise).

The footprint is the actor's 2D box in the radar frame (centre ``x_radar_m, y_radar_m``, heading
``yaw_radar_deg``, ``length_m`` x ``width_m``); height is ignored because the elevation of a
4-element vertical baseline is too coarse to gate on. The gate is an ellipse around the nearest
point of the box: ``range_gate_m`` along the detection's line of sight (about one range cell)
and ``max(range_gate_m, R tan(azimuth_gate_deg))`` across it, because cross-range error grows
with range while range error does not. The truth radial velocity of a detection is that of the
nearest box point: the actor's relative velocity (``vx_radar_mps, vy_radar_mps``; rigid
translation, no yaw rate) projected on the unit vector to that point.

All pair computations are vectorised over (detection, actor) pairs of the same frame (a pandas
merge on ``frame``); only the one-to-one assignment loops over frames.

References
----------
.. [1] design.md section 7 (association classes) and section 4.1 (1.318 m range cell).
.. [2] H. W. Kuhn, "The Hungarian method for the assignment problem", 1955 (via
       ``scipy.optimize.linear_sum_assignment``).
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment
from scipy.spatial import cKDTree

from core.checks import require
from core.errors import BadInput

from .joins import key_join, pair_index, pair_isin, rows_by_frame, sorted_join, with_columns

__all__ = [
    "AssociationConfig", "LABELS", "TRUE", "VELOCITY_AMBIGUOUS", "GHOST", "CLUTTER",
    "ROAD_USER_CLASSES", "STATIC_CLASSES", "STATIC_SCATTERER_IDS", "associate",
    "detection_errors", "actor_frames",
    "scatterer_table",
]

TRUE = "TRUE"
VELOCITY_AMBIGUOUS = "VELOCITY_AMBIGUOUS"
GHOST = "GHOST"
CLUTTER = "CLUTTER"
#: Labels in order of precedence (a detection takes the first that applies).
LABELS = (TRUE, VELOCITY_AMBIGUOUS, CLUTTER, GHOST)
#: Actor classes that are targets (detections on them can be TRUE).
ROAD_USER_CLASSES = ("car", "truck", "motorcycle", "bicycle", "pedestrian")
#: Static infrastructure: detections on it are CLUTTER, never ghosts.
STATIC_CLASSES = ("guard_rail",)
#: Scatterer actor ids of modelled static clutter without a truth row (radarsim.rcs ground).
STATIC_SCATTERER_IDS = (-2,)

_DET_COLUMNS = ("frame", "x_m", "y_m", "range_m", "radial_velocity_mps")
_TRUTH_COLUMNS = ("frame", "actor_id", "actor_class", "length_m", "width_m", "x_radar_m",
                  "y_radar_m", "yaw_radar_deg", "vx_radar_mps", "vy_radar_mps", "range_m",
                  "azimuth_deg")
#: The truth columns `_pairs` gathers per pair (the class is taken from the column's array).
_PAIR_TRUTH_COLUMNS = ("actor_id", "length_m", "width_m", "x_radar_m", "y_radar_m",
                       "yaw_radar_deg", "vx_radar_mps", "vy_radar_mps")


@dataclass(frozen=True, kw_only=True, slots=True)
class AssociationConfig:
    """Gates of the association and the visibility rule for detection probability.

    Parameters
    ----------
    range_gate_m : float
        Footprint growth along the line of sight, m (default 1.5: one 1.318 m range cell plus
        margin for the interpolation-free range estimate).
    azimuth_gate_deg : float
        Cross-range growth as an angle, deg: the cross-range gate is
        ``max(range_gate_m, R tan(azimuth_gate_deg))`` (default 3 deg, about a third of the
        9.6 deg azimuth resolution).
    velocity_gate_mps : float
        Radial-velocity gate, m/s (default 1.0: ~10 Doppler bins of 0.1065 m/s, enough for
        the spread of radial velocity across an extended body and the azimuth error).
    unambiguity_window_mps : float
        Velocity-unambiguity rate counts detections whose truth |radial velocity| is within
        this window, m/s (default 40.8, the DDMA promise of design.md 4.1).
    fov_deg : float
        An actor-frame counts for detection probability only if |azimuth| <= fov_deg (80 deg,
        the published azimuth FOV) ...
    max_range_m : float
        ... and its centre range <= max_range_m (default 253 m, the 192-bin real-ADC range).
    pd_range_bin_m : float
        Width of the range bins of detection probability versus range, m.
    pd_min_count : int
        Minimum actor-frames in a range bin for its Pd to be used by ``max_range_pd90``.
    require_scatterer : bool
        A detection is TRUE or VELOCITY_AMBIGUOUS of an actor only if it also lies within the
        position gate of one of that actor's scatterers in the frame (when a scatterer table is
        given). Default True; False restores the footprint-only rule (numbers before the fix of
        One point 13.9 m from every scatterer of a truck doubled a range RMSE).

    Raises
    ------
    ValueError
        If a gate or width is not finite and positive, or ``pd_min_count`` < 1.
    """

    range_gate_m: float = 1.5
    azimuth_gate_deg: float = 3.0
    velocity_gate_mps: float = 1.0
    unambiguity_window_mps: float = 40.8
    fov_deg: float = 80.0
    max_range_m: float = 253.0
    pd_range_bin_m: float = 10.0
    pd_min_count: int = 5
    require_scatterer: bool = True

    def __post_init__(self) -> None:
        require(self, ("range_gate_m", "azimuth_gate_deg", "velocity_gate_mps",
                       "unambiguity_window_mps", "fov_deg", "max_range_m", "pd_range_bin_m"),
                gt=0)
        require(self, "azimuth_gate_deg", lt=90, unit="deg")
        require(self, "fov_deg", le=180, unit="deg")
        require(self, "pd_min_count", "integer", ge=1)
        require(self, "require_scatterer", "bool")

    def to_dict(self) -> dict:
        """Plain dict of the gates (for manifests)."""
        return asdict(self)


def _require(df: pd.DataFrame, columns, what: str) -> None:
    missing = [c for c in columns if c not in df.columns]
    if missing:
        raise BadInput(f"{what} lacks column(s) {missing}; has {list(df.columns)}")


def _gate_cost(det_x, det_y, ref_x, ref_y, cfg: AssociationConfig) -> np.ndarray:
    """Position-gate cost (<= 1 inside) of detections at (det_x, det_y) against reference
    points: an ellipse of ``range_gate_m`` along the detection's line of sight and
    ``max(range_gate_m, R tan(azimuth_gate_deg))`` across it."""
    ox, oy = det_x - ref_x, det_y - ref_y
    r_det = np.hypot(det_x, det_y)
    ux, uy = det_x / np.maximum(r_det, 1e-9), det_y / np.maximum(r_det, 1e-9)
    gate_t = np.maximum(cfg.range_gate_m, r_det * math.tan(math.radians(cfg.azimuth_gate_deg)))
    return np.hypot((ox * ux + oy * uy) / cfg.range_gate_m, (-ox * uy + oy * ux) / gate_t)


#: `_pairs` of no pair: its columns and dtypes.
_EMPTY_PAIRS = pd.DataFrame({c: pd.Series(dtype=t) for c, t in (
    ("det_index", "int64"), ("frame", "int64"), ("actor_id", "int64"), ("actor_class", "str"),
    ("is_static", bool), ("pos_cost", float), ("dv_mps", float), ("alias_k", "int64"),
    ("resid_mps", float), ("truth_radial_velocity_mps", float), ("near_x_m", float),
    ("near_y_m", float), ("near_range_m", float), ("box_distance_m", float))})


def _gate_reach(detections: pd.DataFrame, truth: pd.DataFrame, d_i: np.ndarray,
                t_i: np.ndarray, cfg: AssociationConfig) -> np.ndarray:
    """(P,) bool: the detection of pair (d_i, t_i) may lie in the position gate of the actor's
    footprint, i.e. within the gate's larger semi-axis of the box's nearest point.

    `_gate_cost` <= 1 needs the miss distance |o| to the nearest box point within
    ``gate_t = max(range_gate_m, R tan(azimuth_gate_deg))`` (the cost is at least |o| /
    gate_t), and the nearest point lies within the half diagonal of the box centre; so a pair
    whose detection is farther than gate_t + half diagonal from the centre is out of the gate.
    A margin of 1e-6 relative covers the rounding of both distances: every pair in the gate is
    kept, and the kept pairs are computed as before."""
    x, y = detections["x_m"].to_numpy(), detections["y_m"].to_numpy()
    gate_t = np.maximum(cfg.range_gate_m,
                        np.hypot(x, y) * math.tan(math.radians(cfg.azimuth_gate_deg)))
    diag = 0.5 * np.hypot(truth["length_m"].to_numpy(), truth["width_m"].to_numpy())
    dx = x[d_i] - truth["x_radar_m"].to_numpy()[t_i]
    dy = y[d_i] - truth["y_radar_m"].to_numpy()[t_i]
    reach = (gate_t[d_i] + diag[t_i]) * (1 + 1e-6) + 1e-6
    return dx * dx + dy * dy <= reach * reach


def _pairs(detections: pd.DataFrame, truth: pd.DataFrame, cfg: AssociationConfig,
           velocity_span_mps: float, rows: np.ndarray | None = None,
           gated: bool = False) -> pd.DataFrame:
    """All (detection, actor) pairs of the same frame with gate distances.

    `rows` (ascending positions) restricts the truth to those rows: the pairs of
    ``truth.iloc[rows]``, without building that table. With `gated`, only the pairs whose
    detection may lie in the position gate (`_gate_reach`; every pair with pos_cost <= 1 is
    among them, in the same order): on a scene of guard-rail segments most pairs are far
    apart, and `associate` reads only the pairs in the gate.

    Returns a frame with columns det_index, actor_id, actor_class, is_static, pos_cost (gate
    units, <= 1 inside the gate), dv_mps (detection minus truth), alias_k, resid_mps,
    truth_radial_velocity_mps, near_x_m, near_y_m (nearest box point), box_distance_m.
    """
    t_frame = truth["frame"].to_numpy()
    d_i, t_i = sorted_join(detections["frame"].to_numpy(),
                           t_frame if rows is None else t_frame[rows])
    if rows is not None:
        t_i = rows[t_i]
    if gated and d_i.size:
        reach = _gate_reach(detections, truth, d_i, t_i, cfg)
        d_i, t_i = d_i[reach], t_i[reach]
    if not d_i.size:
        return _EMPTY_PAIRS.copy()
    # The joined columns (detection's, then its actor's), gathered by position.
    p = {c: detections[c].to_numpy()[d_i] for c in _DET_COLUMNS}
    p.update((c, truth[c].to_numpy()[t_i]) for c in _PAIR_TRUTH_COLUMNS)
    yaw = np.radians(p["yaw_radar_deg"])
    c, s = np.cos(yaw), np.sin(yaw)
    dx = p["x_m"] - p["x_radar_m"]
    dy = p["y_m"] - p["y_radar_m"]
    # Box-local coordinates, clamped onto the box: nearest point of the (filled) footprint.
    lx, ly = c * dx + s * dy, -s * dx + c * dy
    hl, hw = 0.5 * p["length_m"], 0.5 * p["width_m"]
    qx, qy = np.clip(lx, -hl, hl), np.clip(ly, -hw, hw)
    near_x = p["x_radar_m"] + c * qx - s * qy
    near_y = p["y_radar_m"] + s * qx + c * qy
    ox, oy = p["x_m"] - near_x, p["y_m"] - near_y
    # The miss distance along / across the detection's line of sight, in gate units.
    pos_cost = _gate_cost(p["x_m"], p["y_m"], near_x, near_y, cfg)
    # Truth radial velocity at the nearest box point (rigid translation).
    r_near = np.maximum(np.hypot(near_x, near_y), 1e-9)
    v_true = (p["vx_radar_mps"] * near_x + p["vy_radar_mps"] * near_y) / r_near
    dv = p["radial_velocity_mps"] - v_true
    k = np.rint(dv / velocity_span_mps) if np.isfinite(velocity_span_mps) else np.zeros_like(dv)
    resid = dv - k * (velocity_span_mps if np.isfinite(velocity_span_mps) else 0.0)
    classes = truth["actor_class"]
    return pd.DataFrame({
        "det_index": d_i, "frame": p["frame"],
        "actor_id": p["actor_id"], "actor_class": classes.array.take(t_i),
        "is_static": classes.isin(STATIC_CLASSES).to_numpy()[t_i],
        "pos_cost": pos_cost, "dv_mps": dv, "alias_k": k.astype(np.int64), "resid_mps": resid,
        "truth_radial_velocity_mps": v_true, "near_x_m": near_x, "near_y_m": near_y,
        "near_range_m": r_near, "box_distance_m": np.hypot(ox, oy),
    })


def _scatterer_support(pairs: pd.DataFrame, detections: pd.DataFrame,
                       scatterers: pd.DataFrame, cfg: AssociationConfig) -> np.ndarray:
    """(P,) bool: the pair's detection lies within the position gate of at least one
    scatterer (RCS > 0) of the pair's actor in the same frame."""
    out = np.zeros(len(pairs), dtype=bool)
    if pairs.empty or scatterers is None or scatterers.empty:
        return out
    lit = scatterers["rcs_m2"].to_numpy() > 0
    # Every (pair, lit scatterer of the pair's frame and actor) combination, as the inner join
    # on (frame, actor_id) gives them (order aside: only whether any is in the gate counts).
    p_i, s_i = key_join(pairs["frame"].to_numpy(), pairs["actor_id"].to_numpy(),
                         scatterers["frame"].to_numpy()[lit],
                         scatterers["actor_id"].to_numpy()[lit])
    if not p_i.size:
        return out
    det = pairs["det_index"].to_numpy()[p_i]
    cost = _gate_cost(detections["x_m"].to_numpy()[det], detections["y_m"].to_numpy()[det],
                      scatterers["x_m"].to_numpy()[lit][s_i],
                      scatterers["y_m"].to_numpy()[lit][s_i], cfg)
    out[np.unique(p_i[cost <= 1.0])] = True
    return out


def associate(detections: pd.DataFrame, truth: pd.DataFrame, *, velocity_span_mps: float,
              config: AssociationConfig | None = None,
              scatterers: pd.DataFrame | None = None) -> pd.DataFrame:
    """Label every detection TRUE / VELOCITY_AMBIGUOUS / CLUTTER / GHOST.

    Parameters
    ----------
    detections : DataFrame
        Point cloud of one run, radar frame: columns ``frame``, ``x_m``, ``y_m``,
        ``range_m``, ``radial_velocity_mps`` (others kept).
    truth : DataFrame
        Ground truth of the same run (scenarios' per-frame, per-actor table).
    velocity_span_mps : float
        The scheme's unambiguous span 2 Vmax, m/s (DDMA 81.8, TDMA 20.4). ``inf`` disables the
        ambiguity test.
    config : AssociationConfig, optional
    scatterers : DataFrame, optional
        `scatterer_table` of the run. If given, a detection that would be a GHOST but lies
        within ``range_gate_m`` in range and ``velocity_gate_mps`` in radial velocity of a
        ground-clutter scatterer (``actor_id`` in `STATIC_SCATTERER_IDS`), i.e. in a
        range-Doppler cell the modelled ground occupies, is CLUTTER (``actor_class``
        "ground"): the ground is modelled static infrastructure too. With
        ``config.require_scatterer`` a detection is TRUE / VELOCITY_AMBIGUOUS of an actor only
        within the position gate of one of that actor's scatterers.

    Returns
    -------
    DataFrame
        A copy of ``detections`` (same row order and index) with columns ``label`` (one of
        `LABELS`), ``actor_id`` (int, -1 for ghosts), ``actor_class`` ("" for ghosts),
        ``truth_radial_velocity_mps`` (truth at the nearest box point; NaN for ghosts),
        ``velocity_alias_k`` (multiple of 2 Vmax removed, 0 unless ambiguous),
        ``box_distance_m`` (2D distance to the actor's footprint, 0 inside).

    Notes
    -----
    Among the road users whose gates a detection passes, the one with the smallest cost
    ``pos_cost^2 + (residual velocity / velocity_gate)^2`` wins (TRUE before ambiguous).
    """
    cfg = config or AssociationConfig()
    _require(detections, _DET_COLUMNS, "detections")
    _require(truth, _TRUTH_COLUMNS, "truth")
    if not (velocity_span_mps > 0):
        raise BadInput(f"velocity_span_mps={velocity_span_mps!r} must be > 0 (2 Vmax)")
    n = len(detections)
    label = np.full(n, GHOST, dtype=object)
    actor_id = np.full(n, -1, dtype=np.int64)
    actor_class = np.full(n, "", dtype=object)
    v_true = np.full(n, np.nan)
    alias_k = np.zeros(n, dtype=np.int64)
    box_dist = np.full(n, np.nan)
    # Only pairs in the position gate can label a detection (`_gate_reach`).
    pairs = _pairs(detections, truth, cfg, velocity_span_mps, gated=True)
    if not pairs.empty:
        in_gate = pairs["pos_cost"].to_numpy() <= 1.0
        road = ~pairs["is_static"].to_numpy()
        if cfg.require_scatterer and scatterers is not None:
            road_gate = in_gate & road
            support = np.ones(len(pairs), dtype=bool)
            support[road_gate] = _scatterer_support(pairs[road_gate], detections.reset_index(
                drop=True), scatterers, cfg)
            in_gate = in_gate & (support | ~road)
        vg = cfg.velocity_gate_mps
        is_true = in_gate & road & (np.abs(pairs["dv_mps"].to_numpy()) <= vg)
        is_amb = in_gate & road & ~is_true & (pairs["alias_k"].to_numpy() != 0) & \
            (np.abs(pairs["resid_mps"].to_numpy()) <= vg)
        is_clut = in_gate & ~road
        rank = np.select([is_true, is_amb, is_clut], [0, 1, 2], default=9)
        cost = pairs["pos_cost"].to_numpy() ** 2 + (pairs["resid_mps"].to_numpy() / vg) ** 2
        # Per detection the first candidate pair in (det_index, rank, cost) order, a stable
        # lexsort (what a stable sort_values + drop_duplicates of the table gives).
        cand = np.flatnonzero(rank < 9)
        det_i = pairs["det_index"].to_numpy()[cand]
        order = np.lexsort((cost[cand], rank[cand], det_i))
        first = order[np.r_[True, det_i[order][1:] != det_i[order][:-1]]] if order.size \
            else order
        best, idx = cand[first], det_i[first]
        label[idx] = np.array(LABELS[:3], dtype=object)[rank[best]]
        actor_id[idx] = pairs["actor_id"].to_numpy()[best]
        actor_class[idx] = pairs["actor_class"].array.take(best).to_numpy()  # (not all P)
        v_true[idx] = pairs["truth_radial_velocity_mps"].to_numpy()[best]
        alias_k[idx] = np.where(rank[best] == 1, pairs["alias_k"].to_numpy()[best], 0)
        box_dist[idx] = pairs["box_distance_m"].to_numpy()[best]
    if scatterers is not None and len(scatterers):
        ground = _ground_match(detections, scatterers, cfg) & (label == GHOST)
        label[ground] = CLUTTER
        actor_id[ground] = STATIC_SCATTERER_IDS[0]
        actor_class[ground] = "ground"
    return with_columns(detections, {
        "label": label, "actor_id": actor_id, "actor_class": actor_class,
        "truth_radial_velocity_mps": v_true, "velocity_alias_k": alias_k,
        "box_distance_m": box_dist})


def _ground_match(detections: pd.DataFrame, scatterers: pd.DataFrame,
                  cfg: AssociationConfig) -> np.ndarray:
    """(D,) bool: detection in a range-Doppler cell occupied by modelled ground clutter.

    Ground clutter fills whole range-Doppler cells over many azimuths, so its angle estimate
    is smeared: a detection is explained by the ground if some ground scatterer of the frame
    lies within ``range_gate_m`` in range and ``velocity_gate_mps`` in radial velocity
    (nearest neighbour in (range, v range_gate / velocity_gate) space, cKDTree per frame).
    On a moving ego the ground's radial velocity varies with azimuth, so the velocity match
    still ties the detection to the right cone of directions.
    """
    out = np.zeros(len(detections), dtype=bool)
    g = scatterers[scatterers["actor_id"].isin(STATIC_SCATTERER_IDS)]
    if g.empty or detections.empty:
        return out
    scale = cfg.range_gate_m / cfg.velocity_gate_mps
    det_frame = detections["frame"].to_numpy()
    pts = np.column_stack([detections["range_m"], detections["radial_velocity_mps"] * scale])
    ref_all = np.column_stack([g["range_m"], g["radial_velocity_mps"] * scale])
    det_rows = rows_by_frame(det_frame)
    for frame, at in g.groupby("frame", sort=False).indices.items():
        rows = det_rows.get(frame)
        if rows is None:
            continue
        # Chebyshev distance: both gates must hold.
        d, _ = cKDTree(ref_all[at]).query(pts[rows], p=np.inf)
        out[rows] = d <= cfg.range_gate_m
    return out


def scatterer_table(frames_scatterers) -> pd.DataFrame:
    """Long table of scatterers from ``[(frame, Scatterers), ...]``.

    Returns
    -------
    DataFrame
        Columns frame, actor_id, x_m, y_m, z_m, range_m, radial_velocity_mps, rcs_m2 (radar
        frame, m, m/s, m^2).
    """
    parts = []
    for frame, sc in frames_scatterers:
        pos = np.asarray(sc.position_m)
        parts.append({
            "frame": np.full(len(sc), int(frame), dtype=np.int64),
            "actor_id": np.asarray(sc.actor_id, dtype=np.int64),
            "x_m": pos[:, 0], "y_m": pos[:, 1], "z_m": pos[:, 2],
            "range_m": sc.range_m, "radial_velocity_mps": sc.radial_velocity_mps,
            "rcs_m2": np.asarray(sc.rcs_m2)})
    if not parts:
        return pd.DataFrame({c: pd.Series(dtype=t) for c, t in (
            ("frame", "int64"), ("actor_id", "int64"), ("x_m", float), ("y_m", float),
            ("z_m", float), ("range_m", float), ("radial_velocity_mps", float),
            ("rcs_m2", float))})
    # One table from the joined columns (what concatenating a table per frame gives).
    return pd.DataFrame({c: np.concatenate([p[c] for p in parts]) for c in parts[0]})


def detection_errors(labelled: pd.DataFrame, truth: pd.DataFrame,
                     scatterers: pd.DataFrame | None = None) -> pd.DataFrame:
    """Range and radial-speed error of TRUE detections.

    The reference is the nearest scatterer (2D distance in the radar x-y plane) of the
    detection's actor in the same frame, when a `scatterer_table` is given and the actor has
    scatterers in that frame; otherwise the nearest point of the actor's footprint (its range
    and the rigid-translation radial velocity there). Other labels get NaN.

    Parameters
    ----------
    labelled : DataFrame
        Output of `associate`.
    truth : DataFrame
        Ground truth used for the labelling.
    scatterers : DataFrame, optional
        `scatterer_table` of the run.

    Returns
    -------
    DataFrame
        ``labelled`` with columns ``range_error_m`` (detection minus reference slant range, m),
        ``radial_velocity_error_mps`` (detection minus reference, m/s),
        ``azimuth_error_deg`` (detection minus nearest scatterer azimuth, deg; NaN for a box
        reference) and ``error_reference`` ("scatterer", "box" or "").
    """
    n = len(labelled)
    # The four columns as arrays, set in place and added at the end (in this order).
    rng_err, vel_err = np.full(n, np.nan), np.full(n, np.nan)
    ref, az_err = np.full(n, "", dtype=object), np.full(n, np.nan)

    def finish() -> pd.DataFrame:
        return with_columns(labelled, {
            "range_error_m": rng_err, "radial_velocity_error_mps": vel_err,
            "error_reference": ref, "azimuth_error_deg": az_err})
    is_true = (labelled["label"] == TRUE).to_numpy()
    if not is_true.any():
        return finish()
    pos = np.flatnonzero(is_true)
    # The TRUE rows' columns from arrays (not a take of every column of the table).
    det = pd.DataFrame({c: labelled[c].to_numpy()[pos] for c in (
        "frame", "actor_id", "x_m", "y_m", "range_m", "radial_velocity_mps")})
    det["row"] = pos
    done = np.zeros(len(labelled), dtype=bool)
    if scatterers is not None and len(scatterers):
        # Nearest scatterer of the detection's (frame, actor): every such pair by sorted
        # integer keys (the inner join's pairs, each detection's scatterers in table order),
        # the first smallest d2 per detection (a stable sort by (row, d2), as before).
        p_i, s_i = key_join(det["frame"].to_numpy(), det["actor_id"].to_numpy(),
                             scatterers["frame"].to_numpy(), scatterers["actor_id"].to_numpy())
        if p_i.size:
            col = {c: scatterers[c].to_numpy()[s_i] for c in ("x_m", "y_m", "range_m",
                                                              "radial_velocity_mps")}
            dx, dy = det["x_m"].to_numpy()[p_i], det["y_m"].to_numpy()[p_i]
            d2 = (dx - col["x_m"]) ** 2 + (dy - col["y_m"]) ** 2
            order = np.lexsort((d2, p_i))
            first = order[np.r_[True, p_i[order][1:] != p_i[order][:-1]]]
            p_i, dx, dy = p_i[first], dx[first], dy[first]
            rows = pos[p_i]
            rng_err[rows] = det["range_m"].to_numpy()[p_i] - col["range_m"][first]
            vel_err[rows] = det["radial_velocity_mps"].to_numpy()[p_i] \
                - col["radial_velocity_mps"][first]
            ref[rows] = "scatterer"
            az_err[rows] = np.degrees(np.arctan2(dy, dx)
                                      - np.arctan2(col["y_m"][first], col["x_m"][first]))
            done[rows] = True
    rest = np.flatnonzero(is_true & ~done)
    if len(rest):
        sub = pd.DataFrame({c: labelled[c].to_numpy()[rest] for c in (
            "frame", "x_m", "y_m", "range_m", "actor_id", "radial_velocity_mps")})
        pairs = _pairs(sub, truth, AssociationConfig(), np.inf, rows=np.flatnonzero(
            truth["actor_id"].isin(sub["actor_id"]).to_numpy()))
        pairs = pairs[pairs["actor_id"].to_numpy() == sub["actor_id"].to_numpy()[
            pairs["det_index"].to_numpy()]]
        rows = rest[pairs["det_index"].to_numpy()]
        rng_err[rows] = labelled["range_m"].to_numpy()[rows] - pairs["near_range_m"].to_numpy()
        vel_err[rows] = pairs["dv_mps"].to_numpy()
        ref[rows] = "box"
    return finish()


def actor_frames(labelled: pd.DataFrame, truth: pd.DataFrame, *,
                 scatterers: pd.DataFrame | None = None,
                 config: AssociationConfig | None = None) -> pd.DataFrame:
    """One row per road-user actor and frame: visible, detected, detection count, peak SNR.

    An actor-frame is ``visible`` if the actor's centre is within ``fov_deg`` and
    ``max_range_m`` and, when a scatterer table is given, the ray caster produced at least one
    scatterer with RCS > 0 for it (so occluded actors do not count against Pd). It is
    ``detected`` if a one-to-one assignment (``linear_sum_assignment`` per frame on the cost
    of `associate`, TRUE pairs only) gives it a detection: one detection can detect at most one
    actor, so two motorcycles side by side need two detections.

    Returns
    -------
    DataFrame
        Columns frame, time_s (if in truth), actor_id, actor_class, range_m, azimuth_deg,
        radial_velocity_mps (truth centre), visible, detected, n_true, n_ambiguous,
        max_snr_db (of the actor's TRUE detections; NaN if none).
    """
    cfg = config or AssociationConfig()
    _require(labelled, ("frame", "label", "actor_id", "snr_db"), "labelled detections")
    keep = ["frame", "actor_id", "actor_class", "range_m", "azimuth_deg",
            "radial_velocity_mps"] + (["time_s"] if "time_s" in truth.columns else [])
    af = truth.loc[truth["actor_class"].isin(ROAD_USER_CLASSES), keep].reset_index(drop=True)
    vis = (np.abs(af["azimuth_deg"].to_numpy()) <= cfg.fov_deg) & \
        (af["range_m"].to_numpy() <= cfg.max_range_m)
    af_frame, af_actor = af["frame"].to_numpy(), af["actor_id"].to_numpy()
    if scatterers is not None:
        lit = scatterers["rcs_m2"].to_numpy() > 0
        vis &= pair_isin(af_frame, af_actor, scatterers["frame"].to_numpy()[lit],
                          scatterers["actor_id"].to_numpy()[lit])
    af["visible"] = vis
    label = labelled["label"].to_numpy()
    det_frame, det_actor = labelled["frame"].to_numpy(), labelled["actor_id"].to_numpy()
    snr = labelled["snr_db"].to_numpy()
    # Per actor-frame: TRUE detections, their peak SNR (NaN if none; NaN SNRs skipped) and
    # VELOCITY_AMBIGUOUS detections (a detection counts for the actor-frame it names).
    tru, amb = label == TRUE, label == VELOCITY_AMBIGUOUS
    at_true = pair_index(af_frame, af_actor, det_frame[tru], det_actor[tru])
    hit = at_true >= 0
    max_snr = np.full(len(af), np.nan, dtype=np.result_type(snr.dtype, np.float32))
    np.fmax.at(max_snr, at_true[hit], snr[tru][hit])
    at_amb = pair_index(af_frame, af_actor, det_frame[amb], det_actor[amb])
    af["n_true"] = np.bincount(at_true[hit], minlength=len(af)).astype(np.int64)
    af["max_snr_db"] = max_snr
    af["n_ambiguous"] = np.bincount(at_amb[at_amb >= 0], minlength=len(af)).astype(np.int64)
    af["detected"] = _assign_one_to_one(labelled, truth, af, cfg, scatterers)
    return af


def _assign_one_to_one(labelled: pd.DataFrame, truth: pd.DataFrame, af: pd.DataFrame,
                       cfg: AssociationConfig,
                       scatterers: pd.DataFrame | None = None) -> np.ndarray:
    """Per frame, linear_sum_assignment between TRUE-gated detections and actors."""
    detected = np.zeros(len(af), dtype=bool)
    tru = labelled[labelled["label"] == TRUE]
    if tru.empty:
        return detected
    # Every (TRUE detection, road user) pair that passes both gates, not only the winner:
    # a detection between two actors is a candidate for both.
    span = np.inf
    pairs = _pairs(tru.reset_index(drop=True), truth, cfg, span, rows=np.flatnonzero(
        truth["actor_class"].isin(ROAD_USER_CLASSES).to_numpy()), gated=True)
    if pairs.empty:
        return detected
    ok = (pairs["pos_cost"] <= 1.0) & (pairs["dv_mps"].abs() <= cfg.velocity_gate_mps)
    pairs = pairs[ok]
    if cfg.require_scatterer and scatterers is not None:
        pairs = pairs[_scatterer_support(pairs, tru.reset_index(drop=True), scatterers, cfg)]
    pairs = pairs.assign(cost=pairs["pos_cost"] ** 2 +
                         (pairs["dv_mps"] / cfg.velocity_gate_mps) ** 2)
    row_of = {key: i for i, key in enumerate(zip(af["frame"].to_numpy(),
                                                 af["actor_id"].to_numpy()))}
    p_det, p_act = pairs["det_index"].to_numpy(), pairs["actor_id"].to_numpy()
    p_cost = pairs["cost"].to_numpy()
    for frame, at in pairs.groupby("frame", sort=False).indices.items():
        dets, d_inv = np.unique(p_det[at], return_inverse=True)
        acts, a_inv = np.unique(p_act[at], return_inverse=True)
        big = 1e6
        cost = np.full((len(dets), len(acts)), big)
        cost[d_inv, a_inv] = p_cost[at]
        r, c = linear_sum_assignment(cost)
        for a in acts[c[cost[r, c] < big]]:
            i = row_of.get((frame, a))
            if i is not None:
                detected[i] = True
    return detected
