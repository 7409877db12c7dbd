"""Front-end model of a TI mmWave chip: scatterers to one ADC frame, real or complex (I/Q).

The IF signal of scatterer s, transmitter k, receiver r at chirp c and fast-time sample n is a
real tone (design.md section 3)

    A_skr cos(2 pi f_s t_n - (2 pi / lambda) path_sc + (2 pi / lambda)(t_k + r_r).u_s + phi_kc)

with beat frequency f_s = 2 S R_s / c + f_D (range plus the fast-time Doppler shift
f_D = -2 v_r / lambda), path_sc = 2 (R_s + v_r t_c) the two-way path at chirp c, u_s the unit
vector to the scatterer and phi_kc the transmit phase of Tx k at chirp c (DDMA phase code with
its quantisation, static and random errors; in TDMA a Tx is silent outside its slot). The
amplitude follows the radar equation ([TI-DDMA] eq. 1) with the element gain pattern.
Board imperfections: every Tx and Rx channel has a static complex gain (`tx_gain_error_db`,
`tx_phase_error_deg`, `rx_gain_error_db`, `rx_phase_error_deg`), so virtual channel (k, r)
carries g_k g_r, and a range bias b delays every echo by 2 b / c (beat frequency
2 S (R + b) / c): what TI's ``measureRangeBiasAndRxChanPhase`` measures and
``compRangeBiasAndRxChanPhase`` corrects (`pipeline.compensation`). The default board is ideal.
A complex (I/Q) ADC mode delivers the analytic tone A_skr exp(j(...)) instead of its real part:
the I channel is the real receiver's sample, Q its quadrature, each with the real receiver's
thermal noise; the image band (negative beat frequencies) is rejected, so a beat frequency f_b
sits at range bin f_b N / f_s of the complex FFT and echoes beyond the IF band are attenuated by
the chip's IF low-pass before they alias.

Because the tone separates into fast-time x slow-time x antenna factors, the whole cube is one
matrix product: (chirp x Rx, scatterer) @ (scatterer, sample). Range migration over the frame
(at most 0.73 m at 40 m/s, under one 1.32 m cell) is neglected: the beat frequency uses the
range at the frame's reference time (the middle of the burst).

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA], eq. 1, section 3.3, tables 3-4, fig. 20.
.. [2] M. A. Richards, Fundamentals of Radar Signal Processing, 2nd ed., ch. 2 (radar equation).
"""
from __future__ import annotations

import warnings
from functools import lru_cache

import numpy as np

from core.errors import BadInput

from .antenna import element_gain_linear
from .interference import synthesize
from .radar_config import ADC_FULL_SCALE_CODE, C_MPS, RadarConfig
from .receiver import IF_LOWPASS_HZ, IF_LOWPASS_ORDER, if_corner_hz, if_filter_gain
from .scene.scatterers import Scatterers
from .shifter import apply_coupling, coupling_matrix, select_codes, shifter_factor

__all__ = ["simulate_frame", "simulate_frame_weights", "received_power_w", "if_filter_gain",
           "transmit_phasors", "programmed_codes",
           "ADCSaturationWarning", "IF_LOWPASS_HZ", "IF_LOWPASS_ORDER", "if_corner_hz",
           "gaussian_noise"]

class ADCSaturationWarning(UserWarning):
    """Some ADC samples were clipped at the int16 full scale."""


def received_power_w(cfg: RadarConfig, scatterers: Scatterers) -> np.ndarray:
    """Received echo power of each scatterer for one Tx-Rx pair at the ADC input, W.

    P_r = P_t G_t(az, el) G_r(az, el) lambda^2 sigma / ((4 pi)^3 R^4 L) x |H_IF(f_b)|^2
    ([TI-DDMA] eq. 1 with the element pattern and the IF low-pass). Static per-Tx gain errors
    are not included.

    Returns
    -------
    (K,) float
        Power, W.
    """
    r = scatterers.range_m
    u = scatterers.unit_vector
    az = np.arctan2(u[:, 1], u[:, 0])
    el = np.arcsin(np.clip(u[:, 2], -1.0, 1.0))
    gt = element_gain_linear(cfg, az, el, cfg.tx_antenna_gain_dbi)
    gr = element_gain_linear(cfg, az, el, cfg.rx_antenna_gain_dbi)
    pt = 1e-3 * 10 ** (cfg.tx_power_dbm / 10)
    loss = 10 ** (cfg.system_loss_db / 10)
    lam = cfg.wavelength_m
    pr = pt * gt * gr * lam ** 2 * scatterers.rcs_m2 / ((4 * np.pi) ** 3 * r ** 4 * loss)
    return pr * if_filter_gain(_beat_frequency_hz(cfg, scatterers), if_corner_hz(cfg))


