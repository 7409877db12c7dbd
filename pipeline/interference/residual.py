"""Weak bursts the chip's fixed threshold misses, found on the low-rank residual of the frame.

The chip flags a sample where |x_n - x_{n-1}| exceeds a fixed multiple (``magDiffSNRdB``, 18 dB)
of its chirp's mean |dx| (TI SWRA725 sections 3.1-3.2, `detection`). A far interferer's burst is
weak: its difference crosses that threshold only where its sweep is fastest, and in many chirps
nowhere, so those chirps are never repaired. On the head-on interference case the first second
keeps half of its 2.7 dB floor rise after the repair for that reason.

Where to look for what the threshold misses:

- the chirp-to-chirp difference cancels an echo only if its phase stays put from chirp to
  chirp; DDMA's Tx codes and the Doppler turn it (3 rad per chirp at 40 m/s), so the difference
  keeps every echo;
- a CFAR on the fast-time envelope of the samples sees the echoes beat: two strong tones five
  range bins apart modulate the envelope fully over 77 samples (on the dense-highway
  interference frames the envelope's peak reaches 21 times its median without any burst);
- the low-rank residual: every echo is the same fast-time tone in every chirp of a frame
  (`lowrank`), so the frame's fast-time subspace holds them all, beating or not, and what is
  left of a row outside it is noise plus interference. A burst is a local excess of it.

So, per chirp x Rx row the chip did not flag: the residual r = x - V V^H x (V the frame's basis
from its unflagged rows, `lowrank.fast_time_basis`, at most `RANK_MAX` components
`RANK_SNR_GATE_DB` over the noise), and its energy over a sliding `window` of samples over the
noise, E_j = mean |r|^2 / sigma^2 (windows `BLOCK` samples apart). A window holds a burst where
E_j exceeds the threshold times max(1, the row's median E): the median takes up what the
subspace does not hold but lies along the whole row (an extended clutter's residual, a same-
slope radar's tone), a burst does not. The window is the shortest burst of interest, 2 B_IF /
|S_v - S_i| = 1 us (32 samples at 30 Msps) for a 30 MHz/us slope difference across the 15 MHz IF
band (design.md 6). Noise alone exceeds 3.5 (5.4 dB) in one window of 10^10 (chi-square of 32
degrees of freedom over 32): the threshold is set instead by the residual structure of frames
without bursts, up to 9.9 dB over their row median on the dense-highway and same-slope
interference frames, plus 1 dB: 11 dB. Only frames in which the chip flagged something are
searched (`with_weak_bursts`). The flagged samples are the burst windows' extents; the repair
method takes them as it takes the chip's flags (and widens, closes and grows them as it does
those).

References
----------
.. [1] [SWRA725] TI, "Interference Mitigation for AWR294x" (2021), sections 3.1-3.3.
.. [2] [Kay1998] S. M. Kay, Fundamentals of Statistical Signal Processing: Detection Theory,
       1998, chapter 7 (energy detector in the complement of a known signal subspace).
.. [3] [Bechter2015] J. Bechter, C. Waldschmidt, "Automotive radar interference mitigation by
       reconstruction and cancellation of interference component", IEEE ICMIM 2015.
"""
from __future__ import annotations

import numba
import numpy as np

from core.errors import BadInput

from .lowrank import fast_time_basis
from .masks import FrameRows, frame_reference
from .rows import dc_removed_rows

__all__ = ["residual_burst_flags", "with_weak_bursts", "RANK_MAX", "RANK_SNR_GATE_DB", "BLOCK"]

#: Components of the frame's fast-time subspace the residual removes at most (the "lowrank"
#: repair's own), and their least energy over the noise, dB (above the Marchenko-Pastur edge
#: of white noise's sample eigenvalues, `lowrank`).
RANK_MAX = 24
RANK_SNR_GATE_DB = 10.0
#: Samples per block of the window sums: windows start every BLOCK samples.
BLOCK = 4
_U = np.uint64  # unsigned loop indices: LLVM vectorises those loops


