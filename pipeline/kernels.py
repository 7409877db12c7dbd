"""Kernels of the signal chain: FFT stages, peak interpolation, local maxima and angle
estimation (the CFAR detector: `pipeline.cfar.peaks`; the DDMA demodulation and azimuth map:
`pipeline.ddma_kernels`). Axis order: chirp/Doppler first, then Rx, then
fast time / range (design.md 3), unless a docstring says otherwise.

Mostly numpy; a pass that numpy can only express through full-size temporaries or index arrays
(the Rx energy, the Doppler window product) is a numba kernel (``cache=True``, compiled once
per machine) that repeats numpy's float32 operations in numpy's order, so outputs are
bit-identical to the numpy formulation it replaced.

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA]: section 5, tables 11, 14, 15, figure 19.
.. [2] TI, AWR1642 TDM-MIMO velocity disambiguation [TI-VEXT]: eq. 8-12, section 4.
"""
from __future__ import annotations

from functools import lru_cache, partial
from typing import NamedTuple

import numba
import numpy as np
import scipy.fft
from scipy.signal import get_window

from .threads import fft_workers, run_parts, spans

#: Unsigned loop indices in the compiled loops (see `_rx_energy`; `ddma_kernels` too): they
#: let LLVM vectorise the loops.
UINT = np.uint64

