"""Stages every MIMO chain shares: frame checks, power and log helpers, range and azimuth
peak interpolation, the zero-padded array DFT, the whole-array likelihood used to score
transmitter/velocity hypotheses, and the point-cloud assembly.

Per-scheme chains (`pipeline.mimo`) compose these with the kernels of `pipeline.kernels`
(range FFT, Doppler FFT, CFAR, local maxima, angle estimation).

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA]: section 5, tables 14, 15.
.. [2] TI, AWR1642 TDM-MIMO velocity disambiguation [TI-VEXT]: section 4.
"""
from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np
import pandas as pd

from core.errors import BadInput
from radarsim.config import C_MPS, RadarConfig

from .cfar import cfar_peaks, noise_mean_factor
from .config import WINDOWS, ProcessingConfig
from .kernels import estimate_angles, layout_of, parabolic_offset
from .peak_refinement import neighbour_bins, peak_patches, refine_peaks_2d

__all__ = ["POINT_CLOUD_COLUMNS", "check_frame", "power_of", "log_power", "point_cloud",
           "empty_cloud", "interp_azimuth", "interp_range", "interp_doppler", "array_dft",
           "refine_hits", "array_likelihood", "refined_likelihood", "hypothesis_cloud"]

#: Columns of every point cloud, in order.
POINT_CLOUD_COLUMNS = ["range_m", "azimuth_deg", "elevation_deg", "radial_velocity_mps",
                       "snr_db", "x_m", "y_m", "z_m", "range_bin", "doppler_bin",
                       "azimuth_bin", "saturated"]
_BIN_COLUMNS = ("range_bin", "doppler_bin", "azimuth_bin")
#: The column labels of every chain's point cloud, made once: each cloud gets a shallow copy
#: (`point_cloud`), its own name but the same labels and the same lookup table, which pandas
#: builds on a label's first lookup (``points["saturated"]``) and keeps with the labels.
_COLUMN_LABELS = pd.Index(POINT_CLOUD_COLUMNS)


def check_frame(cfg: RadarConfig, adc: np.ndarray) -> None:
    if not isinstance(cfg, RadarConfig):
        raise BadInput(f"cfg must be a radarsim.RadarConfig, got {type(cfg).__name__}")
    if not isinstance(adc, np.ndarray):
        raise BadInput(f"adc must be a numpy.ndarray, got {type(adc).__name__}")
    if adc.dtype != cfg.adc_dtype:
        raise BadInput(f"adc dtype must be {cfg.adc_dtype} ({cfg.adc_mode} ADC samples), got "
                       f"{adc.dtype}")
    want = (cfg.n_chirps, cfg.n_rx, cfg.n_samples)
    if adc.shape != want:
        raise BadInput(f"adc shape {adc.shape} does not match the config "
                       f"(n_chirps, n_rx, n_samples) = {want}")


def power_of(x: np.ndarray, consume: bool = False) -> np.ndarray:
    """|x|^2 of a C-contiguous complex64 array as float32 (re^2 + im^2 on the float32 view,
    without the square root of np.abs); `consume=True` squares x's memory in place."""
    v = x.view(np.float32)
    v = np.square(v, out=v) if consume else np.square(v)
    return v[..., 0::2] + v[..., 1::2]


def log_power(p: np.ndarray) -> np.ndarray:
    return np.log(np.maximum(p, 1e-30))


