"""EGE compression (HWA compression engine, ``HWA_AccelModeCompress``: method EGE, both passes,
``EGEKarrayLength = 3``, ``scaleFactorBW = 4``, header on, dither on, as the demo's RangeProc
compression paramset; k-array {3, 4, 5, 7, 9, 11, 13, 15} as its ``EGEKparam``). The device
TRM's section on the HWA compression/decompression engine (AWR294x TRM, Radar Hardware
Accelerator chapter) was not available to us as text: the model follows the SDK's register
fields and the demo's settings (rangeprochwaDDMA.c) and [TI-DDMA] section 5.2 (block layout and
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

Implementation: the encoder decides per block (a cold-block test, a scale-factor search that
stops at the first fit, dither only where a block is requantised), which vectorised numpy could
only express as full-cube temporaries and index gathers; the block loop is compiled with numba
(``cache=True``: compiled once per machine, loaded by every later process). Same arithmetic in
the same float32 order as the numpy version it replaced (bit-identical output), about 6x faster
on an R79 cube.

References
----------
.. [1] [TI-DDMA] section 5.2-5.3 (tables 6-8): block layout, 50 % ratio, decompression.
.. [2] TI MMWAVE-MCUPLUS-SDK, DDM demo, datapath/dpu/rangeprocDDMA/rangeprochwaDDMA.c:
       ``rangeProcHWA_ConfigHWACommon`` (EGEKparam, compression LFSR) and the compression
       paramset of ``rangeProcHWA_ConfigHWA``; MCU+ SDK HWA driver ``HWA_AccelModeCompress``.
"""
from __future__ import annotations

import numba
import numpy as np

from core.errors import BadInput

from ..ege_format import (
    EGE_HEADER_BITS,
    EGE_K_ARRAY,
    HWA_OUTPUT_SCALE,
    ege_budget_bits,
    ege_min_ratio,
)
from ..threads import run_parts, spans

__all__ = ["ege_compress", "ege_block_bits", "ege_min_ratio", "HWA_OUTPUT_SCALE", "EGE_K_ARRAY",
           "EGE_HEADER_BITS"]

_MAX_SHIFT = 15  # a 4-bit scale factor
_U = np.uint64  # unsigned loop indices: LLVM vectorises those loops (see `_block_shift`)
_SPLITMIX_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_SPLITMIX_M1 = np.uint64(0xBF58476D1CE4E5B9)
_SPLITMIX_M2 = np.uint64(0x94D049BB133111EB)


@numba.njit(cache=True, nogil=True)
def _dither(index: int) -> np.float32:
    """The encoder's dither (``ditherEnable = 1`` in the demo) for the value at flat cube
    position `index`: a triangular offset in (-1, 1) quantisation steps (sum of two uniforms),
    from a splitmix64 hash of the position, so it is deterministic and never periodic across
    chirps (a repeating sequence would put lines into the Doppler spectrum). TPDF dither makes
    the error independent of the signal, of variance step^2 / 4 (Wannamaker, Lipshitz &
    Vanderkooy, J. AES 48(6), 2000). The HWA's own LFSR is not documented publicly."""
    z = np.uint64(index) + _SPLITMIX_GAMMA
    z = (z ^ (z >> np.uint64(30))) * _SPLITMIX_M1
    z = (z ^ (z >> np.uint64(27))) * _SPLITMIX_M2
    z = z ^ (z >> np.uint64(31))
    u1 = np.float32(z >> np.uint64(40))                    # both < 2^24, exact in float32
    u2 = np.float32((z >> np.uint64(8)) & np.uint64(0xFFFFFF))
    return (u1 + u2) * np.float32(2.0 ** -24) - np.float32(1.0)


