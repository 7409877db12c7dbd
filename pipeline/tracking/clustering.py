"""Clustering and allocation: new tracks from the points no track took (an injected part).

`leader_clusters` groups points in range, azimuth and radial velocity around the strongest
ones; `LeaderClusterAllocator` turns the accepted clusters into DETECT tracks (state from the
centroid, covariance from the group extent and the point noise) and, with ``merge_tracks``,
refuses clusters of the same group as a live track or a stronger cluster (`same_group`).
The allocator takes typed arguments, edits none of them and returns `NewTracks`; the tracker
gives the ids.

References
----------
.. [1] TI mmWave SDK, "Group tracker" (gtrack) design: allocation from unassociated points.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from core.checks import require

from .ego_motion import EgoVelocity
from .models import RangeAzimuthDoppler, wrap_pi
from .track_state import NewTracks, Points, Tracks

__all__ = ["leader_clusters", "same_group", "Allocator", "LeaderClusterAllocator",
           "MergeConfig", "AllocationConfig"]


@dataclass(frozen=True, kw_only=True, slots=True)
class MergeConfig:
    """One track per group (``TrackerConfig.merging``; read by the allocator and by the
    tracker's duplicate removal).

    Parameters
    ----------
    merge_tracks : bool
        Keep one track per group (an addition to TI's design): a cluster of the same group as
        a live track or a stronger cluster starts no track, and a track duplicating another
        is freed. Otherwise a vehicle whose points fall into two leader clusters keeps two
        tracks that share its points.
    merge_depth_m, merge_width_m, merge_velocity_mps : float
        Same-group test (`same_group`): centroids within these distances along and across
        the line of sight (across: plus 2 x range x azimuth sigma) and radial velocities
        within this difference. Keep merge_width_m below the lane width, so vehicles abreast
        at the same speed stay separate where the radar can resolve them.
    """

    merge_tracks: bool = True
    merge_depth_m: float = 5.0
    merge_width_m: float = 2.0
    merge_velocity_mps: float = 1.0

    def __post_init__(self) -> None:
        require(self, "merge_tracks", "bool")
        require(self, ("merge_depth_m", "merge_width_m", "merge_velocity_mps"), gt=0)


@dataclass(frozen=True, kw_only=True, slots=True)
class AllocationConfig:
    """What the leader-cluster allocator reads (``TrackerConfig.allocation``).

    Parameters
    ----------
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
    group_depth_m, group_width_m, group_velocity_spread_mps : float
        Expected extent of a group (initial dispersion, uniform spread: extent^2 / 12).
    init_velocity_std_mps : float
        Initial standard deviation of the (unobserved) cross-range velocity.
    init_accel_std_mps2 : float
        Initial standard deviation of the acceleration (CA model).
    allow_static_tracks : bool
        Whether static points may start tracks (and confirm DETECT tracks: the associator's
        `AssociationRules` take it from here).
    """

    alloc_min_points: int = 1
    alloc_min_snr_db: float = 15.0
    alloc_min_speed_mps: float = 0.5
    alloc_range_m: float = 5.0
    alloc_azimuth_deg: float = 4.0
    alloc_radial_velocity_mps: float = 1.0
    group_depth_m: float = 4.0
    group_width_m: float = 1.8
    group_velocity_spread_mps: float = 1.0
    init_velocity_std_mps: float = 10.0
    init_accel_std_mps2: float = 3.0
    allow_static_tracks: bool = False

    def __post_init__(self) -> None:
        require(self, "alloc_min_snr_db")
        require(self, "alloc_min_speed_mps", ge=0)
        require(self, ("alloc_range_m", "alloc_azimuth_deg", "alloc_radial_velocity_mps",
                       "group_depth_m", "group_width_m", "group_velocity_spread_mps",
                       "init_velocity_std_mps", "init_accel_std_mps2"), gt=0)
        require(self, "alloc_min_points", "integer", ge=1)
        require(self, "allow_static_tracks", "bool")


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
            & (np.abs(wrap_pi(azimuth_rad[:, None] - azimuth_rad[None, :])) <= max_azimuth_rad)
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


def same_group(cfg: MergeConfig, sensor: RangeAzimuthDoppler, xy_a: np.ndarray,
               vr_a: np.ndarray, xy_b: np.ndarray, vr_b: np.ndarray) -> np.ndarray:
    """(A, B) bool: b lies within merge_depth_m along and merge_width_m across the line of
    sight to a, with radial velocity within merge_velocity_mps.

    Parameters
    ----------
    cfg : MergeConfig
    sensor : RangeAzimuthDoppler
        Mount position (the line of sight starts there) and azimuth noise.
    xy_a : (A, 2), xy_b : (B, 2) float
        Vehicle-frame positions, m.
    vr_a : (A,), vr_b : (B,) float
        Radial velocities, m/s.
    """
    d = xy_a - sensor.mount_xy_m
    los = d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-6)[:, None]
    delta = xy_b[None, :, :] - xy_a[:, None, :]                              # (A, B, 2)
    depth = np.einsum("abk,ak->ab", delta, los)
    width = delta[..., 1] * los[:, None, 0] - delta[..., 0] * los[:, None, 1]
    # Across the line of sight the limit grows by two azimuth sigmas (the spread of two
    # centroids of one vehicle); where that passes a lane width the radar, whose resolution
    # is several sigmas, cannot split vehicles abreast anyway.
    width_lim = cfg.merge_width_m + 2 * np.hypot(d[:, 0], d[:, 1]) * math.radians(
        sensor.noise.azimuth_std_deg)
    return ((np.abs(depth) <= cfg.merge_depth_m) & (np.abs(width) <= width_lim[:, None])
            & (np.abs(vr_a[:, None] - vr_b[None, :]) <= cfg.merge_velocity_mps))


class Allocator(Protocol):
    """What the tracker asks of an allocator."""

    def allocate(self, points: Points, candidates: np.ndarray, ego: EgoVelocity | None,
                 tracks: Tracks, room: int) -> NewTracks:
        """New tracks from the `candidates` (bool (N,)) points, at most `room` of them."""
        ...


class LeaderClusterAllocator:
    """DETECT tracks from leader clusters of the candidate points (TI gtrack allocation).

    Parameters
    ----------
    cfg : AllocationConfig
        alloc_* thresholds, group extent, init_* standard deviations, static points.
    sensor : RangeAzimuthDoppler
        Mount pose and point noise Rm.
    merging : MergeConfig
        One track per group: clusters of the same group as a live track or a stronger
        cluster start none.
    n_state : int
        State length of the motion model (`MotionConfig.n_state`).
    """

    def __init__(self, cfg: AllocationConfig, sensor: RangeAzimuthDoppler, *,
                 merging: MergeConfig = MergeConfig(), n_state: int = 4) -> None:
        self.cfg = cfg
        self.merging = merging
        self.sensor = sensor
        self.n_state = n_state

    def allocate(self, points: Points, candidates: np.ndarray, ego: EgoVelocity | None,
                 tracks: Tracks, room: int) -> NewTracks:
        cfg, sensor = self.cfg, self.sensor
        r, az, vr, snr = points
        mount, yaw, rm = sensor.mount_xy_m, sensor.mount_yaw_rad, sensor.noise_cov
        cidx = np.flatnonzero(candidates)
        if cidx.size < cfg.alloc_min_points or room <= 0:
            return NewTracks.none(self.n_state)
        clusters = leader_clusters(r[cidx], az[cidx], vr[cidx], snr[cidx], cfg.alloc_range_m,
                                   math.radians(cfg.alloc_azimuth_deg),
                                   cfg.alloc_radial_velocity_mps, cfg.alloc_min_points)
        if not clusters:
            return NewTracks.none(self.n_state)
        sizes = np.array([c.size for c in clusters])
        members = cidx[np.concatenate(clusters)]
        label = np.repeat(np.arange(len(clusters)), sizes)
        mean = lambda a: np.bincount(label, weights=a) / sizes  # noqa: E731
        r_c, vr_c = mean(r[members]), mean(vr[members])
        # Azimuth mean about the leader, so the +/-pi seam cannot bias it.
        lead_az = az[members][np.r_[0, np.cumsum(sizes)[:-1]]]
        az_c = lead_az + mean(wrap_pi(az[members] - np.repeat(lead_az, sizes)))
        snr_sum_db = 10 * np.log10(np.bincount(label, weights=10 ** (snr[members] / 10)))
        theta = az_c + yaw
        speed = np.abs(vr_c + (ego[0] * np.cos(theta) + ego[1] * np.sin(theta)
                               if ego is not None else 0.0))
        ok = snr_sum_db >= cfg.alloc_min_snr_db
        if not cfg.allow_static_tracks:
            ok &= speed >= cfg.alloc_min_speed_mps
        if self.merging.merge_tracks:
            # A cluster of the same group as a live track (points just outside its gate), or
            # as a stronger cluster of this frame, starts no second track.
            xy_c = mount + r_c[:, None] * np.column_stack([np.cos(theta), np.sin(theta)])
            if tracks.size:
                h, _ = sensor.predict(tracks.x)
                ok &= ~same_group(self.merging, sensor, xy_c, vr_c, tracks.x[:, :2],
                                  h[:, 2]).any(axis=1)
            ok &= ~np.tril(same_group(self.merging, sensor, xy_c, vr_c, xy_c, vr_c)
                           & ok[None, :], -1).any(axis=1)
        ok_idx = np.flatnonzero(ok)[:room]
        k = ok_idx.size
        if k == 0:
            return NewTracks.none(self.n_state)
        r_c, az_c, vr_c, theta, n_c = r_c[ok_idx], az_c[ok_idx], vr_c[ok_idx], theta[ok_idx], \
            sizes[ok_idx]
        u = np.column_stack([np.cos(theta), np.sin(theta)])
        tang = np.column_stack([-u[:, 1], u[:, 0]])
        n = self.n_state
        x0 = np.zeros((k, n))
        x0[:, :2] = mount + r_c[:, None] * u
        x0[:, 2:4] = vr_c[:, None] * u
        disp0 = np.zeros((k, 3, 3))
        disp0[:, 0, 0] = cfg.group_depth_m ** 2 / 12
        disp0[:, 1, 1] = (cfg.group_width_m / np.maximum(r_c, 1.0)) ** 2 / 12
        disp0[:, 2, 2] = cfg.group_velocity_spread_mps ** 2 / 12
        # Initial covariance: the centroid's spread mapped to Cartesian, radial velocity known
        # to the point noise, cross-range velocity unknown (init_velocity_std_mps).
        var_r = rm[0, 0] + disp0[:, 0, 0]
        var_t = (rm[1, 1] + disp0[:, 1, 1]) * r_c ** 2
        var_vr = rm[2, 2] + disp0[:, 2, 2]
        p0 = np.zeros((k, n, n))
        outer = lambda a, b: a[:, :, None] * b[:, None, :]  # noqa: E731
        p0[:, :2, :2] = (var_r[:, None, None] * outer(u, u)
                         + var_t[:, None, None] * outer(tang, tang))
        p0[:, 2:4, 2:4] = (var_vr[:, None, None] * outer(u, u)
                           + cfg.init_velocity_std_mps ** 2 * outer(tang, tang))
        higher = np.arange(4, n)  # acceleration states of higher-order models
        p0[:, higher, higher] = cfg.init_accel_std_mps2 ** 2
        member_track = np.where(np.isin(label, ok_idx),
                                np.searchsorted(ok_idx, label).clip(0, k - 1), -1)
        return NewTracks(x0, p0, disp0, n_c.astype(float), n_c.astype(np.int64), members,
                         member_track)
