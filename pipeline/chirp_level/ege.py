"""EGE compression (HWA compression engine, ``HWA_AccelModeCompress``: method EGE, both passes,
``EGEKarrayLength = 3``, ``scaleFactorBW = 4``, header on, dither on, as the demo's RangeProc
compression paramset; k-array {3, 4, 5, 7, 9, 11, 13, 15} as its ``EGEKparam``). The device
TRM's section on the HWA compression/decompression engine (AWR294x TRM, Radar Hardware
Accelerator chapter) was not available to us as text: the model follows the SDK's register
fields and the demo's settings (rangeprochwaDDMA.c) and seed 000 section 5.2 (block layout and
ratio), and says where it assumes. Model: each block of 4 Rx x 8 range bins of one chirp (32
complex samples of 16-bit I/Q, 128 bytes) must fit 64 bytes. Pass 1 picks, per block, the
smallest right-shift s (the scale factor, 4 bits in the header) for which the
exponential-Golomb codes of the 64 shifted integers, with the best order k of the 8-entry
k-array (3-bit index in the header), fit the budget; pass 2 encodes. Decompression restores
q x 2^s. The demo enables dither (an LFSR seeded by ``HWA_configCmpLFSRSeed0``): modelled as
non-subtractive triangular dither of +/-1 step before rounding, so every I and Q value is
within 1.5 x 2^s of its input and the error, independent of the signal, has variance
2^(2s) / 4 (the tests check both). ASSUMED: sign-magnitude EG codes (1 sign bit + EG_k of |q|:
k + 1 + 2 floor(log2(1 + |q| >> k)) bits), a deterministic hash in place of the undocumented
LFSR sequence, and the 16-bit HWA output scale of `HWA_OUTPUT_SCALE` (no saturation of the
16-bit output is modelled).

`ege_compress` is the model; the block format it shares with `ProcessingConfig` (k-array,
header, budget) lives in `pipeline.ege_format`.

References
----------
.. [1] TI, seed 000 section 5.2-5.3 (tables 6-8): block layout, 50 % ratio, decompression.
.. [2] TI MMWAVE-MCUPLUS-SDK, DDM demo, datapath/dpu/rangeprocDDMA/rangeprochwaDDMA.c:
       ``rangeProcHWA_ConfigHWACommon`` (EGEKparam, compression LFSR) and the compression
       paramset of ``rangeProcHWA_ConfigHWA``; MCU+ SDK HWA driver ``HWA_AccelModeCompress``.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..ege_format import (EGE_HEADER_BITS, EGE_K_ARRAY, HWA_OUTPUT_SCALE, ege_budget_bits,
                          ege_min_ratio)

__all__ = ["ege_compress", "ege_block_bits", "ege_min_ratio", "HWA_OUTPUT_SCALE", "EGE_K_ARRAY",
           "EGE_HEADER_BITS"]

_MAX_SHIFT = 15  # a 4-bit scale factor
def _dither(index: np.ndarray) -> np.ndarray:
    """The encoder's dither (``ditherEnable = 1`` in the demo) for values at flat cube
    positions `index`: triangular offsets in (-1, 1) quantisation steps (sum of two uniforms),
    from a splitmix64 hash of the position, so it is deterministic and never periodic across
    chirps (a repeating sequence would put lines into the Doppler spectrum). TPDF dither makes
    the error independent of the signal, of variance step^2 / 4 (Wannamaker, Lipshitz &
    Vanderkooy, J. AES 48(6), 2000). The HWA's own LFSR is not documented publicly."""
    # The same splitmix64 steps, in place on two uint64 buffers: on interference frames most
    # blocks are requantised and fresh temporaries per step dominated the cost.
    z = index.astype(np.uint64)
    z += np.uint64(0x9E3779B97F4A7C15)
    w = z >> np.uint64(30)
    z ^= w
    z *= np.uint64(0xBF58476D1CE4E5B9)
    np.right_shift(z, np.uint64(27), out=w)
    z ^= w
    z *= np.uint64(0x94D049BB133111EB)
    np.right_shift(z, np.uint64(31), out=w)
    z ^= w
    np.right_shift(z, np.uint64(8), out=w)
    w &= np.uint64(0xFFFFFF)
    z >>= np.uint64(40)
    u = z.astype(np.float32)
    u += w.astype(np.float32)          # u1 + u2: both < 2^24, the float32 sum as before
    u *= np.float32(2.0 ** -24)
    u -= np.float32(1.0)
    return u


