"""Timing helpers shared by the benchmarks: medians, and the FFT floor a chain is measured
against."""
from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
import scipy.fft


def median_time_s(fn: Callable[[], object], repeats: int = 9, warmup: int = 2,
                  clock: Callable[[], float] = time.perf_counter) -> float:
    """Median time of `fn()` over `repeats` calls after `warmup` calls, s: wall time, or with
    ``clock=time.thread_time`` this thread's CPU time (then `fn` must not hand work to other
    threads)."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        t0 = clock()
        fn()
        times.append(clock() - t0)
    return float(np.median(times))


def fft_floor_once(cfg, x32: np.ndarray, workers: int = -1) -> None:
    """The floor of a receive chain: the range rFFT of the float32 frame `x32` (n_chirps,
    n_rx, n_samples) plus the Doppler FFT over one Tx's slow-time sequence (the scheme's: all
    chirps for DDMA, one slot per code period for TDMA), scipy.fft with `workers` threads (-1:
    all cores)."""
    per = int(round(cfg.scheme.slow_time_period_s(cfg) / cfg.chirp_period_s))
    rf = scipy.fft.rfft(x32, axis=-1, workers=workers)[..., : cfg.n_samples // 2]
    scipy.fft.fft(rf.reshape(-1, per, cfg.n_rx, rf.shape[-1]), axis=0, workers=workers)