@numba.njit(cache=True, nogil=True)
def _block_shift(v: np.ndarray, budget: int, kk: np.ndarray, m: np.ndarray,
                 qa: np.ndarray) -> int:
    """Scale factor s of one block (pass 1 of the encoder): the smallest s for which the
    EG code length with the best order of `kk` fits `budget` bits, `_MAX_SHIFT` if none.

    v : (n_val,) float32 values in HWA LSB. The length at (s, k) is sum_j (2 + k + 2
    floor(log2(|q_j| + 2^k)) - 2 k), q = rint(v / 2^s), each logarithm read off the IEEE
    exponent field of the float32 sum |q_j| + 2^k (biased exponent - 127; exact below 2^24).
    Every (s, k) is one pass over the values in loops LLVM vectorises (unsigned indices from
    0), s ascending. m, qa (n_val,) float32 are scratch buffers.

    This returns what the formulation it replaced returned, for every input (the test
    compares the two bit for bit): that one bounded each (s, k) first from a histogram of the
    bit lengths L of |v| (|v| < 2^L, clipped to 0..31), skipping an order whose lower bound
    exceeded the budget and taking one whose upper bound fitted (no L at the clip) without the
    length above. Both shortcuts agree with the length above: per value, with a = L - s - k - 1
    and f(a) = max(a, 0) + [a = 0], f(a) <= floor(log2(1 + (|q| >> k))) <= f(a + 1)
    (|q| <= 2^(L-s)), and the float32 sum can only round up to the next power of two, so its
    logarithm is at least the exact one and, as |q| + 2^k <= 2^(L-s) + 2^k, at most the upper
    bound's. A length that fits is found at the same s either way.
    """
    n_val = v.size
    mi = m.view(np.int32)
    for s in range(_MAX_SHIFT + 1):
        step = np.float32(2.0 ** -s)
        for j in range(_U(n_val)):
            qa[j] = abs(np.rint(v[j] * step))
        for k in kk:
            two_k = np.float32(2.0 ** k)
            lead = 0
            for j in range(_U(n_val)):
                m[j] = qa[j] + two_k
                lead += (mi[j] >> 23) - 127 - k  # floor(log2(|q| + 2^k)) - k
            if n_val * (2 + k) + 2 * lead <= budget:
                return s
    return _MAX_SHIFT


@numba.njit(cache=True, nogil=True)
def _hot_block(vv: np.ndarray, c: int, lo: int, bins2: int, scale: np.float32, budget: int,
               kk: np.ndarray, first: int, v: np.ndarray, m: np.ndarray,
               qa: np.ndarray) -> int:
    """Encode + decode of the block vv[c, :, lo : lo + bins2] that is not cold (`ege_blocks`),
    in place: its scale factor s (`_block_shift`), then, if s > 0, every value requantised
    with the dither of its flat frame position first + j (j = rx x bins2 + t). v, m, qa
    (n_val,) float32 are scratch buffers. Returns s."""
    n_r = vv.shape[1]
    ub, ulo, uc = _U(bins2), _U(lo), _U(c)
    for r in range(_U(n_r)):
        for t in range(ub):
            v[r * ub + t] = vv[uc, r, ulo + t] * scale
    s = _block_shift(v, budget, kk, m, qa)
    if s == 0:  # s = 0: only the (unmodelled) 16-bit rounding
        return s
    down = np.float32(2.0 ** -s)
    up = np.float32(2.0 ** s) / scale
    f0 = _U(first)
    for j in range(_U(v.size)):
        m[j] = np.rint(v[j] * down + _dither(f0 + j)) * up
    for r in range(_U(n_r)):
        for t in range(ub):
            vv[uc, r, ulo + t] = m[r * ub + t]
    return s


