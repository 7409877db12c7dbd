"""Typed data passed between the tracker's parts: a frame's points, the track set, results;
and track maintenance (DETECT -> ACTIVE -> FREE, `MaintenanceConfig`).

The track set is struct-of-arrays (T live tracks) and immutable in use: every stage returns a
new `Tracks` (or a typed result) instead of editing its input, so a part can be swapped or
tested on its own.

References
----------
.. [1] TI mmWave SDK, "Group tracker" (gtrack) design: DETECT -> ACTIVE -> FREE with
       det2act = 3, det2free = 3, act2free = 10.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pandas as pd

from core.checks import require
from core.errors import BadInput

__all__ = ["Points", "Tracks", "Association", "NewTracks", "POINT_COLUMNS",
           "MaintenanceConfig", "maintain", "expired"]

#: Point-cloud columns the tracker reads.
POINT_COLUMNS = ("range_m", "azimuth_deg", "radial_velocity_mps", "snr_db")


class Points(NamedTuple):
    """One frame's point cloud (radar frame), (N,) float each.

    Attributes
    ----------
    range_m : m
    azimuth_rad : rad, radar frame
    radial_velocity_mps : m/s relative to the radar (negative = approaching)
    snr_db : dB
    """

    range_m: np.ndarray
    azimuth_rad: np.ndarray
    radial_velocity_mps: np.ndarray
    snr_db: np.ndarray

    @property
    def size(self) -> int:
        return int(self.range_m.size)

    @classmethod
    def from_frame(cls, points: pd.DataFrame) -> "Points":
        """Checked arrays of a point-cloud DataFrame (columns `POINT_COLUMNS`).

        Every row is kept, a range <= 0 included (the SDK reports a return nearer than the
        profile's range bias at 0 m); `usable` says which rows the tracker can use.

        Raises
        ------
        core.errors.BadInput
            Not a DataFrame, a missing column, non-finite values.
        """
        if not isinstance(points, pd.DataFrame):
            raise BadInput(f"points must be a pandas DataFrame, got {type(points).__name__}")
        if len(points) == 0:
            return cls(*(np.zeros(0) for _ in range(4)))
        missing = [c for c in POINT_COLUMNS if c not in points.columns]
        if missing:
            raise BadInput(f"points is missing columns {missing}; needs {list(POINT_COLUMNS)}")
        r, az, vr, snr = _point_columns(points)
        for name, arr in zip(POINT_COLUMNS, (r, az, vr, snr)):
            if not np.all(np.isfinite(arr)):
                raise BadInput(f"points column {name} contains non-finite values")
        return cls(r, np.radians(az), vr, snr)

    def usable(self) -> np.ndarray:
        """(N,) bool: the points with a position, range_m > 0. A point at 0 m (a return
        nearer than the range bias, clamped as TI's SDK clamps it) has no azimuth to place it
        by and no group to join: the tracker skips it instead of failing the frame."""
        return self.range_m > 0

    def select(self, keep: np.ndarray) -> "Points":
        """The points where `keep` (N,) bool is True."""
        return Points(*(a[keep] for a in self))


def _point_columns(points: pd.DataFrame) -> list[np.ndarray]:
    """The `POINT_COLUMNS` of a frame as float64 arrays (the columns must exist).

    One ``to_numpy`` of the whole frame, then its columns: reading a column builds a Series
    (and copies the frame's ``attrs``), ten times the cost of the conversion on a frame of a
    few dozen points. Column by column when the frame has duplicate names or columns that
    are no numbers. The same float64 values either way.
    """
    locs = [points.columns.get_loc(c) for c in POINT_COLUMNS]
    if all(isinstance(i, (int, np.integer)) for i in locs):
        try:
            arr = points.to_numpy(dtype=np.float64)
        except (TypeError, ValueError):
            pass
        else:
            return [np.ascontiguousarray(arr[:, i]) for i in locs]
    return [points[c].to_numpy(dtype=np.float64) for c in POINT_COLUMNS]


@dataclass(frozen=True, slots=True)
class Tracks:
    """The live tracks, struct-of-arrays (T tracks, state length n).

    Attributes
    ----------
    track_id : (T,) int
    x : (T, n) float
        State [x, y, vx, vy(, ax, ay)], vehicle frame, relative velocity.
    p : (T, n, n) float
        State covariance.
    dispersion : (T, 3, 3) float
        Group dispersion D in measurement space (range m, azimuth rad, radial velocity m/s).
    n_est : (T,) float
        Running estimate of the number of points per frame of the group.
    hits, misses, age : (T,) int
        Consecutive hits, consecutive misses, frames since the track started.
    active : (T,) bool
        ACTIVE (else DETECT).
    """

    track_id: np.ndarray
    x: np.ndarray
    p: np.ndarray
    dispersion: np.ndarray
    n_est: np.ndarray
    hits: np.ndarray
    misses: np.ndarray
    age: np.ndarray
    active: np.ndarray

    @classmethod
    def empty(cls, n_state: int) -> "Tracks":
        return cls(np.zeros(0, dtype=np.int64), np.zeros((0, n_state)),
                   np.zeros((0, n_state, n_state)), np.zeros((0, 3, 3)), np.zeros(0),
                   np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64),
                   np.zeros(0, dtype=np.int64), np.zeros(0, dtype=bool))

    @property
    def size(self) -> int:
        return int(self.track_id.size)

    def replace(self, **changes) -> "Tracks":
        return dataclasses.replace(self, **changes)

    def select(self, keep: np.ndarray) -> "Tracks":
        """The tracks where `keep` (bool (T,) or indices) holds."""
        return Tracks(*(getattr(self, f.name)[keep] for f in dataclasses.fields(self)))

    def concat(self, other: "Tracks") -> "Tracks":
        """These tracks followed by `other`."""
        return Tracks(*(np.concatenate([getattr(self, f.name), getattr(other, f.name)])
                        for f in dataclasses.fields(self)))


class Association(NamedTuple):
    """Result of an associator.

    Attributes
    ----------
    track_index : (N,) int
        Track each point updates (-1: none).
    innovation : (N, 3) float
        Measurement residual of each point against its track (range m, azimuth rad, radial
        velocity m/s); rows of unassociated points are not meaningful.
    jacobian : (T, 3, n) float
        Measurement Jacobian of every track at its predicted state.
    """

    track_index: np.ndarray
    innovation: np.ndarray
    jacobian: np.ndarray


@dataclass(frozen=True, slots=True)
class NewTracks:
    """Tracks an allocator starts (K new tracks, ids not yet given).

    Attributes
    ----------
    x, p, dispersion, n_est : as in `Tracks`, K rows.
    n_points : (K,) int
        Points that started each track.
    members : (M,) int
        Indices (into the frame's points) of the points of every cluster considered.
    member_track : (M,) int
        New track (0..K-1) each of those points started, -1 for a rejected cluster.
    """

    x: np.ndarray
    p: np.ndarray
    dispersion: np.ndarray
    n_est: np.ndarray
    n_points: np.ndarray
    members: np.ndarray
    member_track: np.ndarray

    @classmethod
    def none(cls, n_state: int) -> "NewTracks":
        z = np.zeros(0, dtype=np.int64)
        return cls(np.zeros((0, n_state)), np.zeros((0, n_state, n_state)),
                   np.zeros((0, 3, 3)), np.zeros(0), z, z, z)

    @property
    def size(self) -> int:
        return int(self.n_points.size)


@dataclass(frozen=True, kw_only=True, slots=True)
class MaintenanceConfig:
    """Track maintenance (``TrackerConfig.maintenance``): confirmation, freeing, capacity.

    Parameters
    ----------
    hits_to_confirm : int
        Consecutive hits that promote DETECT to ACTIVE (TI det2act: 3).
    misses_to_free_detect : int
        Consecutive misses that free a DETECT track (TI det2free: 3).
    misses_to_free_active : int
        Consecutive misses that free an ACTIVE track (TI act2free: 10).
    max_tracks : int
        Most live tracks; allocation stops there.
    """

    hits_to_confirm: int = 3
    misses_to_free_detect: int = 3
    misses_to_free_active: int = 10
    max_tracks: int = 256

    def __post_init__(self) -> None:
        require(self, ("hits_to_confirm", "misses_to_free_detect", "misses_to_free_active",
                       "max_tracks"), "integer", ge=1)


def maintain(tracks: Tracks, hit: np.ndarray, cfg: MaintenanceConfig) -> Tracks:
    """One frame of the DETECT -> ACTIVE state machine: age, consecutive hits and misses.

    DETECT needs consecutive hits: a miss resets the count (TI det2act).

    Parameters
    ----------
    tracks : Tracks
    hit : (T,) bool
        The tracks that took points this frame.
    cfg : MaintenanceConfig
    """
    hits = np.where(hit, tracks.hits + 1, 0)
    return tracks.replace(age=tracks.age + 1, hits=hits,
                          misses=np.where(hit, 0, tracks.misses + 1),
                          active=tracks.active | (hits >= cfg.hits_to_confirm))


def expired(tracks: Tracks, cfg: MaintenanceConfig) -> np.ndarray:
    """(T,) bool: the tracks freed by their consecutive misses (ACTIVE and DETECT limits)."""
    return tracks.misses >= np.where(tracks.active, cfg.misses_to_free_active,
                                     cfg.misses_to_free_detect)