__all__ = ["window", "range_fft", "windowed", "samples_windowed", "doppler_fft", "slow_time_fft",
           "doppler_windowed",
           "rx_energy", "rx_energy_bins",
           "ArrayLayout",
           "array_layout", "layout_of", "local_max_mask", "parabolic_offset",
           "estimate_angles", "UINT"]


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
        return scipy.fft.fft(x, axis=-1, workers=fft_workers(), overwrite_x=True)
    x = windowed(adc, win, np.float32)  # int16 -> float32 and window in one pass
    return scipy.fft.rfft(x, axis=-1, workers=fft_workers())[..., : adc.shape[-1] // 2]


def windowed(x: np.ndarray, win: np.ndarray, dtype) -> np.ndarray:
    """``np.multiply(x, win, dtype=dtype)`` (win broadcast against x), in blocks of axis 0 on
    the cores (`pipeline.threads`): the same products."""
    out = np.empty(np.broadcast_shapes(x.shape, win.shape), dtype)
    per_row = win.ndim == x.ndim and win.shape[0] > 1

    def block(lo: int, hi: int) -> None:
        if _samples_case(x, win, out):
            samples_windowed(x[lo:hi], win, out[lo:hi])
        else:
            np.multiply(x[lo:hi], win[lo:hi] if per_row else win, out=out[lo:hi], dtype=dtype)

    run_parts([partial(block, lo, hi) for lo, hi in spans(out.shape[0])])
    return out


def _samples_case(x: np.ndarray, win: np.ndarray, out: np.ndarray) -> bool:
    return (x.dtype == np.int16 and x.ndim == 3 and win.dtype == np.float32 and win.ndim == 1
            and out.dtype == np.float32)


def samples_windowed(x: np.ndarray, win: np.ndarray, out: np.ndarray) -> np.ndarray:
    """``np.multiply(x, win, out=out, dtype=np.float32)`` of (n0, n1, n) int16 samples and an
    (n,) float32 window, bit for bit (each int16 is exact in float32, then one float32
    product), as one compiled loop instead of numpy's casting buffer (~3x faster)."""
    _samples_times_window(x, win, out)
    return out


@numba.njit(cache=True, nogil=True)
def _samples_times_window(x, w, out):
    n0, n1, n2 = x.shape
    for c in range(n0):
        for r in range(n1):
            for j in range(n2):
                out[c, r, j] = np.float32(x[c, r, j]) * w[j]


def doppler_fft(x: np.ndarray, win: np.ndarray, axis: int = 0) -> np.ndarray:
    """Windowed complex FFT over slow time along `axis` (in natural bin order 0..N-1), into the
    windowed copy (pocketfft gathers strided columns itself: the same transforms, bit for bit,
    as over a transposed contiguous copy)."""
    if axis == 0 and x.dtype == np.complex64 and win.dtype == np.float32 and x.ndim >= 2:
        return slow_time_fft(doppler_windowed(x, win))
    shape = [1] * x.ndim
    shape[axis] = -1
    w = win.reshape(shape)
    return slow_time_fft(windowed(x, w, np.result_type(x.dtype, w.dtype)), axis)


def slow_time_fft(xw: np.ndarray, axis: int = 0) -> np.ndarray:
    """The FFT of `doppler_fft` over an already windowed cube (overwritten), on `fft_workers`
    threads."""
    return scipy.fft.fft(xw, axis=axis, workers=fft_workers(), overwrite_x=True)


def doppler_windowed(x: np.ndarray, win: np.ndarray, out: np.ndarray | None = None,
                     split: bool = True) -> np.ndarray:
    """``np.multiply(x, win[:, None, ...])`` of a complex64 cube and a float32 window along axis
    0, bit for bit: numpy casts the window to complex64 and multiplies complex numbers,
    (re w - im 0, re 0 + im w) (which keeps NaN, inf and signed zeros as they come out of that
    product); the compiled loop does the same arithmetic in about half numpy's time (no casting
    buffer). Into `out` (C-contiguous, x's shape) if given; chirps in parts on the cores
    (`pipeline.threads`) unless `split` is False.

    With `out` given, x's last axis may be longer than out's: the product of its first
    ``out.shape[-1]`` entries (x a whole rFFT output, Nyquist bin included, read in place:
    its C-contiguous rows need no copy, a view of the first bins would).
    """
    out = np.empty(x.shape, np.complex64) if out is None else out
    x3 = x.reshape(x.shape[0], -1, x.shape[-1])
    o3 = out.reshape(x3.shape[:2] + out.shape[-1:])
    if not split:
        _complex_times_real(x3, win, o3, 0, x.shape[0])
        return out
    run_parts([partial(_complex_times_real, x3, win, o3, lo, hi) for lo, hi in spans(x.shape[0])])
    return out


@numba.njit(cache=True, nogil=True)
def _complex_times_real(x, w, out, lo, hi):
    """out[c] = x[c, :, :n2] * complex(w[c], 0) as numpy's complex64 multiply computes it, c in
    lo..hi-1, n2 = out.shape[2] <= x.shape[2]."""
    n1, n2 = out.shape[1], out.shape[2]
    zero = np.float32(0.0)
    for c in range(lo, hi):
        wr = w[c]
        for r in range(n1):
            # A row as a C-typed array (a copy only when x is strided, e.g. a view of the first
            # n_b bins of an rFFT's n_b + 1; none when x is the whole output): on a strided x
            # the loop below does not vectorise, and the row copy costs less than that (a
            # 64-chirp R79 block: 31 -> 16 us).
            row = np.ascontiguousarray(x[c, r])
            dst = out[c, r]
            for b in range(n2):
                v = row[b]
                dst[b] = complex(v.real * wr - v.imag * zero, v.real * zero + v.imag * wr)


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
    # On the calling thread: the pass is short (~0.2 ms on an R79 frame), so a second part
    # could save at most ~0.1 ms of wall time on an idle core, and it costs CPU (the hand-off,
    # two cores streaming one cube: 0.03-0.07 ms measured on a loaded 2-core machine).
    _rx_energy(spec.view(np.float32), out, 0, spec.shape[2])
    return out


def rx_energy_bins(spec: np.ndarray, out: np.ndarray, b0: int, b1: int) -> None:
    """`rx_energy` of range bins b0..b1-1 only, into out[:, b0:b1] (the same values), on the
    calling thread: for a pass that has just computed those bins of `spec` (the DDMA chain's
    Doppler FFT by range spans, `ddma_kernels.ddma_spectra_power`).

    spec : (n_chirps, n_rx, n_range) complex64 and out : (n_chirps, n_range) float32, both
    C-contiguous.
    """
    _rx_energy(spec.view(np.float32), out, b0, b1)


@numba.njit(cache=True, nogil=True)
def _rx_energy(v: np.ndarray, out: np.ndarray, b0: int, b1: int) -> None:
    """out[c, b] = sum over r (in order) of v[c, r, 2b]^2 + v[c, r, 2b + 1]^2, float32, for
    range bins b0 <= b < b1."""
    n_c, n_r, _ = v.shape
    # Unsigned indices: numba wraps a negative signed index around, which keeps LLVM from
    # vectorising the loops (range(b0, b1) with signed b: 4x slower).
    lo, hi, one, two = UINT(b0), UINT(b1), UINT(1), UINT(2)
    for c in range(n_c):
        dst = out[c]
        row = v[c, 0]
        for b in range(lo, hi):
            re = row[two * b]
            im = row[two * b + one]
            dst[b] = re * re + im * im
        for r in range(1, n_r):
            row = v[c, r]
            for b in range(lo, hi):
                re = row[two * b]
                im = row[two * b + one]
                dst[b] += re * re + im * im


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
    ([TI-DDMA] table 14; applied to log magnitudes it is Gaussian interpolation)."""
    den = 2 * y0 - y_plus - y_minus
    with np.errstate(divide="ignore", invalid="ignore"):
        off = np.where(den > 0, 0.5 * (y_plus - y_minus) / den, 0.0)
    return np.clip(off, -0.5, 0.5)


def estimate_angles(virt: np.ndarray, sin_az_cos_el: np.ndarray, h_idx: np.ndarray,
                    h_pos: np.ndarray, v_idx: np.ndarray, v_pos: np.ndarray,
                    v_height_wl: float) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth and elevation from the virtual-array samples ([TI-DDMA] table 15).

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
    # At el = +/-90 deg with wx = 0 (0 / 0: a beam symmetric about boresight, e.g. Tx-to-Rx
    # leakage, whose float32 powers can tie exactly) the azimuth is undefined: 0 is reported.
    sin_az = np.clip(np.divide(sin_az_cos_el, cos_el, out=np.zeros_like(cos_el),
                               where=(sin_az_cos_el != 0) | (cos_el != 0)), -1.0, 1.0)
    return np.arcsin(sin_az), np.arcsin(sin_el)
