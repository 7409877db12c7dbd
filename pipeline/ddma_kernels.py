"""Kernels of the empty-band DDMA demodulation ([TI-DDMA] table 11) and its coherent azimuth
map: the Tx-order metric, the demodulation gather and the zero-padded azimuth DFT with its
power map.

The map of the R79 row (12 virtual channels at lambda/2 positions 0..11, 48 azimuth bins) is a
pruned 48-point FFT computed straight from the spectra in one compiled pass (`_fft_map`: gather,
transform and |.|^2 per block of range bins in cache); any other row or bin count is the
zero-padded DFT as one complex GEMM. Compiled loops over columns compute every column alone, so
the outputs are the same bits whatever the split into parts.

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA]: section 5, tables 11, 14.
.. [2] I. J. Good, "The interaction algorithm and practical Fourier analysis" (1958), and
       L. H. Thomas (1963) [Good-Thomas]: the prime-factor index maps of the 12-point DFT.
"""
from __future__ import annotations

from functools import partial
from typing import NamedTuple

import numba
import numpy as np
import scipy.fft

from .kernels import UINT, rx_energy_bins, slow_time_fft
from .stages import power_of
from .threads import run_parts, spans

__all__ = ["AzimuthMap", "azimuth_map", "FFT_MAP_BINS", "FFT_MAP_POSITIONS", "ddma_metric",
           "ddma_gather", "ddma_coherent_power", "ddma_spectra_power", "fft48_power"]

#: Azimuth bins and row length (lambda/2 positions) of the map computed as a pruned FFT.
FFT_MAP_BINS = 48
FFT_MAP_POSITIONS = 12
#: Range bins per block of `_fft_map`: the block's samples (12 x 1024 complex) and a 64-byte
#: line of the spectra (8 complex64 range bins) per read stay in cache.
RANGE_BLOCK = 8


class AzimuthMap(NamedTuple):
    """What the demodulation and the azimuth map of a DDMA configuration need (`azimuth_map`).

    Attributes
    ----------
    n_subbands, n_tx : int
        N sub-bands and the transmitters of the metric's cyclic sum.
    tx_pos : (P,) int64
        Sub-band positions of the transmitters entering the map (0 = the first Tx).
    dft : (n_az, P x n_rx) complex64
        The map as a matrix: zero-padded azimuth DFT (channel coefficients folded in) applied to
        the demodulated rows p n_rx + rx.
    slot : (P x n_rx,) int64
        Horizontal position (lambda/2) of each row when the map is the pruned 48-point FFT
        (`fft48_power`), empty otherwise.
    coef : (P x n_rx,) complex64
        Channel coefficient of each row (1 without compensation).
    """

    n_subbands: int
    n_tx: int
    tx_pos: np.ndarray
    dft: np.ndarray
    slot: np.ndarray
    coef: np.ndarray


def azimuth_map(n_subbands: int, n_tx: int, tx_pos: np.ndarray, positions: np.ndarray,
                coef: np.ndarray | None, n_az: int) -> AzimuthMap:
    """The `AzimuthMap` of a row: demodulated rows p n_rx + rx (p in `tx_pos`) at horizontal
    positions `positions` (lambda/2; -1: a channel off the row, weight 0), times `coef`
    (None: 1), `n_az`-point zero-padded DFT e^{-2j pi pos k / n_az} (complex64, then times
    the coefficient, as `compensation.apply_coefficients` on `stages.array_dft`). The pruned
    FFT serves it when ``n_az == FFT_MAP_BINS`` and the positions are distinct, in
    0..FFT_MAP_POSITIONS - 1."""
    positions = np.asarray(positions, np.int64)
    coef = np.ones(positions.size, np.complex64) if coef is None else \
        np.asarray(coef, np.complex64)
    fft = (n_az == FFT_MAP_BINS and np.unique(positions).size == positions.size
           and positions.min() >= 0 and positions.max() < FFT_MAP_POSITIONS)
    steer = np.exp(-2j * np.pi * np.outer(np.arange(n_az), positions) / n_az)
    dft = np.where(positions >= 0, steer, 0).astype(np.complex64) * coef
    plan = AzimuthMap(n_subbands, n_tx, np.asarray(tx_pos, np.int64), dft,
                      positions if fft else np.empty(0, np.int64), coef)
    for a in plan[2:]:
        a.flags.writeable = False
    return plan


