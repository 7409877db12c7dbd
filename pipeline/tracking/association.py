"""Gating and association of points to tracks (an injected tracker part).

An associator maps each point of a frame to at most one track. `GatedMaximumLikelihood` is
TI's gtrack rule: a point is a candidate of a track when it passes the group gate (squared
Mahalanobis distance under the group residual covariance H P H' + Rm + D) and hard limits in
depth, width and radial velocity; among its candidates it joins the most likely one (smallest
d^2 + ln det S). Any object with the same `associate` method can replace it
(``GroupTracker(cfg, associator=...)``).

References
----------
.. [1] TI mmWave SDK, "Group tracker" (gtrack) design: gating with group dispersion.
.. [2] Y. Bar-Shalom, X. R. Li, T. Kirubarajan, "Estimation with Applications to Tracking and
       Navigation", Wiley 2001, section 2.5 (gating).
"""
from __future__ import annotations

import math
from typing import Protocol

import numpy as np

from .config import TrackerConfig
from .models import RangeAzimuthDoppler, wrap_pi
from .state import Association, Points, Tracks

__all__ = ["Associator", "GatedMaximumLikelihood"]


class Associator(Protocol):
    """What the tracker asks of an associator."""

    def associate(self, tracks: Tracks, points: Points, static: np.ndarray) -> Association:
        """Track index per point (-1: none), innovations, and the tracks' Jacobians."""
        ...


class GatedMaximumLikelihood:
    """Group gate + maximum-likelihood choice (TI gtrack).

    Static points may update ACTIVE tracks (a vehicle that stops) but, unless
    `allow_static_tracks`, not DETECT ones: otherwise a track started by a false alarm next
    to a guard rail is confirmed by the rail.

    Parameters
    ----------
    cfg : TrackerConfig
        Gate sizes (gate_mahalanobis, gate_depth_m, gate_width_m, gate_velocity_mps), point
        noise, allow_static_tracks.
    sensor : RangeAzimuthDoppler
        Measurement model (mount pose and Rm).
    """

    def __init__(self, cfg: TrackerConfig, sensor: RangeAzimuthDoppler) -> None:
        self.cfg = cfg
        self.sensor = sensor

    def associate(self, tracks: Tracks, points: Points, static: np.ndarray) -> Association:
        cfg = self.cfg
        r, az, vr = points.range_m, points.azimuth_rad, points.radial_velocity_mps
        n, t = points.size, tracks.size
        if n == 0 or t == 0:
            return Association(np.full(n, -1, dtype=np.int64), np.zeros((n, 3)),
                               np.zeros((t, 3, tracks.x.shape[1])))
        h, jac = self.sensor.predict(tracks.x)
        s_grp = (jac @ tracks.p @ jac.transpose(0, 2, 1) + self.sensor.noise_cov
                 + tracks.dispersion)                                            # (T, 3, 3)
        s_inv = np.linalg.inv(s_grp)
        _, logdet = np.linalg.slogdet(s_grp)
        y = np.stack([r[None, :] - h[:, 0:1], wrap_pi(az[None, :] - h[:, 1:2]),
                      vr[None, :] - h[:, 2:3]], axis=-1)                       # (T, N, 3)
        d2 = np.sum((y @ s_inv) * y, axis=-1)                                      # (T, N)
        # Hard limits in depth (along the line of sight to the predicted centroid) and width,
        # widened by 3 sigma of the point noise so far groups are not cut by the azimuth error.
        theta_t = h[:, 1] + self.sensor.mount_yaw_rad
        los = np.stack([np.cos(theta_t), np.sin(theta_t)], axis=-1)              # (T, 2)
        pts = self.sensor.position(r, az)
        delta = pts[None, :, :] - tracks.x[:, None, :2]                          # (T, N, 2)
        depth = delta[..., 0] * los[:, None, 0] + delta[..., 1] * los[:, None, 1]
        width = delta[..., 1] * los[:, None, 0] - delta[..., 0] * los[:, None, 1]
        width_lim = cfg.gate_width_m + 3 * h[:, 0:1] * math.radians(cfg.azimuth_std_deg)
        gated = ((d2 <= cfg.gate_mahalanobis)
                 & (np.abs(depth) <= cfg.gate_depth_m + 3 * cfg.range_std_m)
                 & (np.abs(width) <= width_lim)
                 & (np.abs(y[..., 2]) <= cfg.gate_velocity_mps))
        if not cfg.allow_static_tracks:
            gated &= ~(static[None, :] & ~tracks.active[:, None])
        score = np.where(gated, d2 + logdet[:, None], np.inf)
        best = np.argmin(score, axis=0)
        ok = np.isfinite(score[best, np.arange(n)])
        return Association(np.where(ok, best, -1), y[best, np.arange(n)], jac)