@lru_cache(maxsize=4)
def _dither_table(size: int) -> np.ndarray:
    """`_dither` of every flat position of a cube of `size` values (read-only): computed once
    per cube size, then gathered (the hash costs 4x the gather)."""
    d = _dither(np.arange(size))
    d.flags.writeable = False
    return d


def _ege_shift(vb: np.ndarray, budget: int) -> tuple[np.ndarray, np.ndarray]:
    """Scale factor s and EG order k of each block (pass 1 of the encoder): the smallest s for
    which the exact code length of the best k fits `budget`.

    vb : (n_blocks, n_val) float32 values in HWA LSB. The bit-length histogram of each block
    (L_j: |v_j| < 2^L_j, clipped to 0..31) bounds the EG prefix of every value: with a =
    L - s - k - 1 and f(a) = max(a, 0) + [a = 0], f(a) <= floor(log2(1 + (|q| >> k))) <= f(a + 1)
    (rint(v / 2^s) keeps |q| in [2^(L-1-s), 2^(L-s)] when L - 1 >= s; a = 0 puts |q| >> k at 1
    or 2, a prefix of exactly one). So bits(s, k) lies between n_val (2 + k) + 2 sum_j f(a_j)
    and the same with a_j + 1, both read off cumulative sums of the histogram. The search
    starts every block at the smallest s whose lower bound fits for some k (no smaller s can
    fit) and, per s, tries the k of the smallest lower bound: a block whose upper bound fits is
    done, the others get the exact length, first of that k, then of every other k whose lower
    bound fits; s is raised only when none fits.
    """
    n_blk, n_val = vb.shape
    # L = biased exponent - 126 of |v|, clipped to 0..31. One bincount over all blocks builds
    # the histogram in descending L (column 32 - L; column 0, L = 32, stays empty) so that
    # both cumulative sums run forwards over contiguous int32 rows: cumsums over reversed
    # int64 views were the costliest step of this function.
    e = np.abs(vb).view(np.int32)
    e >>= 23
    np.clip(e, 126, 126 + 31, out=e)
    np.subtract((np.arange(n_blk, dtype=np.int32) * 33 + 126 + 32)[:, None], e, out=e)
    hist_r = np.bincount(e.reshape(-1), minlength=n_blk * 33).reshape(n_blk, 33)
    above_r = np.cumsum(hist_r, axis=1, dtype=np.int32)          # count with L >= 32 - i
    g_r = np.cumsum(above_r, axis=1, dtype=np.int32)             # sum over u >= 32 - i of above
    g = g_r[:, 31::-1]          # g[:, t] = sum over u > t of #(L >= u) = sum_j max(L_j - t, 0)
    hist = hist_r[:, 32:0:-1]   # hist[:, t] = #(L = t)
    # Only the orders whose sign + suffix bits alone fit can ever be chosen (3, 4, 5 of the
    # demo's k-array at 50 %): the others would only widen every table below.
    kk = EGE_K_ARRAY[n_val * (2 + EGE_K_ARRAY) <= budget].astype(np.int32)
    # Lower bounds at s = 0 first (most blocks fit there), the full (s, k) table for the rest.
    fsum = g + hist             # fsum[:, t] = sum_j f(L_j - t)
    t0 = np.minimum(kk + 1, 31)
    lower0 = n_val * (2 + kk)[None, :] + 2 * fsum[:, t0]                 # (blocks, K)
    shift = np.zeros(n_blk, dtype=np.int32)  # int32: ldexp's fast loop (int64 is 15x slower)
    k_sel = lower0.argmin(axis=-1)
    rest = np.flatnonzero(lower0[np.arange(n_blk), k_sel] > budget)
    if rest.size:
        t = np.minimum(np.arange(_MAX_SHIFT + 1)[:, None] + kk[None, :] + 1, 31)
        low = n_val * (2 + kk)[None, None, :] + 2 * fsum[rest][:, t]     # (rest, S, K)
        fits = low.min(axis=-1) <= budget
        shift[rest] = np.where(fits.any(axis=-1), fits.argmax(axis=-1), _MAX_SHIFT)
        k_sel[rest] = low[np.arange(rest.size), shift[rest]].argmin(axis=-1)

    def lower(i: np.ndarray) -> np.ndarray:
        """(len(i), K) lower bounds of blocks i at their current s."""
        return n_val * (2 + kk)[None, :] + 2 * fsum[i[:, None],
                                                    np.minimum(shift[i, None] + kk + 1, 31)]

    def upper_fits(i: np.ndarray) -> np.ndarray:
        """Blocks i whose upper bound fits at their current (s, k): they need no exact
        length (a value with L = 31, the clip, has no bound)."""
        k = kk[k_sel[i]]
        return (n_val * (2 + k) + 2 * fsum[i, shift[i] + k] <= budget) & (hist[i, 31] == 0)

    todo = np.arange(n_blk)
    for _ in range(_MAX_SHIFT + 1):
        todo = todo[~upper_fits(todo)]
        if todo.size == 0:
            break
        q = np.rint(np.ldexp(vb[todo], -shift[todo, None]))   # float32, exact scaling
        over = _eg_bits_f32(q.copy(), kk[k_sel[todo]]) > budget
        if over.any():  # the other orders whose lower bound fits
            failed = np.flatnonzero(over)
            j, k = np.nonzero(lower(todo[failed]) <= budget)
            other = k != k_sel[todo[failed[j]]]
            row, k = failed[j[other]], k[other]
            ok = _eg_bits_f32(q[row], kk[k]) <= budget
            k_sel[todo[row[ok]]] = k[ok]
            over[row[ok]] = False
        todo = todo[over & (shift[todo] < _MAX_SHIFT)]
        if todo.size == 0:
            break
        shift[todo] += 1
        k_sel[todo] = lower(todo).argmin(axis=-1)
    return shift, kk[k_sel]


