"""Kernels of the empty-band DDMA demodulation ([TI-DDMA] table 11) and its coherent azimuth
map: the Tx-order metric, the demodulation gather and the zero-padded azimuth DFT as a complex
GEMM with its power map, whole or in blocks of range bins that stay in cache.

Compiled loops (numba, ``cache=True``) repeat numpy's float32 operations in numpy's order, and a
GEMM is only split where the BLAS at hand gives the whole product's bits (checked once per
process and layout), so every output is bit for bit the numpy formulation's.

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA]: section 5, tables 11, 14.
"""
from __future__ import annotations

from functools import lru_cache

import numba
import numpy as np
import scipy.fft

from .kernels import UINT, rx_energy_bins, slow_time_fft
from .threads import run_parts, spans

__all__ = ["ddma_metric", "ddma_gather", "ddma_coherent_power", "ddma_spectra_power",
           "DDMA_RANGE_BLOCK"]


def ddma_gather(spec: np.ndarray, tx1_band: np.ndarray, tx_pos: np.ndarray,
                n_subbands: int) -> np.ndarray:
    """Demodulated DDMA samples of the transmitters at sub-band positions `tx_pos`, for every
    range and Doppler bin ([TI-DDMA] table 11): Tx p of Doppler bin d at range bin b sits at
    chirp-bin d + n_dop ((tx1_band[d, b] + p) mod N). The whole frame in one block of
    `ddma_coherent_power`'s gather (the chains gather per block inside it).

    Parameters
    ----------
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler spectra over all chirps.
    tx1_band : (n_dop, n_range) int
        Sub-band of the first Tx per Doppler bin of a sub-band and range bin.
    tx_pos : (P,) int
        Sub-band positions of the wanted transmitters (0 = the first Tx).
    n_subbands : int
        N (n_dop = n_chirps / N).

    Returns
    -------
    (P x n_rx, n_range x n_dop) complex64
        Row p n_rx + rx, column b n_dop + d.
    """
    n_c, n_rx, n_b = spec.shape
    out = np.empty((tx_pos.size * n_rx, n_b * (n_c // n_subbands)), np.complex64)
    _gather_block(spec, tx1_band, tx_pos.astype(np.int64), n_subbands, out, 0, n_b)
    return out


#: Range bins per block of `ddma_coherent_power`: the block's gathered samples (12 x 1024
#: complex64), its GEMM output (48 x 1024) and power (48 x 1024 float32), ~0.7 MB for an R79
#: frame, stay in a core's L2 (1 MB here), and the gather reads whole 64-byte lines of the
#: spectra (8 complex64 range bins). Measured on the R79 frame, process_frame alternating in
#: one process: 8 bins 0.2-0.36 ms CPU less than 4 (1 and 2 parts); 16 slower again.
DDMA_RANGE_BLOCK = 8


def ddma_coherent_power(spec: np.ndarray, energy: np.ndarray, tx_pos: np.ndarray,
                        n_subbands: int, n_tx: int, dft: np.ndarray,
                        range_block: int = DDMA_RANGE_BLOCK) -> tuple[np.ndarray, np.ndarray]:
    """Empty-band demodulation and the coherent azimuth power map of a DDMA frame, in blocks of
    range bins ([TI-DDMA] table 11 and section 5.4).

    Per block of `range_block` range bins: the Tx order of every (Doppler, range) cell (the
    argmax over j of `ddma_metric`, `_band_argmax`), the demodulated samples of the
    transmitters at sub-band positions `tx_pos` (`ddma_gather`), their product with `dft` and
    its power |.|^2 (re^2 + im^2 in float32, as `stages.power_of`). The block's samples, product
    and power stay in cache instead of three frame-sized passes through memory; blocks of range
    bins run in parts on the cores (`pipeline.threads`). A column block of a GEMM is the same
    arithmetic as the whole product with the BLAS at hand (checked once per process and
    layout, `_col_blocks_exact`; where it is not, one block), so the map is bit for bit
    ``power_of(dft @ ddma_gather(spec, argmax(ddma_metric(energy)), ...))``.

    Parameters
    ----------
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler spectra over all chirps, C-contiguous.
    energy : (n_chirps, n_range) float32
        `spec`'s energy summed over Rx (`rx_energy`).
    tx_pos : (P,) int
        Sub-band positions of the transmitters entering the map (0 = the first Tx).
    n_subbands, n_tx : int
        N sub-bands and the transmitters of the metric's cyclic sum.
    dft : (n_az, P x n_rx) complex64
        Azimuth DFT (channel coefficients folded in) applied to the rows p n_rx + rx.
    range_block : int
        Range bins per block.

    Returns
    -------
    power : (n_az, n_range x n_dop) float32
        Column b n_dop + d.
    tx1_band : (n_dop, n_range) intp
        Sub-band of the first Tx per Doppler bin of a sub-band and range bin.
    """
    return _coherent_power(spec, energy, tx_pos, n_subbands, n_tx, dft, range_block, False)


def ddma_spectra_power(xw: np.ndarray, tx_pos: np.ndarray, n_subbands: int, n_tx: int,
                       dft: np.ndarray, range_block: int = DDMA_RANGE_BLOCK
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Doppler FFT over the chirps of a windowed cube, its Rx energy and `ddma_coherent_power`,
    in one pass by spans of range bins on the cores.

    Each part transforms its range bins of `xw` in place (``scipy.fft.fft`` along the chirps,
    one worker), sums their energy over Rx (`kernels.rx_energy_bins`) and builds their part of
    the map (`ddma_coherent_power` reads only its own range bins' energy and spectra). Every
    range bin's transform is the same arithmetic in any batch of columns (pocketfft), so `spec`
    is bit for bit `kernels.slow_time_fft` (xw) and the rest `rx_energy` and
    `ddma_coherent_power` on it. Against the three passes one after the other (the FFT on
    pocketfft's own threads, the energy and the map each in parts) the frame waits twice less
    for the slower core and hands off to threads twice less: R79 DDMA frame, 2 cores, 40
    alternating rounds, 0.45 ms less wall time (faster in 82 % of rounds), 0.3 ms more CPU
    (the energy reads half rows). With one part (`pipeline.threads.inline`, one core) the FFT
    runs whole on all cores first, as `slow_time_fft`.

    Parameters
    ----------
    xw : (n_chirps, n_rx, n_range) complex64, C-contiguous
        Range spectra times the Doppler window; overwritten by the spectra.
    tx_pos, n_subbands, n_tx, dft, range_block
        As `ddma_coherent_power`.

    Returns
    -------
    spec : (n_chirps, n_rx, n_range) complex64
        `xw` itself, transformed: Doppler bins in natural order.
    energy : (n_chirps, n_range) float32
        `spec`'s energy summed over Rx.
    power, tx1_band
        As `ddma_coherent_power`.
    """
    energy = np.empty((xw.shape[0], xw.shape[2]), np.float32)
    power, tx1_band = _coherent_power(xw, energy, tx_pos, n_subbands, n_tx, dft, range_block,
                                      True)
    return xw, energy, power, tx1_band


def _coherent_power(spec, energy, tx_pos, n_subbands, n_tx, dft, range_block, transform):
    """`ddma_coherent_power`; with `transform`, `spec` is the windowed cube, transformed along
    the chirps in place and `energy` filled first, per part (`ddma_spectra_power`)."""
    n_c, n_rx, n_b = spec.shape
    n_dop = n_c // n_subbands
    n_az, n_rows = dft.shape[0], tx_pos.size * n_rx
    tx1_band = np.empty((n_dop, n_b), np.intp)
    power = np.empty((n_az, n_b * n_dop), np.float32)
    pos = tx_pos.astype(np.int64)
    blk = max(1, min(range_block, n_b))
    parts = spans(n_b, multiple=blk)
    bounds = tuple((b0 * n_dop, min(b0 + blk, hi) * n_dop)
                   for lo, hi in parts for b0 in range(lo, hi, blk))
    if not _col_blocks_exact(dft.shape, dft.strides, n_rows, bounds):
        blk, parts = n_b, [(0, n_b)]
    if transform and len(parts) == 1:  # nothing to overlap: the whole FFT on all cores
        slow_time_fft(spec)
        rx_energy_bins(spec, energy, 0, n_b)
        transform = False

    def part(lo: int, hi: int) -> None:
        if transform:
            # The part's spectra and energy in one call each: an FFT call per block of bins
            # costs more in calls than it saves in cache (R79, 8-32 bins: 0.9-2.2 ms CPU more).
            _doppler_fft_bins(spec, lo, hi)
            rx_energy_bins(spec, energy, lo, hi)
        _band_argmax(energy, n_subbands, n_tx, tx1_band, lo, hi)
        for b0 in range(lo, hi, blk):
            b1 = min(b0 + blk, hi)
            x = np.empty((n_rows, (b1 - b0) * n_dop), np.complex64)
            _gather_block(spec, tx1_band, pos, n_subbands, x, b0, b1)
            _power_into((dft @ x).view(np.float32), power, b0 * n_dop)

    run_parts([lambda lo=lo, hi=hi: part(lo, hi) for lo, hi in parts])
    return power, tx1_band


def _doppler_fft_bins(spec: np.ndarray, lo: int, hi: int) -> None:
    """`slow_time_fft` of range bins lo..hi-1 of `spec`, in place, on the calling thread."""
    view = spec[:, :, lo:hi]
    out = scipy.fft.fft(view, axis=0, workers=1, overwrite_x=True)
    if not np.may_share_memory(out, spec):  # a scipy that does not transform views in place
        view[...] = out


@lru_cache(maxsize=16)
def _col_blocks_exact(w_shape, w_strides, k: int, bounds: tuple) -> bool:
    """Whether the column blocks `bounds` ((lo, hi), ...) of a complex64 GEMM w @ x, w of this
    layout and x (k, n) C-contiguous, each computed from its own contiguous (k, hi - lo) copy,
    give the bits of the whole product (random operands)."""
    g = np.random.default_rng(0)
    n = bounds[-1][1]

    def cplx(shape):
        return (g.standard_normal(shape) + 1j * g.standard_normal(shape)).astype(np.complex64)

    w = cplx(w_shape[::-1]).T if w_strides[0] < w_strides[-1] else cplx(w_shape)
    x = cplx((k, n))
    whole = w @ x
    return all(np.array_equal(whole[:, lo:hi], w @ np.ascontiguousarray(x[:, lo:hi]))
               for lo, hi in bounds)


@numba.njit(cache=True, nogil=True)
def _band_argmax(energy, n_sb, n_tx, out, b0, b1):
    """out[d, b] = argmax over j of Z_j (`ddma_metric`: ((S_j + S_j+1) + S_j+2) + ..., float32,
    sub-band indices mod N), the first maximum (the first NaN, as numpy's argmax), for range
    bins b0..b1-1 (the inner, contiguous loop)."""
    n_dop = energy.shape[0] // n_sb
    nb = b1 - b0
    top = np.empty(nb, energy.dtype)
    z = np.empty(nb, energy.dtype)
    best = np.empty(nb, np.int64)
    for d in range(n_dop):
        for j in range(n_sb):
            row = energy[j * n_dop + d, b0:b1]
            for t in range(nb):
                z[t] = row[t]
            for m in range(1, n_tx):
                row = energy[((j + m) % n_sb) * n_dop + d, b0:b1]
                for t in range(nb):
                    z[t] = z[t] + row[t]
            if j == 0:
                for t in range(nb):
                    top[t] = z[t]
                    best[t] = 0
            else:
                for t in range(nb):
                    if top[t] == top[t] and (z[t] > top[t] or z[t] != z[t]):
                        top[t] = z[t]
                        best[t] = j
        for t in range(nb):
            out[d, b0 + t] = best[t]


@numba.njit(cache=True, nogil=True)
def _gather_block(spec, tx1_band, tx_pos, n_sb, out, b0, b1):
    """`ddma_gather` of range bins b0..b1-1 into out (P x n_rx, (b1 - b0) x n_dop): Doppler bins
    outer, range bins inner (reads run along range, writes stay in the block)."""
    n_rx = spec.shape[1]
    n_dop = tx1_band.shape[0]
    for d in range(n_dop):
        for b in range(b0, b1):
            band = tx1_band[d, b]
            col = (b - b0) * n_dop + d
            for i in range(tx_pos.size):
                c = ((band + tx_pos[i]) % n_sb) * n_dop + d
                for rx in range(n_rx):
                    out[i * n_rx + rx, col] = spec[c, rx, b]


@numba.njit(cache=True, nogil=True)
def _power_into(yv, out, col0):
    """out[:, col0 + j] = yv[:, 2j]^2 + yv[:, 2j + 1]^2: |y|^2 of a complex64 product seen as
    float32 (re, im) pairs, as `stages.power_of` (two rounded squares, a rounded sum)."""
    m, n2 = yv.shape
    n, c0, one, two = UINT(n2 // 2), UINT(col0), UINT(1), UINT(2)
    for i in range(m):
        row = yv[i]
        dst = out[i]
        for j in range(n):  # unsigned: numba would wrap a negative signed index around,
            re = row[two * j]  # which keeps LLVM from vectorising the loop (3x slower)
            im = row[two * j + one]
            dst[c0 + j] = re * re + im * im


def ddma_metric(power: np.ndarray, n_subbands: int, n_tx: int) -> np.ndarray:
    """Empty-band DDMA metric Z_j = sum_{m < n_tx} S_{(j+m) mod N} ([TI-DDMA] table 11).

    Parameters
    ----------
    power : (n_chirps, ...) float
        Energy per Doppler bin (summed over Rx), Doppler first, bins in natural order.

    Returns
    -------
    (n_subbands, n_chirps // n_subbands, ...) float
        Z_j for every Doppler bin d of a sub-band.
    """
    s = power.reshape(n_subbands, -1, *power.shape[1:])
    ext = np.concatenate([s, s[: n_tx - 1]], axis=0)  # cyclic extension over sub-bands
    z = ext[:n_subbands].copy()
    for m in range(1, n_tx):  # n_tx - 1 <= 3 shifted adds, not a loop over bins
        z += ext[m: m + n_subbands]
    return z
