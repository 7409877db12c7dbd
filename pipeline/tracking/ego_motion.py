"""Ego-motion estimation from one radar frame: RANSAC of radial velocity versus azimuth.

On a moving ego every static reflector shows the same signature: seen along the vehicle-frame
direction theta = azimuth + mount yaw, its radial velocity is
v_r = -(v_x cos(theta) + v_y sin(theta)), (v_x, v_y) the radar's velocity over ground in the
vehicle frame. Model "longitudinal" assumes v_y = 0 (v_r = -v_ego cos(theta)); model "planar"
also fits v_y, which a lane change or a curve brings (side slip of the body, yaw rate times the
mount's lever arm). The largest consensus set of points on that curve is taken as the static
world; its fit gives the ego velocity and the point labels static / moving that the tracker
uses to keep static clutter from starting tracks.

References
----------
.. [1] M. A. Fischler and R. C. Bolles, "Random sample consensus", Comm. ACM 24(6), 1981.
.. [2] P. H. S. Torr and A. Zisserman, "MLESAC", CVIU 78, 2000 (the truncated-quadratic, MSAC,
       score used here).
.. [3] D. Kellner et al., "Instantaneous ego-motion estimation using Doppler radar", ITSC 2013.
.. [4] TI, "AWR1642 velocity disambiguation" [TI-VEXT], section 5 and design.md section 5.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from core.checks import one_of, require
from core.errors import BadInput

__all__ = [
    "EgoModel", "EgoMotionConfig", "EgoMotionEstimate", "EGO_MODELS", "estimate_ego_motion",
    "ground_radial_velocity", "static_mask", "EgoVelocity", "EgoFrame", "RansacEgoMotion",
]


@dataclass(frozen=True, kw_only=True, slots=True)
class EgoModel:
    """A model of the radar's velocity over ground seen in the static world's radial velocity.

    Parameters
    ----------
    name : str
    description : str
    lateral : bool
        Whether v_y is fitted (planar) or fixed at 0 (longitudinal).
    """

    name: str
    description: str
    lateral: bool


#: Ego-motion models by the name used in `EgoMotionConfig.model`.
EGO_MODELS: dict[str, EgoModel] = {m.name: m for m in (
    EgoModel(name="longitudinal", lateral=False,
             description="v_r = -v_x cos(theta): the radar moves along the vehicle's x axis"),
    EgoModel(name="planar", lateral=True,
             description="v_r = -(v_x cos(theta) + v_y sin(theta)): also lateral motion "
                         "(Kellner 2013)"),
)}


@dataclass(frozen=True, kw_only=True, slots=True)
class EgoMotionConfig:
    """Settings of the RANSAC ego-speed estimator and of the static labels
    (``TrackerConfig.ego_motion``).

    Parameters
    ----------
    model : {"planar", "longitudinal"}
        See `EGO_MODELS`.
    n_hypotheses : int
        Hypotheses drawn per frame (minimal samples of one point per fitted parameter). With
        one parameter and no more eligible points than this, every eligible point is a
        hypothesis.
    inlier_threshold_mps : float
        Base half-width of the inlier band around -v cos(theta), m/s.
    azimuth_std_deg : float
        Per-point azimuth noise, deg. The band widens by `n_sigma` |v sin(theta)| sigma_az,
        the radial-velocity error an azimuth error causes on a moving ego.
    n_sigma : float
        Width of the azimuth term in standard deviations.
    min_abs_cos : float
        Conditioning of a minimal sample: a one-parameter seed needs |cos(theta)| (or
        |sin(theta)| when fitting v_y alone) at least this; a two-point seed needs
        |sin(theta_1 - theta_2)| at least this.
    min_inliers : int
        Fewest inliers for a valid estimate.
    min_inlier_fraction : float
        Smallest fraction of all points that must be inliers for a valid estimate.
    max_speed_mps : float
        Hypotheses with |v| above this are discarded (physically impossible ego speeds).
    max_lateral_ratio : float
        Planar model: hypotheses with |v_y| > max_lateral_ratio |v_x| are discarded. A car
        cannot move sideways by itself: its lateral velocity at the radar comes from side slip
        and yaw rate, both of which need forward speed (0.15 allows 8.5 deg). This also keeps
        a crossing vehicle, whose radial velocity goes as sin(theta), from being taken for the
        static world when the ego stands still.
    static_threshold_mps : float
        Static labelling of the tracker's ego-motion part (`RansacEgoMotion`), see
        `static_mask`; its azimuth term uses the measurement noise's azimuth sigma, not
        `azimuth_std_deg` above.

    Raises
    ------
    ValueError
        On a value out of its domain; the message names the field, the value and the limit.
    """

    model: str = "planar"
    n_hypotheses: int = 64
    inlier_threshold_mps: float = 0.3
    azimuth_std_deg: float = 1.0
    n_sigma: float = 3.0
    min_abs_cos: float = 0.25
    min_inliers: int = 5
    min_inlier_fraction: float = 0.1
    max_speed_mps: float = 70.0
    max_lateral_ratio: float = 0.15
    static_threshold_mps: float = 0.3

    def __post_init__(self) -> None:
        one_of("model", self.model, EGO_MODELS)
        require(self, ("n_hypotheses", "min_inliers"), "integer", ge=1)
        require(self, ("inlier_threshold_mps", "max_speed_mps", "static_threshold_mps"), gt=0)
        require(self, ("azimuth_std_deg", "n_sigma", "max_lateral_ratio"), ge=0)
        require(self, "min_abs_cos", ge=0, lt=1)
        require(self, "min_inlier_fraction", ge=0, le=1)


@dataclass(frozen=True, slots=True)
class EgoMotionEstimate:
    """Result of `estimate_ego_motion`.

    Attributes
    ----------
    ego_speed_mps : float
        Radar velocity over ground along +x of the vehicle frame (the ego speed), m/s (NaN
        when not valid; the given value when it was passed in).
    ego_lateral_mps : float
        Radar velocity over ground along +y of the vehicle frame, m/s (0 for the
        longitudinal model, NaN when not valid).
    static : (N,) bool
        True for the inliers of the static-world fit (all False when not valid).
    n_inliers : int
        Number of static points.
    valid : bool
        Whether the consensus met `min_inliers` and `min_inlier_fraction`.
    """

    ego_speed_mps: float
    ego_lateral_mps: float
    static: np.ndarray
    n_inliers: int
    valid: bool


def _as_1d(name: str, value) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim != 1:
        raise BadInput(f"{name} must be one-dimensional, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise BadInput(f"{name} contains non-finite values")
    return arr


def ground_radial_velocity(azimuth_deg, radial_velocity_mps, ego_speed_mps: float,
                           mount_yaw_deg: float = 0.0, ego_lateral_mps: float = 0.0
                           ) -> np.ndarray:
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
    ego_lateral_mps : float
        Radar velocity over ground along +y of the vehicle frame, m/s.

    Returns
    -------
    (N,) float
        v_r + v_x cos(theta) + v_y sin(theta), theta = az + yaw, m/s: zero for a static
        reflector.
    """
    theta = np.radians(np.asarray(azimuth_deg, dtype=np.float64) + mount_yaw_deg)
    return (np.asarray(radial_velocity_mps, dtype=np.float64) + ego_speed_mps * np.cos(theta)
            + ego_lateral_mps * np.sin(theta))