def point_cloud(cfg: RadarConfig, proc: ProcessingConfig, range_pos: np.ndarray,
                velocity: np.ndarray, az: np.ndarray, el: np.ndarray, snr_db: np.ndarray,
                bins: dict[str, np.ndarray]) -> pd.DataFrame:
    """Point cloud of n detections (`POINT_CLOUD_COLUMNS`, ``saturated`` False), sorted by
    (range, Doppler, azimuth) bin. range_m is the interpolated range less the profile's range
    bias, clamped at 0 m as TI's SDK does (a detection at 0 m has x = y = z = 0).

    range_pos : (n,) fractional range bin; velocity (m/s), az, el (rad), snr_db : (n,);
    bins : "range_bin", "doppler_bin", "azimuth_bin" -> (n,) int."""
    rng_m = range_pos * cfg.range_resolution_m
    if proc.range.doppler_coupling_correction:
        # f_beat = 2 S R / c + f_D with f_D = -2 v / lambda: undo the Doppler shift.
        rng_m = rng_m + velocity * C_MPS / (cfg.slope_hz_per_s * cfg.wavelength_m)
    # compRangeBiasAndRxChanPhase rangeBias (`pipeline.compensation`): an exact shift. A
    # return nearer than the bias (Tx-to-Rx leakage in range bin 0-1 once a positive bias is
    # applied) would land at a negative range: the SDK's AoA DPU clamps it to 0 (``if (range
    # < 0) range = 0``, DSP and HWA paths alike) and keeps the detection, so does the chain.
    rng_m = np.maximum(rng_m - proc.calibration.range_bias_m, 0.0)
    order = np.lexsort((bins["azimuth_bin"], bins["doppler_bin"], bins["range_bin"]))
    rng_m, velocity, az, el, snr_db = (x[order] for x in (rng_m, velocity, az, el, snr_db))
    bins = {k: v[order] for k, v in bins.items()}
    cos_el = np.cos(el)
    columns = [rng_m, np.degrees(az), np.degrees(el), velocity, snr_db,
               rng_m * cos_el * np.cos(az), rng_m * cos_el * np.sin(az), rng_m * np.sin(el),
               *(bins[k] for k in _BIN_COLUMNS),
               # Filled by `pipeline.saturation.apply_policy`; present from the start, so that
               # the policy replaces a column instead of growing the frame.
               np.zeros(rng_m.size, dtype=bool)]
    # Built on positions, then labelled: pandas would make a new Index of the 12 strings
    # (and, on the first lookup, its hash table) for every cloud. The copy keeps a name given
    # to one cloud's labels on that cloud. 0.19-0.28 -> 0.12-0.17 ms per cloud with two
    # lookups (60 points, best of 400 alternated).
    points = pd.DataFrame(dict(enumerate(columns)), copy=False)
    points.columns = _COLUMN_LABELS.copy()
    return points


def interp_azimuth(power_az: np.ndarray, a: np.ndarray) -> np.ndarray:
    """wx / pi from the azimuth bin of each peak and its cyclic neighbours.

    power_az : (n, n_fft) float; a : (n,) int -> (n,) sin(az) cos(el)."""
    n_fft = power_az.shape[-1]
    rows = np.arange(a.size)
    y = log_power(power_az)
    off = parabolic_offset(y[rows, (a - 1) % n_fft], y[rows, a], y[rows, (a + 1) % n_fft])
    k = a + off
    k = np.where(k >= n_fft / 2, k - n_fft, k)  # table 14 step 4: mirror to [-N/2, N/2)
    return 2.0 * k / n_fft


@lru_cache(maxsize=32)
def _offset_table(window_name: str, n: int = 512) -> tuple[np.ndarray, np.ndarray]:
    """(g, d): the log-parabola offset g a tone at fractional bin offset d gives through a
    `window_name` (scipy name) FFT of `n` points, on a 401-point grid of d in [-0.5, 0.5]; g
    is monotone for every registered window, so np.interp(g_measured, g, d) undoes the
    interpolator's bias (Hann/Hamming up to 0.016 bin, Blackman 0.007, rectangular 0.167).
    Range uses the 512-point periodic window's kernel (the bias changes by < 1e-4 bin from 64
    points up); Doppler the FFT's own length (slow time is often shorter)."""
    from scipy.signal import get_window
    w = get_window(window_name, n, fftbins=True)
    d = np.linspace(-0.5, 0.5, 401)
    k = np.arange(-1, 2)
    x = (w * np.exp(2j * np.pi * (d[:, None, None] - k[None, :, None])
                    * np.arange(n) / n)).sum(axis=-1)
    y = np.log(np.maximum(np.abs(x) ** 2, np.finfo(float).tiny))  # rect at d = 0: exact zeros
    g = parabolic_offset(y[:, 0], y[:, 1], y[:, 2])
    g.setflags(write=False)
    d.setflags(write=False)
    return g, d


