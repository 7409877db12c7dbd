"""Kernels of the signal chain: FFT stages, DDMA demodulation, peak interpolation, local
maxima, candidate CFAR and angle estimation. Axis order: chirp/Doppler first, then Rx, then
fast time / range (DESIGN 3), unless a docstring says otherwise.

Mostly numpy; a pass that numpy can only express through full-size temporaries or index arrays
(the Rx energy, the DDMA demodulation gather) is a numba kernel (``cache=True``, compiled once
per machine) that repeats numpy's float32 operations in numpy's order, so outputs are
bit-identical to the numpy formulation it replaced.

References
----------
.. [1] TI, AWR2944 DDMA application note (seed 000): section 5, tables 11, 14, 15, figure 19.
.. [2] TI, AWR1642 TDM-MIMO velocity disambiguation (seed 001): eq. 8-12, section 4.
"""
from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numba
import numpy as np
import scipy.fft
from scipy.signal import get_window

from .cfar import CFAR_MODES, noise_estimate, training_offsets
from .threads import run_parts, spans

__all__ = ["window", "range_fft", "doppler_fft", "rx_energy", "gemm_power", "ddma_metric",
           "ddma_gather", "ddma_coherent_power",
           "ArrayLayout",
           "array_layout", "layout_of", "local_max_mask", "parabolic_offset", "candidate_cfar",
           "cfar_peaks",
           "training_table",
           "estimate_angles"]


@lru_cache(maxsize=32)
def window(name: str, n: int) -> np.ndarray:
    """(n,) float32 periodic (DFT-even) window by scipy name; cached per (name, n) and
    read-only (scipy builds it anew in 0.15 ms, several times per frame)."""
    w = get_window(name, n, fftbins=True).astype(np.float32)
    w.flags.writeable = False
    return w


