"""Field of view of the reported detections: the TI demos' ``cfarFovCfg`` (range, m; radial
velocity, m/s) and ``aoaFovCfg`` (azimuth, elevation, deg) drop detections outside the given
intervals after detection and angle estimation (mmWave SDK 3.x user guide, sec. "Configuration
(.cfg) File Format"). The four limits are a `FovConfig` (``ProcessingConfig.fov``); None keeps
everything.

The SDK's CFAR DPU applies the Doppler limits to the detection's Doppler index, i.e. to the
aliased velocity, before the AoA DPU extends it beyond +/-Vmax (``extendedMaxVelocity``): a
chain with velocity extension applies `FovConfig.velocity_mps` itself, in its CFAR step
(`in_interval`), and leaves it out of the fields it has `apply_fov` apply
(`pipeline.mimo.MimoChain.fov_fields`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from core.errors import BadInput

__all__ = ["FOV_FIELDS", "FovConfig", "check_interval", "apply_fov", "in_interval"]

#: FovConfig field -> the point-cloud column it bounds.
FOV_FIELDS = {"range_m": "range_m", "velocity_mps": "radial_velocity_mps",
              "azimuth_deg": "azimuth_deg", "elevation_deg": "elevation_deg"}


def check_interval(name: str, value) -> tuple[float, float] | None:
    """`value` as a (lo, hi) pair of finite floats with lo <= hi, or None.

    Raises
    ------
    ValueError
        Naming the field, the value and the rule.
    """
    if value is None:
        return None
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise BadInput(f"{name}={value!r} must be a (min, max) pair of numbers or None") \
            from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
        raise BadInput(f"{name}={value!r} must be finite with min <= max")
    return (lo, hi)


@dataclass(frozen=True, kw_only=True, slots=True)
class FovConfig:
    """Field of view of the reported detections (``cfarFovCfg`` range / Doppler, ``aoaFovCfg``):
    detections outside are dropped (`apply_fov`).

    Parameters
    ----------
    range_m, velocity_mps, azimuth_deg, elevation_deg : (min, max) or None
        Limits in m, m/s (radial velocity), deg, deg; None: no limit (default).
    """

    range_m: tuple[float, float] | None = None
    velocity_mps: tuple[float, float] | None = None
    azimuth_deg: tuple[float, float] | None = None
    elevation_deg: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        for name in FOV_FIELDS:
            object.__setattr__(self, name, check_interval(name, getattr(self, name)))


def apply_fov(points: pd.DataFrame, fov: FovConfig, fields=tuple(FOV_FIELDS)) -> pd.DataFrame:
    """The detections of `points` inside every interval `fov` sets among `fields`.

    Parameters
    ----------
    points : pandas.DataFrame
        Point cloud with the columns of `FOV_FIELDS` (range_m m, radial_velocity_mps m/s,
        azimuth_deg and elevation_deg deg).
    fov : FovConfig
    fields : iterable of str
        The `FOV_FIELDS` to apply (default all; a chain that applies one itself, earlier in
        its steps, leaves it out: `pipeline.mimo.MimoChain.fov_fields`).

    Returns
    -------
    pandas.DataFrame
        The rows inside (the same frame when no limit is set), attrs kept.
    """
    keep = np.ones(len(points), dtype=bool)
    limited = False
    for field in fields:
        column = FOV_FIELDS[field]
        bounds = getattr(fov, field)
        if bounds is not None:
            values = points[column].to_numpy()
            keep &= (values >= bounds[0]) & (values <= bounds[1])
            limited = True
    if not limited:
        return points
    out = points[keep].reset_index(drop=True)
    out.attrs = dict(points.attrs)
    return out


def in_interval(values: np.ndarray, bounds: tuple[float, float] | None) -> np.ndarray:
    """(n,) bool: `values` (n,) inside [lo, hi]; all True when `bounds` is None."""
    if bounds is None:
        return np.ones(np.shape(values), dtype=bool)
    return (values >= bounds[0]) & (values <= bounds[1])
