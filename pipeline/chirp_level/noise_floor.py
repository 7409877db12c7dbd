"""Noise-floor rise over thermal after the range and Doppler FFTs of the chirp-level output: the
metric interference cases are judged on (design.md section 7: noise-floor rise over thermal).
"""
from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np
import scipy.fft

from radarsim.config import RadarConfig

from ..config import WINDOWS, ProcessingConfig
from ..kernels import doppler_windowed, window
from ..threads import fft_workers
from .stage import range_stage, range_stage_key

__all__ = ["NoiseFloor", "noise_floor_rise", "noise_floor_key"]


def noise_floor_key(proc) -> tuple:
    """The settings `noise_floor_rise` reads, as values: the range stage's sub-configs
    (`range_stage_key`, the first range bin among them) and the Doppler window's. Two settings
    with equal keys give the same floor for the same frame."""
    return (*range_stage_key(proc), proc.doppler)


class NoiseFloor(NamedTuple):
    """Noise-floor rise over thermal, dB, after the range FFT and after the Doppler FFT."""

    range_db: float
    doppler_db: float


def noise_floor_rise(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig | None = None,
                     range_stride: int = 4, rf: np.ndarray | None = None) -> NoiseFloor:
    """Noise floor after the range and Doppler FFTs relative to the thermal floor, dB.

    The floor is the median cell power / ln 2 (the mean of exponential cells; echoes occupy
    few cells and do not move it) over range bins >= `proc.range.min_bin`; the thermal
    reference is sigma^2 sum w_r^2 (x sum w_d^2 after the Doppler FFT), sigma =
    `cfg.noise_rms_lsb`. After the Doppler FFT a bursty interferer has spread over all
    Doppler bins, so that rise equals 10 log10(1 + burst energy / noise energy); after the
    range FFT the median sees the chirps without bursts and rises less.

    Parameters
    ----------
    cfg : RadarConfig
    adc : (n_chirps, n_rx, n_samples) int16
    proc : ProcessingConfig, optional
        The chirp-level switches applied first (default `ProcessingConfig()`).
    range_stride : int
        Doppler FFT of every `range_stride`-th range bin only (cost).
    rf : (n_chirps, n_rx, n_range) complex64, optional
        The chirp-level output if already computed.

    Returns
    -------
    NoiseFloor
    """
    proc = proc or ProcessingConfig()
    if rf is None:
        rf = range_stage(cfg, adc, proc)
    wr = window(WINDOWS[proc.range.window], cfg.n_samples).astype(np.float64)
    wd = window(WINDOWS[proc.doppler.window], cfg.n_chirps).astype(np.float64)
    # Thermal noise variance per sample: sigma^2 (real), 2 sigma^2 (I and Q each sigma^2).
    sigma2 = cfg.noise_rms_lsb ** 2 * (2 if cfg.is_complex else 1)
    ref_r = sigma2 * np.sum(wr ** 2)
    sub = rf[:, :, proc.range.min_bin::range_stride]
    floor_r = float(_power_median(sub)) / np.log(2)
    # The FFT on every core, or on this thread alone inside `pipeline.threads.inline` (a sweep
    # cell's frames already keep the cores busy): the same transforms either way.
    # (`doppler_windowed`: numpy's complex64 x float32 window product, bit for bit.)
    spec = scipy.fft.fft(doppler_windowed(sub, wd.astype(np.float32)), axis=0,
                         workers=fft_workers(), overwrite_x=True)
    floor_d = float(_power_median(spec)) / np.log(2)
    return NoiseFloor(10 * np.log10(floor_r / ref_r),
                      10 * np.log10(floor_d / (ref_r * np.sum(wd ** 2))))


