"""The chip's chirp-level chain before the radar cube is stored (R79 demo RangeProc DPU).

Seed 004 section 2 / seed 000 section 5.1 (table 5): per chirp, the HWA estimates and removes
the DC of each Rx (param 2-3), gathers interference statistics (param 3), zeroes the samples the
statistics flag and takes the windowed range FFT (param 4), then EGE-compresses the range FFT to
50 % in blocks of 4 antennas x 8 range bins (param 5, section 5.2); the Doppler stage
decompresses first (section 5.3). Each step is switchable in `ProcessingConfig`
(`dc_removal`, `interference_mitigation`, `compression`); `range_stage` is the hook the chains
call instead of a bare range FFT.

Interference mitigation, as TI documents it (with where this model assumes):

* Statistics per chirp and Rx (SWRA725 sec. 3.1): absSum = sum |x_n| and diffAbsSum =
  sum |x_n - x_{n-1}|, scaled to means and then by the ``intfMitigCfg`` SNRs into the thresholds
  AbsThreshold = mean |x| 10^(magSNRdB / 20) and AbsDiffThreshold = mean |dx| 10^(magDiffSNRdB
  / 20): the SDK's ``rangeProcHWADDMA_findIntfStatsStaticParams`` programs the HWA scale as
  10^(SNRdB / 20) / numSamples x 2^(8 + shift), i.e. an amplitude ratio over the mean.
  ``intfMitigCfg -1 15 18`` (the shipped profile, TI's defaults) gives 15 and 18 dB.
* Localisation (SWRA725 sec. 3.2; HWA_INTERFTHRESH_MODE_*): a sample whose |x| and/or |dx|
  exceeds its threshold gets an interference indicator bit. The DDM demo's RangeProc programs
  ``thresholdMode = MAGDIFF`` with per-Rx built-in statistics, so the default mode is
  "magdiff"; the other HWA modes are selectable (`INTF_THRESHOLD_MODES`).
* Mitigation (SWRA725 sec. 3.3; HWA_INTERFMITIGATION_PATH_*): the DDM demo's RangeProc
  (rangeprochwaDDMA.c, ``rangeProcHWA_ConfigHWA``, current MCU+ SDK) enables it
  (``interfMitigation.enable = 1``) on the windowed zero-out path with left/right hysteresis
  orders 3 and a count threshold of 1 (an older release left it disabled with a TODO), so the
  harness turns it on by default. ASSUMED here: the hysteresis extends every flagged run by
  `intf_hysteresis_samples` samples on each side and those samples are set to zero. The
  "windowed" part is a 5-sample taper (the demo programs samples 2-6 of a 16-point Hann in
  Q5, ``hwaInterfMitigWindow``), but where the HWA applies it is not documented publicly: it
  is not modelled (a hard zero).

EGE compression (HWA compression engine, ``HWA_AccelModeCompress``: method EGE, both passes,
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

References
----------
.. [1] TI, seed 000 section 5.1-5.3 (tables 5-8), seed 004 section 2-4.
.. [2] TI SWRA725, "Interference Mitigation for AWR294x" (2021), sections 3.1-3.3.
.. [3] TI MMWAVE-MCUPLUS-SDK, DDM demo: ``MmwDemo_CLIIntfMitigCfg`` (mmw_cli.c),
       ``rangeProcHWADDMA_findIntfStatsStaticParams``, ``rangeProcHWA_ConfigHWACommon``
       (EGEKparam, compression LFSR) and ``rangeProcHWA_ConfigHWA`` (mitigation and
       compression paramsets) in datapath/dpu/rangeprocDDMA/rangeprochwaDDMA.c; the DPC's
       ``hwaInterfMitigWindow`` (16-point Hann, Q5); MCU+ SDK HWA driver API
       ``HWA_PreProcessing.interfMitigation``, ``HWA_AccelModeCompress``.
"""
from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np
import scipy.fft

from radarsim.config import RadarConfig

