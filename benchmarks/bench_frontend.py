"""Front-end synthesis speed: `simulate_frame` on the R79 presets with K = 100 scatterers.

Target: median <= 25 ms per frame on a 2-core machine, DDMA and TDMA. Two floors are
timed in the same run: the thermal-noise generation alone (the largest fixed cost, independent
of K) and the real float32 GEMM alone ((n_chirps x n_rx, 2K) @ (2K, n_samples)), so the ratios
say how much of a frame is overhead beyond those two.
"""
from __future__ import annotations

import os
import time

import numpy as np

import radarsim
from benchmarks._timing import median_time_s
from radarsim.frontend import gaussian_noise

TARGET_S = 25e-3
N_SCATTERERS = 100


def _scene(k: int, seed: int = 0) -> radarsim.Scatterers:
    """K scatterers 5-200 m, +/-70 deg azimuth, +/-5 deg elevation, +/-30 m/s radial, 1-10 m^2."""
    g = np.random.default_rng(seed)
    return radarsim.Scatterers.from_spherical(g.uniform(5.0, 200.0, k), g.uniform(-70.0, 70.0, k),
                                              g.uniform(-5.0, 5.0, k),
                                              g.uniform(-30.0, 30.0, k), g.uniform(1.0, 10.0, k))


def _best_time_s(fn, repeats: int) -> float:
    """Fastest of `repeats` calls, s: approximates the uncontended time when other processes
    share the cores (the median is the figure of record)."""
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def run(repeats: int = 21, warmup: int = 3) -> list[str]:
    sc = _scene(N_SCATTERERS)
    rng = np.random.default_rng(0)
    cfg = radarsim.presets.r79_ddma()
    shape = (cfg.n_chirps * cfg.n_rx, cfg.n_samples)
    t_noise = median_time_s(lambda: gaussian_noise(rng, shape, 7.0), repeats, warmup)
    t_zig = median_time_s(lambda: rng.standard_normal(shape, dtype=np.float32), repeats, warmup)
    lhs = rng.standard_normal((shape[0], 2 * N_SCATTERERS), dtype=np.float32)
    rhs = rng.standard_normal((2 * N_SCATTERERS, shape[1]), dtype=np.float32)
    t_gemm = median_time_s(lambda: lhs @ rhs, repeats, warmup)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    lines = [f"machine: {os.cpu_count()} cpus, 1-min load average {load:.2f} "
             "(other processes inflate the medians)",
             f"floor  noise generation (Box-Muller float32, {shape[0]}x{shape[1]}): "
             f"{1e3 * t_noise:6.2f} ms  (numpy float32 ziggurat: {1e3 * t_zig:.2f} ms)",
             f"floor  GEMM alone ({shape[0]}x{2 * N_SCATTERERS} @ {2 * N_SCATTERERS}x{shape[1]} "
             f"float32): {1e3 * t_gemm:6.2f} ms"]
    for name, preset in (("ddma", radarsim.presets.r79_ddma), ("tdma", radarsim.presets.r79_tdma)):
        c = preset()
        t = median_time_s(lambda c=c: radarsim.simulate_frame(c, sc, rng), repeats, warmup)
        t0 = median_time_s(lambda c=c: radarsim.simulate_frame(c, radarsim.Scatterers.empty(),
                                                                rng), repeats, warmup)
        best = _best_time_s(lambda c=c: radarsim.simulate_frame(c, sc, rng), repeats)
        verdict = "met" if t <= TARGET_S else "MISSED"
        lines.append(f"simulate_frame r79_{name} K={N_SCATTERERS}: median {1e3 * t:6.2f} ms "
                     f"(target <= {1e3 * TARGET_S:.0f} ms: {verdict}), best {1e3 * best:.2f} ms; "
                     f"K=0 {1e3 * t0:.2f} ms; {t / (t_noise + t_gemm):.2f} x (noise + GEMM "
                     "floors)")
    return lines
