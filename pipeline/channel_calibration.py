"""Offline ``measureRangeBiasAndRxChanPhase``: range bias and channel coefficients of a board
from frames of a static reflector at a known range.

TI's procedure (mmWave SDK 3.x object-detection DPC, "Range bias and rx channel gain/phase
measurement"): a strong reflector (a corner reflector) stands at boresight at distance X; the
strongest peak of the zero-Doppler detection matrix within the search window is interpolated
(a parabola through the peak and its neighbours), and range bias = interpolated range - X.
The virtual-antenna samples x_i of the peak give the coefficients
c_i = x_min conj(x_i) / |x_i|^2 (x_min = min |x_i|, so |c_i| <= 1 and Q15 holds them), which
give every channel the same phase and amplitude: those of a target on boresight.

Here, on a capture:

- the virtual-antenna samples of a static reflector are demodulated from the range-FFT cube
  by the scheme's transmit code, x = (W* W^T)^-1 W* y over all chirps of a frame
  (TDMA: the mean of each Tx's chirps; DDMA: the zero-Doppler bin of each Tx's sub-band; BPM:
  Hadamard decoding), which is the SDK's zero-Doppler sample for every scheme with the whole
  frame's coherent gain (TI reads the first chirp of the 1D-FFT cube);
- range: the strongest bin of sum_i |x_i|^2 (summed over frames) with |range - R| <= W,
  interpolated as the chain interpolates a detection's range (parabola on the log power with
  the range window's bias undone, `pipeline.stages.interp_range`), so the measured bias is the
  board's and subtracting it puts the reflector at R; the harness's window is R +/- W (TI's
  ``searchWin`` D spans X +/- D/2);
- channels: the samples are averaged over frames (coherently: the reflector is static), then
  c_i = x_min a_i conj(x_i) / |x_i|^2 with a_i the steering phase of a target at the chosen
  azimuth (0: TI's boresight) and elevation 0, and the whole vector is rotated so channel 0's
  coefficient is real and positive (normalised to the first channel; a common phase does not
  move any angle).

Accuracy (used by the tests): with per-channel, per-frame SNR s_i of the demodulated sample
(noise from the residual of the static model at the peak bin), the phase of channel i relative
to channel 0 after F frames has the Cramer-Rao bound
sigma^2 = 1 / (2 F s_i) + 1 / (2 F s_0) rad^2; the range bias has
sigma_R = dR sqrt(3) / (pi sqrt(2 SNR)) (design.md 8, rectangular window) with SNR the sum of s_i
over channels and frames.

References
----------
.. [1] TI, mmWave SDK 3.x ``objdethwa`` DPC documentation (``objectdetectioninternal.h``),
       "Range bias and rx channel gain/phase measurement and compensation".
.. [2] S. M. Kay, Fundamentals of Statistical Signal Processing: Estimation Theory, 1993,
       sec. 3.11 (phase CRB of a complex sinusoid in white noise).
"""
from __future__ import annotations

import math
from collections.abc import Iterable
from typing import NamedTuple

import numpy as np

from core.errors import BadInput
from radarsim.config import RadarConfig

from .chirp_level.stage import range_stage
from .compensation import chip_order_coefficients, comp_line
from .config import WINDOWS, ProcessingConfig
from .saturation import monitor
from .stages import interp_range

__all__ = ["ChannelCalibration", "measure_channel_calibration", "static_virtual_samples",
           "MIN_CALIBRATION_SNR_DB", "SECOND_RETURN_DB"]

#: Per-channel, per-frame SNR a calibration needs, dB: below it one frame's phase error
#: 1 / sqrt(2 SNR) exceeds 4 deg and the range-bias CRB 2 % of a bin for 12 channels
#: (a corner reflector at a few metres gives 40-60 dB).
MIN_CALIBRATION_SNR_DB = 20.0
#: A second return this close to the reflector's power (dB below it) near the peak makes the
#: measurement ambiguous: beyond what one point target gives through the range window's kernel,
#: it either is the strongest return (the wrong reflector, bins off) or merges with the
#: reflector's main lobe and drags the interpolated range (two equal returns 1.5 bins apart
#: move it by 0.7 bin).
SECOND_RETURN_DB = 10.0


