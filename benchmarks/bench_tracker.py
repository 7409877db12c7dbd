"""Group-tracker time per frame on a dense highway scene: 30 vehicles with several points each,
guard-rail clutter seen from a moving ego and random false alarms (synthesised point clouds),
and, when the scenario runner and the chain are installed, on the simulated DDMA point clouds
of the catalogue's dense_highway case (target: <= 5 ms per frame on 2 cores)."""
from __future__ import annotations

import numpy as np
import pandas as pd

from benchmarks._timing import median_time_s
from pipeline.tracking import GroupTracker, MotionConfig, MountConfig, TrackerConfig

N_ACTORS = 30
POINTS_PER_ACTOR = 6
N_RAIL_POINTS = 40
N_FALSE_ALARMS = 20
EGO_SPEED_MPS = 25.0
FRAME_PERIOD_S = 0.05
N_FRAMES = 60


def dense_highway_frames(rng: np.random.Generator, n_frames: int = N_FRAMES
                         ) -> list[tuple[float, pd.DataFrame]]:
    """Point clouds (radar at the vehicle origin, boresight +x) of a 5-lane highway.

    Returns
    -------
    list of (time_s, DataFrame) with range_m, azimuth_deg, radial_velocity_mps, snr_db.
    """
    lanes = np.array([-7.0, -3.5, 0.0, 3.5, 7.0])
    y0 = lanes[rng.integers(0, lanes.size, N_ACTORS)]
    x0 = np.linspace(10.0, 160.0, N_ACTORS) + rng.uniform(-2, 2, N_ACTORS)
    vx = rng.uniform(-8.0, 8.0, N_ACTORS)          # relative to the ego, m/s
    frames = []
    for i in range(n_frames):
        t = i * FRAME_PERIOD_S
        cx = x0 + vx * t
        off = rng.uniform(-0.5, 0.5, (N_ACTORS, POINTS_PER_ACTOR, 2)) * [4.5, 1.8]
        p = np.stack([cx, y0], axis=-1)[:, None, :] + off
        v = np.broadcast_to(np.stack([vx, np.zeros(N_ACTORS)], -1)[:, None, :], p.shape)
        p, v = p.reshape(-1, 2), v.reshape(-1, 2)
        rail = np.column_stack([rng.uniform(5, 150, N_RAIL_POINTS),
                                rng.choice([-9.5, 9.5], N_RAIL_POINTS)])
        fa = np.column_stack([rng.uniform(5, 150, N_FALSE_ALARMS),
                              rng.uniform(-40, 40, N_FALSE_ALARMS)])
        pos = np.vstack([p, rail, fa])
        vel = np.vstack([v, np.tile([-EGO_SPEED_MPS, 0.0], (N_RAIL_POINTS, 1)),
                         np.column_stack([rng.uniform(-30, 30, N_FALSE_ALARMS),
                                          np.zeros(N_FALSE_ALARMS)])])
        r = np.hypot(pos[:, 0], pos[:, 1])
        az = np.degrees(np.arctan2(pos[:, 1], pos[:, 0]))
        vr = np.einsum("ij,ij->i", pos, vel) / r
        n = r.size
        frames.append((t, pd.DataFrame({
            "range_m": r + rng.normal(0, 0.2, n),
            "azimuth_deg": az + rng.normal(0, 1.0, n),
            "radial_velocity_mps": vr + rng.normal(0, 0.1, n),
            "snr_db": rng.uniform(13, 30, n)})))
    return frames


def run_tracker(frames, ego: float | None) -> GroupTracker:
    tracker = GroupTracker(TrackerConfig(motion=MotionConfig(frame_period_s=FRAME_PERIOD_S)),
                           rng=np.random.default_rng(0))
    for t, pc in frames:
        tracker.step(pc, t, ego)
    return tracker


def _scenario_frames(n_frames: int = 30):
    """DDMA point clouds, ego speeds and mount of the dense_highway case."""
    from harness.cell import components
    from harness.cell import config as cellconfig
    from harness.cell import run as cell
    from harness.cell import spec as cellspec
    from harness.sweep import streams
    comps = components.default_components()
    run = comps.run_scenario("dense_highway", 0, None)
    radar, procs = cellconfig.build_configs(cellspec.CellSpec(scenario="dense_highway"), comps)
    ego = run.ego.drop_duplicates("frame").set_index("frame").iloc[:n_frames]
    frames = []
    for f in ego.index:
        sc = cell.frame_scatterers(comps, run, int(f), 0)
        adc = comps.simulate_frame(radar["ddma"], sc, streams.frame_rng(0, int(f), "ddma"))
        frames.append((float(ego.loc[f, "time_s"]),
                       comps.process_frame(radar["ddma"], adc, procs["ddma"])))
    return frames, ego["ego_speed_mps"].tolist(), run.mount


def run() -> list[str]:
    frames = dense_highway_frames(np.random.default_rng(0))
    n_pts = int(np.median([len(pc) for _, pc in frames]))
    lines = []
    for label, ego in (("ego speed given", EGO_SPEED_MPS), ("ego speed by RANSAC", None)):
        tracker = run_tracker(frames, ego)
        t_frame = median_time_s(lambda: run_tracker(frames, ego), repeats=5, warmup=1) / len(frames)
        lines.append(f"tracker, {N_ACTORS} actors, {n_pts} points/frame, {label}: "
                     f"{t_frame * 1e3:.2f} ms per frame (target <= 5 ms), "
                     f"{tracker.n_tracks} live tracks at the end")
    sframes, speeds, mount = _scenario_frames()
    cfg = TrackerConfig(mount=MountConfig(mount_x_m=mount.x_m, mount_y_m=mount.y_m,
                                          mount_yaw_deg=mount.yaw_deg),
                        motion=MotionConfig(frame_period_s=FRAME_PERIOD_S))

    def track_scenario():
        tracker = GroupTracker(cfg, rng=np.random.default_rng(0))
        for (t, pc), v in zip(sframes, speeds):
            tracker.step(pc, t, v)
        return tracker

    t_frame = median_time_s(track_scenario, repeats=5, warmup=1) / len(sframes)
    n_pts = int(np.median([len(pc) for _, pc in sframes]))
    lines.append(f"tracker, dense_highway scenario (DDMA chain, {n_pts} points/frame): "
                 f"{t_frame * 1e3:.2f} ms per frame, {track_scenario().n_tracks} live "
                 "tracks at the end")
    # Floor measured in the same run: copying one point cloud.
    pc = frames[0][1]
    t_floor = median_time_s(lambda: pc.copy(), repeats=50, warmup=5)
    lines.append(f"floor: copying one point-cloud DataFrame {t_floor * 1e3:.3f} ms")
    return lines
