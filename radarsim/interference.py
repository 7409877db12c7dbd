"""FMCW-FMCW mutual interference: other radars' direct paths into the victim's ADC.

Every interferer is a chirping radar on another vehicle. Its signal reaches the victim one way
(spreading 1/R^2, not 1/R^4) and, after the victim's mixer, appears at the instantaneous
difference frequency

    f_d(t) = f_v(t) - f_i(t - tau),   f_v(t) = f0_v + S_v (t - T_c),   f_i(t) = f0_i + S_i (t - A_m)

(victim chirp c starting its ramp at T_c, interferer ramp m starting at A_m, one-way delay
tau = R / c). Whenever |f_d| falls inside the victim's IF passband (B_IF: the receiver's IF
corner, `receiver.if_corner_hz`) the ADC sees a short chirped burst; its duration is
2 B_IF / |S_v - S_i| and it is centred on the crossing time where f_d = 0. An I/Q receiver
(complex ADC modes) sees the analytic burst, and in complex 1x, whose image band is filtered,
only its f_d > 0 half (B_IF / |S_v - S_i|, starting at the crossing). With equal slopes f_d is
constant: a tone, i.e. a ghost target (at the one-way
Doppler -v_r / lambda, half the echo's) instead of a raised noise floor.

Signal model (per interferer i, victim chirp c, Rx r, sample time t inside the ADC window)::

    x = A_i sqrt(H(f_d(t))) cos(psi(t) + k r_r . u_i)
    psi(t) = 2 pi [f0_v u + S_v u^2 / 2 - f0_i (w0 + tau_c) - S_i (w0 - tau_c)^2 / 2] - theta_i

with u = t - T_c, w0 = t - A_m, tau_c = (R_i + v_r,i t_c) / c at the chirp's time t_c (frame
middle = 0, as the echoes), A_i = sqrt(2 P_r,i) x the ADC scale and H the victim's IF low-pass
power response (`receiver.if_filter_gain`) at the instantaneous frequency (quasi-static: valid
while |S_v - S_i| << B_IF^2, 1e13 Hz/s against 2.7e14 Hz^2 here). Each radar's phase restarts
with every ramp (the textbook FMCW model) and theta_i is the interferer's fixed phase offset.
The carrier terms (f0_i tau and the Rx term) carry the same sign convention as the victim's own
echoes (design.md 3: -(2 pi / lambda) x path in the positive-frequency bins), so a same-slope ghost
appears at the interferer's direction and at its one-way range and Doppler.

Received power (one-way radar equation, Friis):

    P_r = P_t,i G_t,i(toward victim) G_r,v(az, el) lambda^2 / ((4 pi R)^2 L_sys)

Synthesis is sparse and vectorised: per interferer, the (victim chirp, interferer ramp) pairs
that overlap are found in closed form, the sample span where |f_d| is below twice the IF corner
(-60 dB) is solved analytically, and only those samples are generated (one flat array over all
pairs, no Python loop over chirps or samples).

References
----------
.. [1] M. Kunert et al., "Study on the state-of-the-art interference effects" (MOSARIM D1.5),
       2012: FMCW-FMCW burst duration and power.
.. [2] TI SWRA725, "Interference mitigation for AWR294x", sec. 2 (crossing interference).
.. [3] G. M. Brooker, "Mutual interference of millimeter-wave radar systems", IEEE Trans.
       EMC 49(1), 2007 (one-way link budget).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from core.errors import BadInput

from .antenna import element_gain_linear
from .chips import ADC_MODES
from .radar_config import C_MPS, RadarConfig
from .receiver import IF_LOWPASS_ORDER, if_corner_hz
from .scene.scatterers import PointGeometry

__all__ = ["Interferers", "received_power_w", "interference_to_noise_db", "synthesize",
           "burst_windows", "interferers_from_truth", "EQUIPMENT_COLUMNS", "PASSBAND_FACTOR",
           "INTERFERER_BOUNDS", "MAX_INTERFERER_RANGE_M"]

#: Bursts are synthesised while |f_d| < PASSBAND_FACTOR x the IF corner: the order-10
#: Butterworth is 60 dB down at twice its corner, so nothing audible is cut.
PASSBAND_FACTOR = 2.0


def _passband_hz(cfg: RadarConfig) -> tuple[float, float]:
    """(lowest, highest) difference frequency f_d the victim's receiver passes, Hz: +/-
    PASSBAND_FACTOR x its IF corner (`receiver.if_corner_hz`, the echoes' low-pass), from 0 Hz
    up only when the ADC mode rejects the image band (complex 1x)."""
    hi = PASSBAND_FACTOR * if_corner_hz(cfg)
    return (0.0 if ADC_MODES[cfg.adc_mode].image_rejected else -hi), hi

#: Columns of the per-actor equipment table `interferers_from_truth` joins on ``actor_id``
#: (one row per equipped actor; mount in the actor's vehicle frame, waveform in SI units).
EQUIPMENT_COLUMNS = ["actor_id", "mount_x_m", "mount_y_m", "mount_z_m", "mount_yaw_deg",
                     "start_freq_hz", "slope_hz_per_s", "chirp_period_s", "ramp_time_s",
                     "chirp_offset_s", "tx_power_dbm", "antenna_gain_dbi",
                     "pattern_exponent_az", "pattern_exponent_el", "phase_rad"]


#: Physical bounds of every interferer parameter, both sides (inclusive), with the reason.
#: They are checked before anything is synthesised: a period of 1e-15 s would ask for 1e10
#: bursts per victim chirp, an offset of 1e300 s loses every digit of the burst timing (the
#: interferer silently vanishes), a power of -1e300 dBm is no radar.
INTERFERER_BOUNDS: dict[str, tuple[float, float, str]] = {
    "radial_velocity_mps": (-200.0, 200.0, "m/s (two vehicles at 360 km/h each)"),
    "tx_gain_dbi": (-300.0, 40.0, "dBi (-300: a pattern null or blocked direction)"),
    "start_freq_hz": (60e9, 90e9, "Hz (automotive radar bands 76-81 GHz, with margin)"),
    "slope_hz_per_s": (-1e15, 1e15, "Hz/s (|slope| <= 1000 MHz/us)"),
    "chirp_period_s": (1e-6, 1e-2, "s (FMCW chirps repeat every 1 us .. 10 ms)"),
    "ramp_time_s": (1e-7, 1e-2, "s"),
    "chirp_offset_s": (-1.0, 1.0, "s (ramps repeat every period: an offset beyond a frame "
                                  "period means nothing more)"),
    "tx_power_dbm": (-40.0, 30.0, "dBm (a radar transmitter's port power)"),
    "phase_rad": (-1e3, 1e3, "rad"),
}
#: Farthest interferer, m (a one-way path: beyond it the power is far under any noise floor,
#: and the path delay must stay well inside a chirp period's float64 precision).
MAX_INTERFERER_RANGE_M = 10_000.0


def _vec(name: str, value, n: int | None, dtype=np.float64) -> np.ndarray:
    a = np.asarray(value, dtype=dtype).reshape(-1)
    if n is not None and a.size != n:
        raise BadInput(f"{name} has {a.size} entries, expected {n} (one per interferer)")
    if not np.all(np.isfinite(a)):
        raise BadInput(f"{name} must be finite, got {a!r}")
    if name in INTERFERER_BOUNDS:
        lo, hi, unit = INTERFERER_BOUNDS[name]
        bad = (a < lo) | (a > hi)
        if bad.any():
            i = int(np.argmax(bad))
            raise BadInput(f"{name}={float(a[i])!r} (interferer {i}) is outside [{lo:g}, {hi:g}] "
                           f"{unit}")
    return a


@dataclass(frozen=True, init=False)
class Interferers(PointGeometry):
    """I interfering radars as seen by the victim in one frame (struct of arrays).

    Parameters
    ----------
    position_m : (I, 3) float
        Interferer antenna position at the frame's reference time (middle of the burst),
        victim radar frame, m (range >= 0.1 m).
    radial_velocity_mps : (I,) float
        d(range)/dt of the interferer seen from the victim, m/s.
    tx_gain_dbi : (I,) float
        The interferer's transmit antenna gain toward the victim (its pattern included), dBi.
    start_freq_hz, slope_hz_per_s : (I,) float
        Interferer ramp start frequency and slope (negative slope: down-chirp), Hz, Hz/s.
    chirp_period_s, ramp_time_s : (I,) float
        Interferer chirp repetition period and active ramp duration (<= period), s.
    chirp_offset_s : (I,) float
        Start of the interferer's ramp 0 relative to the victim's first ramp start, s (any
        sign; ramps repeat every period before and after).
    tx_power_dbm : (I,) float
        Interferer power at its antenna port, dBm.
    phase_rad : (I,) float, optional
        Fixed phase offset theta_i of each interferer, rad (default 0).
    visible : (I,) bool, optional
        False where another actor blocks the direct path (default all True).

    Raises
    ------
    ValueError
        On wrong shapes, non-finite values, a value outside `INTERFERER_BOUNDS` (both sides:
        periods, offsets, powers, gains, frequencies, slopes, speeds), a range outside
        [0.1, `MAX_INTERFERER_RANGE_M`] m, or a ramp longer than its period.
    """

    position_m: np.ndarray
    radial_velocity_mps: np.ndarray
    tx_gain_dbi: np.ndarray
    start_freq_hz: np.ndarray
    slope_hz_per_s: np.ndarray
    chirp_period_s: np.ndarray
    ramp_time_s: np.ndarray
    chirp_offset_s: np.ndarray
    tx_power_dbm: np.ndarray
    phase_rad: np.ndarray
    visible: np.ndarray

    def __init__(self, *, position_m, radial_velocity_mps, tx_gain_dbi, start_freq_hz,
                 slope_hz_per_s, chirp_period_s, ramp_time_s, chirp_offset_s, tx_power_dbm,
                 phase_rad=None, visible=None) -> None:
        pos = np.asarray(position_m, dtype=np.float64).reshape(-1, 3)
        if not np.all(np.isfinite(pos)):
            raise BadInput("position_m must be finite")
        n = pos.shape[0]
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731
        set_("position_m", pos)
        for name, val in (("radial_velocity_mps", radial_velocity_mps),
                          ("tx_gain_dbi", tx_gain_dbi), ("start_freq_hz", start_freq_hz),
                          ("slope_hz_per_s", slope_hz_per_s),
                          ("chirp_period_s", chirp_period_s), ("ramp_time_s", ramp_time_s),
                          ("chirp_offset_s", chirp_offset_s), ("tx_power_dbm", tx_power_dbm),
                          ("phase_rad", np.zeros(n) if phase_rad is None else phase_rad)):
            set_(name, _vec(name, val, n))
        vis = np.ones(n, dtype=bool) if visible is None else \
            np.asarray(visible, dtype=bool).reshape(-1)
        if vis.size != n:
            raise BadInput(f"visible has {vis.size} entries, expected {n}")
        set_("visible", vis)
        rng_m = np.linalg.norm(pos, axis=1)
        if n and not (0.1 <= rng_m.min() and rng_m.max() <= MAX_INTERFERER_RANGE_M):
            raise BadInput(f"interferer range must be in [0.1, {MAX_INTERFERER_RANGE_M:g}] m "
                           f"(position_m), got {rng_m.min():g}..{rng_m.max():g} m")
        if np.any(self.ramp_time_s > self.chirp_period_s * (1 + 1e-9)):
            raise BadInput("ramp_time_s must be <= chirp_period_s")

    def __len__(self) -> int:
        return self.position_m.shape[0]

    def subset(self, mask: np.ndarray) -> "Interferers":
        """The interferers where `mask` is True."""
        m = np.asarray(mask, dtype=bool)
        return Interferers(position_m=self.position_m[m],
                           radial_velocity_mps=self.radial_velocity_mps[m],
                           tx_gain_dbi=self.tx_gain_dbi[m], start_freq_hz=self.start_freq_hz[m],
                           slope_hz_per_s=self.slope_hz_per_s[m],
                           chirp_period_s=self.chirp_period_s[m], ramp_time_s=self.ramp_time_s[m],
                           chirp_offset_s=self.chirp_offset_s[m],
                           tx_power_dbm=self.tx_power_dbm[m], phase_rad=self.phase_rad[m],
                           visible=self.visible[m])


def received_power_w(cfg: RadarConfig, itf: Interferers) -> np.ndarray:
    """Interference power at the victim's ADC input per Rx inside the IF passband, W.

    P_r = P_t G_t lambda^2 G_r(az, el) / ((4 pi R)^2 L_sys) (one-way radar equation); zero where
    the direct path is blocked. lambda is the victim's wavelength; L_sys the victim's lumped
    system loss (radome, cabling, implementation), as in its echo budget.

    Returns
    -------
    (I,) float
        Power, W.
    """
    if len(itf) == 0:
        return np.zeros(0)
    u = itf.unit_vector
    az = np.arctan2(u[:, 1], u[:, 0])
    el = np.arcsin(np.clip(u[:, 2], -1.0, 1.0))
    gr = element_gain_linear(cfg, az, el, cfg.rx_antenna_gain_dbi)
    pt = 1e-3 * 10 ** (itf.tx_power_dbm / 10)
    gt = 10 ** (itf.tx_gain_dbi / 10)
    loss = 10 ** (cfg.system_loss_db / 10)
    pr = pt * gt * gr * cfg.wavelength_m ** 2 / ((4 * np.pi * itf.range_m) ** 2 * loss)
    return np.where(itf.visible, pr, 0.0)


def interference_to_noise_db(cfg: RadarConfig, itf: Interferers) -> float:
    """In-burst interference-to-noise ratio at the victim's ADC, dB: the summed passband power
    of the visible interferers whose sweep crosses the victim's IF band during the frame, over
    the thermal noise k T NF B. NaN when no interferer makes a burst."""
    if not len(itf):
        return float("nan")
    pw = received_power_w(cfg, itf)
    live = [i for i in np.flatnonzero(pw > 0) if _bursts(cfg, itf, i).count.size]
    p = float(np.sum(pw[live])) if live else 0.0
    return 10 * math.log10(p / cfg.noise_power_w) if p > 0 else float("nan")


def _victim_times(cfg: RadarConfig):
    """Victim timing: ramp start of every chirp (first ramp at 0), ADC sample offsets within
    the ramp, chirp time relative to the frame middle (the echoes' t_c)."""
    return tuple(cfg.scheme.chirp_timing(cfg))  # the scheme owns the chirp periods


class _Bursts:
    """Sample spans of one interferer: (chirp, first sample, sample count, ramp start)."""

    __slots__ = ("chirp", "n0", "count", "ramp_start_s", "tau_s")

    def __init__(self, chirp, n0, count, ramp_start_s, tau_s):
        self.chirp, self.n0, self.count = chirp, n0, count
        self.ramp_start_s, self.tau_s = ramp_start_s, tau_s


def _bursts(cfg: RadarConfig, itf: Interferers, i: int) -> _Bursts:
    """Closed-form sample spans of interferer i inside the victim's passband, all chirps."""
    fs = cfg.adc_rate_sps
    n_s = cfg.n_samples
    ramp_start, t_c = _victim_times(cfg)
    tau = (itf.range_m[i] + itf.radial_velocity_mps[i] * t_c) / C_MPS  # (C,)
    t_first = ramp_start + cfg.adc_start_time_s  # absolute time of sample 0 per chirp
    t_last = t_first + (n_s - 1) / fs
    per, tr, off = itf.chirp_period_s[i], itf.ramp_time_s[i], itf.chirp_offset_s[i]
    # Interferer ramps m whose delayed span [A_m + tau, A_m + tau + Tr] meets the ADC window.
    m_lo = np.floor((t_first - tau - off - tr) / per).astype(np.int64) + 1
    m_hi = np.floor((t_last - tau - off) / per).astype(np.int64)
    n_m = np.maximum(m_hi - m_lo + 1, 0)
    chirp = np.repeat(np.arange(cfg.n_chirps), n_m)
    m = m_lo[chirp] + (np.arange(chirp.size) - np.repeat(np.cumsum(n_m) - n_m, n_m))
    a_m = off + m * per
    tau_p = tau[chirp]
    # Time span where the delayed ramp is active.
    lo = a_m + tau_p
    hi = a_m + tau_p + tr
    # f_d(t) = f0_v - f0_i + S_v (t - T_c) - S_i (t - tau - A_m) = alpha + dS t.
    ds = cfg.slope_hz_per_s - itf.slope_hz_per_s[i]
    alpha = (cfg.start_freq_hz - itf.start_freq_hz[i] - cfg.slope_hz_per_s * ramp_start[chirp]
             + itf.slope_hz_per_s[i] * (tau_p + a_m))
    f_lo, f_hi = _passband_hz(cfg)
    if abs(ds) > 0:
        t_a = (f_lo - alpha) / ds
        t_b = (f_hi - alpha) / ds
        lo = np.maximum(lo, np.minimum(t_a, t_b))
        hi = np.minimum(hi, np.maximum(t_a, t_b))
    else:
        inside = (alpha > f_lo) & (alpha < f_hi)
        hi = np.where(inside, hi, lo - 1.0)  # empty span
    t0 = t_first[chirp]
    # Clipped in float before the integer cast (spans may be empty or far outside).
    n0 = np.clip(np.ceil((lo - t0) * fs - 1e-9), 0, n_s).astype(np.int64)
    n1 = np.clip(np.floor((hi - t0) * fs + 1e-9), -1, n_s - 1).astype(np.int64) + 1
    count = np.maximum(n1 - n0, 0)
    keep = count > 0
    return _Bursts(chirp[keep], n0[keep], count[keep], a_m[keep], tau_p[keep])


def burst_windows(cfg: RadarConfig, itf: Interferers) -> pd.DataFrame:
    """Where the bursts of each interferer fall in the victim frame.

    Returns
    -------
    pandas.DataFrame
        One row per (interferer, victim chirp, interferer ramp) overlap with a burst:
        ``interferer``, ``chirp``, ``first_sample``, ``n_samples``, ``crossing_time_s`` (time
        of f_d = 0 after the victim's ramp start; NaN for equal slopes).
    """
    rows = []
    ramp_start, _ = _victim_times(cfg)
    for i in range(len(itf)):
        b = _bursts(cfg, itf, i)
        ds = cfg.slope_hz_per_s - itf.slope_hz_per_s[i]
        alpha = (cfg.start_freq_hz - itf.start_freq_hz[i] - cfg.slope_hz_per_s
                 * ramp_start[b.chirp] + itf.slope_hz_per_s[i] * (b.tau_s + b.ramp_start_s))
        cross = -alpha / ds - ramp_start[b.chirp] if ds else np.full(b.chirp.size, np.nan)
        rows.append(pd.DataFrame({"interferer": i, "chirp": b.chirp, "first_sample": b.n0,
                                  "n_samples": b.count, "crossing_time_s": cross}))
    if not rows:
        return pd.DataFrame({c: pd.Series(dtype=float) for c in (
            "interferer", "chirp", "first_sample", "n_samples", "crossing_time_s")})
    return pd.concat(rows, ignore_index=True)


def synthesize(cfg: RadarConfig, itf: Interferers, out: np.ndarray | None = None,
               analytic: bool = False) -> np.ndarray:
    """Interference samples at the victim's ADC (before rounding and clipping), LSB.

    Parameters
    ----------
    cfg : RadarConfig
        The victim radar.
    itf : Interferers
    out : (n_chirps x n_rx, n_samples) float32, optional
        Buffer to add into (the front end's noise buffer); a new zero array if None. For a
        complex ADC mode: complex64, or float32 (n_chirps x n_rx, 2 n_samples) of interleaved
        I and Q (the front end's buffer).
    analytic : bool
        Return the complex analytic samples A sqrt(H) exp(j psi) instead (tests, metrics);
        `out` must then be None.

    Returns
    -------
    (n_chirps x n_rx, n_samples) float32 for a real ADC; complex64 I/Q samples
    A sqrt(H) exp(j psi) for a complex ADC mode or when `analytic` (the I/Q receiver sees the
    analytic signal: positive f_d in the positive-frequency bins, as the echoes)
    """
    n_c, n_r, n_s = cfg.n_chirps, cfg.n_rx, cfg.n_samples
    cplx = analytic or cfg.is_complex
    if out is None:
        out = np.zeros((n_c * n_r, n_s), dtype=np.complex64 if cplx else np.float32)
    elif analytic:
        raise BadInput("analytic=True builds its own output; pass out=None")
    flat = out.view(np.complex64) if cplx and out.dtype == np.float32 else out
    if flat.shape != (n_c * n_r, n_s) or flat.dtype != (np.complex64 if cplx else np.float32):
        raise BadInput(f"out has shape {out.shape} and dtype {out.dtype}; the "
                       f"{cfg.adc_mode} ADC needs {n_c * n_r} rows of {n_s} "
                       f"{'complex' if cplx else 'real'} samples")
    flat = flat.reshape(-1)
    if len(itf) == 0:
        return out
    power = received_power_w(cfg, itf)
    amp = np.sqrt(2 * power) * cfg.adc_code_per_sqrt_w  # (I,) sine peak, LSB
    u = itf.unit_vector
    k_wave = 2 * np.pi / cfg.wavelength_m
    rx_phase = k_wave * (u @ cfg.rx_positions_m.T)  # (I, R)
    ramp_start, _ = _victim_times(cfg)
    fs = cfg.adc_rate_sps
    row_off = (np.arange(n_r) * n_s).astype(np.int64)  # flat offset of each Rx row
    fc = np.float32(1.0 / if_corner_hz(cfg))
    for i in np.flatnonzero(amp > 0):  # a loop over interferers only
        b = _bursts(cfg, itf, i)
        total = int(b.count.sum())
        if total == 0:
            continue
        # Per burst (float64): phase (cycles) and instantaneous frequency at its first sample;
        # within a burst psi is exactly quadratic in the sample index k.
        f0v, sv = cfg.start_freq_hz, cfg.slope_hz_per_s
        f0i, si = itf.start_freq_hz[i], itf.slope_hz_per_s[i]
        u0 = cfg.adc_start_time_s + b.n0 / fs                     # t - T_c at the first sample
        w00 = ramp_start[b.chirp] + u0 - b.ramp_start_s           # t - A_m
        w_0 = w00 - b.tau_s
        c0 = (np.mod(f0v * u0, 1.0) + np.mod(0.5 * sv * u0 * u0, 1.0)
              - np.mod(f0i * (w00 + b.tau_s), 1.0) - np.mod(0.5 * si * w_0 * w_0, 1.0)
              - itf.phase_rad[i] / (2 * np.pi))
        fd0 = f0v + sv * u0 - f0i - si * w_0                      # Hz
        c1 = fd0 / fs                                             # cycles per sample
        c2 = np.float32((sv - si) / (2 * fs * fs))                # cycles per sample^2
        dfd = np.float32((sv - si) / fs)                          # Hz per sample
        pair = np.repeat(np.arange(b.chirp.size), b.count)
        k = (np.arange(total) - np.repeat(np.cumsum(b.count) - b.count, b.count)) \
            .astype(np.float32)
        cyc = np.mod(c0, 1.0).astype(np.float32)[pair] + k * (c1.astype(np.float32)[pair]
                                                              + c2 * k)
        psi = np.float32(2 * np.pi) * (cyc - np.floor(cyc))
        f_d = fd0.astype(np.float32)[pair] + dfd * k
        env = np.float32(amp[i]) / np.sqrt(np.float32(1) + (np.abs(f_d) * fc)
                                           ** (2 * IF_LOWPASS_ORDER))
        base = (b.chirp * (n_r * n_s) + b.n0)[pair] + k.astype(np.int64)   # Rx 0 flat index
        cos_p, sin_p = env * np.cos(psi), env * np.sin(psi)
        for r in range(n_r):  # 4 receivers: x_r = env cos(psi + phi_r)
            cr, sr = np.float32(math.cos(rx_phase[i, r])), np.float32(math.sin(rx_phase[i, r]))
            if cplx:
                flat[base + row_off[r]] += (cos_p * cr - sin_p * sr) \
                    + 1j * (sin_p * cr + cos_p * sr)
            else:
                flat[base + row_off[r]] += cos_p * cr - sin_p * sr
    return out


def interferers_from_truth(cfg: RadarConfig, truth_frame: pd.DataFrame,
                          equipment: pd.DataFrame, *, occlusion: bool = True) -> Interferers:
    """Interferers of one frame: equipped actors' radars seen from the victim.

    Parameters
    ----------
    cfg : RadarConfig
        The victim (only its pattern settings are used here; the interferer pattern is a
        cosine power pattern with its own exponents).
    truth_frame : pandas.DataFrame
        Truth rows of one frame with the radar-frame columns (``actor_id``, ``x_radar_m``,
        ``y_radar_m``, ``z_radar_m``, ``yaw_radar_deg``, ``vx_radar_mps``, ``vy_radar_mps``,
        ``length_m``, ``width_m``, ``height_m``).
    equipment : pandas.DataFrame
        `EQUIPMENT_COLUMNS`, one row per equipped actor (mount in the actor's vehicle frame,
        height above the ground).
    occlusion : bool
        Block a direct path that passes through another actor's box (ray-box slab test of
        `raycast.ray_box_intersect`, all interferer x box pairs at once).

    Returns
    -------
    Interferers
        One per equipped actor present in the frame, in ``actor_id`` order.
    """
    from .scene.raycast import ray_box_intersect

    missing = [c for c in EQUIPMENT_COLUMNS if c not in equipment.columns]
    if missing:
        raise BadInput(f"equipment lacks columns {missing}")
    rows = truth_frame.merge(equipment, on="actor_id", how="inner").sort_values("actor_id")
    if rows.empty:
        return _empty()
    yaw = np.radians(rows["yaw_radar_deg"].to_numpy(float))
    cy, sy = np.cos(yaw), np.sin(yaw)
    mx, my = rows["mount_x_m"].to_numpy(float), rows["mount_y_m"].to_numpy(float)
    ground_z = rows["z_radar_m"].to_numpy(float) - 0.5 * rows["height_m"].to_numpy(float)
    pos = np.column_stack([rows["x_radar_m"].to_numpy(float) + cy * mx - sy * my,
                           rows["y_radar_m"].to_numpy(float) + sy * mx + cy * my,
                           ground_z + rows["mount_z_m"].to_numpy(float)])
    r = np.linalg.norm(pos, axis=1)
    u = pos / np.maximum(r, 1e-9)[:, None]
    vel = np.column_stack([rows["vx_radar_mps"], rows["vy_radar_mps"]]).astype(float)
    v_r = np.sum(vel * u[:, :2], axis=1)
    # The victim seen from the interferer: -u rotated into the interferer's boresight frame.
    b_yaw = yaw + np.radians(rows["mount_yaw_deg"].to_numpy(float))
    dx, dy, dz = -u[:, 0], -u[:, 1], -u[:, 2]
    lx = np.cos(b_yaw) * dx + np.sin(b_yaw) * dy
    ly = -np.sin(b_yaw) * dx + np.cos(b_yaw) * dy
    az_i = np.arctan2(ly, lx)
    el_i = np.arcsin(np.clip(dz, -1.0, 1.0))
    g_pat = np.clip(np.cos(az_i), 0, None) ** rows["pattern_exponent_az"].to_numpy(float) * \
        np.clip(np.cos(el_i), 0, None) ** rows["pattern_exponent_el"].to_numpy(float)
    with np.errstate(divide="ignore"):
        g_db = rows["antenna_gain_dbi"].to_numpy(float) + 10 * np.log10(g_pat)
    visible = g_pat > 0
    g_db = np.where(visible, g_db, -300.0)
    if occlusion and len(truth_frame) > 1:
        tf = truth_frame
        centres = np.column_stack([tf["x_radar_m"], tf["y_radar_m"], tf["z_radar_m"]]) \
            .astype(float)
        half = 0.5 * np.column_stack([tf["length_m"], tf["width_m"], tf["height_m"]]) \
            .astype(float)
        t_hit, _ = ray_box_intersect(u, centres, half,
                                     np.radians(tf["yaw_radar_deg"].to_numpy(float)))
        own = rows["actor_id"].to_numpy()[:, None] == tf["actor_id"].to_numpy()[None, :]
        blocked = np.any((t_hit < r[:, None] - 0.05) & ~own, axis=1)
        visible &= ~blocked
    return Interferers(position_m=pos, radial_velocity_mps=v_r, tx_gain_dbi=g_db,
                       start_freq_hz=rows["start_freq_hz"].to_numpy(float),
                       slope_hz_per_s=rows["slope_hz_per_s"].to_numpy(float),
                       chirp_period_s=rows["chirp_period_s"].to_numpy(float),
                       ramp_time_s=rows["ramp_time_s"].to_numpy(float),
                       chirp_offset_s=rows["chirp_offset_s"].to_numpy(float),
                       tx_power_dbm=rows["tx_power_dbm"].to_numpy(float),
                       phase_rad=rows["phase_rad"].to_numpy(float), visible=visible)


def _empty() -> Interferers:
    z = np.zeros(0)
    return Interferers(position_m=np.zeros((0, 3)), radial_velocity_mps=z, tx_gain_dbi=z,
                       start_freq_hz=z, slope_hz_per_s=z, chirp_period_s=z, ramp_time_s=z,
                       chirp_offset_s=z, tx_power_dbm=z)


Interferers.empty = staticmethod(_empty)  # type: ignore[attr-defined]