class ChannelCalibration(NamedTuple):
    """Result of `measure_channel_calibration`.

    Attributes
    ----------
    range_bias_m : float
        Measured range minus the target range, m.
    measured_range_m : float
        Interpolated range of the reflector, m.
    range_bin : int
        Peak range bin.
    coefficients : (n_virtual,) complex
        Correction of each virtual channel (`RadarConfig.virtual_positions_m` order).
    chip_coefficients : (n_tx_chip x n_rx_chip,) complex
        The same in the chip order of the CLI line (1 for channels the profile does not use).
    samples : (n_virtual,) complex
        Frame-averaged demodulated sample of each virtual channel at the peak.
    snr_db : (n_virtual,) float
        Per-channel, per-frame SNR of the demodulated sample, dB.
    n_frames : int
    """

    range_bias_m: float
    measured_range_m: float
    range_bin: int
    coefficients: np.ndarray
    chip_coefficients: np.ndarray
    samples: np.ndarray
    snr_db: np.ndarray
    n_frames: int

    @property
    def line(self) -> str:
        """The ``compRangeBiasAndRxChanPhase`` line."""
        return comp_line(self.range_bias_m, self.chip_coefficients)

    def phase_crb_rad(self) -> np.ndarray:
        """(n_virtual,) CRB standard deviation of each channel's phase relative to channel 0,
        rad (0 for channel 0)."""
        s = 10 ** (self.snr_db / 10) * self.n_frames
        out = np.sqrt(1 / (2 * s) + 1 / (2 * s[0]))
        out[0] = 0.0
        return out

    def range_crb_m(self, range_resolution_m: float) -> float:
        """CRB standard deviation of the range (hence of the bias), m: design.md 8's
        dR sqrt(3) / (pi sqrt(2 SNR)) with SNR summed over channels and frames."""
        snr = float(np.sum(10 ** (self.snr_db / 10))) * self.n_frames
        return range_resolution_m * math.sqrt(3) / (math.pi * math.sqrt(2 * snr))