def _eg_bits_f32(q: np.ndarray, k: np.ndarray) -> np.ndarray:
    """`ege_block_bits` of float32 integer blocks (n, n_val) with per-block k, via the IEEE
    exponent (exact for |q| < 2^24); q is overwritten. floor(log2(1 + |q| >> k)) =
    floor(log2(|q| + 2^k)) - k, so one add replaces the shift (scale, floor, + 1)."""
    m = np.abs(q, out=q)
    m += np.ldexp(np.float32(1), k.astype(np.int32))[:, None]
    return _eg_bits_from(m, k)


def _eg_bits_from(m: np.ndarray, k) -> np.ndarray:
    """EG_k code length of blocks given m = |q| + 2^k (n, n_val) float32: the sum of
    floor(log2(|q| + 2^k)) is that of the biased IEEE exponents less 127 per value, summed by a
    float32 matrix-vector product (8x numpy's int row sums; exact, as every partial sum is an
    integer below 255 n_val < 2^24)."""
    n_val = m.shape[1]
    e = (m.view(np.int32) >> 23).astype(np.float32) @ np.ones(n_val, np.float32)
    lead = e.astype(np.int64) - (127 + np.asarray(k)) * n_val
    return n_val * (2 + np.asarray(k)) + 2 * lead


def ege_block_bits(q: np.ndarray, k) -> np.ndarray:
    """Exact EG_k code length of integer blocks, sign-magnitude, bits (header excluded).

    Parameters
    ----------
    q : (..., n) integer-valued float or int
        Quantised values of each block (last axis).
    k : int or (...,) int
        EG order of each block.

    Returns
    -------
    (...,) int
        sum over the block of 1 sign bit + k + 1 + 2 floor(log2(1 + |q| >> k)).
    """
    k = np.asarray(k)
    m = np.floor(np.ldexp(np.abs(np.asarray(q, dtype=np.float64)), -k[..., None])) + 1
    lead = np.floor(np.log2(m)).astype(np.int64)
    return np.sum(2 + k[..., None] + 2 * lead, axis=-1)


