"""Scenario + RCS benchmark: per-frame cost of traffic step, ray casting and scatterer merge.

Dense random highway (`dense_highway`: 30 vehicles incl. trucks and motorcycles, 4 lanes, guard
rails), one rear-left radar. Target: <= 10 ms per frame per radar on 2 cores. The traffic
figure is the whole `run_scenario` (highway-env stepping + truth tables) divided by its frames;
the RCS figure is the median `scene_scatterers` call over the run's frames.
"""
from __future__ import annotations

import time

import numpy as np

from benchmarks._timing import median_time_s


def run() -> list[str]:
    import scenarios
    from radarsim.rcs import RcsConfig, scene_scatterers

    name = "dense_highway"
    t0 = time.perf_counter()
    sim = scenarios.run_scenario(name, seed=0)
    traffic_s = (time.perf_counter() - t0) / sim.n_frames
    frames = list(sim.frames())
    traffic_s = min(traffic_s, median_time_s(
        lambda: scenarios.run_scenario(name, seed=0), repeats=3, warmup=0) / sim.n_frames)
    rng = np.random.default_rng(0)
    cfg = RcsConfig()
    times, ks = [], []
    for f in frames:
        t0 = time.perf_counter()
        sc = scene_scatterers(f.truth, rng, cfg, radar_velocity_mps=f.radar_velocity_mps,
                              mount_height_m=f.mount_height_m)
        times.append(time.perf_counter() - t0)
        ks.append(len(sc))
    rcs_s = float(np.median(times))
    total_ms = 1e3 * (traffic_s + rcs_s)
    n_actors = sim.truth[sim.truth.actor_class != "guard_rail"].actor_id.nunique()
    return [
        f"{name}: {sim.n_frames} frames at {sim.frame_rate_hz:g} Hz, {n_actors} vehicles, "
        f"median K = {int(np.median(ks))} scatterers per frame",
        f"traffic step + truth   {1e3 * traffic_s:7.2f} ms/frame",
        f"ray cast + RCS + merge {1e3 * rcs_s:7.2f} ms/frame (median)",
        f"total                  {total_ms:7.2f} ms/frame per radar (target <= 10 ms)",
    ]


if __name__ == "__main__":
    print("\n".join(run()))
