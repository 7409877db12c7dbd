"""DC estimation and removal per chirp and Rx ([TI-DAZ] section 2; [TI-DDMA] table 5, HWA
params 2-3): the mean of each chirp's samples, subtracted in the spectrum through the window's
few significant bins (FFT(w (x - m)) = FFT(w x) - m FFT(w)).
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
import scipy.fft

from ..kernels import window

__all__ = ["remove_dc", "window_spectrum"]


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
