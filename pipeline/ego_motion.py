"""Ego-motion estimation from one radar frame: RANSAC of radial velocity versus azimuth.

On a moving ego every static reflector shows the same signature: seen along the vehicle-frame
direction theta = azimuth + mount yaw, its radial velocity is v_r = -v_ego cos(theta) (the ego
moves along +x of the vehicle frame, yaw rate neglected). The largest consensus set of points on
that curve is taken as the static world; its fit gives the ego speed and the point labels
static / moving that the tracker uses to keep static clutter from starting tracks.

References
----------
.. [1] M. A. Fischler and R. C. Bolles, "Random sample consensus", Comm. ACM 24(6), 1981.
.. [2] P. H. S. Torr and A. Zisserman, "MLESAC", CVIU 78, 2000 (the truncated-quadratic, MSAC,
       score used here).
.. [3] D. Kellner et al., "Instantaneous ego-motion estimation using Doppler radar", ITSC 2013.
.. [4] TI, "AWR1642 velocity disambiguation" (seed 001), section 5 and DESIGN section 5.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "EgoMotionConfig", "EgoMotionEstimate", "estimate_ego_motion", "ground_radial_velocity",
    "static_mask",
]


@dataclass(frozen=True, kw_only=True, slots=True)
class EgoMotionConfig:
    """Settings of the RANSAC ego-speed estimator.

    Parameters
    ----------
    n_hypotheses : int
        Hypotheses drawn per frame (one point each: the model has one parameter). When the
        frame holds no more eligible points than this, every eligible point is a hypothesis.
    inlier_threshold_mps : float
        Base half-width of the inlier band around -v cos(theta), m/s.
    azimuth_std_deg : float
        Per-point azimuth noise, deg. The band widens by `n_sigma` |v sin(theta)| sigma_az,
        the radial-velocity error an azimuth error causes on a moving ego.
    n_sigma : float
        Width of the azimuth term in standard deviations.
    min_abs_cos : float
        Points with |cos(theta)| below this cannot seed a hypothesis (v = -v_r / cos(theta)
        is ill-conditioned near +/-90 deg).
    min_inliers : int
        Fewest inliers for a valid estimate.
    min_inlier_fraction : float
        Smallest fraction of all points that must be inliers for a valid estimate.
    max_speed_mps : float
        Hypotheses with |v| above this are discarded (physically impossible ego speeds).

    Raises
    ------
    ValueError
        On a value out of its domain; the message names the field, the value and the limit.
    """

    n_hypotheses: int = 64
    inlier_threshold_mps: float = 0.3
    azimuth_std_deg: float = 1.0
    n_sigma: float = 3.0
    min_abs_cos: float = 0.25
    min_inliers: int = 5
    min_inlier_fraction: float = 0.1
    max_speed_mps: float = 70.0

    def __post_init__(self) -> None:
        for name in ("n_hypotheses", "min_inliers"):
            val = getattr(self, name)
            if not isinstance(val, (int, np.integer)) or val < 1:
                raise ValueError(f"{name}={val!r} must be an integer >= 1")
        for name in ("inlier_threshold_mps", "max_speed_mps"):
            val = getattr(self, name)
            if not (math.isfinite(val) and val > 0):
                raise ValueError(f"{name}={val!r} must be a finite number > 0")
        for name in ("azimuth_std_deg", "n_sigma"):
            val = getattr(self, name)
            if not (math.isfinite(val) and val >= 0):
                raise ValueError(f"{name}={val!r} must be a finite number >= 0")
        if not 0 <= self.min_abs_cos < 1:
            raise ValueError(f"min_abs_cos={self.min_abs_cos!r} must be in [0, 1)")
        if not 0 <= self.min_inlier_fraction <= 1:
            raise ValueError(f"min_inlier_fraction={self.min_inlier_fraction!r} must be in "
                             "[0, 1]")


@dataclass(frozen=True, slots=True)
class EgoMotionEstimate:
    """Result of `estimate_ego_motion`.

    Attributes
    ----------
    ego_speed_mps : float
        Ego speed along +x of the vehicle frame, m/s (NaN when not valid).
    static : (N,) bool
        True for the inliers of the static-world fit (all False when not valid).
    n_inliers : int
        Number of static points.
    valid : bool
        Whether the consensus met `min_inliers` and `min_inlier_fraction`.
    """

    ego_speed_mps: float
    static: np.ndarray
    n_inliers: int
    valid: bool


def _as_1d(name: str, value) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains non-finite values")
    return arr


def ground_radial_velocity(azimuth_deg, radial_velocity_mps, ego_speed_mps: float,
                           mount_yaw_deg: float = 0.0) -> np.ndarray:
    """Radial velocity over ground: the measured one with the ego's share removed.

    Parameters
    ----------
    azimuth_deg : (N,) float
        Radar-frame azimuth, deg.
    radial_velocity_mps : (N,) float
        Measured radial velocity (relative to the radar), m/s.
    ego_speed_mps : float
        Ego speed along +x of the vehicle frame, m/s.
    mount_yaw_deg : float
        Radar boresight yaw in the vehicle frame, deg.

    Returns
    -------
    (N,) float
        v_r + v_ego cos(az + yaw), m/s: zero for a static reflector.
    """
    theta = np.radians(np.asarray(azimuth_deg, dtype=np.float64) + mount_yaw_deg)
    return np.asarray(radial_velocity_mps, dtype=np.float64) + ego_speed_mps * np.cos(theta)


def static_mask(azimuth_deg, radial_velocity_mps, ego_speed_mps: float,
                mount_yaw_deg: float = 0.0, threshold_mps: float = 0.3,
                azimuth_std_deg: float = 1.0, n_sigma: float = 3.0) -> np.ndarray:
    """Label points static for a known ego speed (e.g. from the vehicle bus).

    A point is static when |v_r + v_ego cos(theta)| <= threshold + n_sigma |v_ego sin(theta)|
    sigma_az, theta = azimuth + mount yaw; the second term is the radial-velocity error an
    azimuth error of sigma_az causes.

    Returns
    -------
    (N,) bool
    """
    az = _as_1d("azimuth_deg", azimuth_deg)
    theta = np.radians(az + mount_yaw_deg)
    resid = np.abs(ground_radial_velocity(az, radial_velocity_mps, ego_speed_mps,
                                          mount_yaw_deg))
    band = threshold_mps + n_sigma * np.abs(ego_speed_mps * np.sin(theta)) * math.radians(
        azimuth_std_deg)
    return resid <= band


def estimate_ego_motion(azimuth_deg, radial_velocity_mps, rng: np.random.Generator,
                        mount_yaw_deg: float = 0.0,
                        cfg: EgoMotionConfig | None = None) -> EgoMotionEstimate:
    """Ego speed and static/moving labels from one frame's detections by RANSAC.

    All hypotheses are scored at once on an (n_hypotheses, N) residual matrix with the MSAC
    truncated-quadratic cost [2]; the best one is refined by least squares on its inliers
    (v = -sum(v_r c) / sum(c^2), c = cos(theta)), twice.

    Parameters
    ----------
    azimuth_deg : (N,) float
        Radar-frame azimuth of each detection, deg.
    radial_velocity_mps : (N,) float
        Measured radial velocity (relative to the radar, negative = approaching), m/s.
    rng : numpy.random.Generator
        Source of the hypothesis samples.
    mount_yaw_deg : float
        Radar boresight yaw in the vehicle frame, deg.
    cfg : EgoMotionConfig, optional
        Estimator settings; defaults to `EgoMotionConfig()`.

    Returns
    -------
    EgoMotionEstimate

    Raises
    ------
    ValueError
        On mismatched or non-finite inputs.
    """
    cfg = EgoMotionConfig() if cfg is None else cfg
    az = _as_1d("azimuth_deg", azimuth_deg)
    vr = _as_1d("radial_velocity_mps", radial_velocity_mps)
    if az.shape != vr.shape:
        raise ValueError(f"azimuth_deg {az.shape} and radial_velocity_mps {vr.shape} must "
                         "have the same shape")
    n = az.size
    invalid = EgoMotionEstimate(math.nan, np.zeros(n, dtype=bool), 0, False)
    need = max(cfg.min_inliers, math.ceil(cfg.min_inlier_fraction * n))
    if n < need:
        return invalid
    theta = np.radians(az + mount_yaw_deg)
    c, s = np.cos(theta), np.abs(np.sin(theta))
    eligible = np.flatnonzero(np.abs(c) >= cfg.min_abs_cos)
    if eligible.size == 0:
        return invalid
    if eligible.size <= cfg.n_hypotheses:
        seeds = eligible
    else:
        seeds = rng.choice(eligible, size=cfg.n_hypotheses, replace=False)
    v_hyp = -vr[seeds] / c[seeds]
    v_hyp = v_hyp[np.abs(v_hyp) <= cfg.max_speed_mps]
    if v_hyp.size == 0:
        return invalid
    sig_az = math.radians(cfg.azimuth_std_deg)

    def band(v):
        # Inlier half-width per point (broadcasts over hypotheses), m/s.
        return cfg.inlier_threshold_mps + cfg.n_sigma * np.abs(v) * s * sig_az

    resid = vr[None, :] + v_hyp[:, None] * c[None, :]            # (H, N)
    bands = band(v_hyp[:, None])                                  # (H, N)
    cost = np.minimum((resid / bands) ** 2, 1.0).sum(axis=1)
    v = float(v_hyp[np.argmin(cost)])
    for _ in range(2):
        inl = np.abs(vr + v * c) <= band(v)
        if not inl.any():
            return invalid
        v = float(-np.dot(vr[inl], c[inl]) / np.dot(c[inl], c[inl]))
    inl = np.abs(vr + v * c) <= band(v)
    n_in = int(inl.sum())
    if n_in < need:
        return invalid
    return EgoMotionEstimate(v, inl, n_in, True)
