"""Group tracker: radar point clouds to tracks, after TI's gtrack design.

Every frame: predict, gate, associate, update, allocate, maintain (seed 001 figure 11). Each
track is an extended Kalman filter in Cartesian vehicle-frame coordinates (ISO 8855: x forward,
y left) whose measurements are the range, azimuth and radial velocity of the points of its group:
several points per vehicle, summarised by their centroid and dispersion. Unassociated points
start tracks by leader clustering; a track is DETECT until it has enough consecutive hits,
then ACTIVE, and is freed after too many consecutive misses.

Velocity convention. The state velocity is the target's velocity RELATIVE to the ego,
expressed in the vehicle frame (what the radar measures and what the ground truth of the
scenarios gives). Ego motion is accounted for where it matters: the radar's velocity over
ground (the ego speed passed in, or estimated by RANSAC over the frame's points, plus the
lateral part a lane change brings, `pipeline.ego_motion`) labels points static or moving,
static points neither start tracks nor confirm DETECT tracks unless configured, the
allocation speed threshold applies to the ground (ego-compensated) radial velocity, and the
output also carries the ground velocity (relative + radar velocity over ground). The ego's
own acceleration and yaw rate enter as process noise.

References
----------
.. [1] TI, "AWR1642 velocity disambiguation" (seed 001), section 5, figure 11.
.. [2] TI mmWave SDK, "Group tracker" (gtrack) design: gating with group dispersion,
       centroid noise Rc = Rm / n + alpha D, alpha = (N_est - n) / ((N_est - 1) n),
       DETECT -> ACTIVE -> FREE with det2act = 3, det2free = 3, act2free = 10.
.. [3] Y. Bar-Shalom, X. R. Li, T. Kirubarajan, "Estimation with Applications to Tracking and
       Navigation", Wiley 2001, sections 5.2 and 6.2 (discrete white-noise acceleration and
       jerk models) and 10.3 (EKF).
.. [4] Y. Bar-Shalom, "Multitarget-Multisensor Tracking", vol. II, p. 117 (centroid noise).
"""
from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from pipeline.ego_motion import EgoMotionConfig, estimate_ego_motion, static_mask

__all__ = [
    "TrackerConfig", "GroupTracker", "track_frames", "MotionModel", "MOTION_MODELS",
    "TRACK_COLUMNS", "TRACK_STATES",
]

#: Track states of the maintenance state machine (FREE tracks are dropped from the output).
TRACK_STATES = ("DETECT", "ACTIVE")

#: Columns of the per-frame track table, in order.
TRACK_COLUMNS = (
    "track_id", "state", "x_m", "y_m", "vx_mps", "vy_mps", "ax_mps2", "ay_mps2",
    "var_x_m2", "var_y_m2", "cov_xy_m2", "var_vx_m2ps2", "var_vy_m2ps2", "cov_vxvy_m2ps2",
    "vx_ground_mps", "vy_ground_mps", "n_points", "age_frames", "time_s",
)

_POINT_COLUMNS = ("range_m", "azimuth_deg", "radial_velocity_mps", "snr_db")


@dataclass(frozen=True, slots=True)
class MotionModel:
    """A linear motion model of the 2D state [x, y, vx, vy(, ax, ay)].

    Attributes
    ----------
    name : str
    n_state : int
        4 (constant velocity) or 6 (constant acceleration).
    transition : callable(dt_s) -> (n_state, n_state) float
    process_noise : callable(dt_s, sigma) -> (n_state, n_state) float
        Discrete white-noise acceleration (CV, sigma in m/s^2) or jerk (CA, m/s^3) [3].
    """

    name: str
    n_state: int
    transition: Callable[[float], np.ndarray]
    process_noise: Callable[[float, float], np.ndarray]


def _per_axis(block: np.ndarray) -> np.ndarray:
    # State order is [x, y, vx, vy, ax, ay]: derivative order major, axis minor.
    return np.kron(block, np.eye(2))


def _cv_transition(dt: float) -> np.ndarray:
    return _per_axis(np.array([[1.0, dt], [0.0, 1.0]]))


def _cv_noise(dt: float, sigma: float) -> np.ndarray:
    g = np.array([dt * dt / 2, dt])
    return _per_axis(np.outer(g, g)) * sigma ** 2


def _ca_transition(dt: float) -> np.ndarray:
    return _per_axis(np.array([[1.0, dt, dt * dt / 2], [0.0, 1.0, dt], [0.0, 0.0, 1.0]]))


def _ca_noise(dt: float, sigma: float) -> np.ndarray:
    g = np.array([dt ** 3 / 6, dt * dt / 2, dt])
    return _per_axis(np.outer(g, g)) * sigma ** 2


#: Motion models by the name users type in `TrackerConfig.motion_model`.
MOTION_MODELS: dict[str, MotionModel] = {
    "cv": MotionModel("cv", 4, _cv_transition, _cv_noise),
    "ca": MotionModel("ca", 6, _ca_transition, _ca_noise),
}