def _beat_frequency_hz(cfg: RadarConfig, scatterers: Scatterers) -> np.ndarray:
    """(K,) beat frequency 2 S (R + b) / c plus the fast-time Doppler shift -2 v_r / lambda, Hz,
    b the board's range bias (`RadarConfig.range_bias_m`, a fixed internal delay 2 b / c)."""
    return (2 * cfg.slope_hz_per_s * (scatterers.range_m + cfg.range_bias_m) / C_MPS
            - 2 * scatterers.radial_velocity_mps / cfg.wavelength_m)


def rx_channel_gain(cfg: RadarConfig) -> np.ndarray | None:
    """(n_rx,) complex static gain of each Rx channel, 10^(g/20) exp(j phi)
    (`rx_gain_error_db`, `rx_phase_error_deg`), or None for an ideal board (the frame is then
    bit-identical to a model without Rx errors)."""
    g = np.asarray(cfg.rx_gain_error_db, dtype=float)
    ph = np.asarray(cfg.rx_phase_error_deg, dtype=float)
    if not (g.any() or ph.any()):
        return None
    return 10 ** (g / 20) * np.exp(1j * np.radians(ph))


def wanted_phase_deg(cfg: RadarConfig) -> tuple[np.ndarray, np.ndarray]:
    """Phase each Tx should be programmed to at each chirp with an ideal shifter, and its gain.

    The scheme's code with `phase_quantization="none"` and no calibration: the shifter delays,
    so the wanted programmed phase is -(applied phase) (+180 deg for a sign-inverted chirp,
    e.g. BPM's -1 through the shifter's 180 deg setting), wrapped to [0, 360).

    Returns
    -------
    wanted_deg : (n_tx, n_chirps) float
    gain : (n_tx, n_chirps) float
        The scheme's ideal gain (0 where a Tx is silent).
    """
    return _wanted_phase_deg(cfg.replace_fields(phase_quantization="none",
                                                shifter_calibration_deg=None))


@lru_cache(maxsize=32)
def _wanted_phase_deg(ideal_cfg: RadarConfig) -> tuple[np.ndarray, np.ndarray]:
    code = ideal_cfg.scheme.transmit_code(ideal_cfg)
    gain = np.asarray(code.gain, dtype=float)
    wanted = np.mod(-np.degrees(np.asarray(code.phase_rad)) + np.where(gain < 0, 180.0, 0.0),
                    360.0)
    wanted.setflags(write=False)
    gain.setflags(write=False)
    return wanted, gain


def programmed_codes(cfg: RadarConfig, code=None) -> np.ndarray:
    """(n_tx, n_chirps) int shifter code of every Tx at every chirp, for any scheme.

    Uncalibrated: the shifter delays, so the code for an applied phase phi (plus pi for a
    sign-inverted chirp) is round(-phi / LSB) mod 2^bits: DDMA gets exactly
    `cfg.phase_codes()` repeated over the frame (its applied phases are multiples of the LSB),
    TDMA code 0, BPM codes 0/32, an ideal ("none") shifter the nearest code. Calibrated
    (`shifter_calibration_deg`): the code whose measured phase is closest to the wanted phase
    (`wanted_phase_deg`, `radarsim.shifter.select_codes`), for every scheme. Silent chirps
    get the code of their wanted phase too (their weight is 0).

    Parameters
    ----------
    cfg : RadarConfig
    code : radarsim.mimo.TransmitCode, optional
        The scheme's code (default `cfg.scheme.transmit_code(cfg)`), uncalibrated case only.
    """
    if cfg.shifter_calibration_deg is not None:
        wanted, _ = wanted_phase_deg(cfg)
        return select_codes(wanted, np.asarray(cfg.shifter_calibration_deg), cfg.phase_lsb_deg)
    code = cfg.scheme.transmit_code(cfg) if code is None else code
    phase = np.asarray(code.phase_rad) + np.where(np.asarray(code.gain) < 0, np.pi, 0.0)
    lsb = np.radians(cfg.phase_lsb_deg)
    return np.mod(np.round(-phase / lsb), 2 ** cfg.phase_shifter_bits).astype(np.int64)


