"""Noise-floor rise over thermal after the range and Doppler FFTs of the chirp-level output: the
metric interference cases are judged on (DESIGN section 7: noise-floor rise over thermal).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.fft

from radarsim.config import RadarConfig

from ..config import WINDOWS, ProcessingConfig
from ..kernels import window
from .stage import RANGE_STAGE_FIELDS, range_stage

__all__ = ["NoiseFloor", "noise_floor_rise", "NOISE_FLOOR_FIELDS"]


#: The `ProcessingConfig` fields `noise_floor_rise` reads (the range stage's and the Doppler
#: window, the first range bin): two settings equal on these give the same floor for the same
#: frame.
NOISE_FLOOR_FIELDS = RANGE_STAGE_FIELDS + ("doppler_window", "min_range_bin")


class NoiseFloor(NamedTuple):
    """Noise-floor rise over thermal, dB, after the range FFT and after the Doppler FFT."""

    range_db: float
    doppler_db: float


def noise_floor_rise(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig | None = None,
                     range_stride: int = 4, rf: np.ndarray | None = None) -> NoiseFloor:
    """Noise floor after the range and Doppler FFTs relative to the thermal floor, dB.

    The floor is the median cell power / ln 2 (the mean of exponential cells; echoes occupy
    few cells and do not move it) over range bins >= `proc.min_range_bin`; the thermal
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
    wr = window(WINDOWS[proc.range_window], cfg.n_samples).astype(np.float64)
    wd = window(WINDOWS[proc.doppler_window], cfg.n_chirps).astype(np.float64)
    # Thermal noise variance per sample: sigma^2 (real), 2 sigma^2 (I and Q each sigma^2).
    sigma2 = cfg.noise_rms_lsb ** 2 * (2 if cfg.is_complex else 1)
    ref_r = sigma2 * np.sum(wr ** 2)
    sub = rf[:, :, proc.min_range_bin::range_stride]
    p = sub.real ** 2 + sub.imag ** 2
    floor_r = float(_median_power(p)) / np.log(2)
    spec = scipy.fft.fft(sub * wd.astype(np.float32)[:, None, None], axis=0, workers=-1)
    pd_ = spec.real ** 2 + spec.imag ** 2
    floor_d = float(_median_power(pd_)) / np.log(2)
    return NoiseFloor(10 * np.log10(floor_r / ref_r),
                      10 * np.log10(floor_d / (ref_r * np.sum(wd ** 2))))


def _median_power(p: np.ndarray) -> np.floating:
    """``np.median(p)`` of a float32 power array, bit for bit, by a radix select.

    Finite non-negative float32 values order as their bit patterns do, so the upper 16 bits
    (sign, exponent, 7 mantissa bits) bin them in order: one bincount finds the bin holding
    each middle rank, and only that bin's few values are partitioned. The two middle values
    are averaged as `numpy.median` does (float32 mean); anything else (NaN, inf, a negative
    or -0 value, another dtype) takes `numpy.median` itself. About half numpy's cost on the
    floor's 147 456-cell maps (one counting pass instead of a full introselect copy).
    """
    a = p.reshape(-1)
    n = a.size
    if a.dtype != np.float32 or n == 0:
        return np.median(p)
    top = a.view(np.uint32) >> 16
    if top.max() >= 0x7F80:  # sign bit, inf or NaN
        return np.median(p)
    cum = np.cumsum(np.bincount(top))

    def ranked(k: int) -> np.float32:
        """The k-th smallest value (0-based)."""
        b = int(np.searchsorted(cum, k, side="right"))
        below = int(cum[b - 1]) if b else 0
        return np.partition(a[top == b], k - below)[k - below]
    if n % 2:
        return ranked(n // 2)
    return np.mean(np.array([ranked(n // 2 - 1), ranked(n // 2)], dtype=np.float32))