def _noise_orders(n_val: int, budget: int) -> tuple[int, int]:
    """The EG order that admits the largest mean |v| in `_cold_sum` (4 for the demo) and the
    next: the orders with which noise-like blocks near that limit fit."""
    best = int(np.argmax(_jensen_mean(n_val, budget)))
    return int(EGE_K_ARRAY[best]), int(EGE_K_ARRAY[min(best + 1, EGE_K_ARRAY.size - 1)])


def _fits_unshifted(vb: np.ndarray, budget: int, orders) -> np.ndarray:
    """Blocks (n_blocks, n_val) of HWA LSB values whose exact EG code length fits `budget`
    with s = 0 and one of `orders` (`_eg_bits_f32`: the exponent of |q| + 2^k)."""
    m = np.rint(vb)
    np.abs(m, out=m)
    ok = np.zeros(vb.shape[0], dtype=bool)
    left = np.arange(vb.shape[0])
    for k in orders:  # each order tried on the blocks the previous ones left
        fit = _eg_bits_from((m if left.size == m.shape[0] else m[left]) + np.float32(2.0 ** k),
                            k) <= budget
        ok[left[fit]] = True
        left = left[~fit]
    return ok


def _cold_sum(n_val: int, budget: int) -> float:
    """Largest sum of |v| (HWA LSB) of a block of n_val values that fits `budget` unshifted,
    whatever the values: |q| = |rint(v)| <= |v| + 1/2 and floor(log2(1 + (|q| >> k))) <=
    log2(1 + |q| / 2^k), which is concave in |q|, so by Jensen's inequality the block's code
    length is at most n_val (2 + k) + 2 n_val log2(1 + (mean |v| + 1/2) / 2^k); the best k gives
    the largest mean. Less a relative 1e-5 for the float32 sums it is compared with."""
    return float(n_val * _jensen_mean(n_val, budget).max() * (1 - 1e-5))


def _jensen_mean(n_val: int, budget: int) -> np.ndarray:
    """(K,) largest mean |v| (HWA LSB) per EG order k of the k-array for which the Jensen bound
    n_val (2 + k) + 2 n_val log2(1 + (mean + 1/2) / 2^k) fits `budget`."""
    k = EGE_K_ARRAY.astype(np.float64)
    return 2.0 ** k * (2.0 ** ((budget / n_val - 2 - k) / 2) - 1) - 0.5