def interp_range(power_r: np.ndarray, r: np.ndarray, n_range: int,
                 window: str | None = None) -> np.ndarray:
    """Fractional range bin from the log power at r-1, r, r+1 (edges not interpolated).

    power_r : (n, 3) float for bins r-1, r, r+1. window : scipy name of the range window the
    spectrum was made with: the log-parabola's bias for that window is undone
    (`_offset_table`); None keeps the raw log-parabola offset."""
    y = log_power(power_r)
    off = parabolic_offset(y[:, 0], y[:, 1], y[:, 2])
    if window is not None:
        g, d = _offset_table(window)
        off = np.interp(off, g, d)
    off = np.where((r <= 0) | (r >= n_range - 1), 0.0, off)
    return r + off


def interp_doppler(power_d: np.ndarray, window: str, n_fft: int) -> np.ndarray:
    """Fractional Doppler offset (bins, in [-0.5, 0.5]) of peaks from their power at d-1, d,
    d+1 (cyclic: every bin is interpolated), the log-parabola's bias for the Doppler window
    undone as for range (`interp_range`, `_offset_table`).

    Parameters
    ----------
    power_d : (n, 3) float
        Power at d-1, d, d+1, or a sum of powers with one kernel (over Rx, or over the DDMA
        Tx sub-bands: each term has the same shape, so the sum's log-parabola offset is one
        term's).
    window : str
        scipy name of the Doppler window.
    n_fft : int
        Length of the Doppler FFT the window spans (no zero padding).

    Returns
    -------
    (n,) float64
    """
    y = log_power(power_d)
    g, d = _offset_table(window, int(n_fft))
    return np.interp(parabolic_offset(y[:, 0], y[:, 1], y[:, 2]), g, d)


@lru_cache(maxsize=16)
def array_dft(cfg: RadarConfig, n_fft: int, row: str) -> np.ndarray:
    """(n_virtual, n_fft) complex64 zero-padded DFT of one row of the virtual array as a
    matrix, so `samples @ W` is the row's n_fft-point azimuth spectrum: element m at horizontal
    position p (lambda/2 units) of the row gets exp(-2j pi p k / n_fft), every other element
    zero. row: "horizontal" (the z = 0 row) or "raised" (Tx2's row)."""
    h_idx, h_pos, v_idx, v_pos, _ = layout_of(cfg)
    idx, pos = (h_idx, h_pos) if row == "horizontal" else (v_idx, v_pos)
    w = np.zeros((cfg.n_virtual, n_fft), dtype=np.complex64)
    w[idx] = np.exp(-2j * np.pi * np.outer(pos, np.arange(n_fft)) / n_fft)
    w.setflags(write=False)
    return w


def empty_cloud() -> pd.DataFrame:
    """A point cloud without rows, with the columns of `POINT_CLOUD_COLUMNS` (float64)."""
    return _empty_cloud().copy()  # a new frame each call (0.014 ms; building one: 0.8 ms)


@lru_cache(maxsize=1)
def _empty_cloud() -> pd.DataFrame:
    return pd.DataFrame({c: pd.Series(dtype=float) for c in POINT_CLOUD_COLUMNS})


def array_likelihood(cfg: RadarConfig, virt: np.ndarray, az_pow: np.ndarray,
                     v_idx: np.ndarray) -> np.ndarray:
    """Likelihood of each transmitter/velocity hypothesis, (n, H).

    Shared by every chain that resolves an ambiguity by hypothesis testing (TDMA and BPM
    velocity hypotheses after their Doppler-phase compensation, classic-DDMA Tx-to-sub-band
    assignments).

    The generalised likelihood of one echo on the whole virtual array, max over (wx, wz) of
    |a(wx, wz)^H x|^2: with wz free, the maximum over wz of |A_h(wx) + A_v(wx) e^{-j wz}|^2 is
    (|A_h(wx)| + |A_v(wx)|)^2, A_h and A_v the zero-padded beams of the horizontal and the
    raised row on the same wx grid. A wrong hypothesis leaves a staircase of slot phases that
    the horizontal row can largely mistake for an angle shift (its Tx groups are four elements
    apart), but the raised row (one slot) then peaks elsewhere, so the sum loses. Without a
    raised row this is the horizontal FFT peak of [TI-VEXT] section 4.

    virt : (n, H, n_virtual) samples of each hypothesis in the virtual-array order of
    `cfg.virtual_positions_m`; az_pow : (n, H, n_az) |A_h|^2; v_idx : raised-row elements.
    """
    if v_idx.size:
        heights, rows = raised_row_dfts(cfg, az_pow.shape[-1])
        if heights.size > 1:
            return _multi_row_likelihood(cfg, virt, heights, rows)
    return _grid_likelihood(cfg, virt, az_pow, v_idx).max(axis=-1)


