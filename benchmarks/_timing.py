"""Timing helper shared by the benchmarks."""
from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np


def median_time_s(fn: Callable[[], object], repeats: int = 9, warmup: int = 2) -> float:
    """Median wall time of `fn()` over `repeats` calls after `warmup` calls, s."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))