def ege_compress(rf: np.ndarray, ratio: float = 0.5, range_bins_per_block: int = 8,
                 scale: float = HWA_OUTPUT_SCALE) -> tuple[np.ndarray, np.ndarray]:
    """EGE compression + decompression of a range-FFT cube, in place.

    Parameters
    ----------
    rf : (n_chirps, n_rx, n_range) complex64
        Range FFT (C-contiguous last axis); n_range must be a multiple of
        `range_bins_per_block`. A block holds all Rx (4 for the R79 demo) x
        `range_bins_per_block` bins of one chirp. Overwritten with the decompressed values.
    ratio : float
        Compressed / uncompressed size (the demo: 0.5: 128 -> 64 bytes).
    range_bins_per_block : int
        The demo: 8 (compressionCfg).
    scale : float
        HWA LSB per rf unit (`HWA_OUTPUT_SCALE`).

    Returns
    -------
    rf : (n_chirps, n_rx, n_range) complex64
        The decompressed cube (the same array).
    shift : (n_chirps, n_range / range_bins_per_block) int8
        Scale factor s of every block: each decompressed I/Q value is within 1.5 x 2^s HWA LSB
        of the input (half a step of rounding plus up to a step of dither; s = 0: not
        requantised, see Notes). The error is independent of the signal, of variance
        2^(2s) / 4 per I/Q value (non-subtractive triangular dither).

    Notes
    -----
    A block whose sum of |values| is small enough fits with s = 0 whatever its values are
    (`_cold_sum`, Jensen's inequality on the EG prefix lengths: sum |v| <= 915 HWA LSB for
    the demo, a mean of 14.3 LSB against the 8.5 LSB of thermal noise); those blocks only see
    the 16-bit rounding of the HWA output (-33 dB below the thermal noise of the R79 profile),
    which is not modelled. Only the other blocks (strong echoes,
    interference, some noise peaks) go through the encoder model.
    """
    n_c, n_r, n_b = rf.shape
    if n_b % range_bins_per_block:
        raise ValueError(f"compression_range_bins_per_block={range_bins_per_block} does not "
                         f"divide the {n_b} range bins")
    nb = n_b // range_bins_per_block
    n_val = 2 * n_r * range_bins_per_block
    budget = ege_budget_bits(n_r, range_bins_per_block, ratio)
    if ratio < ege_min_ratio(n_r, range_bins_per_block):
        raise ValueError(f"compression_ratio={ratio:g} is below "
                         f"{ege_min_ratio(n_r, range_bins_per_block):.4f}: no EG code of the "
                         f"k-array fits a block of {n_r} Rx x {range_bins_per_block} bins")
    vv = rf.view(np.float32).reshape(n_c, n_r, nb, 2 * range_bins_per_block)
    # sum |v| of every block: |I|, |Q| summed over its bins by one matrix-vector product
    # (much faster than add.reduceat), then over the Rx.
    mag = np.abs(rf.view(np.float32)).reshape(-1, 2 * range_bins_per_block)
    total = (mag @ np.ones(2 * range_bins_per_block, np.float32)).reshape(n_c, n_r, nb) \
        .sum(axis=1).reshape(-1)                                      # (C nb,), rf units
    shift = np.zeros(n_c * nb, dtype=np.int8)
    hot = np.flatnonzero(total > _cold_sum(n_val, budget) / np.float32(scale))
    if hot.size:
        # One fancy-index gather (faster than a transposed copy of the cube even when most
        # blocks are hot, as with interference).
        c_i, b_i = np.divmod(hot, nb)
        vb = vv[c_i, :, b_i, :].reshape(hot.size, n_val)
        vb *= np.float32(scale)
        # Most hot blocks are noise-like and fit unshifted with the orders that suit noise:
        # an exact check of those two orders spares them the full search.
        s = np.zeros(hot.size, dtype=np.int32)
        search = ~_fits_unshifted(vb, budget, _noise_orders(n_val, budget))
        s[search], _ = _ege_shift(vb[search], budget)
        shift[hot] = s
        moved = s > 0  # s = 0: only the (unmodelled) 16-bit rounding
        rows, s = hot[moved], s[moved]
        if rows.size:
            q = vb[moved]
            q *= np.ldexp(np.float32(1), -s)[:, None]   # / step, exact for a power of two
            q += _dither_table(n_c * nb * n_val).reshape(-1, n_val)[rows]
            np.rint(q, out=q)
            q *= np.ldexp(np.float32(1), s)[:, None] / np.float32(scale)  # int32 s: fast loop
            c_i, b_i = np.divmod(rows, nb)
            vv[c_i, :, b_i, :] = q.reshape(rows.size, n_r, 2 * range_bins_per_block)
    shift = shift.reshape(n_c, nb)
    return rf, shift