def residual_burst_flags(x: np.ndarray, vectors: np.ndarray, noise_var: float,
                         threshold_db: float, window: int) -> np.ndarray:
    """Samples of a burst in rows whose echoes lie in a known fast-time subspace.

    Parameters
    ----------
    x : (R, n) float32 or complex64
        Rows with their offset removed.
    vectors : (n, k) same dtype
        Orthonormal basis of the echoes' fast-time subspace.
    noise_var : float
        Noise power per sample (> 0).
    threshold_db : float
        A window holds a burst where its residual energy over the noise exceeds the row's
        median one (at least the noise) by this, dB.
    window : int
        Samples per window, a multiple of `BLOCK` (windows start every `BLOCK` samples).

    Returns
    -------
    (R, n) bool
        The samples of every burst window.

    Raises
    ------
    BadInput
        A window that is not a multiple of `BLOCK` in [BLOCK, n].

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> n = 384
    >>> tone = np.cos(2 * np.pi * 40.3 * np.arange(n) / n)
    >>> v = np.linalg.qr(np.column_stack([tone, np.sin(2 * np.pi * 40.3 * np.arange(n) / n)]))[0]
    >>> x = 30 * tone + rng.standard_normal((4, n))
    >>> x[2, 100:140] += 6 * np.cos(0.9 * np.arange(40) ** 1.5)   # a weak burst
    >>> f = residual_burst_flags(x.astype(np.float32), v.astype(np.float32), 1.0, 11.0, 32)
    >>> f.any(axis=1).tolist(), bool(f[2, 110:130].all())
    ([False, False, True, False], True)
    """
    return _flags_and_hits(x, vectors, noise_var, threshold_db, window)[0]