from .config import INTF_THRESHOLD_MODES, WINDOWS, ProcessingConfig
from .kernels import range_fft, window

__all__ = ["range_stage", "remove_dc", "interference_flags", "zero_flagged", "ege_compress",
           "ege_block_bits", "ege_min_ratio", "NoiseFloor", "noise_floor_rise",
           "NOISE_FLOOR_FIELDS", "INTF_THRESHOLD_MODES", "HWA_OUTPUT_SCALE", "EGE_K_ARRAY", "EGE_HEADER_BITS"]

#: Range-FFT value -> 16-bit HWA output LSB: the demo's range FFT scales its last 3 butterfly
#: stages by 1/2 (butterflyScaling = 7), i.e. 1/8 of the unscaled FFT of the int16 samples.
HWA_OUTPUT_SCALE = 1.0 / 8.0
#: EGE orders of the k-array: EGEKarrayLength = 3 (8 entries), the values the DDM demo's
#: RangeProc programs (rangeprochwaDDMA.c, ``rangeProcHWA_ConfigHWACommon``: EGEKparam).
EGE_K_ARRAY = np.array([3, 4, 5, 7, 9, 11, 13, 15])
#: Block header: scale factor (scaleFactorBW = 4) + k index (3 bits).
EGE_HEADER_BITS = 4 + 3
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


# ------------------------------------------------------------------------------- kernels
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


def interference_flags(adc: np.ndarray, dc: np.ndarray | None, mag_snr_db: float,
                       magdiff_snr_db: float, mode: str = "magdiff") -> np.ndarray:
    """Interference indicator bits (before hysteresis) of every sample.

    Parameters
    ----------
    adc : (n_chirps, n_rx, n_samples) int16 or float
    dc : (n_chirps, n_rx, 1) float or None
        DC estimate removed before the statistics (None: none).
    mag_snr_db, magdiff_snr_db : float
        ``intfMitigCfg`` magSNRdB and magDiffSNRdB: thresholds over the mean |x| and mean
        |x_n - x_{n-1}| of the same chirp and Rx, amplitude dB.
    mode : str
        Key of `INTF_THRESHOLD_MODES`.

    Returns
    -------
    (n_chirps, n_rx, n_samples) bool
        Sample 0 has no difference; in "magdiff" mode it is never flagged.
    """
    if mode not in INTF_THRESHOLD_MODES:
        raise ValueError(f"intf_threshold_mode={mode!r} is not one of "
                         f"{sorted(INTF_THRESHOLD_MODES)}")
    m = INTF_THRESHOLD_MODES[mode]
    n = adc.shape[-1]
    a2 = adc.reshape(-1, n)
    flags = None
    if m.difference:
        d, thr = _diff_statistics(a2, magdiff_snr_db)
        flags = np.zeros(a2.shape, dtype=bool)
        np.greater(d, thr[:, None], out=flags[:, 1:])
    if m.magnitude:
        x = a2.astype(np.complex64 if np.iscomplexobj(adc) else np.float32)  # I/Q: |complex|
        if dc is not None:
            x -= dc.reshape(-1, 1)
        a = np.abs(x)
        thr = a.sum(axis=-1, keepdims=True) * np.float32(10 ** (mag_snr_db / 20) / n)
        fm = a > thr
        if flags is None:
            flags = fm
        elif m.both_required:
            flags &= fm
        else:
            flags |= fm
    return flags.reshape(adc.shape)


