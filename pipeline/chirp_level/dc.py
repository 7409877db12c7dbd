"""DC estimation and removal per chirp and Rx ([TI-DAZ] section 2; [TI-DDMA] table 5, HWA
params 2-3): the mean of each chirp's samples, subtracted in the spectrum through the window's
few significant bins (FFT(w (x - m)) = FFT(w x) - m FFT(w)).
"""
from __future__ import annotations

from functools import lru_cache

import numba
import numpy as np
import scipy.fft

from ..kernels import window

__all__ = ["remove_dc", "window_spectrum", "subtract_dc"]


def remove_dc(adc: np.ndarray) -> np.ndarray:
    """Per chirp and Rx mean of the samples (the HWA DC estimate), float32.

    Parameters
    ----------
    adc : (n_chirps, n_rx, n_samples) int16, float or complex (I/Q)

    Returns
    -------
    (n_chirps, n_rx, 1) float32 (complex64 for I/Q)
        The DC estimate to subtract.
    """
    n = adc.shape[-1]
    if np.iscomplexobj(adc):  # I/Q frames: the complex mean (I and Q DC together)
        return (adc.sum(axis=-1, dtype=np.complex128, keepdims=True) / n).astype(np.complex64)
    # int32 holds any sum of n < 2^16 int16 samples exactly (and is twice as fast as int64)
    acc = np.float64
    if adc.dtype.kind == "i":
        acc = np.int32 if adc.dtype.itemsize <= 2 and n < 2 ** 16 else np.int64
    s = adc.sum(axis=-1, dtype=acc, keepdims=True)
    return (s / n).astype(np.float32)


@lru_cache(maxsize=32)
def window_spectrum(name: str, n: int, full: bool = False) -> tuple:
    """Non-negligible bins (k, W[k]) of the window's rFFT (Hann: k = 0, 1), or of its full FFT
    for complex samples (Hann: k = 0, 1, n - 1); cached per window."""
    w64 = window(name, n).astype(np.float64)
    w = scipy.fft.fft(w64) if full else scipy.fft.rfft(w64)[: n // 2]
    big = np.flatnonzero(np.abs(w) > 1e-6 * np.abs(w).max())
    return tuple((int(k), np.complex64(w[k])) for k in big)


def subtract_dc(rf: np.ndarray, m: np.ndarray, bins: np.ndarray, weights: np.ndarray) -> None:
    """``rf[..., k] -= m * w`` for each bin k of `bins` and its w of `weights` (the window's
    spectrum, `window_spectrum`), in place: the DC estimates' spectrum taken off a range FFT,
    bit for bit as numpy's complex64 arithmetic computes it (m cast to complex64, the complex
    product, the complex difference), in one compiled pass instead of two numpy calls and a
    temporary per bin (a 64-chirp R79 block, 2 bins: 4.6 -> 1.5 us).

    Parameters
    ----------
    rf : (n_chirps, n_rx, n) complex64, C-contiguous
        Range spectra (a whole rFFT output may be passed), n > max(bins).
    m : (n_chirps, n_rx) float32
        DC estimates.
    bins : (K,) int64
    weights : (K,) complex64
    """
    _subtract_dc(rf, m, bins, weights)


@numba.njit(cache=True, nogil=True)
def _subtract_dc(rf, m, ks, ws):
    """rf[c, r, ks[i]] -= complex64(m[c, r]) * ws[i] as numpy's complex64 multiply and subtract
    compute them: (m wr - 0 wi, m wi + 0 wr), then re and im differences (float32)."""
    n_c, n_r = m.shape
    zero = np.float32(0.0)
    for c in range(n_c):
        for r in range(n_r):
            x = m[c, r]
            for i in range(ks.size):
                w = ws[i]
                pr = x * w.real - zero * w.imag
                pi = x * w.imag + zero * w.real
                v = rf[c, r, ks[i]]
                rf[c, r, ks[i]] = complex(v.real - pr, v.imag - pi)