def transmit_phasors(cfg: RadarConfig, rng: np.random.Generator | None = None) -> np.ndarray:
    """Complex transmit weight of every Tx at every chirp.

    The scheme's ideal transmit code (`radarsim.mimo.MimoScheme.transmit_code`: DDMA the
    applied, negated and quantised shifter phase of the code period repeated over the frame;
    TDMA each Tx active only in its slot; BPM the Hadamard signs), times the static per-Tx gain
    and phase errors, times exp(j e) with e a random per-chirp error of `phase_noise_deg_rms`.
    Then, for every scheme, the shifter's per-code error at the programmed code
    (`programmed_codes`; tables `shifter_phase_error_deg`, `shifter_gain_error_db`) and the Tx
    coupling C @ w (`tx_coupling_db`, `tx_coupling_deg`); all-zero tables and the identity
    coupling leave the weights bit-identical.

    Parameters
    ----------
    cfg : RadarConfig
    rng : numpy.random.Generator, optional
        Required when `cfg.phase_noise_deg_rms > 0`.

    Returns
    -------
    (n_tx, n_chirps) complex128
        Rows Tx1..Tx{n_tx}.
    """
    code = cfg.scheme.transmit_code(cfg)
    codes = programmed_codes(cfg, code)
    if cfg.shifter_calibration_deg is None:
        gain, phase = code.gain, code.phase_rad
    else:
        # The calibrated chip programs codes: nominal applied phase -q LSB, sign in the code.
        gain, phase = np.abs(code.gain), -np.radians(codes * cfg.phase_lsb_deg)
    return apply_transmit_errors(cfg, _tx_weights(cfg, gain, phase, rng), codes)


def _tx_weights(cfg: RadarConfig, gain: np.ndarray, phase: np.ndarray,
                rng: np.random.Generator | None) -> np.ndarray:
    """gain x static Tx gain error x exp(j (phase + static Tx phase error + per-chirp noise))."""
    phase = phase + np.radians(np.asarray(cfg.tx_phase_error_deg))[:, None]
    if cfg.phase_noise_deg_rms > 0:
        if rng is None:
            raise BadInput("rng is required when phase_noise_deg_rms > 0")
        phase = phase + np.radians(cfg.phase_noise_deg_rms) * rng.standard_normal(phase.shape)
    return gain * 10 ** (np.asarray(cfg.tx_gain_error_db)[:, None] / 20) * np.exp(1j * phase)


def code_weights(cfg: RadarConfig, codes: np.ndarray, active: np.ndarray | None = None,
                 rng: np.random.Generator | None = None) -> np.ndarray:
    """Transmit weights of an explicit code sequence, with every error of the front end.

    Parameters
    ----------
    cfg : RadarConfig
        Error tables, static / per-chirp errors, coupling.
    codes : (n_tx, n_c) int
        Programmed code of each Tx at each chirp (applied phase -q LSB).
    active : (n_tx, n_c) bool, optional
        Which Tx transmit at each chirp (default: all).
    rng : numpy.random.Generator, optional
        Required when `cfg.phase_noise_deg_rms > 0`.

    Returns
    -------
    (n_tx, n_c) complex128
    """
    codes = np.asarray(codes, dtype=np.int64)
    on = np.ones(codes.shape) if active is None else np.asarray(active, dtype=float)
    w = _tx_weights(cfg, on, -np.radians(codes * cfg.phase_lsb_deg), rng)
    return apply_transmit_errors(cfg, w, codes)