@dataclass(frozen=True, kw_only=True, slots=True)
class TrackerConfig:
    """Settings of the group tracker (all SI, unit in the name).

    Parameters
    ----------
    motion_model : {"cv", "ca"}
        Constant velocity or constant acceleration, see `MOTION_MODELS`.
    frame_period_s : float
        Time step used for the first frame (afterwards the difference of `time_s`).
    mount_x_m, mount_y_m, mount_yaw_deg : float
        Radar pose in the vehicle frame: p_vehicle = Rz(yaw) p_radar + mount.
    range_std_m, azimuth_std_deg, radial_velocity_std_mps : float
        Per-point measurement noise (diagonal Rm).
    process_noise_accel_mps2 : float
        CV model: standard deviation of the white-noise acceleration (includes the ego's).
    process_noise_jerk_mps3 : float
        CA model: standard deviation of the white-noise jerk.
    gate_mahalanobis : float
        Gate on the squared Mahalanobis distance of a point to a group, with the group
        residual covariance H P H' + Rm + D (D: group dispersion). Default: the chi-square
        99.9 % point for 3 degrees of freedom.
    gate_depth_m, gate_width_m, gate_velocity_mps : float
        Hard gating limits: largest distance of a point from the predicted centroid along the
        line of sight (depth) and across it (width), and largest radial-velocity difference.
    group_depth_m, group_width_m, group_velocity_spread_mps : float
        Expected extent of a group (initial dispersion, uniform spread: extent^2 / 12).
    dispersion_update_weight : float
        Weight of a frame's sample dispersion in the running dispersion estimate, (0, 1].
    centroid_jitter_weight : float
        Centroid noise Rc = Rm / n + (alpha + w / n) D: w = 0 is TI's formula (a fixed set of
        reflection points), w = 1 treats each frame's points as a fresh sample of the body.
    alloc_min_points : int
        Fewest points in a cluster to start a track.
    alloc_min_snr_db : float
        Smallest summed (linear) SNR of a cluster to start a track, dB.
    alloc_min_speed_mps : float
        Smallest |ground radial velocity| of a cluster centroid to start a track (ignored
        when `allow_static_tracks`). Without an ego-speed estimate the measured radial
        velocity is used.
    alloc_range_m, alloc_azimuth_deg, alloc_radial_velocity_mps : float
        Leader clustering: a point joins the leader's cluster when it is within these
        distances of the leader in range, azimuth and radial velocity.
    init_velocity_std_mps : float
        Initial standard deviation of the (unobserved) cross-range velocity.
    init_accel_std_mps2 : float
        Initial standard deviation of the acceleration (CA model).
    hits_to_confirm : int
        Consecutive hits that promote DETECT to ACTIVE (TI det2act: 3).
    misses_to_free_detect : int
        Consecutive misses that free a DETECT track (TI det2free: 3).
    misses_to_free_active : int
        Consecutive misses that free an ACTIVE track (TI act2free: 10).
    max_tracks : int
        Most live tracks; allocation stops there.
    merge_tracks : bool
        Keep one track per group (an addition to TI's design): a cluster of the same group as
        a live track or a stronger cluster starts no track, and a track duplicating another
        is freed. Otherwise a vehicle whose points fall into two leader clusters keeps two
        tracks that share its points.
    merge_depth_m, merge_width_m, merge_velocity_mps : float
        Duplicate test: centroids within these distances along and across the line of sight
        (across: plus 2 x range x azimuth sigma) and radial velocities within this difference.
        Keep merge_width_m below the lane width, so vehicles abreast at the same speed stay
        separate where the radar can resolve them.
    allow_static_tracks : bool
        Whether static points may start tracks.
    static_threshold_mps : float
        Static labelling with a known ego speed, see `pipeline.ego_motion.static_mask`.
    ego_motion : EgoMotionConfig
        RANSAC settings: the whole ego velocity when `step` gets no ego speed, the lateral
        part only (planar model) when it does.

    Raises
    ------
    ValueError
        On a value out of its domain; the message names the field, the value and the limit.
    """

    motion_model: str = "cv"
    frame_period_s: float = 0.05
    mount_x_m: float = 0.0
    mount_y_m: float = 0.0
    mount_yaw_deg: float = 0.0
    range_std_m: float = 0.25
    azimuth_std_deg: float = 1.5
    radial_velocity_std_mps: float = 0.15
    process_noise_accel_mps2: float = 3.0
    process_noise_jerk_mps3: float = 10.0
    gate_mahalanobis: float = 16.27
    gate_depth_m: float = 5.0
    gate_width_m: float = 3.0
    gate_velocity_mps: float = 3.0
    group_depth_m: float = 4.0
    group_width_m: float = 1.8
    group_velocity_spread_mps: float = 1.0
    dispersion_update_weight: float = 0.2
    centroid_jitter_weight: float = 1.0
    alloc_min_points: int = 1
    alloc_min_snr_db: float = 15.0
    alloc_min_speed_mps: float = 0.5
    alloc_range_m: float = 5.0
    alloc_azimuth_deg: float = 4.0
    alloc_radial_velocity_mps: float = 1.0
    init_velocity_std_mps: float = 10.0
    init_accel_std_mps2: float = 3.0
    hits_to_confirm: int = 3
    misses_to_free_detect: int = 3
    misses_to_free_active: int = 10
    max_tracks: int = 256
    merge_tracks: bool = True
    merge_depth_m: float = 5.0
    merge_width_m: float = 2.0
    merge_velocity_mps: float = 1.0
    allow_static_tracks: bool = False
    static_threshold_mps: float = 0.3
    ego_motion: EgoMotionConfig = field(default_factory=EgoMotionConfig)

    def __post_init__(self) -> None:
        if self.motion_model not in MOTION_MODELS:
            raise ValueError(f"motion_model={self.motion_model!r} is not one of "
                             f"{sorted(MOTION_MODELS)}")
        for name in ("mount_x_m", "mount_y_m", "mount_yaw_deg", "alloc_min_snr_db"):
            val = getattr(self, name)
            if not math.isfinite(val):
                raise ValueError(f"{name}={val!r} must be finite")
        for name in ("frame_period_s", "range_std_m", "azimuth_std_deg",
                     "radial_velocity_std_mps", "process_noise_accel_mps2",
                     "process_noise_jerk_mps3", "gate_mahalanobis", "gate_depth_m",
                     "gate_width_m", "gate_velocity_mps", "group_depth_m", "group_width_m",
                     "group_velocity_spread_mps", "alloc_range_m", "alloc_azimuth_deg",
                     "alloc_radial_velocity_mps", "init_velocity_std_mps",
                     "init_accel_std_mps2", "static_threshold_mps", "merge_depth_m",
                     "merge_width_m", "merge_velocity_mps"):
            val = getattr(self, name)
            if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
                raise ValueError(f"{name}={val!r} must be a finite number > 0")
        if not (math.isfinite(self.alloc_min_speed_mps) and self.alloc_min_speed_mps >= 0):
            raise ValueError(f"alloc_min_speed_mps={self.alloc_min_speed_mps!r} must be a "
                             "finite number >= 0")
        if not (math.isfinite(self.centroid_jitter_weight) and self.centroid_jitter_weight >= 0):
            raise ValueError(f"centroid_jitter_weight={self.centroid_jitter_weight!r} must be "
                             "a finite number >= 0")
        if not 0 < self.dispersion_update_weight <= 1:
            raise ValueError(f"dispersion_update_weight={self.dispersion_update_weight!r} "
                             "must be in (0, 1]")
        for name in ("alloc_min_points", "hits_to_confirm", "misses_to_free_detect",
                     "misses_to_free_active", "max_tracks"):
            val = getattr(self, name)
            if not isinstance(val, (int, np.integer)) or isinstance(val, bool) or val < 1:
                raise ValueError(f"{name}={val!r} must be an integer >= 1")
        for name in ("allow_static_tracks", "merge_tracks"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name}={getattr(self, name)!r} must be a bool")
        if not isinstance(self.ego_motion, EgoMotionConfig):
            raise ValueError(f"ego_motion={self.ego_motion!r} must be an EgoMotionConfig")

    @property
    def n_state(self) -> int:
        """Length of the state vector (4 for CV, 6 for CA)."""
        return MOTION_MODELS[self.motion_model].n_state

    @property
    def measurement_noise(self) -> np.ndarray:
        """Per-point measurement covariance Rm, (3, 3): range m^2, azimuth rad^2, (m/s)^2."""
        return np.diag([self.range_std_m ** 2, math.radians(self.azimuth_std_deg) ** 2,
                        self.radial_velocity_std_mps ** 2])

    @property
    def process_noise_sigma(self) -> float:
        """The process-noise intensity of the selected motion model."""
        return (self.process_noise_accel_mps2 if self.motion_model == "cv"
                else self.process_noise_jerk_mps3)


