"""Ground-truth tables of a scenario run, and the single highway-env -> ISO 8855 conversion.

highway-env draws on a screen: x to the right, y DOWN, so its y axis points to the driver's
RIGHT and its headings turn clockwise. Everything in this project uses ISO 8855 / the radar
convention (x forward, y LEFT, z up, yaw counter-clockwise). The flip y -> -y (and heading ->
-heading) happens in `highway_to_iso` and nowhere else; `iso_lateral_to_highway` is the same map
used the other way when a scenario places an actor at an ISO lateral offset.

`build_tables` turns the raw per-frame states recorded from highway-env into

* `truth`: one row per frame and actor (ego excluded) with `TRUTH_COLUMNS`: pose and velocity
  relative to the ego in its vehicle frame, and in the radar frame of the mount
  (p_vehicle = Rz(yaw) p_radar + mount_xyz). Velocities are inertial relative velocities
  (actor minus the ego centre, or minus the radar point including the ego's yaw rate x mount
  lever arm) expressed in the moving frame, so radial_velocity_mps is d(range)/dt.
* `ego`: one row per frame with `EGO_COLUMNS` (world ISO frame).
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from .catalog import Mount

__all__ = ["TRUTH_COLUMNS", "EGO_COLUMNS", "RAW_ACTOR_COLUMNS", "RAW_EGO_COLUMNS",
           "highway_to_iso", "iso_lateral_to_highway", "build_tables", "radar_velocity_mps",
           "ego_yaw_rate_rps"]

TRUTH_COLUMNS = ["frame", "time_s", "actor_id", "actor_class", "length_m", "width_m",
                 "height_m", "x_m", "y_m", "yaw_deg", "vx_mps", "vy_mps", "x_radar_m",
                 "y_radar_m", "z_radar_m", "yaw_radar_deg", "vx_radar_mps", "vy_radar_mps",
                 "range_m", "azimuth_deg", "radial_velocity_mps"]
EGO_COLUMNS = ["frame", "time_s", "ego_speed_mps", "ego_x_m", "ego_y_m", "ego_yaw_deg"]
#: Raw actor states as recorded from highway-env (its own axes, y right).
RAW_ACTOR_COLUMNS = ["frame", "actor_id", "actor_class", "length_m", "width_m", "height_m",
                     "x_hw", "y_hw", "heading_hw", "vx_hw", "vy_hw"]
#: Raw ego states (highway-env axes); speed is signed (negative when reversing).
RAW_EGO_COLUMNS = ["frame", "x_hw", "y_hw", "heading_hw", "speed_mps"]


def highway_to_iso(x_hw, y_hw, heading_hw, vx_hw, vy_hw):
    """highway-env world (y right, clockwise heading) -> ISO world (y left, CCW yaw).

    Parameters
    ----------
    x_hw, y_hw : array_like
        Position, m.
    heading_hw : array_like
        Heading, rad (highway-env's, clockwise on the ground).
    vx_hw, vy_hw : array_like
        Velocity, m/s.

    Returns
    -------
    x, y, yaw_rad, vx, vy : numpy.ndarray
        ISO world frame (x forward along the road, y left, yaw counter-clockwise).
    """
    return (np.asarray(x_hw, float), -np.asarray(y_hw, float), -np.asarray(heading_hw, float),
            np.asarray(vx_hw, float), -np.asarray(vy_hw, float))


def iso_lateral_to_highway(lateral_left_m):
    """An ISO lateral offset (positive to the LEFT) as a highway-env lane lateral coordinate."""
    return -np.asarray(lateral_left_m, dtype=float) if np.ndim(lateral_left_m) \
        else -float(lateral_left_m)


def _wrap_deg(a):
    return (np.asarray(a) + 180.0) % 360.0 - 180.0


def ego_yaw_rate_rps(ego: pd.DataFrame) -> np.ndarray:
    """(F,) ego yaw rate from the per-frame yaw (central differences), rad/s."""
    yaw = np.unwrap(np.radians(ego["ego_yaw_deg"].to_numpy(float)))
    t = ego["time_s"].to_numpy(float)
    if yaw.size < 2:
        return np.zeros(yaw.size)
    return np.gradient(yaw, t)


def radar_velocity_mps(ego_speed_mps, yaw_rate_rps, mount: Mount) -> np.ndarray:
    """Velocity of the radar over the ground in its own frame, m/s.

    v = Rz(-yaw_mount) [(v_ego, 0) + omega x r_mount] (no side slip).

    Returns
    -------
    (F, 3) float
    """
    v = np.atleast_1d(np.asarray(ego_speed_mps, float))
    w = np.atleast_1d(np.asarray(yaw_rate_rps, float))
    vx = v - w * mount.y_m
    vy = w * mount.x_m
    c, s = np.cos(np.radians(mount.yaw_deg)), np.sin(np.radians(mount.yaw_deg))
    return np.column_stack([c * vx + s * vy, -s * vx + c * vy, np.zeros(v.size)])


def build_tables(raw_actors: pd.DataFrame, raw_ego: pd.DataFrame, mount: Mount,
                 frame_rate_hz: float) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Truth and ego tables from raw highway-env states (vectorised over all rows).

    Parameters
    ----------
    raw_actors : pandas.DataFrame
        `RAW_ACTOR_COLUMNS`, one row per frame and actor.
    raw_ego : pandas.DataFrame
        `RAW_EGO_COLUMNS`, one row per frame.
    mount : Mount
    frame_rate_hz : float

    Returns
    -------
    truth : pandas.DataFrame
        `TRUTH_COLUMNS`, sorted by frame and actor_id.
    ego : pandas.DataFrame
        `EGO_COLUMNS`.
    """
    ex, ey, eyaw, _, _ = highway_to_iso(raw_ego["x_hw"], raw_ego["y_hw"],
                                        raw_ego["heading_hw"], 0.0, 0.0)
    frames = raw_ego["frame"].to_numpy(np.int64)
    ego = pd.DataFrame({"frame": frames, "time_s": frames / frame_rate_hz,
                        "ego_speed_mps": raw_ego["speed_mps"].to_numpy(float),
                        "ego_x_m": ex, "ego_y_m": ey,
                        "ego_yaw_deg": _wrap_deg(np.degrees(eyaw))})
    omega = ego_yaw_rate_rps(ego)
    if raw_actors.empty:
        return pd.DataFrame({c: pd.Series(dtype=float) for c in TRUTH_COLUMNS}).astype(
            {"frame": np.int64, "actor_id": np.int64, "actor_class": object}), ego
    idx = np.searchsorted(frames, raw_actors["frame"].to_numpy(np.int64))
    x, y, yaw, vx, vy = highway_to_iso(raw_actors["x_hw"], raw_actors["y_hw"],
                                       raw_actors["heading_hw"], raw_actors["vx_hw"],
                                       raw_actors["vy_hw"])
    e_yaw = eyaw[idx]
    c, s = np.cos(e_yaw), np.sin(e_yaw)
    e_v = ego["ego_speed_mps"].to_numpy()[idx]
    # Ego-centre velocity in the world: v_ego along its heading (no side slip).
    dvx = vx - e_v * c
    dvy = vy - e_v * s
    dx, dy = x - ex[idx], y - ey[idx]
    xv, yv = c * dx + s * dy, -s * dx + c * dy
    vxv, vyv = c * dvx + s * dvy, -s * dvx + c * dvy
    yaw_v = _wrap_deg(np.degrees(yaw - e_yaw))
    # Radar frame: subtract the radar point's own velocity omega x r_mount, then rotate.
    w = omega[idx]
    ym = np.radians(mount.yaw_deg)
    cm, sm = np.cos(ym), np.sin(ym)
    px, py = xv - mount.x_m, yv - mount.y_m
    xr, yr = cm * px + sm * py, -sm * px + cm * py
    rvx, rvy = vxv + w * mount.y_m, vyv - w * mount.x_m
    vxr, vyr = cm * rvx + sm * rvy, -sm * rvx + cm * rvy
    zr = 0.5 * raw_actors["height_m"].to_numpy(float) - mount.z_m
    rng = np.sqrt(xr ** 2 + yr ** 2 + zr ** 2)
    truth = pd.DataFrame({
        "frame": raw_actors["frame"].to_numpy(np.int64),
        "time_s": raw_actors["frame"].to_numpy(np.int64) / frame_rate_hz,
        "actor_id": raw_actors["actor_id"].to_numpy(np.int64),
        "actor_class": raw_actors["actor_class"].astype(object).to_numpy(),
        "length_m": raw_actors["length_m"].to_numpy(float),
        "width_m": raw_actors["width_m"].to_numpy(float),
        "height_m": raw_actors["height_m"].to_numpy(float),
        "x_m": xv, "y_m": yv, "yaw_deg": yaw_v, "vx_mps": vxv, "vy_mps": vyv,
        "x_radar_m": xr, "y_radar_m": yr, "z_radar_m": zr,
        "yaw_radar_deg": _wrap_deg(yaw_v - mount.yaw_deg),
        "vx_radar_mps": vxr, "vy_radar_mps": vyr,
        "range_m": rng, "azimuth_deg": np.degrees(np.arctan2(yr, xr)),
        "radial_velocity_mps": (xr * vxr + yr * vyr) / np.maximum(rng, 1e-9),
    })
    truth = truth.sort_values(["frame", "actor_id"], kind="stable").reset_index(drop=True)
    return truth[TRUTH_COLUMNS], ego
