"""Timing helpers shared by the benchmarks: medians, and the FFT floor a chain is measured
against."""
from __future__ import annotations

import time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import scipy.fft

import pipeline
from pipeline.threads import inline

#: Alternating rounds of a value against its floor; each figure is the best of them.
ROUNDS = 11


class Timed(NamedTuple):
    """Best wall time and best process CPU time (all threads) of a callable, s."""

    wall_s: float
    cpu_s: float


class ChainTiming(NamedTuple):
    """A chain against its FFT floor (`chain_against_floor`)."""

    chain: Timed         # process_frame as called: its passes split over the cores
    one_thread: Timed    # the same inside `pipeline.threads.inline`, as a sweep cell runs it
    floor_wall_s: float  # the floor's FFTs on every core: the least wall time of any chain
    floor_cpu_s: float   # the same FFTs on one core: their work itself, the least CPU

    @property
    def cpu_ratio(self) -> float:
        return self.chain.cpu_s / self.floor_cpu_s

    @property
    def one_thread_cpu_ratio(self) -> float:
        return self.one_thread.cpu_s / self.floor_cpu_s

    @property
    def wall_ratio(self) -> float:
        return self.chain.wall_s / self.floor_wall_s


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


def alternating_best(fns: dict[str, Callable[[], object]], rounds: int = ROUNDS
                     ) -> dict[str, Timed]:
    """Best wall and process-CPU time of each callable over `rounds` rounds, each round calling
    every callable once in turn (after one warm-up call each), so load from other processes
    hits values and floors alike; the best of several is the figure least moved by it."""
    wall = {k: [] for k in fns}
    cpu = {k: [] for k in fns}
    for fn in fns.values():
        fn()
    for _ in range(rounds):
        for k, fn in fns.items():
            w, c = time.perf_counter(), time.process_time()
            fn()
            wall[k].append(time.perf_counter() - w)
            cpu[k].append(time.process_time() - c)
    return {k: Timed(min(wall[k]), min(cpu[k])) for k in fns}


def chain_against_floor(cfg, adc: np.ndarray, rounds: int = ROUNDS) -> ChainTiming:
    """`pipeline.process_frame(cfg, adc)`, as called and on one thread (`threads.inline`),
    against `fft_floor_once` of the same frame (float32, converted outside the timing) on
    every core and on one core, alternating rounds.

    Splitting a pass over two cores costs CPU (hand-offs, two cores sharing the memory
    bandwidth and the last-level cache): it buys wall time on an idle machine. A sweep keeps
    the cores busy with whole frames and runs each chain on one thread, so both are timed."""
    x = adc.astype(np.float32)

    def one_thread():
        with inline():
            pipeline.process_frame(cfg, adc)

    t = alternating_best({"chain": lambda: pipeline.process_frame(cfg, adc),
                          "one_thread": one_thread,
                          "floor": lambda: fft_floor_once(cfg, x),
                          "floor1": lambda: fft_floor_once(cfg, x, workers=1)}, rounds)
    return ChainTiming(t["chain"], t["one_thread"], t["floor"].wall_s, t["floor1"].cpu_s)


def fft_floor_once(cfg, x32: np.ndarray, workers: int = -1) -> None:
    """The floor of a receive chain: the range rFFT of the float32 frame `x32` (n_chirps,
    n_rx, n_samples) plus the Doppler FFT over one Tx's slow-time sequence (the scheme's: all
    chirps for DDMA, one slot per code period for TDMA), scipy.fft with `workers` threads (-1:
    all cores)."""
    per = int(round(cfg.scheme.slow_time_period_s(cfg) / cfg.chirp_period_s))
    rf = scipy.fft.rfft(x32, axis=-1, workers=workers)[..., : cfg.n_samples // 2]
    scipy.fft.fft(rf.reshape(-1, per, cfg.n_rx, rf.shape[-1]), axis=0, workers=workers)