def range_fft(adc: np.ndarray, win: np.ndarray) -> np.ndarray:
    """Windowed range FFT of each chirp and Rx.

    Real samples: real FFT, keeping the n_samples / 2 positive bins (the others mirror them).
    Complex (I/Q) samples: complex FFT, keeping all n_samples bins, bin k at beat frequency
    k f_s / N (the image band is rejected on the chip, so there is no mirror).

    Parameters
    ----------
    adc : (n_chirps, n_rx, n_samples) int16 (real) or complex64 (I/Q)
    win : (n_samples,) float32

    Returns
    -------
    (n_chirps, n_rx, n_samples // 2) or (n_chirps, n_rx, n_samples) complex64
    """
    if np.iscomplexobj(adc):
        x = windowed(adc, win, np.complex64)
        return scipy.fft.fft(x, axis=-1, workers=-1, overwrite_x=True)
    x = windowed(adc, win, np.float32)  # int16 -> float32 and window in one pass
    return scipy.fft.rfft(x, axis=-1, workers=-1)[..., : adc.shape[-1] // 2]


def windowed(x: np.ndarray, win: np.ndarray, dtype) -> np.ndarray:
    """``np.multiply(x, win, dtype=dtype)`` (win broadcast against x), in blocks of axis 0 on
    the cores (`pipeline.threads`): the same products."""
    out = np.empty(np.broadcast_shapes(x.shape, win.shape), dtype)
    per_row = win.ndim == x.ndim and win.shape[0] > 1

    def block(lo: int, hi: int) -> None:
        np.multiply(x[lo:hi], win[lo:hi] if per_row else win, out=out[lo:hi], dtype=dtype)

    run_parts([lambda lo=lo, hi=hi: block(lo, hi) for lo, hi in spans(out.shape[0])])
    return out


def doppler_fft(x: np.ndarray, win: np.ndarray, axis: int = 0) -> np.ndarray:
    """Windowed complex FFT over slow time along `axis` (in natural bin order 0..N-1), into the
    windowed copy (pocketfft gathers strided columns itself: the same transforms, bit for bit,
    as over a transposed contiguous copy)."""
    if axis == 0 and x.dtype == np.complex64 and win.dtype == np.float32 and x.ndim >= 2:
        xw = _doppler_windowed(x, win)
    else:
        shape = [1] * x.ndim
        shape[axis] = -1
        w = win.reshape(shape)
        xw = windowed(x, w, np.result_type(x.dtype, w.dtype))
    return scipy.fft.fft(xw, axis=axis, workers=-1, overwrite_x=True)


def _doppler_windowed(x: np.ndarray, win: np.ndarray) -> np.ndarray:
    """``np.multiply(x, win[:, None, ...])`` of a complex64 cube and a float32 window along axis
    0, bit for bit: numpy casts the window to complex64 and multiplies complex numbers,
    (re w - im 0, re 0 + im w) (which keeps NaN, inf and signed zeros as they come out of that
    product); the compiled loop does the same arithmetic in about half numpy's time (no casting
    buffer). Chirps in parts on the cores (`pipeline.threads`)."""
    out = np.empty(x.shape, np.complex64)
    x3 = x.reshape(x.shape[0], -1, x.shape[-1])
    o3 = out.reshape(x3.shape)
    run_parts([lambda lo=lo, hi=hi: _complex_times_real(x3, win, o3, lo, hi)
               for lo, hi in spans(x.shape[0])])
    return out


@numba.njit(cache=True, nogil=True)
def _complex_times_real(x, w, out, lo, hi):
    """out[c] = x[c] * complex(w[c], 0) as numpy's complex64 multiply computes it, c in lo..hi-1."""
    n1, n2 = x.shape[1], x.shape[2]
    zero = np.float32(0.0)
    for c in range(lo, hi):
        wr = w[c]
        for r in range(n1):
            for b in range(n2):
                v = x[c, r, b]
                out[c, r, b] = complex(v.real * wr - v.imag * zero, v.real * zero + v.imag * wr)


def rx_energy(spec: np.ndarray) -> np.ndarray:
    """Energy summed over Rx, |x|^2 = re^2 + im^2 in float32, Rx added in order.

    Parameters
    ----------
    spec : (n_chirps, n_rx, n_range) complex64, C-contiguous

    Returns
    -------
    (n_chirps, n_range) float32
        Bit for bit ``stages.power_of(spec).sum(axis=1)``, without its full-size temporary.
    """
    out = np.empty((spec.shape[0], spec.shape[2]), np.float32)
    v = spec.view(np.float32)
    run_parts([lambda lo=lo, hi=hi: _rx_energy(v[lo:hi], out[lo:hi])
               for lo, hi in spans(spec.shape[0])])  # chirps in parts on the cores
    return out


@numba.njit(cache=True, nogil=True)
def _rx_energy(v: np.ndarray, out: np.ndarray) -> None:
    """out[c, b] = sum over r (in order) of v[c, r, 2b]^2 + v[c, r, 2b + 1]^2, float32."""
    n_c, n_r, _ = v.shape
    n_b = out.shape[1]
    for c in range(n_c):
        for b in range(n_b):
            re = v[c, 0, 2 * b]
            im = v[c, 0, 2 * b + 1]
            out[c, b] = re * re + im * im
        for r in range(1, n_r):
            for b in range(n_b):
                re = v[c, r, 2 * b]
                im = v[c, r, 2 * b + 1]
                out[c, b] += re * re + im * im


def ddma_gather(spec: np.ndarray, tx1_band: np.ndarray, tx_pos: np.ndarray,
                n_subbands: int, out: np.ndarray | None = None,
                range_span: tuple[int, int] | None = None) -> np.ndarray:
    """Demodulated DDMA samples of the transmitters at sub-band positions `tx_pos`, for every
    range and Doppler bin (seed 000 table 11): Tx p of Doppler bin d at range bin b sits at
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

    out : (P x n_rx, n_range x n_dop) complex64, optional
        Written and returned (default: a new array).
    range_span : (lo, hi), optional
        Only the columns of range bins lo <= b < hi (tx1_band read there only).

    Returns
    -------
    (P x n_rx, n_range x n_dop) complex64
        Row p n_rx + rx, column b n_dop + d (one flat gather, no index arrays).
    """
    n_c, n_rx, n_b = spec.shape
    n_dop = n_c // n_subbands
    if out is None:
        out = np.empty((tx_pos.size * n_rx, n_b * n_dop), np.complex64)
    lo, hi = (0, n_b) if range_span is None else range_span
    _ddma_gather(spec, tx1_band, tx_pos.astype(np.int64), n_subbands, out, lo, hi)
    return out


@numba.njit(cache=True, nogil=True)
def _ddma_gather(spec, tx1_band, tx_pos, n_sb, out, b0, b1):
    """`ddma_gather`'s loop: Doppler bins outer, range bins b0..b1-1 inner (reads run along
    range)."""
    n_rx = spec.shape[1]
    n_dop = tx1_band.shape[0]
    for d in range(n_dop):
        for b in range(b0, b1):
            band = tx1_band[d, b]
            for i in range(tx_pos.size):
                c = ((band + tx_pos[i]) % n_sb) * n_dop + d
                for rx in range(n_rx):
                    out[i * n_rx + rx, b * n_dop + d] = spec[c, rx, b]


def gemm_power(w: np.ndarray, x: np.ndarray) -> np.ndarray:
    """|w @ x|^2 as float32 (re^2 + im^2, as `stages.power_of`), the product and the square
    computed per block of rows of `w` on the cores (`pipeline.threads`).

    A row block of a GEMM is the same arithmetic as the whole one with the BLAS at hand (checked
    once per process and operand layout, `_row_blocks_exact`; where it is not, one block), so
    the map is the same bits either way.

    Parameters
    ----------
    w : (m, k) complex64
    x : (k, n) complex64

    Returns
    -------
    (m, n) float32
    """
    m = w.shape[0]
    out = np.empty((m, x.shape[1]), np.float32)
    blocks = spans(m, multiple=_ROW_MULTIPLE)
    if len(blocks) > 1 and not _row_blocks_exact(w.shape, w.strides, x.shape, x.strides,
                                                 blocks[0][1]):
        blocks = [(0, m)]

    def block(lo: int, hi: int) -> None:
        y = (w[lo:hi] @ x).view(np.float32)
        np.square(y, out=y)
        np.add(y[:, 0::2], y[:, 1::2], out=out[lo:hi])

    run_parts([lambda lo=lo, hi=hi: block(lo, hi) for lo, hi in blocks])
    return out


_ROW_MULTIPLE = 8  # row blocks start at multiples of the usual GEMM kernel widths


@lru_cache(maxsize=16)
def _row_blocks_exact(w_shape, w_strides, x_shape, x_strides, cut: int) -> bool:
    """Whether rows [0, cut) and [cut, m) of a complex64 GEMM of this layout give the bits of the
    whole product (random operands with the same shapes and strides)."""
    g = np.random.default_rng(0)

    def operand(shape, strides):
        base = np.empty(shape[::-1] if strides[0] < strides[-1] else shape, np.complex64)
        base.real, base.imag = g.standard_normal(base.shape), g.standard_normal(base.shape)
        return base.T if strides[0] < strides[-1] else base

    w, x = operand(w_shape, w_strides), operand(x_shape, x_strides)
    whole = w @ x
    return bool(np.array_equal(whole[:cut], w[:cut] @ x)
                and np.array_equal(whole[cut:], w[cut:] @ x))


#: Range bins per block of `ddma_coherent_power`: the block's gathered samples (12 x 512
#: complex64), its GEMM output (48 x 512) and power (48 x 512 float32) stay in a core's L2.
DDMA_RANGE_BLOCK = 4


def ddma_coherent_power(spec: np.ndarray, energy: np.ndarray, tx_pos: np.ndarray,
                        n_subbands: int, n_tx: int, dft: np.ndarray,
                        range_block: int = DDMA_RANGE_BLOCK) -> tuple[np.ndarray, np.ndarray]:
    """Empty-band demodulation and the coherent azimuth power map of a DDMA frame, in blocks of
    range bins (seed 000 table 11 and section 5.4).

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

    def part(lo: int, hi: int) -> None:
        _band_argmax(energy, n_subbands, n_tx, tx1_band, lo, hi)
        for b0 in range(lo, hi, blk):
            b1 = min(b0 + blk, hi)
            x = np.empty((n_rows, (b1 - b0) * n_dop), np.complex64)
            _gather_block(spec, tx1_band, pos, n_subbands, x, b0, b1)
            y = (dft @ x).view(np.float32)
            np.square(y, out=y)
            np.add(y[:, 0::2], y[:, 1::2], out=power[:, b0 * n_dop: b1 * n_dop])

    run_parts([lambda lo=lo, hi=hi: part(lo, hi) for lo, hi in parts])
    return power, tx1_band


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


def ddma_metric(power: np.ndarray, n_subbands: int, n_tx: int) -> np.ndarray:
    """Empty-band DDMA metric Z_j = sum_{m < n_tx} S_{(j+m) mod N} (seed 000 table 11).

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


class ArrayLayout(NamedTuple):
    """Rows of a virtual array (`array_layout`)."""

    h_idx: np.ndarray       # (n_h,) int: one virtual element per horizontal position, z = 0
    h_pos: np.ndarray       # (n_h,) int: their positions, lambda/2 units
    v_idx: np.ndarray       # (n_v,) int: elements of the raised row
    v_pos: np.ndarray       # (n_v,) int: their horizontal positions, lambda/2 units
    # height of the raised row, wavelengths (0 if none); (n_v,) float per element when the
    # raised elements lie on several rows (antenna-on-package grids)
    v_height_wl: float | np.ndarray


def array_layout(virtual_positions_m: np.ndarray, wavelength_m: float) -> ArrayLayout:
    """Horizontal and vertical sub-arrays of the virtual array, in lambda/2 units.

    Parameters
    ----------
    virtual_positions_m : (n_virtual, 3) float
        Virtual element positions in the demodulated order.

    Returns
    -------
    ArrayLayout, with
    h_idx : (n_h,) int
        Virtual elements on the z = 0 row, one per horizontal position, sorted by position.
    h_pos : (n_h,) int
        Their positions in lambda/2 (0, 1, ...).
    v_idx, v_pos : (n_v,) int
        Elements of the raised row and their horizontal positions.
    v_height_wl : float or (n_v,) float
        Height of the raised row in wavelengths (0 if none); per element when the elements
        off the z = 0 row lie on several rows (the IWR6843AOP's 4 x 4 grid), which
        `estimate_angles` then combines.
    """
    y = np.rint(virtual_positions_m[:, 1] / (wavelength_m / 2)).astype(int)
    z = virtual_positions_m[:, 2] / wavelength_m
    low = np.isclose(z, 0.0)
    h_pos, first = np.unique(y[low], return_index=True)
    h_idx = np.flatnonzero(low)[first]
    v_idx = np.flatnonzero(~low)
    v_height = float(z[v_idx[0]]) if v_idx.size else 0.0
    if v_idx.size and not np.allclose(z[v_idx], v_height):
        v_height = z[v_idx]
    return ArrayLayout(h_idx, h_pos, v_idx, y[v_idx], v_height)


@lru_cache(maxsize=32)
def layout_of(cfg) -> ArrayLayout:
    """`array_layout` of a `radarsim.RadarConfig`'s virtual array, computed once per
    configuration (~0.1 ms a call, several calls per frame); its arrays are read-only."""
    layout = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    for a in layout:
        if isinstance(a, np.ndarray):
            a.flags.writeable = False
    return layout


def _multi_row_sin_el(virt: np.ndarray, wx: np.ndarray, h_idx: np.ndarray, h_pos: np.ndarray,
                      v_idx: np.ndarray, v_pos: np.ndarray, heights: np.ndarray) -> np.ndarray:
    """sin(el) from several raised rows (heights h_k, wavelengths): each row's beam phase
    against the z = 0 row's, wz_k = 2 pi h_k sin(el), unwrapped from the nearest row outwards
    (a row within lambda/2 is unambiguous) and combined by least squares with weights
    |A_k|^2. A loop over the few rows, vectorised over detections. (n,) float."""
    a_h = np.einsum("nm,nm->n", virt[:, h_idx], np.exp(-1j * wx[:, None] * h_pos[None, :]))
    rows = np.unique(np.round(heights, 6))
    num = np.zeros(wx.shape)
    den = np.zeros(wx.shape)
    s = None
    for h in rows[np.argsort(np.abs(rows), kind="stable")]:
        m = np.isclose(heights, h)
        a_v = np.einsum("nm,nm->n", virt[:, v_idx[m]],
                        np.exp(-1j * wx[:, None] * v_pos[m][None, :]))
        wz = np.angle(a_v * np.conj(a_h))
        if s is not None:
            wz = wz + 2 * np.pi * np.round((2 * np.pi * h * s - wz) / (2 * np.pi))
        w = np.abs(a_v) ** 2
        num += w * h * wz
        den += w * h * h
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.where(den > 0, num / (2 * np.pi * den), 0.0)
    return np.clip(s, -1.0, 1.0)


def local_max_mask(power: np.ndarray, axes_cyclic: dict[int, bool],
                   mask: np.ndarray | None = None) -> np.ndarray:
    """Cells greater than their two neighbours along each listed axis (ties: see below).

    Parameters
    ----------
    power : (...) float
    axes_cyclic : {axis: cyclic}
        Axes to compare along; on a non-cyclic axis an edge cell is compared with its one
        neighbour only.
    mask : (...) bool, optional
        Prior mask to AND into (modified in place and returned).

    Returns
    -------
    (...) bool
    """
    mask = np.ones(power.shape, dtype=bool) if mask is None else mask
    for axis, cyclic in axes_cyclic.items():
        p = np.moveaxis(power, axis, -1)  # views: no copies of the map
        m = np.moveaxis(mask, axis, -1)
        # One comparison per neighbour pair serves both cells; on an exact tie the first
        # (lower-index) cell wins, so a two-cell plateau still yields one maximum.
        rises = p[..., 1:] > p[..., :-1]
        m[..., 1:] &= rises
        m[..., :-1] &= ~rises
        if cyclic:
            wraps = p[..., 0] > p[..., -1]
            m[..., 0] &= wraps
            m[..., -1] &= ~wraps
    return mask


def parabolic_offset(y_minus: np.ndarray, y0: np.ndarray, y_plus: np.ndarray) -> np.ndarray:
    """Peak offset 0.5 (y+ - y-) / (2 y0 - y+ - y-) in bins, clipped to +/-0.5
    (seed 000 table 14; applied to log magnitudes it is Gaussian interpolation)."""
    den = 2 * y0 - y_plus - y_minus
    with np.errstate(divide="ignore", invalid="ignore"):
        off = np.where(den > 0, 0.5 * (y_plus - y_minus) / den, 0.0)
    return np.clip(off, -0.5, 0.5)


@lru_cache(maxsize=32)
def training_table(size: int, guard_cells: int, window_cells: int, stride: int = 1) -> np.ndarray:
    """(size, 2 x window_cells) int: the cyclic training positions of every position along a
    CFAR axis of `size` cells, lagging cells first (read-only, cached per configuration)."""
    lag, lead = training_offsets(guard_cells, window_cells, stride)
    table = (np.arange(size)[:, None] + np.concatenate([lag, lead])) % size
    table.flags.writeable = False
    return table


def candidate_cfar(power: np.ndarray, cand: tuple[np.ndarray, ...], axis: int,
                   guard_cells: int, window_cells: int, mode: str,
                   os_rank: int, stride: int = 1) -> np.ndarray:
    """Noise estimate of a CFAR along a cyclic `axis`, only at candidate cells.

    The cyclic training positions of every position along `axis` come from a small
    (size, 2 x window_cells) table, so each candidate's training cells are one flat `take`;
    they are reduced with `cfar.noise_estimate`. Equals `cfar.cfar_map(...)[cand]`.

    Parameters
    ----------
    power : (...) float
    cand : tuple of (n,) int arrays
        Indices of the candidate cells (as from np.nonzero).
    axis : int
        The cyclic CFAR axis.
    stride : int
        Training-cell spacing, bins.

    Returns
    -------
    (n,) float
    """
    power = np.ascontiguousarray(power)
    size = power.shape[axis]
    step = int(np.prod(power.shape[axis + 1:], dtype=np.int64))  # flat step along `axis`
    table = training_table(size, guard_cells, window_cells, stride)  # (size, 2W)
    pos = cand[axis]
    row_start = np.ravel_multi_index(cand, power.shape) - pos * step
    train = power.reshape(-1)[row_start[:, None] + table[pos] * step]  # (n, 2W)
    return noise_estimate(train, window_cells, mode, os_rank)


def cfar_peaks(power: np.ndarray, mode: str, alpha: float, guard_cells: int,
               window_cells: int, os_rank: int, stride: int, neighbours: dict[int, bool],
               first_bin: int = 0) -> tuple[tuple[np.ndarray, ...], np.ndarray, np.ndarray]:
    """Detections of a cyclic CFAR along the last axis among local maxima.

    A cell is a detection when it is a local maximum (`local_max_mask`) along the last axis
    (cyclic) and along the other axes listed in `neighbours`, its index on axis 1 is at least
    `first_bin`, and it exceeds `alpha` x the noise estimate of its training cells
    (`candidate_cfar`). A mode with a compiled detector (`CfarMode.peaks`) runs it; the others
    take `candidate_mask`, local maxima and gathered training cells; both give the same cells.

    Parameters
    ----------
    power : (n0, n1, n_cfar) float32
        Square-law map, C-contiguous (DDMA: (azimuth, range, Doppler)).
    mode : str
        Key of `cfar.CFAR_MODES`.
    neighbours : {axis: cyclic}
        Axes 0 and/or 1 to check for a local maximum too (the last axis always is).

    Returns
    -------
    cells : tuple of three (n,) int arrays
        Indices of the detections, C order.
    noise, peak : (n,) float32
        Noise estimate (the mode's statistic) and power of each.
    """
    cm = CFAR_MODES[mode]
    if cm.compiled_peaks:
        # Rows of axis 0 in parts on the cores (`pipeline.threads`), joined in C order.
        table = training_table(power.shape[-1], guard_cells, window_cells, stride)
        flags = (0 in neighbours, neighbours.get(0, False), 1 in neighbours,
                 neighbours.get(1, False))
        found = run_parts([lambda span=span: cm.peaks(power, alpha, table, os_rank, flags,
                                                      first_bin, span)
                           for span in spans(power.shape[0])])
        idx = np.concatenate([f[0] for f in found], axis=1)
        noise = np.concatenate([f[1] for f in found])
        cells = tuple(idx)
        return cells, noise, power[cells]
    mask = cm.candidate_mask(power, 2, alpha, os_rank)
    mask[:, :first_bin] = False
    local_max_mask(power, {**neighbours, 2: True}, mask=mask)
    cand = np.unravel_index(np.flatnonzero(mask), power.shape)
    noise = candidate_cfar(power, cand, 2, guard_cells, window_cells, mode, os_rank, stride)
    peak = power[cand]
    hit = peak > alpha * noise
    return tuple(c[hit] for c in cand), noise[hit], peak[hit]


def estimate_angles(virt: np.ndarray, sin_az_cos_el: np.ndarray, h_idx: np.ndarray,
                    h_pos: np.ndarray, v_idx: np.ndarray, v_pos: np.ndarray,
                    v_height_wl: float) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth and elevation from the virtual-array samples (seed 000 table 15).

    A e^{j psi} = h . conj(e^{j m wx}) over the horizontal row, A e^{j(psi + wz)} the same over
    the raised row; wz = arg of their product with conjugate; sin(el) = wz / (2 pi h / lambda)
    (1.6 pi for the 0.8 lambda EVM row). The FFT measures wx = pi sin(az) cos(el), so
    sin(az) = (wx / pi) / cos(el).

    Parameters
    ----------
    virt : (n, n_virtual) complex
        Virtual-antenna samples at each detection, in the demodulated order.
    sin_az_cos_el : (n,) float
        wx / pi from the interpolated azimuth FFT peak.

    Returns
    -------
    azimuth_rad, elevation_rad : (n,) float
    """
    wx = np.pi * sin_az_cos_el
    if v_idx.size and np.ndim(v_height_wl):
        sin_el = _multi_row_sin_el(virt, wx, h_idx, h_pos, v_idx, v_pos,
                                   np.asarray(v_height_wl, dtype=float))
    elif v_idx.size:
        a_h = np.einsum("nm,nm->n", virt[:, h_idx], np.exp(-1j * wx[:, None] * h_pos[None, :]))
        a_v = np.einsum("nm,nm->n", virt[:, v_idx], np.exp(-1j * wx[:, None] * v_pos[None, :]))
        wz = np.angle(a_v * np.conj(a_h))
        sin_el = np.clip(wz / (2 * np.pi * v_height_wl), -1.0, 1.0)
    else:
        sin_el = np.zeros_like(wx)
    cos_el = np.sqrt(1 - sin_el ** 2)
    sin_az = np.clip(sin_az_cos_el / cos_el, -1.0, 1.0)
    return np.arcsin(sin_az), np.arcsin(sin_el)
