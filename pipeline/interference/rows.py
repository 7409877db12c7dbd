"""The flagged rows of a frame, DC removed and repaired, as the range FFT takes them in place of
theirs (`repaired_rows`, `RepairedRows`), with the compiled passes that gather, convert and
window them."""
from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from core.errors import BadInput

from ..threads import run_parts, spans
from .masks import FrameRows
from .methods import repair

__all__ = ["RepairedRows", "repaired_rows", "dc_removed_rows"]


class RepairedRows(NamedTuple):
    """The flagged chirp x Rx rows of a frame, DC removed and repaired: what the range FFT
    takes in their place, times the range window (`repaired_rows`)."""

    rows: np.ndarray      # (R,) increasing row indices, chirp * n_rx + Rx
    samples: np.ndarray   # (R, n_samples) float32 (complex64 for I/Q): repaired, not windowed
    window: np.ndarray    # (n_samples,) float32 range window
    dc: np.ndarray | None  # (n_chirps, n_rx) DC estimates, the repaired rows' 0 (None: none)
    means: np.ndarray     # (R,) what the repair still subtracts from each row (0: nothing)

    def windowed(self) -> np.ndarray:
        """(R, n_samples) the repaired rows, their `means` subtracted, times the window
        (numpy's products; rows in parts on the cores)."""
        y = np.empty_like(self.samples)
        # (x - 0) is x bit for bit (-0 and NaN included): no subtraction pass without means
        centre = bool(self.means.any())

        def part(lo: int, hi: int) -> None:
            x = self.samples[lo:hi]
            if centre:
                x = np.subtract(x, self.means[lo:hi, None], out=y[lo:hi])
            np.multiply(x, self.window, out=y[lo:hi])
        run_parts([lambda lo=lo, hi=hi: part(lo, hi) for lo, hi in spans(len(y))])
        return y

    def windowed_block(self, adc: np.ndarray, c0: int, out: np.ndarray) -> np.ndarray:
        """The windowed samples of chirps c0 .. c0 + len(adc) - 1 into `out` and returned:
        `adc` (chirps, n_rx, n_samples) int16, those chirps of the frame, each row as
        float32 times the window (`kernels.samples_windowed`), the repaired rows' (real
        frames) in its place, as `windowed()` has them: one compiled pass, no row windowed
        twice."""
        n_rx, n = adc.shape[1], adc.shape[-1]
        if out.shape != adc.shape or not out.flags.c_contiguous:
            # a reshape of a strided `out` would be a copy: the results would be lost
            raise BadInput(f"out must be a C-contiguous {adc.shape} array, got {out.shape} "
                           f"(C-contiguous: {out.flags.c_contiguous})")
        lo, hi = np.searchsorted(self.rows, (c0 * n_rx, (c0 + len(adc)) * n_rx))
        _windowed_rows(adc.reshape(-1, n), self.samples, self.means, self.rows, self.window,
                       c0 * n_rx, lo, hi, out.reshape(-1, n))
        return out

    def without_dc(self, c0: int, c1: int) -> np.ndarray:
        """(c1 - c0, n_rx) the DC estimates of chirps c0 .. c1 - 1 with the repaired rows' set
        to 0 (their DC was removed before the FFT)."""
        return self.dc[c0:c1]


def repaired_rows(adc: np.ndarray, dc: np.ndarray | None, rows: np.ndarray,
                  flags: np.ndarray, win: np.ndarray, intf) -> RepairedRows:
    """The flagged rows, DC removed and repaired by ``intf.method`` (the chip
    zeroes), with the window they are multiplied by.

    Parameters
    ----------
    adc : (n_chirps, n_rx, n_samples) int16, or complex64 I/Q
    dc : (n_chirps, n_rx, 1) float or None
        DC estimates (None: no DC removal).
    rows : (R,) int
        Increasing flagged rows (`flagged_rows`).
    flags : (R, n_samples) bool
        Their interference flags.
    win : (n_samples,) float32
        The range window.
    intf : pipeline.interference.InterferenceConfig
        Its repair method and hysteresis (enabled).

    Returns
    -------
    RepairedRows
    """
    n_rx, n = adc.shape[1], adc.shape[-1]
    a2 = adc.reshape(-1, n)
    y = np.empty((len(rows), n), np.complex64 if np.iscomplexobj(adc) else np.float32)
    parts = spans(len(rows))  # elementwise passes in parts on the cores: the same values

    compiled = dc is not None and a2.dtype == np.int16

    def dc_removed(lo: int, hi: int) -> None:
        if compiled:  # one pass: gather, convert and subtract (numpy's float32 steps)
            dc_removed_rows(a2, rows, dc.reshape(-1).astype(np.float32, copy=False), y, lo, hi)
        elif dc is None:
            y[lo:hi] = a2[rows[lo:hi]]
        else:
            np.subtract(a2[rows[lo:hi]], dc.reshape(-1, 1)[rows[lo:hi]], out=y[lo:hi],
                        dtype=y.dtype)

    method = intf.method
    # a method may leave its rows' means to the window product (one pass less over the rows)
    centre = method.centres_rows and y.dtype == np.float32
    frame = FrameRows(a2, rows, n_rx)
    means = np.zeros(len(rows), y.dtype)
    run_parts([lambda lo=lo, hi=hi: dc_removed(lo, hi) for lo, hi in parts])
    repair(y, flags, win, intf.hysteresis_samples, method, frame=frame, remove_mean=not centre)
    if centre:
        run_parts([lambda lo=lo, hi=hi: y[lo:hi].mean(axis=-1, out=means[lo:hi])
                   for lo, hi in parts])
    dc0 = None
    if dc is not None:
        dc0 = dc[..., 0].copy()
        dc0.reshape(-1)[rows] = 0
    return RepairedRows(rows, y, win, dc0, means)


@numba.njit(cache=True, nogil=True)
def _windowed_rows(a2, y, means, rows, w, row0, lo, hi, out):
    """out[r] <- w x (y[i] - means[i] if rows[i] == row0 + r for an i in lo .. hi - 1, else
    float32(a2[r])), float32 differences and products (numpy's ``np.subtract`` and
    ``np.multiply`` of each pair, element by element); rows[lo:hi] increasing, within
    row0 .. row0 + len(a2) - 1."""
    n = np.uint64(a2.shape[1])  # unsigned: lets LLVM vectorise the loops
    i = lo
    for r in range(a2.shape[0]):
        o = out[r]
        if i < hi and rows[i] == row0 + r:
            s = y[i]
            m = means[i]
            for t in range(n):
                o[t] = (s[t] - m) * w[t]
            i += 1
        else:
            a = a2[r]
            for t in range(n):
                o[t] = np.float32(a[t]) * w[t]


@numba.njit(cache=True, nogil=True)
def dc_removed_rows(a2, rows, dc, out, lo, hi):
    """out[i] <- float32(a2[rows[i]]) - dc[rows[i]] for i in lo .. hi - 1 (int16 rows, float32
    DC estimates: numpy's ``np.subtract(a, dc, dtype=float32)``, element by element)."""
    n = a2.shape[1]
    for i in range(lo, hi):
        r = rows[i]
        d = dc[r]
        for t in range(n):
            out[i, t] = np.float32(a2[r, t]) - d
