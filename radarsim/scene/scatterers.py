"""Point scatterers in the radar frame: the interface between the RCS model and the front end.

A `Scatterers` set is what the front end sees of a scene at one frame: K points with position,
velocity (relative to the radar, ego motion included) and radar cross-section. Conventions of
design.md section 3: radar frame x along boresight, y left, z up; metres, m/s, m^2.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from core.errors import BadInput

__all__ = ["Scatterers", "PointGeometry", "MAX_RCS_M2", "MAX_SPEED_MPS"]

#: Largest RCS of one scatterer, m^2 (90 dBsm, far above any real object: a large ship is about
#: 60 dBsm, a truck's flat back about 30 dBsm; tests use ~63 dBsm for far calibrated targets).
#: Far beyond it (1e300) the received power overflows float32 and the ADC frame silently becomes
#: garbage (all zeros).
MAX_RCS_M2 = 1e9
#: Largest relative speed of a scatterer, m/s (road users close at < 150 m/s; the front end's
#: Doppler model assumes v << c).
MAX_SPEED_MPS = 1000.0


def _as_float_array(name: str, value, shape_tail: tuple[int, ...]) -> np.ndarray:
    # A boolean is a number to numpy (True -> 1.0), never to a user: `rcs_m2=[True]` is a bug
    # upstream, not 1 m^2.
    if np.asarray(value).dtype == np.bool_:
        raise BadInput(f"{name} must hold real numbers, got booleans")
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise BadInput(f"{name} must hold real numbers: {exc}") from None
    if arr.ndim != 1 + len(shape_tail) or arr.shape[1:] != shape_tail:
        want = "(K, " + ", ".join(map(str, shape_tail)) + ")" if shape_tail else "(K,)"
        raise BadInput(f"{name} must have shape {want}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise BadInput(f"{name} contains non-finite values")
    return arr


class PointGeometry:
    """Range and direction of points ``position_m`` (K, 3) in the radar frame: shared by the
    scatterers and the interfering radars."""

    __slots__ = ()
    position_m: np.ndarray

    @property
    def range_m(self) -> np.ndarray:
        """(K,) slant range, m."""
        return np.linalg.norm(self.position_m, axis=1)

    @property
    def unit_vector(self) -> np.ndarray:
        """(K, 3) unit vectors from the radar to each point."""
        return self.position_m / self.range_m[:, None]


@dataclass(frozen=True, slots=True, init=False)
class Scatterers(PointGeometry):
    """K point scatterers in the radar frame.

    Parameters
    ----------
    position_m : (K, 3) float
        Position at the frame's reference time (the middle of the chirp burst), radar frame, m.
    velocity_mps : (K, 3) float
        Velocity relative to the radar (ego motion included), radar frame, m/s.
    rcs_m2 : (K,) float
        Radar cross-section, m^2, >= 0.
    actor_id : (K,) int, optional
        Ground-truth actor of each scatterer; -1 for none (clutter, multipath). Default all -1.

    Raises
    ------
    ValueError
        On a wrong shape, a non-numeric or non-finite value, a negative RCS or one above
        `MAX_RCS_M2`, a speed above `MAX_SPEED_MPS`, a scatterer at the radar (range < 1 mm)
        or mismatched K.
    """

    position_m: np.ndarray
    velocity_mps: np.ndarray
    rcs_m2: np.ndarray
    actor_id: np.ndarray

    def __init__(self, position_m, velocity_mps, rcs_m2, actor_id=None) -> None:
        pos = _as_float_array("position_m", np.reshape(position_m, (-1, 3))
                              if np.size(position_m) == 0 else position_m, (3,))
        vel = _as_float_array("velocity_mps", np.reshape(velocity_mps, (-1, 3))
                              if np.size(velocity_mps) == 0 else velocity_mps, (3,))
        rcs = _as_float_array("rcs_m2", rcs_m2, ())
        k = pos.shape[0]
        if vel.shape[0] != k or rcs.shape[0] != k:
            raise BadInput(f"position_m, velocity_mps and rcs_m2 must have the same K, got "
                           f"{pos.shape[0]}, {vel.shape[0]}, {rcs.shape[0]}")
        if np.any(rcs < 0):
            raise BadInput(f"rcs_m2 must be >= 0, got min {rcs.min():g}")
        if np.any(rcs > MAX_RCS_M2):
            raise BadInput(f"rcs_m2={rcs.max():g} exceeds the limit {MAX_RCS_M2:g} m^2 "
                           "(90 dBsm)")
        speed = np.linalg.norm(vel, axis=1) if k else np.zeros(0)
        if np.any(speed > MAX_SPEED_MPS):
            raise BadInput(f"velocity_mps: speed {speed.max():g} m/s exceeds the limit "
                           f"{MAX_SPEED_MPS:g} m/s")
        if k and np.min(np.linalg.norm(pos, axis=1)) < 1e-3:
            raise BadInput("position_m: a scatterer sits at the radar (range < 1 mm)")
        if actor_id is None:
            aid = np.full(k, -1, dtype=np.int64)
        else:
            aid = np.asarray(actor_id)
            if aid.shape != (k,) or not np.issubdtype(aid.dtype, np.integer):
                raise BadInput(f"actor_id must be an integer array of shape ({k},), got "
                               f"{aid.dtype} {aid.shape}")
            aid = aid.astype(np.int64)
        for name, arr in (("position_m", pos), ("velocity_mps", vel), ("rcs_m2", rcs),
                          ("actor_id", aid)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def __len__(self) -> int:
        return self.rcs_m2.shape[0]

    @classmethod
    def empty(cls) -> "Scatterers":
        """A set with K = 0 scatterers (pure-noise frame)."""
        return cls(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0))

    @classmethod
    def from_spherical(cls, range_m, azimuth_deg, elevation_deg, radial_velocity_mps, rcs_m2,
                       actor_id=None) -> "Scatterers":
        """Point targets given by range, azimuth (atan2(y, x), positive left), elevation and a
        purely radial velocity (design.md 3), all (K,) arrays in m, deg, deg, m/s, m^2."""
        r = np.atleast_1d(np.asarray(range_m, dtype=np.float64))
        az = np.radians(np.atleast_1d(np.asarray(azimuth_deg, dtype=np.float64)))
        el = np.radians(np.atleast_1d(np.asarray(elevation_deg, dtype=np.float64)))
        u = np.column_stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        vr = np.atleast_1d(np.asarray(radial_velocity_mps, dtype=np.float64))
        return cls(r[:, None] * u, vr[:, None] * u, np.atleast_1d(rcs_m2), actor_id)

    @classmethod
    def concatenate(cls, parts: list["Scatterers"]) -> "Scatterers":
        """Join several sets into one (order preserved)."""
        if not parts:
            return cls.empty()
        return cls._of_checked(np.concatenate([p.position_m for p in parts]),
                               np.concatenate([p.velocity_mps for p in parts]),
                               np.concatenate([p.rcs_m2 for p in parts]),
                               np.concatenate([p.actor_id for p in parts]))

    def select(self, keep: np.ndarray) -> "Scatterers":
        """The scatterers where `keep` ((K,) bool or indices) holds, in order."""
        return self._of_checked(self.position_m[keep], self.velocity_mps[keep],
                                self.rcs_m2[keep], self.actor_id[keep])

    @classmethod
    def _of_checked(cls, pos: np.ndarray, vel: np.ndarray, rcs: np.ndarray,
                    aid: np.ndarray) -> "Scatterers":
        """A set from the (new) arrays of checked sets (joined or subset: every rule of
        `__init__` still holds), without checking them again (the scene builds several sets a
        frame)."""
        out = object.__new__(cls)
        for name, arr in (("position_m", pos), ("velocity_mps", vel), ("rcs_m2", rcs),
                          ("actor_id", aid)):
            arr.setflags(write=False)
            object.__setattr__(out, name, arr)
        return out

    @property
    def radial_velocity_mps(self) -> np.ndarray:
        """(K,) d(range)/dt, m/s; negative = approaching (design.md 3)."""
        return np.einsum("kd,kd->k", self.velocity_mps, self.unit_vector)

    @property
    def azimuth_deg(self) -> np.ndarray:
        """(K,) atan2(y, x), deg, positive to the left."""
        return np.degrees(np.arctan2(self.position_m[:, 1], self.position_m[:, 0]))

    @property
    def elevation_deg(self) -> np.ndarray:
        """(K,) asin(z / r), deg."""
        return np.degrees(np.arcsin(np.clip(self.position_m[:, 2] / self.range_m, -1, 1)))
