"""Phase-shifter calibration as the chip does it: measure every code, then program by table.

`calibrate_shifters` steps each transmitter alone through all 2^bits shifter codes against a
corner reflector at boresight, measures the complex echo at the reflector's range bin (thermal
noise and per-chirp phase noise included), estimates every code's phase and gain relative to
code 0, and returns the config with the measured table in `shifter_calibration_deg`: from then
on `RadarConfig.phase_codes` programs, for each wanted phase, the code whose MEASURED phase is
closest. The hardware error tables are unchanged; the residual is set by the code grid and the
measurement noise (`shifter_phase_residual_deg`).

Measurement model (per Tx k, code q, repeat r): the range-FFT bin of the reflector, summed
coherently over the Rx (boresight: equal phases), is
z = sqrt(SNR) w_k(q) + n with n ~ CN(0, 1), SNR = n_rx (a^2 / 2) / sigma^2 x n_samples / 2 the
bin SNR of a real tone of peak a in noise of std sigma (rectangular window, tone on a bin), and
w_k(q) the radiated transmit weight of the front end (shifter table, static error, per-chirp
phase noise, coupling summed over the elements). ADC rounding (sigma >> 1 LSB) is neglected.

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA], section 4.2: uncalibrated > +/-10 deg,
   calibrated +/-2 deg (AWR2243), ghost 20 dB lower after calibration (figures 7-8).
.. [2] S. M. Kay, Fundamentals of Statistical Signal Processing: Estimation Theory (1993),
   ex. 15.13: phase estimate variance 1 / (2 SNR) for a tone in complex white noise.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from core.errors import BadInput

from .frontend import programmed_codes, received_power_w, wanted_phase_deg
from .radar_config import RadarConfig
from .scene.scatterers import Scatterers
from .shifter import coupling_matrix, phase_residual_deg, shifter_factor, wrap_deg

__all__ = ["calibrate_shifters", "measure_shifters", "ShifterCalibration", "ShifterMeasurement",
           "min_calibration_snr_db", "MAX_CALIBRATION_REPEATS",
           "shifter_phase_residual_deg", "resolve_calibration", "CALIBRATION_REQUEST_KEYS"]

#: Keys of a calibration request (a sweep's ``shifter_calibration_deg = {seed = 0, ...}``): the
#: measurement's generator seed and `calibrate_shifters`' set-up arguments.
CALIBRATION_REQUEST_KEYS = ("seed", "range_m", "rcs_m2", "n_repeats", "thermal_noise")


class ShifterMeasurement(NamedTuple):
    """Per-code shifter measurement relative to code 0.

    phase_error_deg : (n_tx, n_codes) float
        Measured phase of code q minus q LSB, deg, wrapped to [-180, 180).
    gain_error_db : (n_tx, n_codes) float
        Measured amplitude of code q over code 0, dB.
    snr_db : float
        SNR of one chirp's measurement (range bin, summed over Rx), dB.
    """

    phase_error_deg: np.ndarray
    gain_error_db: np.ndarray
    snr_db: float


class ShifterCalibration(NamedTuple):
    """Full output of `calibrate_shifters`.

    config : RadarConfig
        Same hardware tables, `shifter_calibration_deg` set: corrected programmed codes.
    measured_phase_error_deg, measured_gain_error_db : (n_tx, n_codes) float
        The estimated per-code table (relative to code 0).
    residual_deg : (n_tx, P) float
        Programmed-minus-wanted phase of the corrected codes over one code period
        (`shifter_phase_residual_deg`; NaN where a Tx is silent).
    residual_rms_deg, residual_max_deg : float
        rms and max |.| of `residual_deg`.
    residual_before_rms_deg, residual_before_max_deg : float
        The same for the uncalibrated input config.
    snr_db : float
        Per-chirp measurement SNR, dB.
    """

    config: RadarConfig
    measured_phase_error_deg: np.ndarray
    measured_gain_error_db: np.ndarray
    residual_deg: np.ndarray
    residual_rms_deg: float
    residual_max_deg: float
    residual_before_rms_deg: float
    residual_before_max_deg: float
    snr_db: float


#: Most chirps averaged per code: the measurement holds n_tx x n_codes x n_repeats complex
#: samples (4 x 64 x 4096 x 16 B = 16 MiB); beyond it a typo is likelier than a plan.
MAX_CALIBRATION_REPEATS = 4096
#: The per-code phase measurement must be good to a quarter of the shifter's LSB (rms), so the
#: code chosen for a wanted phase is rarely the neighbour of the right one.
CALIBRATION_PHASE_FRACTION_OF_LSB = 0.25


def _check_args(range_m: float, rcs_m2: float, n_repeats: int) -> None:
    if not (isinstance(range_m, (int, float)) and not isinstance(range_m, bool)
            and math.isfinite(range_m) and range_m > 0):
        raise BadInput(f"range_m={range_m!r} must be a finite distance > 0 m")
    if not (isinstance(rcs_m2, (int, float)) and not isinstance(rcs_m2, bool)
            and math.isfinite(rcs_m2) and rcs_m2 > 0):
        raise BadInput(f"rcs_m2={rcs_m2!r} must be > 0")
    if not isinstance(n_repeats, (int, np.integer)) or isinstance(n_repeats, bool) or \
            not 1 <= n_repeats <= MAX_CALIBRATION_REPEATS:
        raise BadInput(f"n_repeats={n_repeats!r} must be an integer in "
                       f"1..{MAX_CALIBRATION_REPEATS}")


def min_calibration_snr_db(cfg: RadarConfig, n_repeats: int) -> float:
    """Least per-chirp SNR, dB, at which `measure_shifters` meets its accuracy.

    A code's phase is the mean of `n_repeats` chirps, each with per-chirp SNR rho (signal
    power over complex noise power), taken relative to code 0: its error is about
    1 / sqrt(rho n_repeats) rad rms (two independent estimates of variance 1 / (2 rho
    n_repeats) each, high-SNR approximation). Requiring at most
    `CALIBRATION_PHASE_FRACTION_OF_LSB` LSB gives rho >= 1 / (n_repeats (f LSB)^2); for the
    AWR2944's 6-bit shifter (LSB 5.625 deg) and 8 repeats that is 23.2 dB.
    """
    sigma_rad = math.radians(CALIBRATION_PHASE_FRACTION_OF_LSB * cfg.phase_lsb_deg)
    return 10 * math.log10(1.0 / (n_repeats * sigma_rad ** 2))


def _measurement_snr(cfg: RadarConfig, range_m: float, rcs_m2: float) -> float:
    """Per-chirp SNR of the reflector's range bin, summed over Rx (linear)."""
    sc = Scatterers(position_m=[[range_m, 0.0, 0.0]], velocity_mps=[[0.0, 0.0, 0.0]],
                    rcs_m2=[rcs_m2])
    a = math.sqrt(2 * received_power_w(cfg, sc)[0]) * cfg.adc_code_per_sqrt_w  # peak, LSB
    return cfg.n_rx * (a * a / 2) / cfg.noise_rms_lsb ** 2 * cfg.n_samples / 2