# ---------------------------------------------------------------------------------------------
# Pure kernels


def _wrap_pi(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


def measurement_model(state: np.ndarray, mount_xy_m: np.ndarray, mount_yaw_rad: float
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Predicted measurements and their Jacobians for a batch of states.

    Parameters
    ----------
    state : (T, n_state) float
        [x, y, vx, vy(, ax, ay)] in the vehicle frame, m, m/s (relative velocity).
    mount_xy_m : (2,) float
        Radar position in the vehicle frame, m.
    mount_yaw_rad : float
        Radar boresight yaw in the vehicle frame, rad.

    Returns
    -------
    h : (T, 3) float
        Range m, radar-frame azimuth rad, radial velocity m/s.
    jac : (T, 3, n_state) float
        d h / d state.
    """
    d = state[:, :2] - mount_xy_m
    v = state[:, 2:4]
    r2 = np.maximum(np.einsum("ti,ti->t", d, d), 1e-6)
    r = np.sqrt(r2)
    dv = np.einsum("ti,ti->t", d, v)
    h = np.column_stack([r, _wrap_pi(np.arctan2(d[:, 1], d[:, 0]) - mount_yaw_rad), dv / r])
    jac = np.zeros((state.shape[0], 3, state.shape[1]))
    jac[:, 0, 0:2] = d / r[:, None]
    jac[:, 1, 0] = -d[:, 1] / r2
    jac[:, 1, 1] = d[:, 0] / r2
    jac[:, 2, 0:2] = v / r[:, None] - d * (dv / (r2 * r))[:, None]
    jac[:, 2, 2:4] = d / r[:, None]
    return h, jac


def leader_clusters(range_m: np.ndarray, azimuth_rad: np.ndarray, radial_velocity_mps: np.ndarray,
                    snr_db: np.ndarray, max_range_m: float, max_azimuth_rad: float,
                    max_velocity_mps: float, min_points: int) -> list[np.ndarray]:
    """Leader clustering of points in range, azimuth and radial velocity.

    Points are visited in order of decreasing SNR; each unclaimed point leads a cluster of the
    unclaimed points within the three distances of it. A cluster with fewer than
    `min_points` members is dropped and only its leader is retired, so its members stay
    available to later leaders. The (M, M) neighbourhood matrix is computed once; points whose
    whole neighbourhood is too small never lead (which keeps sparse clutter cheap).

    Parameters
    ----------
    range_m, azimuth_rad, radial_velocity_mps, snr_db : (M,) float
    max_range_m, max_azimuth_rad, max_velocity_mps : float
        Cluster half-widths around the leader.
    min_points : int

    Returns
    -------
    list of (k,) int arrays
        Member indices of each accepted cluster, leader first.
    """
    m = range_m.size
    if m < min_points:
        return []
    near = ((np.abs(range_m[:, None] - range_m[None, :]) <= max_range_m)
            & (np.abs(_wrap_pi(azimuth_rad[:, None] - azimuth_rad[None, :])) <= max_azimuth_rad)
            & (np.abs(radial_velocity_mps[:, None] - radial_velocity_mps[None, :])
               <= max_velocity_mps))
    order = np.argsort(-snr_db, kind="stable")
    leaders = order[near.sum(axis=1)[order] >= min_points]
    free = np.ones(m, dtype=bool)
    clusters = []
    # Sequential by nature (each cluster claims points from the next); one pass per leader.
    for lead in leaders:
        if not free[lead]:
            continue
        members = np.flatnonzero(near[lead] & free)
        if members.size >= min_points:
            members = np.concatenate(([lead], members[members != lead]))
            free[members] = False
            clusters.append(members)
        else:
            free[lead] = False
    return clusters


# ---------------------------------------------------------------------------------------------
# Stage object


class GroupTracker:
    """TI-style group tracker over a sequence of radar frames.

    Parameters
    ----------
    cfg : TrackerConfig, optional
        Defaults to `TrackerConfig()`.
    rng : numpy.random.Generator, optional
        Source of the RANSAC samples of the ego-motion estimate (used only when `step` gets no
        ego speed). Default: `numpy.random.default_rng(0)`, so a run is reproducible.

    Notes
    -----
    The tracker is the one stateful stage of the pipeline: it keeps its tracks between calls
    (struct-of-arrays, T live tracks). `step` returns the live tracks; nothing else of a frame
    is kept on the object.
    """

    def __init__(self, cfg: TrackerConfig | None = None,
                 rng: np.random.Generator | None = None) -> None:
        self.cfg = TrackerConfig() if cfg is None else cfg
        if not isinstance(self.cfg, TrackerConfig):
            raise ValueError(f"cfg must be a TrackerConfig, got {type(self.cfg).__name__}")
        self._rng = np.random.default_rng(0) if rng is None else rng
        self._model = MOTION_MODELS[self.cfg.motion_model]
        self._mount = np.array([self.cfg.mount_x_m, self.cfg.mount_y_m])
        self._yaw = math.radians(self.cfg.mount_yaw_deg)
        self._rm = self.cfg.measurement_noise
        self.reset()

    def reset(self) -> None:
        """Drop every track and forget the time of the last frame."""
        n = self._model.n_state
        self._id = np.zeros(0, dtype=np.int64)
        self._x = np.zeros((0, n))
        self._p = np.zeros((0, n, n))
        self._disp = np.zeros((0, 3, 3))
        self._n_est = np.zeros(0)
        self._hits = np.zeros(0, dtype=np.int64)
        self._misses = np.zeros(0, dtype=np.int64)
        self._age = np.zeros(0, dtype=np.int64)
        self._active = np.zeros(0, dtype=bool)
        self._next_id = 0
        self._last_time_s: float | None = None
        self._last_ego: tuple[float, float] | None = None

    @property
    def n_tracks(self) -> int:
        """Number of live (DETECT or ACTIVE) tracks."""
        return int(self._id.size)

    # -- public --------------------------------------------------------------------------------

    def step(self, points: pd.DataFrame, time_s: float,
             ego_speed_mps: float | None = None) -> pd.DataFrame:
        """Advance the tracker by one frame.

        Parameters
        ----------
        points : pandas.DataFrame
            The frame's point cloud in the RADAR frame, columns at least range_m,
            azimuth_deg, radial_velocity_mps (relative to the radar) and snr_db; one row per
            detection (may be empty).
        time_s : float
            Frame time, s; must increase from call to call.
        ego_speed_mps : float, optional
            Ego speed along +x of the vehicle frame, m/s. When None it is estimated from the
            frame's points by RANSAC (the last valid estimate is kept when RANSAC fails).

        Returns
        -------
        pandas.DataFrame
            One row per live track, columns `TRACK_COLUMNS`: track_id (int), state ("DETECT"
            or "ACTIVE"), x_m, y_m (vehicle frame, the group centroid), vx_mps, vy_mps
            (relative to the ego), ax_mps2, ay_mps2 (NaN for the CV model), covariance entries
            var_x_m2, var_y_m2, cov_xy_m2, var_vx_m2ps2, var_vy_m2ps2, cov_vxvy_m2ps2,
            vx_ground_mps, vy_ground_mps (relative + radar velocity over ground; NaN without
            an ego-speed estimate),
            n_points (points associated this frame), age_frames, time_s.

        Raises
        ------
        ValueError
            On a missing column, non-finite values, or a time that does not increase.
        """
        return self.step_with_points(points, time_s, ego_speed_mps)[0]

    def step_with_points(self, points: pd.DataFrame, time_s: float,
                         ego_speed_mps: float | None = None
                         ) -> tuple[pd.DataFrame, pd.DataFrame]:
        """As `step`, also returning the points labelled with `track_id` (-1: none; the id of
        a track started from them counts) and `is_static`."""
        cfg = self.cfg
        r, az, vr, snr = _point_arrays(points)
        dt = self._time_step(time_s)

        static, ego = self._ego_motion(np.degrees(az), vr, ego_speed_mps)

        self._predict(dt)
        assoc, innov, jac = self._associate(r, az, vr, static)
        n_pts = self._update(assoc, innov, jac)
        self._maintain(n_pts > 0)
        keep = self._misses < np.where(self._active, cfg.misses_to_free_active,
                                       cfg.misses_to_free_detect)
        if cfg.merge_tracks:
            keep &= ~self._duplicates()
        self._select(keep)
        n_pts = n_pts[keep]
        assoc_id = np.full(r.size, -1, dtype=np.int64)
        if self._id.size:
            # Map association indices (pre-freeing) to ids; points of freed tracks get -1.
            old_index = np.cumsum(keep) - 1
            hit = assoc >= 0
            ok = hit.copy()
            ok[hit] = keep[assoc[hit]]
            assoc_id[ok] = self._id[old_index[assoc[ok]]]
        n_new = self._allocate(r, az, vr, snr, static, assoc, ego, assoc_id)
        n_pts = np.concatenate([n_pts, n_new])

        self._last_time_s = float(time_s)
        tracks = self._table(n_pts, float(time_s), ego)
        labelled = points.copy() if len(points) else pd.DataFrame(
            {c: np.zeros(0) for c in _POINT_COLUMNS})
        labelled["track_id"] = assoc_id
        labelled["is_static"] = static
        return tracks, labelled

    # -- stages ----------------------------------------------------------------------------------

    def _time_step(self, time_s: float) -> float:
        if not math.isfinite(time_s):
            raise ValueError(f"time_s={time_s!r} must be finite")
        if self._last_time_s is None:
            return self.cfg.frame_period_s
        dt = float(time_s) - self._last_time_s
        if dt <= 0:
            raise ValueError(f"time_s={time_s!r} must exceed the previous frame's time "
                             f"{self._last_time_s!r}")
        return dt

    def _ego_motion(self, az_deg: np.ndarray, vr: np.ndarray, ego_speed_mps: float | None
                    ) -> tuple[np.ndarray, tuple[float, float] | None]:
        """Static labels of the points and the radar velocity over ground (v_x, v_y) used this
        frame (None: unknown).

        A given ego speed is the speed over ground (vehicle bus). With the planar ego-motion
        model the frame's RANSAC estimate (v_x, v_y) is used when it agrees with that speed
        (|hypot(v_x, v_y) - speed| <= 0.5 m/s + 5 %): in a lane change the velocity is not
        along the vehicle's x axis, and taking the bus speed as v_x mislabels the static world
        seen to the side. Otherwise (v_x, v_y) = (speed, 0). Without a speed both are
        estimated; the last valid estimate is kept when RANSAC fails. Points are labelled
        with the same rule (`static_mask`) whichever the source.
        """
        cfg = self.cfg
        if ego_speed_mps is not None:
            if not math.isfinite(ego_speed_mps):
                raise ValueError(f"ego_speed_mps={ego_speed_mps!r} must be finite or None")
            speed = float(ego_speed_mps)
            self._last_ego = (speed, 0.0)
            if cfg.ego_motion.model == "planar":
                est = estimate_ego_motion(az_deg, vr, self._rng, cfg.mount_yaw_deg,
                                          cfg.ego_motion)
                if est.valid and abs(math.hypot(est.ego_speed_mps, est.ego_lateral_mps)
                                     - abs(speed)) <= 0.5 + 0.05 * abs(speed):
                    self._last_ego = (est.ego_speed_mps, est.ego_lateral_mps)
            ego = self._last_ego
        else:
            est = estimate_ego_motion(az_deg, vr, self._rng, cfg.mount_yaw_deg, cfg.ego_motion)
            if est.valid:
                self._last_ego = (est.ego_speed_mps, est.ego_lateral_mps)
            ego = self._last_ego
        if ego is None:
            return np.zeros(az_deg.size, dtype=bool), None
        static = static_mask(az_deg, vr, ego[0], cfg.mount_yaw_deg, cfg.static_threshold_mps,
                             cfg.azimuth_std_deg, ego_lateral_mps=ego[1])
        return static, ego

    def _predict(self, dt: float) -> None:
        if not self._id.size:
            return
        f = self._model.transition(dt)
        q = self._model.process_noise(dt, self.cfg.process_noise_sigma)
        self._x = self._x @ f.T
        self._p = f @ self._p @ f.T + q

    def _associate(self, r: np.ndarray, az: np.ndarray, vr: np.ndarray, static: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Maximum-likelihood association of each point to one gated track.

        Static points may update ACTIVE tracks (a vehicle that stops) but, unless
        `allow_static_tracks`, not DETECT ones: otherwise a track started by a false alarm
        next to a guard rail is confirmed by the rail.

        Returns the track index per point (-1: none), (N, 3) innovations of each point
        against its track and the (T, 3, n_state) measurement Jacobians."""
        cfg = self.cfg
        n, t = r.size, self._id.size
        if n == 0 or t == 0:
            return (np.full(n, -1, dtype=np.int64), np.zeros((n, 3)),
                    np.zeros((t, 3, self._model.n_state)))
        h, jac = measurement_model(self._x, self._mount, self._yaw)
        s_grp = jac @ self._p @ jac.transpose(0, 2, 1) + self._rm + self._disp   # (T, 3, 3)
        s_inv = np.linalg.inv(s_grp)
        _, logdet = np.linalg.slogdet(s_grp)
        y = np.stack([r[None, :] - h[:, 0:1], _wrap_pi(az[None, :] - h[:, 1:2]),
                      vr[None, :] - h[:, 2:3]], axis=-1)                       # (T, N, 3)
        d2 = np.sum((y @ s_inv) * y, axis=-1)                                      # (T, N)
        # Hard limits in depth (along the line of sight to the predicted centroid) and width,
        # widened by 3 sigma of the point noise so far groups are not cut by the azimuth error.
        theta_t = h[:, 1] + self._yaw
        los = np.stack([np.cos(theta_t), np.sin(theta_t)], axis=-1)              # (T, 2)
        theta_p = az + self._yaw
        pts = self._mount + r[:, None] * np.column_stack([np.cos(theta_p), np.sin(theta_p)])
        delta = pts[None, :, :] - self._x[:, None, :2]                           # (T, N, 2)
        depth = delta[..., 0] * los[:, None, 0] + delta[..., 1] * los[:, None, 1]
        width = delta[..., 1] * los[:, None, 0] - delta[..., 0] * los[:, None, 1]
        width_lim = cfg.gate_width_m + 3 * h[:, 0:1] * math.radians(cfg.azimuth_std_deg)
        gated = ((d2 <= cfg.gate_mahalanobis)
                 & (np.abs(depth) <= cfg.gate_depth_m + 3 * cfg.range_std_m)
                 & (np.abs(width) <= width_lim)
                 & (np.abs(y[..., 2]) <= cfg.gate_velocity_mps))
        if not cfg.allow_static_tracks:
            gated &= ~(static[None, :] & ~self._active[:, None])
        score = np.where(gated, d2 + logdet[:, None], np.inf)
        best = np.argmin(score, axis=0)
        ok = np.isfinite(score[best, np.arange(n)])
        return np.where(ok, best, -1), y[best, np.arange(n)], jac

    def _update(self, assoc: np.ndarray, innov: np.ndarray, jac: np.ndarray) -> np.ndarray:
        """Group EKF update with the centroid of each track's points; returns points/track."""
        cfg = self.cfg
        t = self._id.size
        hit = assoc >= 0
        counts = np.bincount(assoc[hit], minlength=t).astype(np.int64)
        upd = np.flatnonzero(counts > 0)
        if upd.size == 0:
            return counts
        idx = assoc[hit]
        y = innov[hit]                                                            # (K, 3)
        nk = counts[upd].astype(float)
        ybar = np.zeros((t, 3))
        np.add.at(ybar, idx, y)
        ybar = ybar[upd] / nk[:, None]
        # Sample dispersion of the points about their centroid (measurement space).
        dev = y - _scatter(t, upd, ybar)[idx]
        scat = np.zeros((t, 3, 3))
        np.add.at(scat, idx, dev[:, :, None] * dev[:, None, :])
        scat = scat[upd]
        # Centroid noise: TI's Rc = Rm / n + alpha D [2], [4] treats D as a fixed set of
        # members of which n are seen; a vehicle's reflection points change from frame to
        # frame, so the centroid also jitters by D / n (sampling of the body).
        n_est = np.maximum(self._n_est[upd], nk)
        n_est = n_est + 0.1 * (nk - n_est)
        alpha = np.where(n_est > 1, np.maximum(n_est - nk, 0) / (np.maximum(n_est - 1, 1e-9) * nk),
                         0.0)
        disp = self._disp[upd]
        r_c = (self._rm / nk[:, None, None]
               + (alpha + cfg.centroid_jitter_weight / nk)[:, None, None] * disp)
        p, jac = self._p[upd], jac[upd]
        pht = p @ jac.transpose(0, 2, 1)
        s = jac @ pht + r_c
        gain = np.linalg.solve(s, pht.transpose(0, 2, 1)).transpose(0, 2, 1)     # (U, n, 3)
        self._x[upd] += np.einsum("uij,uj->ui", gain, ybar)
        p_new = p - gain @ s @ gain.transpose(0, 2, 1)
        self._p[upd] = 0.5 * (p_new + p_new.transpose(0, 2, 1))
        # Running dispersion from groups with >= 2 points, floored at the measurement noise.
        multi = nk >= 2
        if multi.any():
            w = cfg.dispersion_update_weight
            sample = scat[multi] / (nk[multi] - 1)[:, None, None]
            disp[multi] = (1 - w) * disp[multi] + w * sample
            diag = np.einsum("uii->ui", disp)
            np.einsum("uii->ui", disp)[...] = np.maximum(diag, np.diag(self._rm))
            self._disp[upd] = disp
        self._n_est[upd] = n_est
        return counts

    def _maintain(self, hit: np.ndarray) -> None:
        cfg = self.cfg
        self._age += 1
        # DETECT needs consecutive hits: a miss resets the count (TI det2act).
        self._hits = np.where(hit, self._hits + 1, 0)
        self._misses = np.where(hit, 0, self._misses + 1)
        self._active |= self._hits >= cfg.hits_to_confirm

    def _same_group(self, xy_a: np.ndarray, vr_a: np.ndarray, xy_b: np.ndarray,
                    vr_b: np.ndarray) -> np.ndarray:
        """(A, B) bool: b lies within merge_depth_m along and merge_width_m across the line of
        sight to a, with radial velocity within merge_velocity_mps."""
        cfg = self.cfg
        d = xy_a - self._mount
        los = d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-6)[:, None]
        delta = xy_b[None, :, :] - xy_a[:, None, :]                              # (A, B, 2)
        depth = np.einsum("abk,ak->ab", delta, los)
        width = delta[..., 1] * los[:, None, 0] - delta[..., 0] * los[:, None, 1]
        # Across the line of sight the limit grows by two azimuth sigmas (the spread of two
        # centroids of one vehicle); where that passes a lane width the radar, whose
        # resolution is several sigmas, cannot split vehicles abreast anyway.
        width_lim = cfg.merge_width_m + 2 * np.hypot(d[:, 0], d[:, 1]) * math.radians(
            cfg.azimuth_std_deg)
        return ((np.abs(depth) <= cfg.merge_depth_m) & (np.abs(width) <= width_lim[:, None])
                & (np.abs(vr_a[:, None] - vr_b[None, :]) <= cfg.merge_velocity_mps))

    def _duplicates(self) -> np.ndarray:
        """Tracks that duplicate a higher-priority track of the same group.

        A vehicle whose points once fell outside its track's gate and started a second track
        would keep two tracks sharing its points; such pairs (`_same_group`) are resolved in
        favour of the ACTIVE, then older, then more-hit, then lower-id track.
        """
        t = self._id.size
        if t < 2:
            return np.zeros(t, dtype=bool)
        h, _ = measurement_model(self._x, self._mount, self._yaw)
        close = self._same_group(self._x[:, :2], h[:, 2], self._x[:, :2], h[:, 2])
        # Priority rank: lexicographic (active, age, hits, -id), larger is better.
        rank = np.empty(t, dtype=np.int64)
        rank[np.lexsort((-self._id, self._hits, self._age, self._active))] = np.arange(t)
        return np.any(close & (rank[:, None] > rank[None, :]), axis=0)

    def _select(self, keep: np.ndarray) -> None:
        for name in ("_id", "_x", "_p", "_disp", "_n_est", "_hits", "_misses", "_age",
                     "_active"):
            setattr(self, name, getattr(self, name)[keep])

    def _allocate(self, r, az, vr, snr, static, assoc, ego, assoc_id) -> np.ndarray:
        """Start DETECT tracks from leader clusters of the unassociated points; returns the
        point count of each new track."""
        cfg = self.cfg
        cand = assoc < 0
        if not cfg.allow_static_tracks:
            cand &= ~static
        room = cfg.max_tracks - self._id.size
        cidx = np.flatnonzero(cand)
        if cidx.size < cfg.alloc_min_points or room <= 0:
            return np.zeros(0, dtype=np.int64)
        clusters = leader_clusters(r[cidx], az[cidx], vr[cidx], snr[cidx], cfg.alloc_range_m,
                                   math.radians(cfg.alloc_azimuth_deg),
                                   cfg.alloc_radial_velocity_mps, cfg.alloc_min_points)
        if not clusters:
            return np.zeros(0, dtype=np.int64)
        sizes = np.array([c.size for c in clusters])
        members = cidx[np.concatenate(clusters)]
        label = np.repeat(np.arange(len(clusters)), sizes)
        mean = lambda a: np.bincount(label, weights=a) / sizes  # noqa: E731
        r_c, vr_c = mean(r[members]), mean(vr[members])
        # Azimuth mean about the leader, so the +/-pi seam cannot bias it.
        lead_az = az[members][np.r_[0, np.cumsum(sizes)[:-1]]]
        az_c = lead_az + mean(_wrap_pi(az[members] - np.repeat(lead_az, sizes)))
        snr_sum_db = 10 * np.log10(np.bincount(label, weights=10 ** (snr[members] / 10)))
        theta = az_c + self._yaw
        speed = np.abs(vr_c + (ego[0] * np.cos(theta) + ego[1] * np.sin(theta)
                               if ego is not None else 0.0))
        ok = snr_sum_db >= cfg.alloc_min_snr_db
        if not cfg.allow_static_tracks:
            ok &= speed >= cfg.alloc_min_speed_mps
        if cfg.merge_tracks:
            # A cluster of the same group as a live track (points just outside its gate), or
            # as a stronger cluster of this frame, starts no second track.
            xy_c = self._mount + r_c[:, None] * np.column_stack([np.cos(theta), np.sin(theta)])
            if self._id.size:
                h, _ = measurement_model(self._x, self._mount, self._yaw)
                ok &= ~self._same_group(xy_c, vr_c, self._x[:, :2], h[:, 2]).any(axis=1)
            ok &= ~np.tril(self._same_group(xy_c, vr_c, xy_c, vr_c) & ok[None, :], -1).any(axis=1)
        ok_idx = np.flatnonzero(ok)[:room]
        if ok_idx.size == 0:
            return np.zeros(0, dtype=np.int64)
        k = ok_idx.size
        r_c, az_c, vr_c, theta, n_c = r_c[ok_idx], az_c[ok_idx], vr_c[ok_idx], theta[ok_idx], \
            sizes[ok_idx]
        u = np.column_stack([np.cos(theta), np.sin(theta)])
        tang = np.column_stack([-u[:, 1], u[:, 0]])
        n = self._model.n_state
        x0 = np.zeros((k, n))
        x0[:, :2] = self._mount + r_c[:, None] * u
        x0[:, 2:4] = vr_c[:, None] * u
        disp0 = np.zeros((k, 3, 3))
        disp0[:, 0, 0] = cfg.group_depth_m ** 2 / 12
        disp0[:, 1, 1] = (cfg.group_width_m / np.maximum(r_c, 1.0)) ** 2 / 12
        disp0[:, 2, 2] = cfg.group_velocity_spread_mps ** 2 / 12
        # Initial covariance: the centroid's spread mapped to Cartesian, radial velocity known
        # to the point noise, cross-range velocity unknown (init_velocity_std_mps).
        var_r = self._rm[0, 0] + disp0[:, 0, 0]
        var_t = (self._rm[1, 1] + disp0[:, 1, 1]) * r_c ** 2
        var_vr = self._rm[2, 2] + disp0[:, 2, 2]
        p0 = np.zeros((k, n, n))
        outer = lambda a, b: a[:, :, None] * b[:, None, :]  # noqa: E731
        p0[:, :2, :2] = (var_r[:, None, None] * outer(u, u)
                         + var_t[:, None, None] * outer(tang, tang))
        p0[:, 2:4, 2:4] = (var_vr[:, None, None] * outer(u, u)
                           + cfg.init_velocity_std_mps ** 2 * outer(tang, tang))
        if n == 6:
            p0[:, 4, 4] = p0[:, 5, 5] = cfg.init_accel_std_mps2 ** 2
        ids = self._next_id + np.arange(k, dtype=np.int64)
        self._next_id += k
        assoc_id[members] = np.where(np.isin(label, ok_idx),
                                     ids[np.searchsorted(ok_idx, label).clip(0, k - 1)], -1)
        self._id = np.concatenate([self._id, ids])
        self._x = np.concatenate([self._x, x0])
        self._p = np.concatenate([self._p, p0])
        self._disp = np.concatenate([self._disp, disp0])
        self._n_est = np.concatenate([self._n_est, n_c.astype(float)])
        self._hits = np.concatenate([self._hits, np.ones(k, dtype=np.int64)])
        self._misses = np.concatenate([self._misses, np.zeros(k, dtype=np.int64)])
        self._age = np.concatenate([self._age, np.ones(k, dtype=np.int64)])
        self._active = np.concatenate([self._active, np.full(k, cfg.hits_to_confirm <= 1)])
        return n_c.astype(np.int64)

    def _table(self, n_pts: np.ndarray, time_s: float, ego: tuple[float, float] | None
               ) -> pd.DataFrame:
        x, p = self._x, self._p
        t = self._id.size
        acc = x[:, 4:6] if x.shape[1] == 6 else np.full((t, 2), np.nan)
        ego_vx, ego_vy = (np.nan, np.nan) if ego is None else ego
        return pd.DataFrame({
            "track_id": self._id.copy(),
            "state": np.where(self._active, "ACTIVE", "DETECT").astype(object),
            "x_m": x[:, 0], "y_m": x[:, 1], "vx_mps": x[:, 2], "vy_mps": x[:, 3],
            "ax_mps2": acc[:, 0], "ay_mps2": acc[:, 1],
            "var_x_m2": p[:, 0, 0], "var_y_m2": p[:, 1, 1], "cov_xy_m2": p[:, 0, 1],
            "var_vx_m2ps2": p[:, 2, 2], "var_vy_m2ps2": p[:, 3, 3],
            "cov_vxvy_m2ps2": p[:, 2, 3],
            "vx_ground_mps": x[:, 2] + ego_vx, "vy_ground_mps": x[:, 3] + ego_vy,
            "n_points": n_pts.astype(np.int64), "age_frames": self._age.copy(),
            "time_s": np.full(t, time_s),
        }, columns=list(TRACK_COLUMNS))


def _scatter(t: int, rows: np.ndarray, values: np.ndarray) -> np.ndarray:
    out = np.zeros((t,) + values.shape[1:])
    out[rows] = values
    return out


def _point_arrays(points: pd.DataFrame) -> tuple[np.ndarray, ...]:
    """(range_m, azimuth_rad, radial_velocity_mps, snr_db) arrays of a point cloud."""
    if not isinstance(points, pd.DataFrame):
        raise ValueError(f"points must be a pandas DataFrame, got {type(points).__name__}")
    if len(points) == 0:
        return tuple(np.zeros(0) for _ in range(4))
    missing = [c for c in _POINT_COLUMNS if c not in points.columns]
    if missing:
        raise ValueError(f"points is missing columns {missing}; needs {list(_POINT_COLUMNS)}")
    r, az, vr, snr = (points[c].to_numpy(dtype=np.float64) for c in _POINT_COLUMNS)
    for name, arr in zip(_POINT_COLUMNS, (r, az, vr, snr)):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"points column {name} contains non-finite values")
    if np.any(r <= 0):
        raise ValueError("points column range_m must be > 0")
    return r, np.radians(az), vr, snr