def static_mask(azimuth_deg, radial_velocity_mps, ego_speed_mps: float,
                mount_yaw_deg: float = 0.0, threshold_mps: float = 0.3,
                azimuth_std_deg: float = 1.0, n_sigma: float = 3.0,
                ego_lateral_mps: float = 0.0) -> np.ndarray:
    """Label points static for a known ego velocity (e.g. from the vehicle bus).

    A point is static when |v_r + v_x cos(theta) + v_y sin(theta)| <= threshold +
    n_sigma |v_x sin(theta) - v_y cos(theta)| sigma_az, theta = azimuth + mount yaw; the
    second term is the radial-velocity error an azimuth error of sigma_az causes.

    Returns
    -------
    (N,) bool
    """
    az = _as_1d("azimuth_deg", azimuth_deg)
    theta = np.radians(az + mount_yaw_deg)
    resid = np.abs(ground_radial_velocity(az, radial_velocity_mps, ego_speed_mps,
                                          mount_yaw_deg, ego_lateral_mps))
    slope = np.abs(ego_speed_mps * np.sin(theta) - ego_lateral_mps * np.cos(theta))
    return resid <= threshold_mps + n_sigma * slope * math.radians(azimuth_std_deg)


def estimate_ego_motion(azimuth_deg, radial_velocity_mps, rng: np.random.Generator,
                        mount_yaw_deg: float = 0.0, cfg: EgoMotionConfig | None = None,
                        ego_speed_mps: float | None = None) -> EgoMotionEstimate:
    """Ego velocity and static/moving labels from one frame's detections by RANSAC.

    The static world satisfies v_r = -(v_x cos(theta) + v_y sin(theta)) (v_y = 0 for the
    longitudinal model; v_x fixed when `ego_speed_mps` is given). Minimal samples (one point
    per free parameter) give the hypotheses, all scored at once on an (n_hypotheses, N)
    residual matrix with the MSAC truncated-quadratic cost [2]; the best is refined by least
    squares on its inliers, twice [3].

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
    ego_speed_mps : float, optional
        Known v_x (e.g. from the vehicle bus): only v_y is fitted (planar model), or only the
        labels are computed (longitudinal model).

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
        raise BadInput(f"azimuth_deg {az.shape} and radial_velocity_mps {vr.shape} must "
                       "have the same shape")
    if ego_speed_mps is not None and not math.isfinite(ego_speed_mps):
        raise BadInput(f"ego_speed_mps={ego_speed_mps!r} must be finite or None")
    n = az.size
    invalid = EgoMotionEstimate(math.nan, math.nan, np.zeros(n, dtype=bool), 0, False)
    need = max(cfg.min_inliers, math.ceil(cfg.min_inlier_fraction * n))
    if n < need:
        return invalid
    fit = _EgoFit.build(az, vr, mount_yaw_deg, cfg, ego_speed_mps)
    p = np.zeros((1, 0)) if fit.k == 0 else _ransac(fit, rng)
    if p is None:
        return invalid
    v = fit.velocity(p)[0]
    inl = fit.inliers(v[None, :])[0] <= 1
    n_in = int(inl.sum())
    if n_in < need:
        return invalid
    return EgoMotionEstimate(float(v[0]), float(v[1]), inl, n_in, True)


class _EgoFit(NamedTuple):
    """One frame's static-world fit: v_r = -(v_x cos(theta) + v_y sin(theta)) as y = -A p with
    the free parameters p (the known v_x, if any, moved into y)."""

    vr: np.ndarray            # (N,) measured radial velocity, m/s
    c: np.ndarray             # (N,) cos(theta), theta the vehicle-frame azimuth
    s: np.ndarray             # (N,) sin(theta)
    design: np.ndarray        # (N, k) design matrix A
    y: np.ndarray             # (N,) target
    ego_speed_mps: float | None
    cfg: EgoMotionConfig

    @classmethod
    def build(cls, az, vr, mount_yaw_deg, cfg, ego_speed_mps) -> "_EgoFit":
        theta = np.radians(az + mount_yaw_deg)
        c, s = np.cos(theta), np.sin(theta)
        if ego_speed_mps is None:
            cols = (c, s) if EGO_MODELS[cfg.model].lateral else (c,)
            y = vr
        else:
            cols = (s,) if EGO_MODELS[cfg.model].lateral else ()
            y = vr + ego_speed_mps * c
        design = np.column_stack(cols) if cols else np.zeros((az.size, 0))
        return cls(vr, c, s, design, y, ego_speed_mps, cfg)

    @property
    def k(self) -> int:
        """Free parameters."""
        return self.design.shape[1]

    def velocity(self, p: np.ndarray) -> np.ndarray:
        """(H, 2) radar velocity (v_x, v_y) of parameter rows p (H, k)."""
        out = np.zeros((p.shape[0], 2))
        if self.ego_speed_mps is None:
            out[:, :self.k] = p
        else:
            out[:, 0] = self.ego_speed_mps
            out[:, 1:1 + self.k] = p
        return out

    def plausible(self, v: np.ndarray) -> np.ndarray:
        """(H,) within the speed limit and the lateral-to-forward bound."""
        return ((np.abs(v[:, 0]) <= self.cfg.max_speed_mps)
                & (np.abs(v[:, 1]) <= self.cfg.max_lateral_ratio * np.abs(v[:, 0]) + 1e-9))

    def inliers(self, v: np.ndarray) -> np.ndarray:
        """(H, N) |residual| / band for velocity rows v (H, 2)."""
        cfg, c, s = self.cfg, self.c, self.s
        resid = self.vr[None, :] + v[:, :1] * c[None, :] + v[:, 1:] * s[None, :]
        band = cfg.inlier_threshold_mps + cfg.n_sigma * math.radians(cfg.azimuth_std_deg) * \
            np.abs(v[:, :1] * s[None, :] - v[:, 1:] * c[None, :])
        return np.abs(resid) / band


def _hypotheses(fit: _EgoFit, rng: np.random.Generator) -> np.ndarray | None:
    """(H, k) parameter rows from minimal samples (one point per parameter), or None."""
    cfg, design, y = fit.cfg, fit.design, fit.y
    if fit.k == 1:
        eligible = np.flatnonzero(np.abs(design[:, 0]) >= cfg.min_abs_cos)
        if eligible.size == 0:
            return None
        seeds = (eligible if eligible.size <= cfg.n_hypotheses
                 else rng.choice(eligible, size=cfg.n_hypotheses, replace=False))
        return (-y[seeds] / design[seeds, 0])[:, None]
    pairs = rng.integers(0, y.size, size=(cfg.n_hypotheses, 2))
    a, b = design[pairs[:, 0]], design[pairs[:, 1]]
    det = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]              # sin(theta_b - theta_a)
    good = np.abs(det) >= cfg.min_abs_cos
    a, b, det, pairs = a[good], b[good], det[good], pairs[good]
    ya, yb = -y[pairs[:, 0]], -y[pairs[:, 1]]
    return np.column_stack([(ya * b[:, 1] - yb * a[:, 1]) / det,
                            (a[:, 0] * yb - b[:, 0] * ya) / det])   # Cramer's rule


def _ransac(fit: _EgoFit, rng: np.random.Generator) -> np.ndarray | None:
    """(1, k) best plausible hypothesis by the MSAC cost, refined twice by least squares on
    its inliers; None when no hypothesis is plausible or too few inliers remain."""
    p = _hypotheses(fit, rng)
    if p is None:
        return None
    p = p[fit.plausible(fit.velocity(p))]
    if p.shape[0] == 0:
        return None
    cost = np.minimum(fit.inliers(fit.velocity(p)) ** 2, 1.0).sum(axis=1)
    p = p[np.argmin(cost)][None, :]
    for _ in range(2):
        inl = fit.inliers(fit.velocity(p))[0] <= 1
        if inl.sum() < fit.k:
            return None
        refined = np.linalg.lstsq(fit.design[inl], -fit.y[inl], rcond=None)[0][None, :]
        if not fit.plausible(fit.velocity(refined))[0]:
            break          # keep the plausible hypothesis rather than leave the bounds
        p = refined
    return p


class EgoVelocity(NamedTuple):
    """Radar velocity over ground in the vehicle frame, m/s."""

    vx_mps: float
    vy_mps: float


class EgoFrame(NamedTuple):
    """What the tracker knows of the ego in one frame.

    Attributes
    ----------
    static : (N,) bool
        Points labelled static (all False when the velocity is unknown).
    velocity : EgoVelocity or None
        Radar velocity over ground used this frame (None: unknown).
    """

    static: np.ndarray
    velocity: EgoVelocity | None


@dataclass(frozen=True, kw_only=True, slots=True)
class RansacEgoMotion:
    """Tracker part: the radar's velocity over ground and the static labels of one frame.

    A given ego speed is the speed over ground (vehicle bus). With a lateral ego model the
    frame's RANSAC estimate (v_x, v_y) is used when it agrees with that speed
    (|hypot(v_x, v_y) - speed| <= 0.5 m/s + 5 %): in a lane change the velocity is not along
    the vehicle's x axis, and taking the bus speed as v_x mislabels the static world seen to
    the side. Otherwise (v_x, v_y) = (speed, 0). Without a speed both are estimated; the
    previous frame's velocity is kept when RANSAC fails. Points are labelled with the same
    rule (`static_mask`) whichever the source.

    Parameters
    ----------
    config : EgoMotionConfig
        RANSAC settings and the static threshold.
    mount_yaw_deg : float
        Radar boresight yaw in the vehicle frame, deg.
    azimuth_std_deg : float
        Per-point azimuth noise of the static labels (`static_mask`), deg.
    """

    config: EgoMotionConfig
    mount_yaw_deg: float
    azimuth_std_deg: float

    def __call__(self, azimuth_deg: np.ndarray, radial_velocity_mps: np.ndarray,
                 ego_speed_mps: float | None, previous: EgoVelocity | None,
                 rng: np.random.Generator) -> EgoFrame:
        """Static labels and radar velocity of a frame.

        Parameters
        ----------
        azimuth_deg, radial_velocity_mps : (N,) float
            The frame's points (radar frame).
        ego_speed_mps : float or None
            Ego speed over ground along +x (vehicle bus), m/s; None: estimate it.
        previous : EgoVelocity or None
            The velocity used in the previous frame (kept when the estimate fails).
        rng : numpy.random.Generator
            RANSAC samples.
        """
        cfg = self.config
        velocity = previous
        if ego_speed_mps is not None:
            if not math.isfinite(ego_speed_mps):
                raise BadInput(f"ego_speed_mps={ego_speed_mps!r} must be finite or None")
            speed = float(ego_speed_mps)
            velocity = EgoVelocity(speed, 0.0)
            if EGO_MODELS[cfg.model].lateral:
                est = estimate_ego_motion(azimuth_deg, radial_velocity_mps, rng,
                                          self.mount_yaw_deg, cfg)
                if est.valid and abs(math.hypot(est.ego_speed_mps, est.ego_lateral_mps)
                                     - abs(speed)) <= 0.5 + 0.05 * abs(speed):
                    velocity = EgoVelocity(est.ego_speed_mps, est.ego_lateral_mps)
        else:
            est = estimate_ego_motion(azimuth_deg, radial_velocity_mps, rng,
                                      self.mount_yaw_deg, cfg)
            if est.valid:
                velocity = EgoVelocity(est.ego_speed_mps, est.ego_lateral_mps)
        if velocity is None:
            return EgoFrame(np.zeros(azimuth_deg.size, dtype=bool), None)
        static = static_mask(azimuth_deg, radial_velocity_mps, velocity.vx_mps,
                             self.mount_yaw_deg, cfg.static_threshold_mps,
                             self.azimuth_std_deg, ego_lateral_mps=velocity.vy_mps)
        return EgoFrame(static, velocity)