def _check_snr(cfg: RadarConfig, range_m: float, rcs_m2: float, n_repeats: int) -> None:
    """Refuse a calibration whose measurement SNR is below `min_calibration_snr_db`."""
    snr_db = 10 * math.log10(max(_measurement_snr(cfg, range_m, rcs_m2), 1e-300))
    need = min_calibration_snr_db(cfg, n_repeats)
    if snr_db < need:
        raise BadInput(
            f"shifter calibration: measurement SNR {snr_db:.1f} dB per chirp (reflector "
            f"range_m={range_m:g} m, rcs_m2={rcs_m2:g}, {n_repeats} repeats) is below the "
            f"{need:.1f} dB needed for a per-code phase error of "
            f"{CALIBRATION_PHASE_FRACTION_OF_LSB:g} LSB = "
            f"{CALIBRATION_PHASE_FRACTION_OF_LSB * cfg.phase_lsb_deg:.2f} deg rms: the table "
            "would be measured on noise; move the reflector closer, use a larger one or more "
            "repeats")


def measure_shifters(cfg: RadarConfig, *, rng: np.random.Generator, range_m: float = 4.5,
                     rcs_m2: float = 10.0, n_repeats: int = 8,
                     thermal_noise: bool = True) -> ShifterMeasurement:
    """Measure every code of every Tx against a corner reflector at boresight.

    Parameters
    ----------
    cfg : RadarConfig
        The radar, with its (unknown to the chip) hardware error tables.
    rng : numpy.random.Generator
        Thermal and per-chirp phase noise.
    range_m : float
        Reflector range, m ([TI-DDMA] figures 7-8: about 4.5 m).
    rcs_m2 : float
        Reflector RCS, m^2 (a 10 m^2 trihedral of about 7 cm edge at 77 GHz).
    n_repeats : int
        Chirps averaged per code, 1..`MAX_CALIBRATION_REPEATS`.
    thermal_noise : bool
        False: a noiseless measurement (the per-chirp phase noise of `cfg` still applies).

    Returns
    -------
    ShifterMeasurement

    Raises
    ------
    ValueError
        Bad set-up values (a measurement at any SNR is allowed: `calibrate_shifters` is the
        one that refuses to use a noisy one).
    """
    if not isinstance(cfg, RadarConfig):
        raise BadInput(f"cfg must be a RadarConfig, got {type(cfg).__name__}")
    if not isinstance(rng, np.random.Generator):
        raise BadInput(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    _check_args(range_m, rcs_m2, n_repeats)
    n_tx, n_codes = cfg.n_tx, 2 ** cfg.phase_shifter_bits
    snr = _measurement_snr(cfg, range_m, rcs_m2)
    # Chirps: Tx k alone at code q, repeat r -> weights (n_tx, n_codes, n_repeats).
    codes = np.broadcast_to(np.arange(n_codes)[None, :, None], (n_tx, n_codes, n_repeats))
    flat = codes.reshape(n_tx, -1)
    w = shifter_factor(np.asarray(cfg.shifter_phase_error_deg),
                       np.asarray(cfg.shifter_gain_error_db), flat)
    w = w * np.exp(-1j * np.radians(flat * cfg.phase_lsb_deg))
    w = w * 10 ** (np.asarray(cfg.tx_gain_error_db)[:, None] / 20) * \
        np.exp(1j * np.radians(np.asarray(cfg.tx_phase_error_deg)))[:, None]
    if cfg.phase_noise_deg_rms > 0:
        w = w * np.exp(1j * np.radians(cfg.phase_noise_deg_rms) * rng.standard_normal(w.shape))
    # Boresight: every element's geometric phase is 0, so Tx k radiates sum_j C[j, k] w_k.
    w = w * coupling_matrix(cfg.tx_coupling_db, cfg.tx_coupling_deg).sum(axis=0)[:, None]
    z = math.sqrt(snr) * w
    if thermal_noise:
        z = z + (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)) / math.sqrt(2)
    zq = z.reshape(n_tx, n_codes, n_repeats).mean(axis=-1)
    rel = zq / zq[:, :1]
    phase = wrap_deg(-np.degrees(np.angle(rel)) - np.arange(n_codes) * cfg.phase_lsb_deg)
    return ShifterMeasurement(phase_error_deg=phase,
                              gain_error_db=20 * np.log10(np.abs(rel)),
                              snr_db=10 * math.log10(snr))


