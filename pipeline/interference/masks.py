"""Masks and reference rows of the interference repair: which samples a repair replaces (the
chip's flags closed over short gaps and widened by the hysteresis) and which rows of the frame
show the echoes without interference (the "lowrank" and "ar" methods learn from them)."""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["widen", "close_gaps", "FrameRows", "REFERENCE_ROWS", "MIN_REFERENCE_ROWS",
           "frame_reference", "reference_rows"]


def widen(flags: np.ndarray, hysteresis: int) -> np.ndarray:
    """(R, n) bool: sample i is masked iff a flag lies in [i - hysteresis, i + hysteresis] of
    its own row (the chip's hysteresis)."""
    if hysteresis <= 0 or not flags.any():
        return flags.copy()
    n = flags.shape[-1]
    c = np.cumsum(np.pad(flags, ((0, 0), (hysteresis + 1, hysteresis)), constant_values=False),
                  axis=-1, dtype=np.int32)
    return (c[:, 2 * hysteresis + 1:] - c[:, :n]) > 0


def close_gaps(mask: np.ndarray, max_gap: int) -> np.ndarray:
    """(R, n) bool: `mask` with every run of unmasked samples of length <= `max_gap` that lies
    between two masked samples of the same row masked too (a morphological closing)."""
    if max_gap <= 0 or not mask.any():
        return mask.copy()
    n = mask.shape[-1]
    idx = np.broadcast_to(np.arange(n), mask.shape)
    last = np.maximum.accumulate(np.where(mask, idx, -n - max_gap - 2), axis=-1)
    nxt = np.minimum.accumulate(np.where(mask, idx, 2 * n + max_gap + 2)[:, ::-1],
                                axis=-1)[:, ::-1]
    return mask | ((nxt - last - 1 <= max_gap) & (last >= 0) & (nxt < n))


class FrameRows(NamedTuple):
    """Where the repaired rows sit in their frame (for the methods that learn from the frame)."""

    samples: np.ndarray   # (N, n) every chirp x Rx row of the frame, as sampled (any offset)
    rows: np.ndarray      # (R,) increasing indices of the repaired rows in `samples`
    n_rx: int             # rows per chirp: row i is chirp i // n_rx, Rx i % n_rx


#: Unflagged rows of the frame (evenly spread) the "lowrank" subspace is estimated from...
REFERENCE_ROWS = 256
#: ... if the frame has at least this many (else the repaired rows, their gaps zeroed).
MIN_REFERENCE_ROWS = 64


def spread_rows(idx: np.ndarray) -> np.ndarray:
    """Up to REFERENCE_ROWS of the indices `idx`, evenly spread."""
    return idx[np.linspace(0, len(idx) - 1, min(REFERENCE_ROWS, len(idx))).astype(np.intp)]


def frame_reference(frame: FrameRows, dtype: np.dtype) -> np.ndarray | None:
    """(N, n) up to REFERENCE_ROWS unflagged rows of the frame, evenly spread, as `dtype`;
    None if it has fewer than MIN_REFERENCE_ROWS."""
    clean = np.ones(len(frame.samples), dtype=bool)
    clean[frame.rows] = False
    idx = np.flatnonzero(clean)
    if len(idx) < MIN_REFERENCE_ROWS:
        return None
    return frame.samples[spread_rows(idx)].astype(dtype, copy=False)


def reference_rows(x: np.ndarray, frame: FrameRows | None, mask) -> np.ndarray:
    """(N, n) rows without interference: up to REFERENCE_ROWS unflagged rows of the frame,
    evenly spread; without a frame (or with too few clean rows), the repaired rows with their
    masked samples (`mask()`, (R, n) bool) zeroed."""
    ref = None if frame is None else frame_reference(frame, x.dtype)
    if ref is not None:
        return ref
    idx = spread_rows(np.arange(len(x)))
    return np.where(mask()[idx], 0, x[idx])
