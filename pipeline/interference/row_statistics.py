"""The per chirp and Rx statistics of the chirp-level chain in one compiled pass over an int16
frame: the DC estimate (`pipeline.chirp_level.dc.remove_dc`) and the interference difference
statistic of the demo's "magdiff" mode (`detection.flagged_rows`), which numpy computes in
five passes (sum, frame max and min, difference, its sum and its row maximum).

Integer sums are exact in any order, and the float32 steps repeat numpy's (the row mean as
float64 then float32, the threshold as float32(sum) x float32(scale)), so the DC estimates,
thresholds and flagged rows are those of `remove_dc` and `flagged_rows` bit for bit; where
numpy's difference path would not be exact int16 arithmetic (a frame spanning more than 32767
codes) the caller keeps numpy's functions (`row_statistics` returns None).
"""
from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from ..threads import run_parts, spans

__all__ = ["RowStatistics", "row_statistics", "row_flags"]


class RowStatistics(NamedTuple):
    """Statistics of each (chirp x Rx) row of an int16 frame.

    Attributes
    ----------
    dc : (n_chirps, n_rx, 1) float32
        Mean of the row's samples (`pipeline.chirp_level.dc.remove_dc`).
    flagged : (n_rows,) int
        Rows whose largest |x_n - x_{n-1}| exceeds their threshold (`flagged_rows`).
    threshold : (n_rows,) float32
        mean |x_n - x_{n-1}| 10^(SNR / 20) of each row.
    """

    dc: np.ndarray
    flagged: np.ndarray
    threshold: np.ndarray


def row_statistics(adc: np.ndarray, magdiff_snr_db: float) -> RowStatistics | None:
    """DC estimate and magdiff interference statistic of every row of an int16 frame, in one
    pass (rows in parts on the cores, `pipeline.threads`); None where numpy's difference path is
    not exact int16 arithmetic (a frame spanning more than 32767 codes) or a row is too long
    for its int32 sums.

    Parameters
    ----------
    adc : (n_chirps, n_rx, n_samples) int16
    magdiff_snr_db : float
        ``intfMitigCfg`` magDiffSNRdB (amplitude dB over the row's mean |dx|).
    """
    n_c, n_rx, n = adc.shape
    if adc.dtype != np.int16 or n < 2 or n >= 2 ** 16:
        return None
    a2 = adc.reshape(-1, n)
    rows = a2.shape[0]
    dc = np.empty(rows, np.float32)
    thr = np.empty(rows, np.float32)
    hit = np.empty(rows, np.bool_)
    lo_hi = np.empty((rows, 2), np.int32)
    scale = np.float32(10 ** (magdiff_snr_db / 20) / n)
    run_parts([lambda lo=lo, hi=hi: _rows(a2, scale, dc, thr, hit, lo_hi, lo, hi)
               for lo, hi in spans(rows)])
    if int(lo_hi[:, 1].max()) - int(lo_hi[:, 0].min()) > np.iinfo(np.int16).max:
        return None
    return RowStatistics(dc.reshape(n_c, n_rx, 1), np.flatnonzero(hit), thr)


@numba.njit(cache=True, nogil=True)
def _rows(a2, scale, dc, thr, hit, lo_hi, r0, r1):
    """Rows r0..r1-1: dc = float32(sum / n); thr = float32(sum |dx|) x scale; hit = max |dx| >
    thr (compared in float32, as numpy compares int16 with float32); lo_hi = (min, max)."""
    n = np.uint64(a2.shape[1])  # unsigned: lets LLVM vectorise the loops (no index wrap)
    one = np.uint64(1)
    for i in range(r0, r1):
        row = a2[i]
        s = np.int64(0)
        mn = np.int32(row[0])
        mx = mn
        for j in range(n):
            x = np.int32(row[j])
            s += x
            mn = min(mn, x)
            mx = max(mx, x)
        ds = np.int64(0)
        dm = np.int32(0)
        for j in range(one, n):
            d = abs(np.int32(row[j]) - np.int32(row[j - one]))
            ds += d
            dm = max(dm, d)
        dc[i] = np.float32(np.float64(s) / a2.shape[1])
        t = np.float32(ds) * scale
        thr[i] = t
        hit[i] = np.float32(dm) > t
        lo_hi[i, 0] = mn
        lo_hi[i, 1] = mx


def row_flags(adc: np.ndarray, rows: np.ndarray, threshold: np.ndarray) -> np.ndarray:
    """(R, n_samples) bool interference flags of the rows `rows` of an int16 frame that
    `row_statistics` accepted: sample j > 0 is flagged iff |x_j - x_{j-1}| > the row's
    threshold, sample 0 never ("magdiff" mode). What numpy's int16 difference, its absolute
    value and the float32 comparison give (`flagged_rows`), in one compiled pass over the
    gathered rows (rows in parts on the cores) instead of four passes and a gather copy.

    Parameters
    ----------
    adc : (n_chirps, n_rx, n_samples) int16
        A frame `row_statistics` did not refuse (no difference overflows int16).
    rows : (R,) int
        Flagged rows (chirp x n_rx + Rx).
    threshold : (n_chirps x n_rx,) float32
        `RowStatistics.threshold`.
    """
    n = adc.shape[-1]
    a2 = adc.reshape(-1, n)
    flags = np.empty((rows.size, n), np.bool_)
    run_parts([lambda lo=lo, hi=hi: _flags(a2, rows, threshold, flags, lo, hi)
               for lo, hi in spans(rows.size)])
    return flags


@numba.njit(cache=True, nogil=True)
def _flags(a2, rows, thr, flags, lo, hi):
    """flags[i] <- the magdiff flags of row rows[i] of a2, i in lo .. hi - 1: |dx| as the
    exact int32 difference (numpy's int16 one where it does not overflow, which the caller
    guarantees), compared as float32 with the row's float32 threshold."""
    n = np.uint64(a2.shape[1])  # unsigned: lets LLVM vectorise the loop
    one = np.uint64(1)
    for i in range(lo, hi):
        row = a2[rows[i]]
        t = thr[rows[i]]
        f = flags[i]
        f[0] = False
        for j in range(one, n):
            f[j] = np.float32(abs(np.int32(row[j]) - np.int32(row[j - one]))) > t