def calibrate_shifters(cfg: RadarConfig, *, rng: np.random.Generator, range_m: float = 4.5,
                       rcs_m2: float = 10.0, n_repeats: int = 8, thermal_noise: bool = True,
                       full_output: bool = False) -> RadarConfig | ShifterCalibration:
    """Calibrate the phase shifters: measure every code, then program codes by the table.

    Parameters
    ----------
    cfg : RadarConfig
        Radar with its hardware error tables (`shifter_phase_error_deg`, ...).
    rng : numpy.random.Generator
        Measurement noise.
    range_m, rcs_m2, n_repeats, thermal_noise
        Measurement set-up, see `measure_shifters`.
    full_output : bool
        False: return the corrected config; True: a `ShifterCalibration` with the measured
        tables and the residual before and after.

    Returns
    -------
    RadarConfig or ShifterCalibration
        The config with the SAME hardware error tables and `shifter_calibration_deg` = the
        measured phase table, so `phase_codes()` returns the corrected programmed codes: per
        Tx and chirp of the code period, the code whose measured phase is closest to the wanted
        phase. Residual rms/max: `shifter_phase_residual_deg`.

    Raises
    ------
    ValueError
        Bad measurement set-up; a per-chirp measurement SNR below `min_calibration_snr_db`
        (the message names the measured and the needed SNR: a table measured on noise makes
        the shifters worse, e.g. a reflector at 100 km gives -634 dB and a residual of 3.96 ->
        76.7 deg rms); or `cfg.phase_quantization == "none"` (no codes to choose).
    """
    if not isinstance(cfg, RadarConfig):
        raise BadInput(f"cfg must be a RadarConfig, got {type(cfg).__name__}")
    _check_args(range_m, rcs_m2, n_repeats)
    if thermal_noise:  # before any measurement: a table measured on noise is never used
        _check_snr(cfg, range_m, rcs_m2, n_repeats)
    meas = measure_shifters(cfg, rng=rng, range_m=range_m, rcs_m2=rcs_m2, n_repeats=n_repeats,
                            thermal_noise=thermal_noise)
    out = cfg.replace_fields(shifter_calibration_deg=meas.phase_error_deg)
    if not full_output:
        return out
    res, before = shifter_phase_residual_deg(out), shifter_phase_residual_deg(cfg)
    return ShifterCalibration(
        config=out, measured_phase_error_deg=meas.phase_error_deg,
        measured_gain_error_db=meas.gain_error_db, residual_deg=res,
        residual_rms_deg=float(np.sqrt(np.nanmean(res ** 2))),
        residual_max_deg=float(np.nanmax(np.abs(res))),
        residual_before_rms_deg=float(np.sqrt(np.nanmean(before ** 2))),
        residual_before_max_deg=float(np.nanmax(np.abs(before))), snr_db=meas.snr_db)