def ddma_gather(spec: np.ndarray, tx1_band: np.ndarray, tx_pos: np.ndarray,
                n_subbands: int) -> np.ndarray:
    """Demodulated DDMA samples of the transmitters at sub-band positions `tx_pos`, for every
    range and Doppler bin ([TI-DDMA] table 11): Tx p of Doppler bin d at range bin b sits at
    chirp-bin d + n_dop ((tx1_band[d, b] + p) mod N).

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
    n_dop = n_c // n_subbands
    out = np.empty((tx_pos.size * n_rx, n_b * n_dop), np.complex64)
    _gather_block(spec, tx1_band, tx_pos.astype(np.int64), n_subbands, out, 0, n_b)
    return out


def ddma_coherent_power(spec: np.ndarray, energy: np.ndarray, plan: AzimuthMap
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Empty-band demodulation and the coherent azimuth power map of a DDMA frame ([TI-DDMA]
    table 11 and section 5.4).

    The Tx order of every (Doppler, range) cell (the argmax over j of `ddma_metric`,
    `_band_argmax`), the demodulated samples of the transmitters at sub-band positions
    ``plan.tx_pos`` (`ddma_gather`) and the power |.|^2 of their azimuth map: the pruned FFT
    (`fft48_power`, per block of range bins, range bins in parts on the cores) where
    ``plan.slot`` is set, else ``power_of(plan.dft @ ddma_gather(...))`` (one GEMM).

    Parameters
    ----------
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler spectra over all chirps, C-contiguous.
    energy : (n_chirps, n_range) float32
        `spec`'s energy summed over Rx (`rx_energy`).
    plan : AzimuthMap

    Returns
    -------
    power : (n_az, n_range x n_dop) float32
        Column b n_dop + d.
    tx1_band : (n_dop, n_range) intp
        Sub-band of the first Tx per Doppler bin of a sub-band and range bin.
    """
    return _coherent_power(spec, energy, plan, False)