def _power_median(z: np.ndarray) -> np.floating:
    """``np.median(z.real ** 2 + z.imag ** 2)`` of a complex64 array, bit for bit.

    A radix select: finite non-negative float32 values order as their bit patterns do. One
    compiled pass over `z` (any strides: the floor reads every 4th range bin in place) makes
    the power map and counts its bit patterns' upper 12 bits (sign, exponent, 3 mantissa bits:
    4 096 bins, which stay in the L1 cache, counted into 4 interleaved tables so that runs of
    equal bins do not wait on each other); then only the bin holding the middle ranks is
    partitioned, and the two middle values are averaged as `numpy.median` does. On the floor's
    147 456-cell maps 0.26-0.30 ms against 0.42 ms for the power map plus a numpy radix select
    over 16-bit bins (same process, loaded machine). Other dtypes and shapes, and maps with NaN
    or inf, take `numpy.median`.
    """
    if z.dtype != np.complex64 or z.ndim != 3 or z.size == 0:
        return np.median(z.real ** 2 + z.imag ** 2)
    p = np.empty(z.shape, np.float32)
    counts = np.zeros((4, 1 << 12), np.int32 if z.size < 2 ** 31 else np.int64)
    _power_histogram(z, p, counts)
    counts = counts.sum(axis=0)
    if counts[_SPECIAL_TOP >> 4:].any():  # inf or NaN (the 12-bit bins from +inf's up)
        return np.median(p)
    return _middle(p.reshape(-1), counts)


#: Upper 16 bits of the smallest float32 bit pattern that is no finite non-negative value
#: (+inf; NaN and every negative value lie above it).
_SPECIAL_TOP = 0x7F80


def _middle(a: np.ndarray, counts: np.ndarray) -> np.floating:
    """The median of the finite non-negative float32 values `a` (flat) from the counts
    `counts` (4 096,) of their bit patterns' upper 12 bits, as `numpy.median` gives it: the
    middle value, or the float32 mean of the two middle values."""
    cum = np.cumsum(counts)
    n = a.size
    ks = [n // 2] if n % 2 else [n // 2 - 1, n // 2]
    bins = np.searchsorted(cum, ks, side="right")
    vals = []
    for b in np.unique(bins):
        below = int(cum[b - 1]) if b else 0
        at = [k - below for k, kb in zip(ks, bins) if kb == b]
        part = np.partition(_bin_members(a, int(b), int(counts[b])), at)
        vals += [part[i] for i in at]
    if n % 2:
        return vals[0]
    return np.mean(np.array(vals, dtype=np.float32))


@numba.njit(cache=True, nogil=True)
def _bin_members(a: np.ndarray, b: int, n: int) -> np.ndarray:
    """The `n` values of the flat float32 array `a` whose bit patterns' upper 12 bits are `b`
    (one pass; ``a[(a.view(np.uint32) >> 20) == b]`` without its two full-size temporaries).
    `n` must be exactly their count (the histogram's): the buffer has n + 1 slots."""
    bits = a.view(np.uint32)
    out = np.empty(n + 1, np.float32)  # branch-free: every value is written, a member kept
    j = 0
    for i in range(bits.size):
        out[j] = a[i]
        j += bits[i] >> 20 == b
    return out[:n]


@numba.njit(cache=True, nogil=True)
def _power_histogram(z: np.ndarray, p: np.ndarray, counts: np.ndarray) -> None:
    """p = re^2 + im^2 of z (float32, as numpy computes it; p C-contiguous), then
    counts[i % 4, upper 12 bits of p[i]] += 1 over p's bit patterns (flat index i)."""
    n0, n1, n2 = z.shape
    for i in range(n0):
        for j in range(n1):
            for k in range(n2):
                v = z[i, j, k]
                p[i, j, k] = v.real * v.real + v.imag * v.imag
    bits = p.reshape(-1).view(np.uint32)
    n = bits.size
    m = n // 4 * 4
    for i in range(0, m, 4):
        counts[0, bits[i] >> 20] += 1
        counts[1, bits[i + 1] >> 20] += 1
        counts[2, bits[i + 2] >> 20] += 1
        counts[3, bits[i + 3] >> 20] += 1
    for i in range(m, n):
        counts[0, bits[i] >> 20] += 1