@numba.njit(cache=True, nogil=True)
def ege_blocks(vv: np.ndarray, bins2: int, scale: np.float32, budget: int, kk: np.ndarray,
                cold: float, shift: np.ndarray, c0: int, c1: int, c_base: int = 0) -> None:
    """EGE encode + decode of every block of `vv` in place (`ege_compress`).

    vv : (n_chirps, n_rx, >= n_blocks x bins2) float32, I/Q interleaved, rf units; block b of
    chirp c holds vv[c, :, b bins2 : (b + 1) bins2] (bins2 = 2 x range bins per block), value
    j = rx x bins2 + t at flat position ((c_base + c) n_blocks + b) n_val + j of the frame (vv
    may be the chirps c_base.. of a frame). Values past the n_blocks blocks are not read or
    written: vv may be a whole rFFT output, Nyquist bin included, whose C-contiguous rows the
    compiled loops read faster than a strided view's. shift : (n_chirps, n_blocks) int8,
    written; its n_blocks is the blocks of a row. Cold blocks (sum |v| <= cold, HWA LSB) fit
    unshifted (`_cold_sum`). Only chirps c0 <= c < c1 (blocks are independent)."""
    n_r = vv.shape[1]
    nb = shift.shape[1]
    n_val = n_r * bins2
    v = np.empty(n_val, np.float32)
    m = np.empty(n_val, np.float32)
    qa = np.empty(n_val, np.float32)
    acc = np.empty(nb * bins2, np.float32)
    for c in range(c0, c1):
        # One float32 partial sum per position t of the row (the same t of every Rx), added
        # along the whole row in a vector, then each block's partial sums in order: the cold
        # test is a shortcut, so its summation order cannot change an output (a cold block
        # that were not skipped would get s = 0 from `_block_shift`, which `_cold_sum`
        # guarantees fits, and stay untouched). A block's sum goes through n_r + bins2 - 1
        # float32 roundings (<= 67 here: 4 Rx, 32 bins), a relative error below 67 x 2^-24 =
        # 4e-6, inside the relative 1e-5 `_cold_sum` keeps as a margin. The whole row's sums
        # come first: a block's encoding rewrites only its own values.
        row = vv[c, 0]
        for t in range(_U(nb * bins2)):
            acc[t] = abs(row[t])
        for r in range(1, n_r):
            row = vv[c, r]
            for t in range(_U(nb * bins2)):
                acc[t] += abs(row[t])
        for b in range(nb):
            lo = b * bins2
            total = np.float32(0.0)
            for t in range(bins2):
                total += acc[lo + t]
            if total * scale <= cold:
                continue
            shift[c, b] = _hot_block(vv, c, lo, bins2, scale, budget, kk,
                                     ((c_base + c) * nb + b) * n_val, v, m, qa)


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
    bins2, budget, kk, cold = ege_setup(n_r, n_b, ratio, range_bins_per_block)
    nb = n_b // range_bins_per_block
    shift = np.zeros((n_c, nb), dtype=np.int8)
    vv = rf.view(np.float32)
    run_parts([lambda lo=lo, hi=hi: ege_blocks(vv, bins2, np.float32(scale), budget, kk, cold,
                                                shift, lo, hi)
               for lo, hi in spans(n_c)])  # chirps in parts on the cores (`pipeline.threads`)
    return rf, shift


def ege_setup(n_rx: int, n_range: int, ratio: float,
              range_bins_per_block: int) -> tuple[int, int, np.ndarray, float]:
    """(bins2, budget bits, usable k-array, cold-block sum) of `ege_blocks` for a cube of
    `n_rx` x `n_range` bins per chirp (`ege_compress`'s parameters).

    Raises
    ------
    ValueError
        If `range_bins_per_block` does not divide `n_range`, or `ratio` is below
        `ege_min_ratio`.
    """
    if n_range % range_bins_per_block:
        raise BadInput(f"compression_range_bins_per_block={range_bins_per_block} does not "
                       f"divide the {n_range} range bins")
    n_val = 2 * n_rx * range_bins_per_block
    budget = ege_budget_bits(n_rx, range_bins_per_block, ratio)
    if ratio < ege_min_ratio(n_rx, range_bins_per_block):
        raise BadInput(f"compression_ratio={ratio:g} is below "
                       f"{ege_min_ratio(n_rx, range_bins_per_block):.4f}: no EG code of the "
                       f"k-array fits a block of {n_rx} Rx x {range_bins_per_block} bins")
    kk = EGE_K_ARRAY[n_val * (2 + EGE_K_ARRAY) <= budget]  # only these can ever fit
    return 2 * range_bins_per_block, budget, kk, _cold_sum(n_val, budget)