def shifter_phase_residual_deg(cfg: RadarConfig) -> np.ndarray:
    """(n_tx, P) phase the shifters really program over the first code period minus the ideal
    programmed phase, relative to each Tx's code 0, deg.

    P = ``cfg.scheme.chirps_per_period(cfg)``. Code-grid rounding plus the table error of the
    chosen code (`radarsim.shifter.phase_residual_deg`); NaN where a Tx is silent. The ideal
    phase is the scheme's code with an ideal shifter (``phase_quantization="none"``).

    Examples
    --------
    >>> import numpy as np, radarsim
    >>> from radarsim.calibration import shifter_phase_residual_deg
    >>> res = shifter_phase_residual_deg(radarsim.presets.r79_ddma())   # floor rule, table 4
    >>> res.shape, float(np.nanmax(np.abs(res)))
    ((4, 6), 3.75)
    """
    p = cfg.scheme.chirps_per_period(cfg)
    wanted, gain = wanted_phase_deg(cfg)
    res = phase_residual_deg(wanted[:, :p], programmed_codes(cfg)[:, :p],
                             np.asarray(cfg.shifter_phase_error_deg), cfg.phase_lsb_deg)
    gain = gain[:, :p]
    return np.where(gain != 0, res, np.nan)


def resolve_calibration(cfg: RadarConfig, request: Mapping | None) -> RadarConfig:
    """`cfg` calibrated as `request` asks: ``{seed[, range_m, rcs_m2, n_repeats,
    thermal_noise]}`` runs `calibrate_shifters` with ``numpy.random.default_rng(seed)``.

    A config is a value and never measures; the harness (a sweep's
    ``shifter_calibration_deg = {seed = 0}``) and the CLI call this for it. None returns `cfg`.

    Raises
    ------
    ValueError
        A seed that is not an integer >= 0, unknown keys, or a bad measurement set-up; every
        message starts with ``shifter_calibration_deg:``.

    Examples
    --------
    >>> import radarsim
    >>> from radarsim.calibration import resolve_calibration
    >>> cfg = radarsim.presets.r79_ddma(shifter={
    ...     "shifter_phase_error_deg": {"distribution": "inl_dnl", "rms": 10.0, "seed": 5}})
    >>> cal = resolve_calibration(cfg, {"seed": 0})
    >>> cal.shifter_calibration_deg is not None and cfg.shifter_calibration_deg is None
    True
    >>> radarsim.presets.r79_ddma(**{"shifter.shifter_calibration_deg": {"seed": 0}})
    Traceback (most recent call last):
    ...
    core.errors.BadInput: shifter_calibration_deg={'seed': 0} is a calibration request, not a
    measured ...
    """
    if request is None:
        return cfg
    if not isinstance(request, Mapping):
        raise BadInput(f"shifter_calibration_deg: a calibration request is a table "
                       f"{{seed, ...}}, got {request!r}")
    kw = dict(request)
    seed = kw.pop("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise BadInput(f"shifter_calibration_deg: seed={seed!r} must be an integer >= 0")
    bad = sorted(set(kw) - set(CALIBRATION_REQUEST_KEYS))
    if bad:
        raise BadInput(f"shifter_calibration_deg: bad calibration spec {dict(request)!r} "
                       f"(unknown key(s) {bad}; known: {list(CALIBRATION_REQUEST_KEYS)})")
    try:
        return calibrate_shifters(cfg, rng=np.random.default_rng(seed), **kw)
    except TypeError as exc:
        raise BadInput(f"shifter_calibration_deg: bad calibration spec {dict(request)!r} "
                       f"({exc})") from None
    except ValueError as exc:
        raise BadInput(f"shifter_calibration_deg: {exc}") from None