def _diff_statistics(a2: np.ndarray, snr_db: float) -> tuple[np.ndarray, np.ndarray]:
    """|x_n - x_{n-1}| of (rows, n) samples and each row's threshold mean |dx| 10^(SNR/20),
    float32 (`interference_flags`). Real int16 rows are differenced in int16 when no
    difference can overflow it (four times cheaper than float32; the int32 row sums are below
    2^24, so the float32 threshold is the same), I/Q rows as complex64."""
    n = a2.shape[-1]
    if np.iscomplexobj(a2):
        d = np.abs(np.subtract(a2[:, 1:], a2[:, :-1], dtype=np.complex64))
    elif a2.dtype == np.int16 and int(a2.max()) - int(a2.min()) <= np.iinfo(np.int16).max:
        d = np.subtract(a2[:, 1:], a2[:, :-1])
        np.abs(d, out=d)
    else:
        d = np.abs(np.subtract(a2[:, 1:], a2[:, :-1], dtype=np.float32))
    total = d.sum(axis=-1, dtype=np.int32 if d.dtype.kind == "i" else np.float32)
    return d, total.astype(np.float32) * np.float32(10 ** (snr_db / 20) / n)


def zero_flagged(x: np.ndarray, flags: np.ndarray, hysteresis: int = 3) -> np.ndarray:
    """Zero the flagged samples, each flagged run widened by `hysteresis` on both sides.

    Parameters
    ----------
    x : (..., n_samples) float32
        DC-removed samples (modified in place and returned).
    flags : (..., n_samples) bool
    hysteresis : int
        Left and right hysteresis order, samples (the demo: 3): sample i is zeroed iff a flag
        lies in [i - hysteresis, i + hysteresis] of its own chirp.
    """
    n = x.shape[-1]
    f = np.flatnonzero(flags)  # flags are sparse: index arithmetic beats dilating the mask
    if f.size:
        col = f % n
        span = np.arange(-hysteresis, hysteresis + 1)
        np.put(x, (f - col)[:, None] + np.clip(col[:, None] + span, 0, n - 1), 0)
    return x


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


def _ege_budget_bits(n_rx: int, range_bins_per_block: int, ratio: float) -> int:
    """Code bits of one block (header excluded) at `ratio` of its 32-bit complex samples."""
    return int(np.floor(ratio * 32 * n_rx * range_bins_per_block)) - EGE_HEADER_BITS


def ege_min_ratio(n_rx: int, range_bins_per_block: int) -> float:
    """Smallest compression ratio whose budget holds a block of zeros: every one of its
    2 n_rx range_bins_per_block I/Q values needs 2 + k bits with the smallest k of the
    k-array, plus the header (0.32 for the demo's 4 Rx x 8 bins and k >= 3)."""
    n_val = 2 * n_rx * range_bins_per_block
    need = n_val * (2 + int(EGE_K_ARRAY.min())) + EGE_HEADER_BITS
    return need / (32 * n_rx * range_bins_per_block)


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
    budget = _ege_budget_bits(n_r, range_bins_per_block, ratio)
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