def _flags_and_hits(x: np.ndarray, vectors: np.ndarray, noise_var: float, threshold_db: float,
                    window: int) -> tuple[np.ndarray, np.ndarray]:
    """`residual_burst_flags` and (R,) bool, the rows with a burst window (the kernel knows
    them: no pass over the (R, n) flags to find them)."""
    n = x.shape[-1]
    if not (isinstance(window, (int, np.integer)) and BLOCK <= window <= n
            and window % BLOCK == 0):
        raise BadInput(f"window={window!r} samples must be a multiple of {BLOCK} in "
                       f"[{BLOCK}, {n}]")
    r = (x @ vectors) @ vectors.conj().T
    out = np.zeros(x.shape, dtype=bool)
    hit = np.zeros(len(x), dtype=bool)
    _burst_windows(x, r, np.float32(window * noise_var),
                   np.float32(10 ** (threshold_db / 10)), window // BLOCK, out, hit)
    return out, hit


@numba.njit(cache=True, nogil=True)
def _burst_windows(x, r, floor, factor, nb, out, hit):
    """out[i] <- the samples of row i's burst windows (`residual_burst_flags`), one pass per
    row: x (R, n) the rows, r (R, n) their projections on the subspace (same dtype), `floor`
    the noise energy of a window (float32), `factor` the threshold as a power ratio (float32),
    nb the blocks of `BLOCK` samples per window; out (R, n) bool, False on entry; hit (R,)
    bool, False on entry, <- True for a row with a burst window.

    Every value is numpy's formulation's, bit for bit: the residual power (x - r)^2 (|x - r|^2
    = re^2 + im^2 for I/Q) in float32; a block's powers added in sample order, the last
    n mod BLOCK samples (added in order) joining the last block; a window's blocks added in
    order; the row's level, the median (the middle order statistic) of the windows a window
    apart, at least `floor`; a window holds a burst where its sum exceeds level x factor; then
    every block of such a window, and every sample of those blocks (the last block's flag to
    the n mod BLOCK samples past it)."""
    n_rows, n = x.shape
    un = _U(n)
    n_blocks = n // BLOCK
    n_win = n_blocks - nb + 1
    n_sub = (n_win + nb - 1) // nb   # windows 0, nb, 2 nb, ...
    mid = n_sub // 2
    p = np.empty(n, np.float32)
    b = np.empty(n_blocks, np.float32)
    e = np.empty(n_win, np.float32)
    sub = np.empty(n_sub, np.float32)
    blk = np.empty(n_blocks, np.bool_)
    for i in range(n_rows):
        xi, ri = x[i], r[i]
        for t in range(un):
            d = xi[t] - ri[t]
            p[t] = (d * np.conj(d)).real  # re^2 + im^2 as re * re - im * (-im)
        for j in range(_U(n_blocks)):
            b[j] = p[BLOCK * j] + p[BLOCK * j + 1]
        for u in range(2, BLOCK):
            for j in range(_U(n_blocks)):
                b[j] += p[BLOCK * j + u]
        tail = np.float32(0)
        for t in range(n_blocks * BLOCK, n):
            tail += p[t]
        b[n_blocks - 1] += tail
        for j in range(_U(n_win)):
            e[j] = b[j]
        for k in range(1, nb):
            for j in range(_U(n_win)):
                e[j] += b[j + k]
        # the median: insertion sort of the few windows a window apart
        for q in range(n_sub):
            v = e[q * nb]
            m = q
            while m > 0 and sub[m - 1] > v:
                sub[m] = sub[m - 1]
                m -= 1
            sub[m] = v
        thr = max(sub[mid], floor) * factor
        blk[:] = False
        any_hit = False
        for j in range(n_win):
            if e[j] > thr:
                any_hit = True
                for k in range(nb):
                    blk[j + k] = True
        if not any_hit:
            continue
        hit[i] = True
        o = out[i]
        for j in range(n_blocks):
            if blk[j]:
                for u in range(BLOCK):
                    o[j * BLOCK + u] = True
        if blk[n_blocks - 1]:
            for t in range(n_blocks * BLOCK, n):
                o[t] = True


def with_weak_bursts(adc: np.ndarray, dc: np.ndarray | None, rows: np.ndarray,
                     flags: np.ndarray, threshold_db: float, window: int
                     ) -> tuple[np.ndarray, np.ndarray]:
    """The chip's flagged rows and flags, plus the rows with weak bursts it did not flag.

    Only in a frame where the chip flagged a row: an interferer's bursts differ in strength
    within a frame (the sweep crosses the IF band at a different time in every chirp), so the
    chip flags some of its chirps long before all; a frame it flags nothing in is left as the
    chip leaves it and costs nothing (most frames of most scenes).

    Parameters
    ----------
    adc : (n_chirps, n_rx, n) int16, or complex64 I/Q
    dc : (n_chirps, n_rx, 1) float or None
        DC estimates (None: each row's mean is removed).
    rows : (R,) int
        Increasing rows the chip flagged (`detection.flagged_rows`).
    flags : (R, n) bool
        Their flags.
    threshold_db, window : float, int
        `residual_burst_flags`.

    Returns
    -------
    rows : (R',) int
        Increasing, the chip's and the new ones.
    flags : (R', n) bool
        The chip's flags of its rows, the burst windows of the new ones.
    """
    n_rx, n = adc.shape[1], adc.shape[-1]
    if len(rows) == 0:  # no interference the chip saw: the frame is left as the chip leaves it
        return rows, flags
    a2 = adc.reshape(-1, n)
    dtype = np.complex64 if np.iscomplexobj(adc) else np.float32
    ref = frame_reference(FrameRows(a2, rows, n_rx), dtype)
    if ref is None:  # too few unflagged rows to learn the echoes from
        return rows, flags
    basis = fast_time_basis(ref, RANK_MAX, 10 ** (RANK_SNR_GATE_DB / 10))
    clean = np.ones(len(a2), dtype=bool)
    clean[rows] = False
    idx = np.flatnonzero(clean)
    if dc is not None and a2.dtype == np.int16:  # one compiled pass, the same float32 steps
        x = np.empty((len(idx), n), dtype)
        dc_removed_rows(a2, idx, dc.reshape(-1).astype(dtype, copy=False), x, 0, len(idx))
    else:
        x = a2[idx].astype(dtype)
        x -= x.mean(axis=-1, keepdims=True) if dc is None else dc.reshape(-1, 1)[idx].astype(dtype)
    new, hit = _flags_and_hits(x, basis.vectors, basis.noise_var, threshold_db, window)
    hit = np.flatnonzero(hit)
    if hit.size == 0:
        return rows, flags
    all_rows = np.concatenate([rows, idx[hit]])
    order = np.argsort(all_rows, kind="stable")
    # each row's flags copied once, straight to its place in row order
    at = np.empty_like(order)
    at[order] = np.arange(len(order))
    merged = np.empty((len(all_rows), n), dtype=bool)
    merged[at[:len(rows)]] = flags.reshape(-1, n)
    merged[at[len(rows):]] = new[hit]
    return all_rows[order], merged