def static_virtual_samples(cfg: RadarConfig, rf: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Zero-Doppler virtual-antenna samples of every range bin, by least squares on the
    scheme's transmit code.

    Parameters
    ----------
    cfg : RadarConfig
    rf : (n_chirps, n_rx, n_range) complex
        Range-FFT cube of one frame.

    Returns
    -------
    x : (n_tx, n_rx, n_range) complex128
        Samples of each Tx (in `tx_order`) and Rx: the virtual channels of a static echo.
    residual_power : (n_range,) float
        Mean power per chirp and Rx of what the static model leaves, over the degrees of
        freedom (n_chirps - n_tx) per Rx: the noise power of one chirp sample.
    """
    w = cfg.scheme.transmit_code(cfg).weights  # (n_tx Tx1.., C)
    w = w[np.array(cfg.tx_order) - 1]  # rows in tx_order (the virtual-array order)
    n_c, n_r, n_b = rf.shape
    y = rf.reshape(n_c, -1).astype(np.complex128)
    gram = np.conj(w) @ w.T  # (T, T)
    x = np.linalg.solve(gram, np.conj(w) @ y)  # (T, R*B)
    res = y - w.T @ x
    dof = max(n_c - w.shape[0], 1)
    res_pow = (np.abs(res) ** 2).reshape(n_c, n_r, n_b).sum(axis=(0, 1)) / (dof * n_r)
    return x.reshape(-1, n_r, n_b), res_pow


def _steering(cfg: RadarConfig, azimuth_deg: float) -> np.ndarray:
    """(n_virtual,) phases of a far target at that azimuth, elevation 0 (design.md 3)."""
    u = np.array([math.cos(math.radians(azimuth_deg)), math.sin(math.radians(azimuth_deg)), 0.0])
    return np.exp(1j * 2 * np.pi / cfg.wavelength_m * (cfg.virtual_positions_m @ u))


def _kernel_power(window: str, offsets: np.ndarray, n: int = 512) -> np.ndarray:
    """Power of an `n`-point `window` (scipy name) FFT kernel at fractional bin `offsets`
    from the tone: what one point target puts into its neighbouring range bins."""
    from scipy.signal import get_window
    w = get_window(window, n, fftbins=True)
    x = (w * np.exp(2j * np.pi * offsets[:, None] * np.arange(n) / n)).sum(axis=-1)
    return np.abs(x) ** 2


def _refuse_second_return(p: np.ndarray, b: int, pos: float, window_bins: np.ndarray,
                          window: str, dr: float) -> None:
    """Raise when the power near the peak (the search window and 3 bins on each side of the
    peak) exceeds what one point target at `pos` gives through the range window's kernel by
    more than `SECOND_RETURN_DB` below the peak: a second return makes the reflector
    ambiguous.

    p : (n_range,) summed power; b : peak bin; pos : interpolated peak, bins."""
    near = np.union1d(window_bins, np.arange(b - 3, b + 4))
    near = near[(near >= 0) & (near < len(p)) & (np.abs(near - b) >= 2)]
    if not len(near):
        return
    k = _kernel_power(window, np.r_[b, near] - pos)
    excess = p[near] - p[b] * k[1:] / k[0]
    i = int(np.argmax(excess))
    if excess[i] > p[b] * 10 ** (-SECOND_RETURN_DB / 10):
        rel = 10 * math.log10(p[near[i]] / p[b])
        raise BadInput(f"ambiguous reflector: a second return at {near[i] * dr:.3f} m "
                       f"({rel:+.1f} dB from the strongest at {b * dr:.3f} m) lies beyond "
                       f"what one point target gives, within {SECOND_RETURN_DB:g} dB of "
                       "it: clear the scene around the reflector or narrow the search window")


def _frame_sums(cfg: RadarConfig, frames: Iterable[np.ndarray], proc: ProcessingConfig):
    """(x_sum (n_tx, n_rx, n_range), p_sum (n_range,), noise_sum (n_range,), n_frames): the
    static virtual samples, their power summed over channels and the residual noise power,
    summed over frames (`static_virtual_samples`).

    Raises
    ------
    core.errors.BadInput
        No frame; a frame with samples at the ADC rails (clipping compresses and mixes the
        channels: the measurement would be wrong).
    """
    x_sum, p_sum, noise_sum, n = None, None, None, 0
    clipped = []
    for adc in frames:
        sat = monitor(adc)
        if sat.saturated:  # the monitor counts a complex sample's I and Q apart
            values = sat.counts.size * sat.n_samples * (2 if np.iscomplexobj(adc) else 1)
            clipped.append(sat.n_saturated_samples / values)
        x, noise = static_virtual_samples(cfg, range_stage(cfg, adc, proc))
        x_sum = x if x_sum is None else x_sum + x
        p = (np.abs(x) ** 2).sum(axis=(0, 1))
        p_sum = p if p_sum is None else p_sum + p
        noise_sum = noise if noise_sum is None else noise_sum + noise
        n += 1
    if n == 0:
        raise BadInput("the capture holds no frame to calibrate on")
    if clipped:
        raise BadInput(f"the capture is clipped: {len(clipped)} of {n} frame(s) have samples at "
                       f"the ADC rails (up to {100 * max(clipped):.3g} % of a frame's values);"
                       " clipping compresses and mixes the channels, so a calibration on it "
                       "is wrong: lower the Rx gain or move the reflector farther")
    return x_sum, p_sum, noise_sum, n


def measure_channel_calibration(cfg: RadarConfig, frames: Iterable[np.ndarray],
                                target_range_m: float, search_window_m: float,
                                proc: ProcessingConfig | None = None, *,
                                azimuth_deg: float = 0.0,
                                min_snr_db: float = MIN_CALIBRATION_SNR_DB
                                ) -> ChannelCalibration:
    """Range bias and channel coefficients of a board from frames of a static reflector.

    Parameters
    ----------
    cfg : RadarConfig
        The radar that recorded the frames.
    frames : iterable of (n_chirps, n_rx, n_samples) ADC frames
    target_range_m : float
        True range of the reflector, m.
    search_window_m : float
        The peak is searched over range bins within target_range_m +/- this, m.
    proc : ProcessingConfig, optional
        Chirp-level chain and range window (the profile's); its own compensation is not
        applied (the measurement is absolute, as the SDK's).
    azimuth_deg : float
        Azimuth the reflector stands at (TI: 0, boresight).
    min_snr_db : float
        Refuse a measurement whose mean per-channel, per-frame SNR is below this, dB.

    Returns
    -------
    ChannelCalibration

    Raises
    ------
    core.errors.BadInput
        No frame; a frame with samples at the ADC rails (clipped); the window holds no range
        bin; no peak in the window (its strongest bin is at an edge of the window); a second
        return near the peak within `SECOND_RETURN_DB` of it (ambiguous reflector); the SNR is
        below `min_snr_db`. Each names the value and the limit.
    """
    proc = ProcessingConfig() if proc is None else proc
    if not (math.isfinite(target_range_m) and target_range_m > 0):
        raise BadInput(f"target_range_m={target_range_m!r} must be a positive distance (m)")
    if not (math.isfinite(search_window_m) and search_window_m > 0):
        raise BadInput(f"search_window_m={search_window_m!r} must be > 0 m")
    if not (math.isfinite(azimuth_deg) and abs(azimuth_deg) < 90):
        raise BadInput(f"azimuth_deg={azimuth_deg!r} must be within (-90, 90) deg")
    dr = cfg.range_resolution_m
    bins = np.arange(cfg.n_range_bins)
    in_win = (np.abs(bins * dr - target_range_m) <= search_window_m) & \
        (bins >= max(proc.range.min_bin, 1)) & (bins < cfg.n_range_bins - 1)
    if not in_win.any():
        raise BadInput(f"target_range_m={target_range_m:g} +/- {search_window_m:g} m holds no "
                       f"range bin the radar reports ({max(proc.range.min_bin, 1) * dr:.3f}.."
                       f"{(cfg.n_range_bins - 2) * dr:.3f} m, {dr:.4f} m per bin)")
    x_sum, p_sum, noise_sum, n = _frame_sums(cfg, frames, proc)
    idx = np.flatnonzero(in_win)
    b = int(idx[np.argmax(p_sum[idx])])
    lo, hi = idx[0], idx[-1]
    if not (p_sum[b] > p_sum[b - 1] and p_sum[b] > p_sum[b + 1]):
        edge = "near" if b == lo else "far"
        raise BadInput(f"target not found: the strongest return within target_range_m="
                       f"{target_range_m:g} +/- {search_window_m:g} m is at the window's "
                       f"{edge} edge ({b * dr:.3f} m) and rises beyond it: no peak "
                       f"in {lo * dr:.3f}..{hi * dr:.3f} m")
    pos = float(interp_range(p_sum[None, b - 1: b + 2], np.array([b]), cfg.n_range_bins,
                             WINDOWS[proc.range.window])[0])
    measured = pos * dr
    xs = x_sum[:, :, b].reshape(-1) / n  # (n_virtual,) virtual-array order
    # Noise variance of one frame's demodulated sample: chirp-sample noise x (W* W^T)^-1_kk.
    w = cfg.scheme.transmit_code(cfg).weights[np.array(cfg.tx_order) - 1]
    var_k = np.real(np.diag(np.linalg.inv(np.conj(w) @ w.T)))  # (T,)
    var = np.repeat(var_k, cfg.n_rx) * noise_sum[b] / n
    snr = np.abs(xs) ** 2 / var
    snr_db = 10 * np.log10(np.maximum(snr, 1e-30))
    mean_snr_db = float(10 * np.log10(np.mean(snr)))
    if mean_snr_db < min_snr_db:
        raise BadInput(f"target too weak or absent: calibration SNR {mean_snr_db:.1f} dB per "
                       f"channel and frame at "
                       f"{measured:.3f} m is below the limit {min_snr_db:g} dB: use a stronger "
                       "or closer reflector")
    _refuse_second_return(p_sum, b, pos, idx, WINDOWS[proc.range.window], dr)
    coef = _steering(cfg, azimuth_deg) * np.conj(xs) / np.abs(xs) ** 2 * np.abs(xs).min()
    coef = coef * np.exp(-1j * np.angle(coef[0]))  # channel 0 real and positive
    return ChannelCalibration(range_bias_m=measured - target_range_m,
                              measured_range_m=measured, range_bin=b, coefficients=coef,
                              chip_coefficients=chip_order_coefficients(cfg, coef),
                              samples=xs, snr_db=snr_db, n_frames=n)