def _grid_likelihood(cfg: RadarConfig, virt: np.ndarray, az_pow: np.ndarray,
                     v_idx: np.ndarray) -> np.ndarray:
    """(|A_h| + |A_v|)^2 on the azimuth grid, (n, H, n_az) (one raised row at most)."""
    if v_idx.size == 0:
        return az_pow
    a_v = np.abs(virt @ array_dft(cfg, az_pow.shape[-1], "raised"))  # (n, H, A)
    return (np.sqrt(az_pow) + a_v) ** 2


def refined_likelihood(cfg: RadarConfig, virt: np.ndarray, az_pow: np.ndarray,
                       v_idx: np.ndarray) -> np.ndarray:
    """`array_likelihood` at each hypothesis' interpolated peak instead of its grid maximum,
    (n, H): the decision between hypotheses no longer depends on where the echo falls on
    the n_az-point azimuth grid (the off-grid loss of a 4x zero-padded 12-element grid, up to
    about 5 %, exceeds the margin of a wrong hypothesis near a blind azimuth of BPM,
    `radarsim.mimo.BpmScheme`).

    The grid statistic's peak bin k and its neighbours give the parabolic offset on the log
    statistic ([TI-DDMA] table 14's interpolation); the statistic is then evaluated exactly at
    wx = 2 pi (k + offset) / n_az and the larger of the two kept. Arrays with several raised
    rows keep the grid statistic of `array_likelihood`.

    virt : (n, H, n_virtual) samples of each hypothesis; az_pow : (n, H, n_az) |A_h|^2 on the
    grid; v_idx : raised-row elements.
    """
    n_az = az_pow.shape[-1]
    if v_idx.size and raised_row_dfts(cfg, n_az)[0].size > 1:
        return array_likelihood(cfg, virt, az_pow, v_idx)
    grid = _grid_likelihood(cfg, virt, az_pow, v_idx)  # (n, H, A)
    k = np.argmax(grid, axis=-1)  # (n, H)
    y = np.take_along_axis(grid, (k[..., None] + np.arange(-1, 2)) % n_az, axis=-1)
    ly = log_power(y)
    wx = 2 * np.pi * (k + parabolic_offset(ly[..., 0], ly[..., 1], ly[..., 2])) / n_az
    # both rows' beams at wx, from one steering over the horizontal then the raised elements
    h_idx, h_pos, _, v_pos, _ = layout_of(cfg)
    steer = np.exp(-1j * wx[..., None] * np.concatenate([h_pos, v_pos])).astype(np.complex64)
    terms = virt[..., np.concatenate([h_idx, v_idx])] * steer  # (n, H, N)
    a_h = np.abs(terms[..., :h_idx.size].sum(axis=-1))
    a_r = np.abs(terms[..., h_idx.size:].sum(axis=-1))
    return np.maximum((a_h + a_r) ** 2, y[..., 1])


#: sin(elevation) grid of the multi-row likelihood: 0.03 steps keep the phase error of a
#: lambda-high row below 0.1 rad (< 1 % of the power), the same for every hypothesis.
_SIN_EL_GRID = np.linspace(-1.0, 1.0, 65)


@lru_cache(maxsize=8)
def raised_row_dfts(cfg: RadarConfig, n_fft: int) -> tuple[np.ndarray, np.ndarray]:
    """(heights (K,) wavelengths, (K, n_virtual, n_fft) complex64): the zero-padded azimuth
    DFT of each raised row of the virtual array (as `array_dft`), rows by height. One row for
    the BOOST/EVM arrays; several for antenna-on-package grids (IWR6843AOP)."""
    _, _, v_idx, v_pos, v_h = layout_of(cfg)
    per = np.broadcast_to(np.asarray(v_h, dtype=float), v_idx.shape)
    heights = np.unique(np.round(per, 6))
    w = np.zeros((heights.size, cfg.n_virtual, n_fft), dtype=np.complex64)
    for k, h in enumerate(heights):  # a few rows
        m = np.isclose(per, h)
        w[k, v_idx[m]] = np.exp(-2j * np.pi * np.outer(v_pos[m], np.arange(n_fft)) / n_fft)
    w.setflags(write=False)
    return heights, w