def ddma_spectra_power(xw: np.ndarray, plan: AzimuthMap
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Doppler FFT over the chirps of a windowed cube, its Rx energy and `ddma_coherent_power`,
    in one pass by spans of range bins on the cores.

    Each part transforms its range bins of `xw` in place (``scipy.fft.fft`` along the chirps,
    one worker), sums their energy over Rx (`kernels.rx_energy_bins`) and builds their part of
    the map (`ddma_coherent_power` reads only its own range bins' energy and spectra). Every
    range bin's transform is the same arithmetic in any batch of columns (pocketfft), so `spec`
    is bit for bit `kernels.slow_time_fft` (xw) and the rest `rx_energy` and
    `ddma_coherent_power` on it. Against the three passes one after the other the frame waits
    twice less for the slower core and hands off to threads twice less (R79 DDMA frame, 2
    cores: 0.45 ms less wall time). With one part (`pipeline.threads.inline`, one core) the FFT
    runs whole on all cores first, as `slow_time_fft`.

    Parameters
    ----------
    xw : (n_chirps, n_rx, n_range) complex64, C-contiguous
        Range spectra times the Doppler window; overwritten by the spectra.
    plan : AzimuthMap

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
    power, tx1_band = _coherent_power(xw, energy, plan, True)
    return xw, energy, power, tx1_band


def _coherent_power(spec, energy, plan, transform):
    """`ddma_coherent_power`; with `transform`, `spec` is the windowed cube, transformed along
    the chirps in place and `energy` filled first, per part (`ddma_spectra_power`)."""
    n_c, n_rx, n_b = spec.shape
    n_dop = n_c // plan.n_subbands
    tx1_band = np.empty((n_dop, n_b), np.intp)
    power = np.empty((plan.dft.shape[0], n_b * n_dop), np.float32)
    fft = plan.slot.size > 0
    parts = spans(n_b, multiple=RANGE_BLOCK)
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
        _band_argmax(energy, plan.n_subbands, plan.n_tx, tx1_band, lo, hi)
        if fft:
            _fft_map(spec, tx1_band, plan.tx_pos, plan.n_subbands, plan.slot, plan.coef, power,
                     lo, hi)

    run_parts([partial(part, lo, hi) for lo, hi in parts])
    if not fft:
        power = power_of(plan.dft @ ddma_gather(spec, tx1_band, plan.tx_pos, plan.n_subbands))
    return power, tx1_band


def _doppler_fft_bins(spec: np.ndarray, lo: int, hi: int) -> None:
    """`slow_time_fft` of range bins lo..hi-1 of `spec`, in place, on the calling thread."""
    view = spec[:, :, lo:hi]
    out = scipy.fft.fft(view, axis=0, workers=1, overwrite_x=True)
    if not np.may_share_memory(out, spec):  # a scipy that does not transform views in place
        view[...] = out


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


#: Twiddle factors W_48^m = e^{-2j pi m / 48} of the pruned FFT (float64 rounded to complex64).
_W48 = np.exp(-2j * np.pi * np.arange(48) / 48).astype(np.complex64)
_HALF = np.float32(0.5)
_SIN60 = np.float32(np.sqrt(3.0) / 2)  # -Im W_3
#: Good-Thomas maps of the 12-point DFT, 12 = 3 x 4 (coprime factors, so no twiddles between
#: the stages): sample (4 n1 + 3 n2) mod 12 is entry (n1, n2) of the 3 x 4 input array...
_PFA_IN = np.array([[(4 * n1 + 3 * n2) % 12 for n2 in range(4)] for n1 in range(3)], np.int64)
#: ... and output (k1, k2) is bin (4 k1 + 9 k2) mod 12, the one congruent to k1 mod 3 and to
#: k2 mod 4 (Chinese remainder theorem).
_PFA_OUT = np.array([[(4 * k1 + 9 * k2) % 12 for k2 in range(4)] for k1 in range(3)], np.int64)


def fft48_power(z: np.ndarray) -> np.ndarray:
    """|X_k|^2 of the 48-point DFT of each column of `z` zero-padded from 12 samples,
    X_k = sum_{n < 12} z_n e^{-2j pi n k / 48}, by the pruned transform of `_fft48_power`
    ([Good-Thomas]; float32).

    Parameters
    ----------
    z : (12, n) complex

    Returns
    -------
    (48, n) float32
    """
    n = z.shape[1]
    zr = np.ascontiguousarray(z.real, np.float32)
    zi = np.ascontiguousarray(z.imag, np.float32)
    out = np.empty((FFT_MAP_BINS, n), np.float32)
    _fft48_power(zr, zi, n, out, 0, np.empty((2, 3, 4, n), np.float32))
    return out


@numba.njit(cache=True, nogil=True)
def _fft48_power(zr, zi, n, out, col0, u):
    """out[k, col0 + c] = |X_k|^2 of column c < n of the 12 samples (zr + j zi) (12, >= n);
    u (2, 3, 4, >= n) float32 is scratch.

    The bins k = 4 q + r (r < 4, q < 12) of the zero-padded transform are four 12-point DFTs
    of twiddled samples: X_{4q+r} = sum_{n < 12} (z_n W48^{nr}) W12^{nq}. Each 12-point DFT is
    a Good-Thomas prime-factor transform (`_PFA_IN`, `_PFA_OUT`): 4-point DFTs along n2 (sums
    only, `_twiddled_dft4`, which also applies the twiddles), then 3-point DFTs along n1 and
    |.|^2 (`_dft3_power`). Per column: 48 complex twiddle products (33 not by 1; the loops
    do not special-case r = 0) and 16 three-point butterflies, under half the arithmetic of a
    radix-3 decimation in time over 16-point sub-transforms, and every pass reads its inputs
    once, in loops over the columns that LLVM vectorises (unsigned indices). R79 map (24 576
    columns): 1.5 -> 0.7 ms CPU, best of 60 alternated."""
    ur, ui = u[0], u[1]
    for r in range(4):
        for n1 in range(3):
            _twiddled_dft4(zr, zi, _PFA_IN[n1], r, ur[n1], ui[n1], n)
        for k2 in range(4):
            # rows passed one by one: a (3, n) column slice of u would reach the loop as a
            # strided array, which LLVM does not vectorise
            _dft3_power(ur[0, k2], ui[0, k2], ur[1, k2], ui[1, k2], ur[2, k2], ui[2, k2],
                        out[4 * _PFA_OUT[0, k2] + r, col0:col0 + n],
                        out[4 * _PFA_OUT[1, k2] + r, col0:col0 + n],
                        out[4 * _PFA_OUT[2, k2] + r, col0:col0 + n], n)


@numba.njit(cache=True, nogil=True)
def _twiddled_dft4(zr, zi, idx, r, ur, ui, n):
    """(ur + j ui)[k2, c] = sum_{n2 < 4} y_{n2} (-j)^{n2 k2}, y_{n2} = z_{idx[n2]} W48^{idx[n2] r},
    for columns c < n: a 4-point DFT, its products by -j as swaps."""
    w0, w1 = _W48[idx[0] * r % 48], _W48[idx[1] * r % 48]
    w2, w3 = _W48[idx[2] * r % 48], _W48[idx[3] * r % 48]
    x0r, x0i, x1r, x1i = zr[idx[0]], zi[idx[0]], zr[idx[1]], zi[idx[1]]
    x2r, x2i, x3r, x3i = zr[idx[2]], zi[idx[2]], zr[idx[3]], zi[idx[3]]
    u0r, u0i, u1r, u1i, u2r, u2i, u3r, u3i = ur[0], ui[0], ur[1], ui[1], ur[2], ui[2], ur[3], ui[3]
    for c in range(UINT(n)):
        y0r, y0i = x0r[c] * w0.real - x0i[c] * w0.imag, x0r[c] * w0.imag + x0i[c] * w0.real
        y1r, y1i = x1r[c] * w1.real - x1i[c] * w1.imag, x1r[c] * w1.imag + x1i[c] * w1.real
        y2r, y2i = x2r[c] * w2.real - x2i[c] * w2.imag, x2r[c] * w2.imag + x2i[c] * w2.real
        y3r, y3i = x3r[c] * w3.real - x3i[c] * w3.imag, x3r[c] * w3.imag + x3i[c] * w3.real
        s02r, s02i, d02r, d02i = y0r + y2r, y0i + y2i, y0r - y2r, y0i - y2i
        s13r, s13i, d13r, d13i = y1r + y3r, y1i + y3i, y1r - y3r, y1i - y3i
        u0r[c], u0i[c] = s02r + s13r, s02i + s13i
        u1r[c], u1i[c] = d02r + d13i, d02i - d13r
        u2r[c], u2i[c] = s02r - s13r, s02i - s13i
        u3r[c], u3i[c] = d02r - d13i, d02i + d13r


@numba.njit(cache=True, nogil=True)
def _dft3_power(ar, ai, br, bi, cr, ci, o0, o1, o2, n):
    """o_k1[c] = |a_c + b_c W3^k1 + c_c W3^{2 k1}|^2 for columns c < n (a = ar + j ai, ...): a
    3-point DFT (W3 = -1/2 - j sin 60 deg) and its power."""
    for c in range(UINT(n)):
        sr, si, dr, di = br[c] + cr[c], bi[c] + ci[c], br[c] - cr[c], bi[c] - ci[c]
        mr, mi = ar[c] - _HALF * sr, ai[c] - _HALF * si
        p0r, p0i = ar[c] + sr, ai[c] + si
        p1r, p1i = mr + _SIN60 * di, mi - _SIN60 * dr
        p2r, p2i = mr - _SIN60 * di, mi + _SIN60 * dr
        o0[c] = p0r * p0r + p0i * p0i
        o1[c] = p1r * p1r + p1i * p1i
        o2[c] = p2r * p2r + p2i * p2i


@numba.njit(cache=True, nogil=True)
def _fft_map(spec, tx1_band, tx_pos, n_sb, slot, coef, out, b0, b1):
    """The map of range bins b0..b1-1 (`ddma_coherent_power` with ``plan.slot`` set): per
    block of `RANGE_BLOCK` bins, the demodulated samples (`_gather_block`), times their channel
    coefficients, into the 12 positions `slot` of the row as float32 (re, im) rows (in cache),
    then `_fft48_power` into out's columns b n_dop + d."""
    n_rows = tx_pos.size * spec.shape[1]
    n_dop = tx1_band.shape[0]
    x = np.empty((n_rows, RANGE_BLOCK * n_dop), np.complex64)
    zr = np.zeros((FFT_MAP_POSITIONS, RANGE_BLOCK * n_dop), np.float32)
    zi = np.zeros((FFT_MAP_POSITIONS, RANGE_BLOCK * n_dop), np.float32)
    u = np.empty((2, 3, 4, RANGE_BLOCK * n_dop), np.float32)
    for lo in range(b0, b1, RANGE_BLOCK):
        hi = min(lo + RANGE_BLOCK, b1)
        n = (hi - lo) * n_dop
        _gather_block(spec, tx1_band, tx_pos, n_sb, x, lo, hi)
        for row in range(n_rows):
            src, c, re, im = x[row], coef[row], zr[slot[row]], zi[slot[row]]
            for j in range(UINT(n)):
                v = src[j] * c
                re[j] = v.real
                im[j] = v.imag
        _fft48_power(zr, zi, n, out, lo * n_dop, u)