def apply_transmit_errors(cfg: RadarConfig, weights: np.ndarray, codes: np.ndarray) -> np.ndarray:
    """Shifter per-code errors and Tx coupling applied to transmit weights.

    Parameters
    ----------
    cfg : RadarConfig
        Holds the error tables and the coupling matrix.
    weights : (n_tx, n_chirps) complex
        Transmit weights with the ideal (quantised) shifter phase and the static / per-chirp
        errors.
    codes : (n_tx, n_chirps) int
        Programmed shifter code of each Tx at each chirp.

    Returns
    -------
    (n_tx, n_chirps) complex128
        C @ (weights x 10^(g[k, q] / 20) exp(-j e[k, q])).
    """
    w = weights * shifter_factor(np.asarray(cfg.shifter_phase_error_deg),
                                 np.asarray(cfg.shifter_gain_error_db), codes)
    return apply_coupling(coupling_matrix(cfg.tx_coupling_db, cfg.tx_coupling_deg), w)


def _chirp_times_s(cfg: RadarConfig, n_chirps: int | None = None) -> np.ndarray:
    """(n_chirps,) chirp start times relative to the middle of the burst, s: the scheme's
    (`MimoScheme.chirp_timing`) for a frame of the config's chirps, else uniform."""
    n_c = cfg.n_chirps if n_chirps is None else n_chirps
    if n_c == cfg.n_chirps:
        return cfg.scheme.chirp_timing(cfg).t_c_s
    return (np.arange(n_c) - (n_c - 1) / 2) * cfg.chirp_period_s