def _multi_row_likelihood(cfg: RadarConfig, virt: np.ndarray, heights: np.ndarray,
                          rows: np.ndarray) -> np.ndarray:
    """max over (wx, el) of |A_h(wx) + sum_k A_k(wx) e^{-j 2 pi h_k sin(el)}|^2, (n, H): the
    generalised likelihood of one echo when the raised elements sit on several rows, whose
    phases one elevation ties together (a free phase per row would absorb the slot phase of a
    Tx that only feeds one row). Elevation on `_SIN_EL_GRID`."""
    n_az = rows.shape[-1]
    a_h = virt @ array_dft(cfg, n_az, "horizontal")                  # (n, H, A)
    a_k = np.einsum("nhv,kva->nhka", virt, rows)                     # (n, H, K, A)
    steer = np.exp(-2j * np.pi * np.outer(heights, _SIN_EL_GRID))   # (K, S)
    total = a_h[..., None] + np.einsum("nhka,ks->nhas", a_k, steer)  # (n, H, A, S)
    return (np.abs(total) ** 2).max(axis=(-2, -1))


class RangeDopplerHits(NamedTuple):
    """CFAR hits of a non-coherent range-Doppler map (`noncoherent_hits`).

    Attributes
    ----------
    range_bin, doppler_bin : (n,) int
        Cells that passed the local-maximum test and the CFAR threshold.
    noise : (n,) float
        The CFAR's noise statistic of each cell (an L-look power, L = `looks`).
    range_pos : (n,) float
        Interpolated range position, bins.
    doppler_offset : (n,) float
        Parabolic Doppler offset from `doppler_bin` on the log power, bins (-0.5..0.5).
    looks : int
        Non-coherent looks summed into the map.
    """

    range_bin: np.ndarray
    doppler_bin: np.ndarray
    noise: np.ndarray
    range_pos: np.ndarray
    doppler_offset: np.ndarray
    looks: int

    def select(self, keep: np.ndarray) -> "RangeDopplerHits":
        """The hits where `keep` (n,) bool is True."""
        return RangeDopplerHits(*(a[keep] for a in self[:5]), self.looks)


def noncoherent_hits(rd: np.ndarray, looks: int, proc: ProcessingConfig) -> RangeDopplerHits:
    """Detect on a non-coherent range-Doppler map: local maximum along Doppler (and range when
    `proc.range.peak_check`), cyclic CFAR along Doppler designed for `looks`-look cells, then
    range and Doppler interpolation. Shared by the chains that detect before they separate the
    transmitters (TDMA and its slot family, classic DDMA).

    Parameters
    ----------
    rd : (n_range, n_dop) float
        Power summed over `looks` virtual channels.
    looks : int
        Number of channels summed (the CFAR threshold's degrees of freedom / 2).
    proc : ProcessingConfig

    Returns
    -------
    RangeDopplerHits
        Empty arrays when nothing passes.
    """
    n_range, n_dop = rd.shape
    cf = proc.cfar
    (_, r, d), noise, _ = cfar_peaks(rd[None], cf.mode, cf.scale(looks=looks), cf.guard_cells,
                                     cf.window_cells, cf.os_rank, cf.training_stride,
                                     {1: False} if proc.range.peak_check else {},
                                     proc.range.min_bin)
    range_pos = interp_range(rd[np.clip(r[:, None] + np.arange(-1, 2), 0, n_range - 1),
                                d[:, None]], r, n_range, WINDOWS[proc.range.window])
    doppler_off = interp_doppler(rd[r[:, None], (d[:, None] + np.arange(-1, 2)) % n_dop],
                                 WINDOWS[proc.doppler.window], n_dop)
    return RangeDopplerHits(r, d, noise, range_pos, doppler_off, looks)