# ------------------------------------------------------------------------------- stage
def range_stage(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> np.ndarray:
    """The chirp-level chain: DC removal, interference mitigation, windowed range FFT,
    EGE compression/decompression, each as `proc` switches it.

    Parameters
    ----------
    cfg : RadarConfig
    adc : (n_chirps, n_rx, n_samples) int16, or complex64 I/Q (complex ADC modes)
    proc : ProcessingConfig

    Returns
    -------
    (n_chirps, n_rx, n_samples // 2) complex64, or (..., n_samples) for I/Q input
        With every switch off, exactly `kernels.range_fft(adc, window)`.
    """
    cplx = np.iscomplexobj(adc)
    win = window(WINDOWS[proc.range_window], cfg.n_samples)
    if not (proc.dc_removal or proc.interference_mitigation or proc.compression):
        return range_fft(adc, win)
    dc = remove_dc(adc) if proc.dc_removal else None
    rows = np.zeros(0, dtype=np.intp)
    if proc.interference_mitigation:
        rows, flags = _flagged_rows(adc, dc, proc)
    if rows.size == 0:
        rf = range_fft(adc, win)
    else:
        # One FFT of the whole frame, the flagged chirps (DC removed, zeroed) swapped in first.
        work = np.complex64 if cplx else np.float32
        x = np.multiply(adc, win, dtype=work)
        y = adc.reshape(-1, cfg.n_samples)[rows]
        y = y.astype(work) if dc is None else np.subtract(y, dc.reshape(-1, 1)[rows], dtype=work)
        zero_flagged(y, flags, proc.intf_hysteresis_samples)
        y *= win
        x.reshape(-1, cfg.n_samples)[rows] = y
        if cplx:
            rf = scipy.fft.fft(x, axis=-1, workers=-1, overwrite_x=True)
        else:
            rf = scipy.fft.rfft(x, axis=-1, workers=-1)[..., : cfg.n_samples // 2]
    if dc is not None:
        # FFT(w (x - m)) = FFT(w x) - m FFT(w): the window's spectrum has a few bins only.
        # The flagged chirps had their DC removed before the FFT.
        m = dc[..., 0]
        if rows.size:
            m = m.copy()
            m.reshape(-1)[rows] = 0
        for k, wk in _window_spectrum(WINDOWS[proc.range_window], cfg.n_samples, cplx):
            rf[..., k] -= m * wk
    if proc.compression:
        rf, _ = ege_compress(rf, proc.compression_ratio, proc.compression_range_bins_per_block)
    return rf


def _flagged_rows(adc: np.ndarray, dc, proc: ProcessingConfig) -> tuple[np.ndarray, np.ndarray]:
    """(chirp x Rx rows with a flagged sample, their (rows, n_samples) flags). A mode that
    uses the difference statistic alone (the demo's "magdiff") takes a fast path: a row is
    flagged iff its largest |dx| exceeds its threshold, and only those rows get their flags
    built."""
    n = adc.shape[-1]
    a2 = adc.reshape(-1, n)
    if not INTF_THRESHOLD_MODES[proc.intf_threshold_mode].magnitude:
        d, thr = _diff_statistics(a2, proc.intf_magdiff_snr_db)
        rows = np.flatnonzero(d.max(axis=-1) > thr)
        flags = np.zeros((rows.size, n), dtype=bool)
        np.greater(d[rows], thr[rows, None], out=flags[:, 1:])
        return rows, flags
    flags = interference_flags(adc, dc, proc.intf_mag_snr_db, proc.intf_magdiff_snr_db,
                               proc.intf_threshold_mode).reshape(-1, n)
    rows = np.flatnonzero(flags.any(axis=-1))
    return rows, flags[rows]


@lru_cache(maxsize=32)
def _window_spectrum(name: str, n: int, full: bool = False) -> tuple:
    """Non-negligible bins (k, W[k]) of the window's rFFT (Hann: k = 0, 1), or of its full FFT
    for complex samples (Hann: k = 0, 1, n - 1); cached per window."""
    w64 = window(name, n).astype(np.float64)
    w = scipy.fft.fft(w64) if full else scipy.fft.rfft(w64)[: n // 2]
    big = np.flatnonzero(np.abs(w) > 1e-6 * np.abs(w).max())
    return tuple((int(k), np.complex64(w[k])) for k in big)


# ------------------------------------------------------------------------------- metrics
#: The `ProcessingConfig` fields `noise_floor_rise` reads (the chirp-level chain's and the
#: windows): two settings equal on these give the same floor for the same frame.
NOISE_FLOOR_FIELDS = ("range_window", "doppler_window", "min_range_bin", "dc_removal",
                      "interference_mitigation", "intf_mag_snr_db", "intf_magdiff_snr_db",
                      "intf_threshold_mode", "intf_hysteresis_samples", "compression",
                      "compression_ratio", "compression_range_bins_per_block")


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
    floor_r = float(np.median(p)) / np.log(2)
    spec = scipy.fft.fft(sub * wd.astype(np.float32)[:, None, None], axis=0, workers=-1)
    pd_ = spec.real ** 2 + spec.imag ** 2
    floor_d = float(np.median(pd_)) / np.log(2)
    return NoiseFloor(10 * np.log10(floor_r / ref_r),
                      10 * np.log10(floor_d / (ref_r * np.sum(wd ** 2))))