def simulate_frame(cfg: RadarConfig, scatterers: Scatterers,
                   rng: np.random.Generator, interferers=None) -> np.ndarray:
    """Simulate one frame of ADC samples as the chip delivers it (real or complex I/Q).

    Parameters
    ----------
    cfg : RadarConfig
        Radar (waveform, MIMO schedule, antenna, RF budget).
    scatterers : Scatterers
        K point scatterers at the frame's reference time (middle of the burst), radar frame.
    rng : numpy.random.Generator
        Source of the thermal noise and the random phase errors; same seed, same bits.
    interferers : radarsim.interference.Interferers, optional
        Other radars whose direct-path bursts are added before rounding and clipping
        (`interference.synthesize`); deterministic, draws nothing from `rng`.

    Returns
    -------
    adc : (n_chirps, n_rx, n_samples) int16 (real ADC) or complex64 (complex ADC modes)
        ADC samples: signal + interference + DC/leakage (`adc_dc_offset_lsb`,
        `tx_leakage_dbfs`) + thermal noise (k T NF B per real channel, B = adc_rate / 2),
        scaled so a sine of `adc_full_scale_dbm` reaches 32767, rounded and clipped to int16;
        complex frames hold int16-valued I and Q parts (what a DCA1000 records): the I/Q
        receiver sees the interference's analytic signal (complex 1x: its image band, f_d < 0,
        rejected) and the DC offset on I and Q alike.

    Warns
    -----
    ADCSaturationWarning
        When any sample clips, with the number and fraction of clipped samples.

    Raises
    ------
    ValueError
        If `scatterers` is not a `Scatterers` or `rng` is not a `numpy.random.Generator`.

    Examples
    --------
    >>> import numpy as np, radarsim
    >>> cfg = radarsim.presets.r79_ddma()
    >>> car = radarsim.Scatterers.from_spherical([30.0], [10.0], [0.0], [-5.0], [10.0])
    >>> adc = radarsim.simulate_frame(cfg, car, rng=np.random.default_rng(0))
    >>> adc.shape, adc.dtype                  # (n_chirps, n_rx, n_samples), real ADC
    ((768, 4, 384), dtype('int16'))
    >>> bool(np.array_equal(adc, radarsim.simulate_frame(cfg, car, np.random.default_rng(0))))
    True
    """
    if not isinstance(cfg, RadarConfig):
        raise BadInput(f"cfg must be a RadarConfig, got {type(cfg).__name__}")
    if not isinstance(scatterers, Scatterers):
        raise BadInput(f"scatterers must be a radarsim.Scatterers, got "
                       f"{type(scatterers).__name__}")
    if not isinstance(rng, np.random.Generator):
        raise BadInput(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    return simulate_frame_weights(cfg, scatterers, rng, transmit_phasors(cfg, rng),
                                  interferers=interferers)


def simulate_frame_weights(cfg: RadarConfig, scatterers: Scatterers, rng: np.random.Generator,
                           tx_weights: np.ndarray, interferers=None) -> np.ndarray:
    """`simulate_frame` with explicit transmit weights (any chirp count and code sequence).

    Used by the shifter calibration and the [TI-DDMA] figure 7-8 experiment, which step one Tx
    through codes no MIMO scheme programs.

    Parameters
    ----------
    cfg, scatterers, rng
        As `simulate_frame`.
    tx_weights : (n_tx, n_c) complex
        Radiated weight of each Tx at each of n_c chirps (e.g. `transmit_phasors`).
    interferers : radarsim.interference.Interferers, optional
        As `simulate_frame` (n_c must then be cfg.n_chirps).

    Returns
    -------
    adc : (n_c, n_rx, n_samples) int16, or complex64 for a complex ADC mode
    """
    tx_w = np.asarray(tx_weights)
    if tx_w.ndim != 2 or tx_w.shape[0] != cfg.n_tx or tx_w.shape[1] < 1:
        raise BadInput(f"tx_weights shape {tx_w.shape} must be (n_tx={cfg.n_tx}, n_chirps)")
    n_c, n_r, n_s = tx_w.shape[1], cfg.n_rx, cfg.n_samples
    cplx = cfg.is_complex
    # Thermal noise first: the output buffer, to which the signal is added in place (complex:
    # I and Q interleaved along the last axis, each with the real channel's noise).
    out = gaussian_noise(rng, (n_c * n_r, 2 * n_s if cplx else n_s), cfg.noise_rms_lsb)
    power = received_power_w(cfg, scatterers) if len(scatterers) else np.zeros(0)
    keep = power > 0  # only scatterers in front of the radar with non-zero power contribute
    if np.any(keep):
        sig = _signal(cfg, scatterers, keep, power[keep], tx_w)
        out += sig.view(np.float32) if cplx else sig
    has_intf = interferers is not None and len(interferers)
    has_dc = bool(cfg.adc_dc_offset_lsb) or cfg.tx_leakage_dbfs is not None
    if has_intf:
        if n_c != cfg.n_chirps:
            raise BadInput(f"interferers need the config's {cfg.n_chirps} chirps, "
                           f"tx_weights has {n_c}")
        synthesize(cfg, interferers, out=out)
    if has_dc:
        dcl = _dc_leakage(cfg)
        out += dcl.view(np.float32) if cplx else dcl
    np.rint(out, out=out)
    # max/min are cheap reductions; the clipped samples are only counted when there are some.
    if out.max() > ADC_FULL_SCALE_CODE or out.min() < -ADC_FULL_SCALE_CODE - 1:
        n_clip = int(np.count_nonzero((out > ADC_FULL_SCALE_CODE)
                                      | (out < -ADC_FULL_SCALE_CODE - 1)))
        warnings.warn(f"ADC saturation: {n_clip} of {out.size} samples "
                      f"({100 * n_clip / out.size:.3g} %) clipped at -{ADC_FULL_SCALE_CODE + 1}"
                      f"/+{ADC_FULL_SCALE_CODE}", ADCSaturationWarning, stacklevel=2)
        np.clip(out, -ADC_FULL_SCALE_CODE - 1, ADC_FULL_SCALE_CODE, out=out)
    if cplx:
        return out.view(np.complex64).reshape(n_c, n_r, n_s)
    return out.astype(np.int16).reshape(n_c, n_r, n_s)


#: Length of the Tx-to-Rx leakage path, m (antenna coupling behind the radome).
LEAKAGE_PATH_M = 0.1


def _dc_leakage(cfg: RadarConfig) -> np.ndarray:
    """(n_samples,) float32 static front-end term, the same on every chirp and Rx: the DC
    offset plus the leakage tone of a `LEAKAGE_PATH_M` path (beat 2 S d / c, 5.9 kHz for the
    R79 slope: far below one range bin, so it looks like a slowly varying offset). Complex
    ADC modes: complex64, the offset on I and Q alike and the tone as exp(j phase)."""
    t_n = np.arange(cfg.n_samples) / cfg.adc_rate_sps + cfg.adc_start_time_s
    dc = float(cfg.adc_dc_offset_lsb)
    x = np.full(cfg.n_samples, dc * (1 + 1j) if cfg.is_complex else dc)
    if cfg.tx_leakage_dbfs is not None:
        amp = ADC_FULL_SCALE_CODE * 10 ** (cfg.tx_leakage_dbfs / 20)
        f_l = 2 * cfg.slope_hz_per_s * LEAKAGE_PATH_M / C_MPS
        ph = 2 * np.pi * f_l * t_n - 4 * np.pi * LEAKAGE_PATH_M / cfg.wavelength_m
        x = x + amp * (np.exp(1j * ph) if cfg.is_complex else np.cos(ph))
    return x.astype(np.complex64 if cfg.is_complex else np.float32)


def gaussian_noise(rng: np.random.Generator, shape: tuple[int, int],
                    sigma: float) -> np.ndarray:
    """Zero-mean Gaussian noise of standard deviation `sigma`, float32, by Box-Muller.

    Box-Muller on float32 uniforms costs a third of numpy's float32 ziggurat for a frame
    (log, sqrt, cos, sin are SIMD ufuncs). The float32 uniforms (2^-24 resolution) truncate
    the tail at sqrt(48 ln 2) = 5.77 sigma, i.e. a probability of 8e-9 per sample (0.01
    samples per R79 frame), immaterial for thermal noise that is rounded to LSBs anyway.

    Parameters
    ----------
    rng : numpy.random.Generator
    shape : (rows, cols), rows x cols even
    sigma : float
        Standard deviation, same unit as the output (LSB).

    Returns
    -------
    (rows, cols) float32

    References
    ----------
    .. [1] G. E. P. Box, M. E. Muller, "A note on the generation of random normal deviates",
       Ann. Math. Stat. 29 (1958).
    """
    n = shape[0] * shape[1]
    half = n // 2
    u = rng.random(n, dtype=np.float32)  # [0, 1)
    out = np.empty(n, dtype=np.float32)
    radius, angle = u[:half], u[half:]
    np.subtract(np.float32(1.0), radius, out=radius)  # (0, 1]: log is finite
    np.log(radius, out=radius)
    radius *= np.float32(-2.0 * sigma * sigma)
    np.sqrt(radius, out=radius)
    angle *= np.float32(2 * np.pi)
    np.cos(angle, out=out[:half])
    np.sin(angle, out=out[half:])
    out[:half] *= radius
    out[half:] *= radius
    return out.reshape(shape)


def _signal(cfg: RadarConfig, sc: Scatterers, keep: np.ndarray, power_w: np.ndarray,
            tx_w: np.ndarray) -> np.ndarray:
    """Noise-free IF samples of the kept scatterers, LSB: real, or complex for I/Q modes.

    The tone of scatterer k at chirp c, Rx r, sample n separates into
    M[c, r, k] = slow[c, k] sum_t w[t, c] ant[t, r, k] and F[k, n] = exp(j 2 pi f_k t_n);
    the real frame is Re(M F), one real float32 GEMM: interleaving (Re M, Im M) against
    (Re F, -Im F) rows gives Re M Re F - Im M Im F; the complex frame is M F (complex64 GEMM).

    Parameters
    ----------
    cfg : RadarConfig
    sc : Scatterers
    keep : (K,) bool
        Scatterers to synthesise (K' of them).
    power_w : (K',) float
        Received power per Tx-Rx pair of the kept scatterers, W.
    tx_w : (n_tx, n_chirps) complex
        Transmit weights (`transmit_phasors`).

    Returns
    -------
    (n_chirps x n_rx, n_samples) float32, or complex64 for a complex ADC mode
    """
    n_c, n_r, n_s, n_t = tx_w.shape[1], cfg.n_rx, cfg.n_samples, cfg.n_tx
    r0 = sc.range_m[keep]
    vr = sc.radial_velocity_mps[keep]
    u = sc.unit_vector[keep]
    n_k = r0.shape[0]
    amp = np.sqrt(2 * power_w) * cfg.adc_code_per_sqrt_w  # (K,) sine peak, LSB
    k_wave = 2 * np.pi / cfg.wavelength_m
    # Slow time: -(2 pi / lambda) x two-way path at each chirp, (C, K); phases reduced mod
    # 2 pi in float64 before the float32 cos/sin.
    t_c = _chirp_times_s(cfg, n_c)
    ph = np.mod(-2 * k_wave * (r0[None, :] + t_c[:, None] * vr[None, :]), 2 * np.pi)
    ph = ph.astype(np.float32)
    slow = np.empty((n_c, 1, n_k), dtype=np.complex64)
    slow.real[:, 0] = np.cos(ph)
    slow.imag[:, 0] = np.sin(ph)
    # Antenna: +(2 pi / lambda)(t_t + r_r).u with the amplitude folded in, (T, R, K).
    ph_t = k_wave * cfg.tx_positions_m @ u.T  # (T, K)
    ph_r = k_wave * cfg.rx_positions_m @ u.T  # (R, K)
    ant = amp * np.exp(1j * (ph_t[:, None, :] + ph_r[None, :, :]))
    rx_gain = rx_channel_gain(cfg)
    if rx_gain is not None:  # board imbalance of the Rx channels (Tx: in the weights)
        ant = ant * rx_gain[None, :, None]
    ant = ant.astype(np.complex64)
    # Sum over Tx of transmit weight x antenna term: (C, T) @ (T, R K), then x slow time.
    m = (tx_w.T.astype(np.complex64) @ ant.reshape(n_t, n_r * n_k)).reshape(n_c, n_r, n_k)
    m *= slow
    lhs = m.view(np.float32).reshape(n_c * n_r, 2 * n_k)  # columns Re M_k, Im M_k interleaved
    # Fast time: beat tone at each sample, phase reduced mod 1 cycle in float64, (K, N).
    f_b = _beat_frequency_hz(cfg, sc)[keep]
    t_n = np.arange(n_s) / cfg.adc_rate_sps
    ph_f = (2 * np.pi * np.mod(f_b[:, None] * t_n[None, :], 1.0)).astype(np.float32)
    if cfg.is_complex:
        fast = np.empty((n_k, n_s), dtype=np.complex64)
        fast.real = np.cos(ph_f)
        fast.imag = np.sin(ph_f)
        return m.reshape(n_c * n_r, n_k) @ fast
    rhs = np.empty((n_k, 2, n_s), dtype=np.float32)
    np.cos(ph_f, out=rhs[:, 0])
    np.sin(ph_f, out=rhs[:, 1])
    np.negative(rhs[:, 1], out=rhs[:, 1])
    return lhs @ rhs.reshape(2 * n_k, n_s)


def saturation_fraction(adc: np.ndarray) -> float:
    """Fraction of samples of an int16 frame (or of the I and Q parts of a complex frame)
    sitting at the clipping rails."""
    x = adc.view(np.float32) if np.iscomplexobj(adc) else adc
    return float(np.mean((x >= ADC_FULL_SCALE_CODE) | (x <= -ADC_FULL_SCALE_CODE - 1)))


def expected_sample_snr_db(cfg: RadarConfig, scatterers: Scatterers) -> np.ndarray:
    """(K,) per-sample SNR of each scatterer's tone at the ADC for one Tx-Rx pair, dB:
    P_r / (k T NF B), the same for real and complex ADC modes.

    Coherent gains then add, for a range FFT of N samples (rectangular window; a window's
    processing loss comes on top): real ADC, 10 log10(N / 2) -- the tone A cos(w t) has power
    A^2 / 2 against noise sigma^2 per sample, and its bin gets (A N / 2)^2 against N sigma^2;
    complex ADC, 10 log10(N) -- the front end's tone A exp(j w t) has power A^2 against noise
    sigma^2 on each of I and Q (2 sigma^2, so the per-sample SNR is the real one), and its bin
    gets (A N)^2 against 2 N sigma^2. (Not 10 log10(2 N): the I/Q noise is twice a real
    rail's.) Then 10 log10(chirps) (Doppler FFT) and 10 log10(channels) (angle FFT). Checked
    on simulated frames, `tests/radarsim/test_sample_snr.py`."""
    return 10 * np.log10(received_power_w(cfg, scatterers) / cfg.noise_power_w)


__all__ += ["saturation_fraction", "expected_sample_snr_db", "apply_transmit_errors",
            "code_weights", "rx_channel_gain"]
