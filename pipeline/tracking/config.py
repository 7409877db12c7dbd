"""Settings of the group tracker: one frozen dataclass, SI units in every name."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from core.checks import one_of, require
from core.errors import BadInput

from .ego_motion import EgoMotionConfig
from .models import MOTION_MODELS
from .parts import PART_REGISTRIES

__all__ = ["TrackerConfig"]


@dataclass(frozen=True, kw_only=True, slots=True)
class TrackerConfig:
    """Settings of the group tracker (all SI, unit in the name).

    Parameters
    ----------
    motion_model : {"cv", "ca"}
        Constant velocity or constant acceleration, a key of `MOTION_MODELS`.
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
        Static labelling with a known ego speed, see `pipeline.tracking.ego_motion.static_mask`.
    ego_motion : EgoMotionConfig
        RANSAC settings: the whole ego velocity when `step` gets no ego speed, the lateral
        part only (planar model) when it does.
    hypothesiser, associator, updater, predictor, allocator : str
        The parts `GroupTracker` builds, by their names in `pipeline.tracking.parts`
        (default TI's gtrack: "group_gate", "max_likelihood", "group_ekf", "kalman",
        "leader_cluster"); each part reads its own few fields of this config.

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
    hypothesiser: str = "group_gate"
    associator: str = "max_likelihood"
    updater: str = "group_ekf"
    predictor: str = "kalman"
    allocator: str = "leader_cluster"

    def __post_init__(self) -> None:
        one_of("motion_model", self.motion_model, MOTION_MODELS)
        require(self, ("mount_x_m", "mount_y_m", "mount_yaw_deg", "alloc_min_snr_db"))
        require(self, ("frame_period_s", "range_std_m", "azimuth_std_deg",
                       "radial_velocity_std_mps", "process_noise_accel_mps2",
                       "process_noise_jerk_mps3", "gate_mahalanobis", "gate_depth_m",
                       "gate_width_m", "gate_velocity_mps", "group_depth_m", "group_width_m",
                       "group_velocity_spread_mps", "alloc_range_m", "alloc_azimuth_deg",
                       "alloc_radial_velocity_mps", "init_velocity_std_mps",
                       "init_accel_std_mps2", "static_threshold_mps", "merge_depth_m",
                       "merge_width_m", "merge_velocity_mps"), gt=0)
        require(self, ("alloc_min_speed_mps", "centroid_jitter_weight"), ge=0)
        require(self, "dispersion_update_weight", gt=0, le=1)
        require(self, ("alloc_min_points", "hits_to_confirm", "misses_to_free_detect",
                       "misses_to_free_active", "max_tracks"), "integer", ge=1)
        require(self, ("allow_static_tracks", "merge_tracks"), "bool")
        for name, registry in PART_REGISTRIES.items():
            registry.lookup(getattr(self, name))
        if not isinstance(self.ego_motion, EgoMotionConfig):
            raise BadInput(f"ego_motion={self.ego_motion!r} must be an EgoMotionConfig")

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
        """The process-noise intensity of the selected motion model (the config field its
        `MotionModel.sigma_field` names)."""
        return getattr(self, MOTION_MODELS[self.motion_model].sigma_field)