def refine_hits(hits: RangeDopplerHits, spec: np.ndarray, n_range_fft: int) -> RangeDopplerHits:
    """The hits' range and Doppler at the maximum of their windowed spectra over the channels
    of `spec` (`pipeline.peak_refinement`), the 3-point estimates as starts.

    Parameters
    ----------
    hits : RangeDopplerHits
    spec : (n_dop, C, n_range) complex64, C-contiguous
        The channels' Doppler spectra the map was summed from (Doppler cyclic; a slot chain's
        `SlotMaps.spec`).
    n_range_fft : int
        Length of the range FFT (no zero padding: n_samples).

    Returns
    -------
    RangeDopplerHits
        ``range_pos`` and ``doppler_offset`` refined; the rest unchanged.
    """
    r, d = hits.range_bin, hits.doppler_bin
    if r.size == 0:
        return hits
    n_dop, _, n_range = spec.shape
    r_idx, on = neighbour_bins(r, n_range, cyclic=False)
    d_idx, _ = neighbour_bins(d, n_dop, cyclic=True)
    # One compiled gather (the channels as one "transmitter"), not numpy's fancy indexing of
    # an (n, Mr, Md, C) copy moved to (n, C, Mr, Md): the same samples, the same bits.
    patch = peak_patches(spec, d_idx[:, None, :], r_idx)  # (n, C, Mr, Md)
    r_off, d_off = refine_peaks_2d(patch, on, hits.range_pos - r, hits.doppler_offset,
                                   n_range_fft, n_dop)
    return hits._replace(range_pos=r + r_off, doppler_offset=d_off)


def hits_snr_db(hits: RangeDopplerHits, peak: np.ndarray, proc: ProcessingConfig,
                n_channels: int, noise_gain: float = 1.0) -> np.ndarray:
    """Detection SNR (dB) of a coherent azimuth peak over `n_channels` unit-weight channels,
    with the noise per channel taken from the hits' L-look CFAR statistic (converted from the
    order statistic to a mean) times `noise_gain` (the channel separation's noise gain).
    (n,) float64, as every float column of a point cloud (`empty_cloud`), whatever the
    precision of the spectra."""
    cf = proc.cfar
    sigma2 = hits.noise.astype(np.float64) / (
        noise_mean_factor(cf.mode, cf.n_training, cf.os_rank, hits.looks) * hits.looks)
    if noise_gain != 1.0:
        sigma2 = sigma2 * noise_gain
    return 10 * np.log10(peak / (n_channels * sigma2))


def hypothesis_cloud(cfg: RadarConfig, proc: ProcessingConfig, hits: RangeDopplerHits,
                     virt: np.ndarray, az_pow: np.ndarray, best: np.ndarray,
                     velocity: np.ndarray, doppler_bin: np.ndarray,
                     noise_gain: float = 1.0) -> pd.DataFrame:
    """Point cloud of the winning hypothesis of each hit: azimuth peak and interpolation,
    angle estimation, SNR and assembly. Shared by the chains that score hypotheses with
    `array_likelihood` (TDMA/BPM velocity, classic-DDMA assignment).

    virt : (n, H, n_virtual) samples and az_pow : (n, H, n_az) horizontal-row power of each
    hypothesis; best : (n,) winning hypothesis; velocity, doppler_bin : (n,) reported values;
    noise_gain : noise gain of the channel separation (`hits_snr_db`).
    """
    rows = np.arange(best.size)
    power_az = az_pow[rows, best]  # (n, A)
    a = np.argmax(power_az, axis=1)
    peak = power_az[rows, a]
    h_idx, h_pos, v_idx, v_pos, v_h = layout_of(cfg)
    sin_term = interp_azimuth(power_az, a)
    az, el = estimate_angles(virt[rows, best], sin_term, h_idx, h_pos, v_idx, v_pos, v_h)
    # Noise per virtual channel from the L-look CFAR estimate; the coherent azimuth spectrum
    # of n_h unit-weight channels has n_h times that noise power.
    snr_db = hits_snr_db(hits, peak, proc, h_idx.size, noise_gain)
    return point_cloud(cfg, proc, hits.range_pos, velocity, az, el, snr_db,
                       {"range_bin": hits.range_bin, "doppler_bin": doppler_bin,
                        "azimuth_bin": a})