def track_frames(point_clouds: Iterable[tuple[float, pd.DataFrame]],
                 cfg: TrackerConfig | None = None,
                 ego_speeds_mps: Sequence[float | None] | None = None,
                 rng: np.random.Generator | None = None) -> pd.DataFrame:
    """Run a fresh `GroupTracker` over a whole sequence of frames.

    Parameters
    ----------
    point_clouds : iterable of (time_s, DataFrame)
        Frames in time order; point clouds in the radar frame as for `GroupTracker.step`.
    cfg : TrackerConfig, optional
    ego_speeds_mps : sequence of float or None, optional
        Ego speed per frame, m/s (None entries, or no sequence: estimate by RANSAC).
    rng : numpy.random.Generator, optional
        Passed to `GroupTracker`.

    Returns
    -------
    pandas.DataFrame
        `frame` (0-based index of the frame in the sequence) followed by `TRACK_COLUMNS`,
        one row per live track and frame.
    """
    tracker = GroupTracker(cfg, rng)
    tables = []
    for frame, (time_s, pc) in enumerate(point_clouds):
        ego = None if ego_speeds_mps is None else ego_speeds_mps[frame]
        tab = tracker.step(pc, time_s, ego)
        tab.insert(0, "frame", np.full(len(tab), frame, dtype=np.int64))
        tables.append(tab)
    if not tables:
        return pd.DataFrame({c: [] for c in ("frame",) + TRACK_COLUMNS})
    return pd.concat(tables, ignore_index=True)
