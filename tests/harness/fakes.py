"""Small, fast stand-ins for the scenario runner, RCS model, front end and chain.

They keep the harness tests independent of the real parts' speed: a "scenario" is one car
approaching along the radar's boresight plus a guard rail; the "ADC" is the scatterer list plus
Gaussian measurement noise drawn from the frame's generator; the "chain" reports each scatterer
as a detection (TDMA without disambiguation folds velocity into +/-Vmax) plus one ghost per
frame. Module-level functions only, so a `Components` of them pickles to worker processes.
"""
from __future__ import annotations

import os
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd

import radarsim
from harness.cell.components import Components

FRAME_DT_S = 0.05
#: The result tables sweep tests compare between runs.
TABLES = ("summary", "detections", "frames", "actors", "truth")


def assert_same_tables(a: Path, b: Path) -> None:
    """Assert two results directories hold equal `TABLES`."""
    for t in TABLES:
        pd.testing.assert_frame_equal(pd.read_parquet(a / f"{t}.parquet"),
                                      pd.read_parquet(b / f"{t}.parquet"))


def fake_run_scenario(name: str, seed: int, duration_s=None, frame_rate_hz=None):
    if name == "boom":
        raise RuntimeError("scenario exploded")
    n = int(round((duration_s or 0.5) / FRAME_DT_S))
    f = np.arange(n)
    speed = {"slow": -5.0, "fast": -30.0}.get(name, -15.0)
    x = 80.0 + speed * f * FRAME_DT_S + 0.1 * seed
    car = pd.DataFrame({
        "frame": f, "time_s": f * FRAME_DT_S, "actor_id": 1, "actor_class": "car",
        "length_m": 4.0, "width_m": 2.0, "height_m": 1.5, "x_m": x, "y_m": 0.0,
        "yaw_deg": 0.0, "vx_mps": speed, "vy_mps": 0.0, "x_radar_m": x, "y_radar_m": 0.0,
        "z_radar_m": 0.0, "yaw_radar_deg": 0.0, "vx_radar_mps": speed, "vy_radar_mps": 0.0,
        "range_m": x, "azimuth_deg": 0.0, "radial_velocity_mps": speed})
    rail = car.assign(actor_id=2, actor_class="guard_rail", length_m=200.0, width_m=0.3,
                      x_m=50.0, y_m=-10.0, x_radar_m=50.0, y_radar_m=-10.0, vx_mps=0.0,
                      vx_radar_mps=0.0, range_m=np.hypot(50, 10), azimuth_deg=-11.3,
                      radial_velocity_mps=0.0)
    truth = pd.concat([car, rail], ignore_index=True).sort_values(["frame", "actor_id"],
                                                                  ignore_index=True)
    ego = pd.DataFrame({"frame": f, "time_s": f * FRAME_DT_S, "ego_speed_mps": 0.0,
                        "ego_x_m": 0.0, "ego_y_m": 0.0, "ego_yaw_deg": 0.0})
    crit = SimpleNamespace(metric="first_detection_range_m", op=">=", value=60.0, actor_id=1)
    case = SimpleNamespace(name=name, must_detect=(1,), criteria=(crit,))
    return SimpleNamespace(truth=truth, ego=ego, mount=None, case=case)


def fake_scene_scatterers(rows: pd.DataFrame, rng: np.random.Generator):
    """One scatterer at the near face centre of each actor (the rail: its point abeam)."""
    pos = np.column_stack([rows["x_radar_m"] - 0.5 * rows["length_m"] *
                           (rows["actor_class"] != "guard_rail"), rows["y_radar_m"],
                           np.zeros(len(rows))])
    vel = np.column_stack([rows["vx_radar_mps"], rows["vy_radar_mps"], np.zeros(len(rows))])
    return radarsim.Scatterers(pos, vel, np.full(len(rows), 10.0),
                               actor_id=rows["actor_id"].to_numpy(dtype=np.int64))


def fake_simulate_frame(cfg, sc, rng):
    noise = rng.normal(0.0, [0.2, 0.05], size=(len(sc), 2))
    return {"sc": sc, "noise": noise, "ghost": rng.uniform([20, -30], [150, 30])}


def fake_process_frame(cfg, adc, proc):
    delay = float(os.environ.get("FAKE_PROCESS_DELAY_S", "0"))
    if delay:
        time.sleep(delay)
    sc, noise = adc["sc"], adc["noise"]
    r = sc.range_m + noise[:, 0]
    v = sc.radial_velocity_mps + noise[:, 1]
    if cfg.mimo == "tdma" and not proc["velocity.tdma_disambiguation"]:
        vmax = cfg.max_unambiguous_velocity_mps
        v = (v + vmax) % (2 * vmax) - vmax
    az = np.radians(sc.azimuth_deg)
    gx, gy = adc["ghost"]
    snr = 10 * np.log10(sc.rcs_m2) + 100 - 40 * np.log10(sc.range_m) + \
        (6.0 if cfg.mimo == "ddma" else 0.0)
    df = pd.DataFrame({"range_m": np.append(r, np.hypot(gx, gy)),
                       "azimuth_deg": np.append(np.degrees(az), np.degrees(np.arctan2(gy, gx))),
                       "elevation_deg": 0.0,
                       "radial_velocity_mps": np.append(v, 3.0),
                       "snr_db": np.append(snr, 12.0)})
    a = np.radians(df["azimuth_deg"])
    df["x_m"], df["y_m"], df["z_m"] = df["range_m"] * np.cos(a), df["range_m"] * np.sin(a), 0.0
    return df


def fake_make_processing(overrides: dict):
    return {"velocity.tdma_disambiguation": True, **overrides}


FAKE = Components(run_scenario=fake_run_scenario, scene_scatterers=fake_scene_scatterers,
                  simulate_frame=fake_simulate_frame, process_frame=fake_process_frame,
                  make_processing=fake_make_processing)


def failing_run_scenario(name: str, seed: int, duration_s=None):
    """A scenario runner that always fails (a duplicate execution that crashes)."""
    raise RuntimeError(f"duplicate execution of {name} failed")


FAILING = Components(run_scenario=failing_run_scenario, scene_scatterers=fake_scene_scatterers,
                     simulate_frame=fake_simulate_frame, process_frame=fake_process_frame,
                     make_processing=fake_make_processing)
