"""Radar configuration: waveform, chip, board, ADC mode, DDMA/TDMA schedule and RF budget.

`RadarConfig` is the single description of a radar that every stage reads. It is a frozen
dataclass with units in its field names; it names its chip (`radarsim.chips.CHIPS`) and board
(`radarsim.boards.BOARDS`), and every chip or method limit (DESIGN section 4.4, each chip's own
values) is checked at construction and named in the error. Derived quantities (resolutions,
unambiguous velocity, phase codes, virtual array) are read-only properties.

References
----------
.. [1] TI, "AWR2944 DDMA waveform for corner radar" (seed 000), tables 2-4, figure 20, eq. 1-10.
.. [2] TI, "AWR1642 velocity disambiguation" (seed 001), TDMA Vmax = lambda / (4 Nt Tc).
"""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .boards import get_board
from .chips import ADC_MODES, CHIPS, get_chip
from scenarios.checks import require

from . import shifter as _shifter
from .mimo import MIMO_SCHEMES, MimoScheme, scheme_of

__all__ = [
    "RadarConfig", "MIMO_SCHEMES", "PHASE_QUANTIZATIONS", "ANTENNA_PATTERNS", "ADC_MODES",
    "C_MPS", "K_BOLTZMANN", "MAX_ADC_RATE_SPS", "MAX_IF_BANDWIDTH_HZ", "BAND_MIN_HZ",
    "BAND_MAX_HZ",
]

C_MPS = 299_792_458.0
K_BOLTZMANN = 1.380649e-23
# The AWR2944's limits, kept for callers of the single-chip era; configs use their chip's.
MAX_ADC_RATE_SPS = CHIPS["AWR2944"].adc["real"].max_rate_sps
MAX_IF_BANDWIDTH_HZ = CHIPS["AWR2944"].if_bandwidth_hz
BAND_MIN_HZ = CHIPS["AWR2944"].band_min_hz
BAND_MAX_HZ = CHIPS["AWR2944"].band_max_hz
MAX_N_TX = CHIPS["AWR2944"].n_tx
MAX_N_RX = CHIPS["AWR2944"].n_rx
ADC_FULL_SCALE_CODE = 32767

#: How a programmed phase is mapped onto the shifter's codes (`radarsim.shifter`).
PHASE_QUANTIZATIONS = _shifter.PHASE_QUANTIZATIONS
#: Element gain patterns.
ANTENNA_PATTERNS = {
    "cosine": "power gain G0 cos(az)^n_az cos(el)^n_el inside +/-90 deg, 0 behind",
    "isotropic": "G0 in every direction (tests)",
}

# Fields re-derived by `replace` when the field they depend on changes and they are not given.
_DEPENDENT_FIELDS = {
    "n_tx": ("tx_order", "n_subbands", "tx_phase_error_deg", "tx_gain_error_db", "tx_channels",
             "shifter_phase_error_deg", "shifter_gain_error_db", "tx_coupling_db",
             "tx_coupling_deg", "shifter_calibration_deg"),
    "mimo": ("tx_order", "n_subbands"),
    "n_rx": ("rx_channels", "rx_phase_error_deg", "rx_gain_error_db"),
    "chip": ("board", "phase_shifter_bits", "adcbuf_interleaved", "tx_positions_wl",
             "rx_positions_wl", "pattern_exponent_az", "pattern_exponent_el"),
    "board": ("tx_positions_wl", "rx_positions_wl", "pattern_exponent_az",
              "pattern_exponent_el"),
}


def _positions(value, n: int, name: str) -> tuple[tuple[float, float], ...]:
    try:
        pos = tuple((float(y), float(z)) for y, z in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}={value!r} must be a sequence of (y, z) pairs in "
                         "wavelengths") from None
    if len(pos) != n or not all(math.isfinite(c) for p in pos for c in p):
        raise ValueError(f"{name} must hold {n} finite (y, z) pairs (one per chip channel), "
                         f"got {value!r}")
    return pos


def _integers(value, name: str, what: str) -> tuple[int, ...]:
    """A sequence of integers, refused (not coerced) otherwise: ``(1.7, 3.9)`` must not become
    (1, 3), nor the string ``'1342'`` the tuple (1, 3, 4, 2)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__") or not all(
            isinstance(c, (int, np.integer)) and not isinstance(c, (bool, np.bool_))
            for c in value):
        raise ValueError(f"{name}={value!r} must be a sequence of integers ({what})")
    return tuple(int(c) for c in value)


def _channels(value, n: int, n_chip: int, name: str, chip: str) -> tuple[int, ...]:
    if value is None:
        return tuple(range(1, n + 1))
    chans = _integers(value, name, f"{n} distinct channel numbers in 1..{n_chip}")
    if len(chans) != n or len(set(chans)) != n or not all(1 <= c <= n_chip for c in chans):
        raise ValueError(f"{name}={value!r} must list {n} distinct channel numbers in "
                         f"1..{n_chip} ({chip})")
    return chans


#: Plausible RF budget of a radar front end: field -> (low, high). Beyond these the radar
#: equation overflows (10^(5000/10) W) or the value is a typo; the AWR2944 EVM sits far inside
#: (12 dBm per Tx, 10 dBi elements, 12 dB noise figure).
RF_BUDGET_LIMITS = {
    "tx_power_dbm": (-40.0, 40.0),          # 40 dBm = 10 W per transmitter
    "tx_antenna_gain_dbi": (-30.0, 50.0),
    "rx_antenna_gain_dbi": (-30.0, 50.0),
    "noise_figure_db": (0.0, 60.0),
    "system_loss_db": (0.0, 100.0),
    "adc_full_scale_dbm": (-100.0, 30.0),
    "temperature_k": (1.0, 1000.0),
    "phase_noise_deg_rms": (0.0, 180.0),
}
#: Per-Tx static errors: field -> (low, high). A gain error far below 0 dB mutes a Tx (tests
#: use -300 dB); above +40 dB it is a typo that overflows the received power.
TX_ERROR_LIMITS = {"tx_gain_error_db": (-400.0, 40.0), "tx_phase_error_deg": (-360.0, 360.0),
                   "rx_gain_error_db": (-400.0, 40.0), "rx_phase_error_deg": (-360.0, 360.0)}
#: Largest board range bias, m: feed lines and internal delays of a real board amount to
#: centimetres; beyond 10 m the value is a typo (TI's measurement searches a few bins).
MAX_RANGE_BIAS_M = 10.0


def _is_number(v) -> bool:
    return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)


def _check_numbers(cfg) -> None:
    """Every numeric field holds a number (a string or bool would fail later without the field
    name)."""
    for f in dataclasses.fields(cfg):
        v = getattr(cfg, f.name)
        if _is_number(f.default) and not _is_number(v):
            raise ValueError(f"{f.name}={v!r} must be a number")


def _check_rf_budget(cfg) -> None:
    """The RF budget lies within `RF_BUDGET_LIMITS`; per-Tx errors hold numbers within
    `TX_ERROR_LIMITS`."""
    for name, (lo, hi) in RF_BUDGET_LIMITS.items():
        v = getattr(cfg, name)
        if not (math.isfinite(v) and lo <= v <= hi):
            raise ValueError(f"{name}={v!r} is outside the plausible range [{lo:g}, {hi:g}]")
    for name, (lo, hi) in TX_ERROR_LIMITS.items():
        v = getattr(cfg, name)
        if v is None:
            continue
        if isinstance(v, (str, bytes)) or not hasattr(v, "__len__") or \
                not all(_is_number(x) and math.isfinite(x) and lo <= x <= hi for x in v):
            raise ValueError(f"{name}={v!r} must be a list of finite numbers in "
                             f"[{lo:g}, {hi:g}] (one per {name[:2].capitalize()})")


@dataclass(frozen=True, kw_only=True, slots=True)
class RadarConfig:
    """One radar: chip, board, waveform, ADC mode, MIMO schedule, antenna and RF budget.

    Parameters (all SI, unit in the name)
    ----------
    chip : str
        Chip name, see `radarsim.chips.CHIPS`; every limit below is this chip's.
    board : str or None
        Board name (`radarsim.boards.BOARDS`): element positions and pattern; default the
        chip's evaluation board.
    adc_mode : {"real", "complex1x", "complex2x"}
        ADC output format (`radarsim.chips.ADC_MODES`): real keeps n_samples/2 range bins,
        complex all n_samples (the max range doubles for the same bandwidth).
    mimo : str
        MIMO scheme, a name of `MIMO_SCHEMES` ("ddma", "tdma", ...); the scheme object owns
        its validation rules, transmit code and unambiguous velocity (`radarsim.mimo`).
    n_tx, n_rx : int
        Active transmitters and receivers (1..the chip's count).
    tx_channels, rx_channels : tuple of int or None
        Chip channel (1-based, TI's Tx0 = 1) of each active Tx / Rx; default 1..n. Tx k of
        `tx_order` and of every per-Tx tuple is the k-th entry here (``txChannelEn 5`` =
        channels (1, 3)).
    tx_positions_wl, rx_positions_wl : tuple of (y, z) or None
        Element positions of every chip channel in wavelengths; default the board's (an
        ``antGeometryCfg`` sets them).
    adcbuf_interleaved : bool or None
        ADC buffer channel interleaving (``adcbufCfg`` ChanInterleave 0); it fixes the raw
        capture layout (`radarsim.capture`); default the chip demo's.
    start_freq_hz, slope_hz_per_s : float
        Ramp start frequency and slope.
    idle_time_s, adc_start_time_s, ramp_end_time_s, chirp_period_s : float
        Chirp timing; the period must equal idle + ramp end time.
    n_samples : int
        ADC samples (real, or complex I/Q pairs) per chirp and Rx.
    adc_rate_sps : float
        ADC sampling rate (samples per second).
    n_chirps : int
        Chirps per frame (all transmitters together).
    n_subbands : int or None
        DDMA Doppler sub-bands; default from the scheme: Nt + 2 for Nt = 4, Nt + 1 otherwise
        (seed 000 3.3), Nt for classic DDMA. Ignored by schemes without sub-bands.
    tx_order : tuple of int or None
        DDMA: which Tx occupies sub-band 0, 1, ...; TDMA: which Tx fires in slot 0, 1, ...
        Default: the board's horizontal Tx first and raised Tx last, in channel order (the R79
        demo's (1, 3, 4, 2) on the AWR2944 EVM), unless the scheme has its own (classic DDMA:
        (1, 2, 3, 4)).
    phase_shifter_bits : int or None
        Shifter resolution, must be the chip's (AWR2944: 6 bits, 5.625 deg per LSB; 0 for a
        chip without shifters, which cannot run schemes that need them); default the chip's.
    phase_quantization : {"floor", "round", "none"}
        How programmed phases map to codes, see `PHASE_QUANTIZATIONS`.
    tx_phase_error_deg, tx_gain_error_db : tuple of float or None
        Static per-Tx phase and gain errors (uncalibrated shifters: > +/-10 deg).
    rx_phase_error_deg, rx_gain_error_db : tuple of float or None
        Static per-Rx phase and gain errors of the board (feed lines, LNA and mixer spread),
        deg and dB; default 0. With the per-Tx errors they give virtual channel (k, r) the
        complex gain g_k g_r that TI's ``compRangeBiasAndRxChanPhase`` corrects.
    range_bias_m : float
        Board range bias, m: every echo is received as if it came from R + range_bias_m (a
        fixed delay 2 b / c of the feed lines and the synthesiser-to-mixer path, as TI's
        ``measureRangeBiasAndRxChanPhase`` measures it); default 0.
    phase_noise_deg_rms : float
        Random per-chirp, per-Tx phase error, deg rms (independent Gaussian).
    shifter_phase_error_deg, shifter_gain_error_db : (n_tx, 2**bits) table, mapping or None
        Per-Tx (rows Tx1..Txn), per-code shifter errors: Tx k at programmed code q gets the
        phase -(q LSB + shifter_phase_error_deg[k][q]) and the amplitude gain
        10^(shifter_gain_error_db[k][q] / 20), on top of the static and per-chirp errors.
        None: all zero. A mapping {distribution, rms, seed[, dnl_fraction]} draws the table
        once at construction (`radarsim.shifter.ShifterErrorSpec`); the field then holds it.
        |phase| <= 180 deg, |gain| <= 10 dB.
    tx_coupling_db, tx_coupling_deg : (n_tx, n_tx) table or None
        Tx-to-Tx coupling C[k][j]: level (dB, -inf = none) and phase (deg) of channel j's
        signal radiated by element k; the diagonal is 0 dB, 0 deg (channel gains are
        `tx_gain_error_db`), off-diagonal levels <= 0 dB. None: identity (no coupling).
    shifter_calibration_deg : (n_tx, 2**bits) table, mapping or None
        The chip's shifter calibration: measured phase error of every code relative to code
        0, deg. When set, `phase_codes` programs the code whose measured phase is closest to
        the wanted phase instead of the `phase_quantization` rule. A mapping
        {seed[, range_m, rcs_m2, n_repeats, thermal_noise]} runs `calibrate_shifters` at
        construction. None: uncalibrated.
    tx_power_dbm : float
        Power per transmitter at the antenna port.
    tx_antenna_gain_dbi, rx_antenna_gain_dbi : float
        Element boresight gains.
    antenna_pattern : {"cosine", "isotropic"}
        Element pattern, see `ANTENNA_PATTERNS`.
    pattern_exponent_az, pattern_exponent_el : float or None
        Exponents n of the cosine power pattern (per element, one way); default the board's.
    noise_figure_db, system_loss_db, temperature_k : float
        Receiver noise figure, lumped losses (radome, cabling, implementation), noise temperature.
    adc_full_scale_dbm : float
        Input-referred power of a full-scale sine at the ADC (receiver gain folded in).
    adc_dc_offset_lsb : float
        Static DC offset of every ADC sample (all chirps and Rx), LSB; 0 = none (default). The
        R79 demo removes it per chirp and Rx before the range FFT (seed 004 section 2).
    tx_leakage_dbfs : float or None
        Tx-to-Rx leakage (antenna coupling, bumper) as a tone from a 0.1 m path at this level
        relative to a full-scale sine, dBFS; None = none (default).

    Raises
    ------
    ValueError
        For every limit of DESIGN 4.4 (with the chip's values) and every out-of-domain value;
        the message names the field, the value and the limit.
    """

    chip: str = "AWR2944"
    board: str | None = None
    adc_mode: str = "real"
    mimo: str = "ddma"
    n_tx: int = 4
    n_rx: int = 4
    start_freq_hz: float = 77e9
    slope_hz_per_s: float = 8.883e12
    idle_time_s: float = 5e-6
    adc_start_time_s: float = 5e-6
    ramp_end_time_s: float = 18.81e-6
    chirp_period_s: float = 23.81e-6
    n_samples: int = 384
    adc_rate_sps: float = 30e6
    n_chirps: int = 768
    n_subbands: int | None = None
    tx_order: tuple[int, ...] | None = None
    tx_channels: tuple[int, ...] | None = None
    rx_channels: tuple[int, ...] | None = None
    tx_positions_wl: tuple[tuple[float, float], ...] | None = None
    rx_positions_wl: tuple[tuple[float, float], ...] | None = None
    adcbuf_interleaved: bool | None = None
    phase_shifter_bits: int | None = None
    phase_quantization: str = "floor"
    tx_phase_error_deg: tuple[float, ...] | None = None
    tx_gain_error_db: tuple[float, ...] | None = None
    rx_phase_error_deg: tuple[float, ...] | None = None
    rx_gain_error_db: tuple[float, ...] | None = None
    range_bias_m: float = 0.0
    phase_noise_deg_rms: float = 0.0
    shifter_phase_error_deg: Any = None
    shifter_gain_error_db: Any = None
    tx_coupling_db: Any = None
    tx_coupling_deg: Any = None
    shifter_calibration_deg: Any = None
    tx_power_dbm: float = 12.0
    tx_antenna_gain_dbi: float = 10.0
    rx_antenna_gain_dbi: float = 10.0
    antenna_pattern: str = "cosine"
    pattern_exponent_az: float | None = None
    pattern_exponent_el: float | None = None
    noise_figure_db: float = 12.0
    system_loss_db: float = 3.0
    temperature_k: float = 290.0
    adc_full_scale_dbm: float = -20.0
    adc_dc_offset_lsb: float = 0.0
    tx_leakage_dbfs: float | None = None

    def __post_init__(self) -> None:
        _set = lambda name, value: object.__setattr__(self, name, value)  # noqa: E731
        _check_numbers(self)
        scheme = scheme_of(self.mimo)
        chip = get_chip(self.chip)
        board = get_board(chip.default_board if self.board is None else self.board)
        if board.chip != chip.name:
            raise ValueError(f"board={board.name!r} carries a {board.chip}, not chip="
                             f"{chip.name!r}")
        _set("board", board.name)
        if self.adc_mode not in ADC_MODES:
            raise ValueError(f"adc_mode={self.adc_mode!r} is not one of {sorted(ADC_MODES)}")
        if not chip.supports(self.adc_mode):
            raise ValueError(f"adc_mode={self.adc_mode!r}: the {chip.name} supports "
                             f"{sorted(chip.adc)} ({chip.datasheet}, receive subsystem)")
        for name, hi in (("n_tx", chip.n_tx), ("n_rx", chip.n_rx)):
            val = getattr(self, name)
            if not isinstance(val, (int, np.integer)) or not 1 <= val <= hi:
                raise ValueError(f"{name}={val!r} must be an integer in 1..{hi} ({chip.name})")
        _set("tx_channels", _channels(self.tx_channels, self.n_tx, chip.n_tx, "tx_channels",
                                      chip.name))
        _set("rx_channels", _channels(self.rx_channels, self.n_rx, chip.n_rx, "rx_channels",
                                      chip.name))
        _set("tx_positions_wl", _positions(board.tx_positions_wl if self.tx_positions_wl is None
                                           else self.tx_positions_wl, chip.n_tx,
                                           "tx_positions_wl"))
        _set("rx_positions_wl", _positions(board.rx_positions_wl if self.rx_positions_wl is None
                                           else self.rx_positions_wl, chip.n_rx,
                                           "rx_positions_wl"))
        if self.adcbuf_interleaved is None:
            _set("adcbuf_interleaved", chip.adcbuf_interleaved_default)
        elif bool(self.adcbuf_interleaved) not in chip.adcbuf_interleave:
            raise ValueError(f"adcbuf_interleaved={self.adcbuf_interleaved!r}: the {chip.name} "
                             "demo firmware accepts only a "
                             f"{'non-' if False in chip.adcbuf_interleave else ''}interleaved "
                             "ADC buffer")
        else:
            _set("adcbuf_interleaved", bool(self.adcbuf_interleaved))
        for name, value in (("pattern_exponent_az", board.pattern_exponent_az),
                            ("pattern_exponent_el", board.pattern_exponent_el)):
            if getattr(self, name) is None:
                _set(name, value)
        require(self, ("n_samples", "n_chirps"), "integer", ge=2)
        if self.n_samples % 2 and not self.is_complex:
            raise ValueError(f"n_samples={self.n_samples} must be even (real ADC: "
                             "n_samples/2 range bins)")
        if self.n_samples > chip.max_adc_samples:
            raise ValueError(f"n_samples={self.n_samples} exceeds the {chip.name} limit of "
                             f"{chip.max_adc_samples} ADC samples per chirp")
        if self.n_chirps > chip.max_chirps:
            raise ValueError(f"n_chirps={self.n_chirps} exceeds the {chip.name} limit of "
                             f"{chip.max_chirps} chirps per frame ({chip.max_chirp_defs} chirp "
                             f"definitions x {chip.max_loops} loops)")
        require(self, ("start_freq_hz", "slope_hz_per_s", "idle_time_s", "ramp_end_time_s",
                       "chirp_period_s", "adc_rate_sps", "temperature_k"), gt=0)
        if not (math.isfinite(self.adc_start_time_s) and self.adc_start_time_s >= 0):
            raise ValueError(f"adc_start_time_s={self.adc_start_time_s!r} must be >= 0")
        require(self, ("tx_power_dbm", "tx_antenna_gain_dbi", "rx_antenna_gain_dbi",
                       "adc_full_scale_dbm"))
        require(self, ("noise_figure_db", "system_loss_db", "phase_noise_deg_rms",
                       "pattern_exponent_az", "pattern_exponent_el"), ge=0)
        _check_rf_budget(self)

        if not (math.isfinite(self.adc_dc_offset_lsb)
                and abs(self.adc_dc_offset_lsb) <= ADC_FULL_SCALE_CODE):
            raise ValueError(f"adc_dc_offset_lsb={self.adc_dc_offset_lsb!r} must be finite and "
                             f"within +/-{ADC_FULL_SCALE_CODE} LSB")
        if self.tx_leakage_dbfs is not None and not (math.isfinite(self.tx_leakage_dbfs)
                                                     and self.tx_leakage_dbfs <= 0):
            raise ValueError(f"tx_leakage_dbfs={self.tx_leakage_dbfs!r} must be <= 0 dBFS or "
                             "None")

        # DESIGN 4.4: chip limits, the chip's values.
        max_rate = chip.adc[self.adc_mode].max_rate_sps
        if self.adc_rate_sps > max_rate:
            raise ValueError(f"adc_rate_sps={self.adc_rate_sps:g} exceeds the {chip.name} "
                             f"limit {max_rate:g} sps ({self.adc_mode} ADC)")
        if not self.is_complex and \
                self.max_beat_frequency_hz > chip.if_bandwidth_hz * (1 + 1e-9):
            raise ValueError(f"adc_rate_sps={self.adc_rate_sps:g}: beat (IF) frequency span "
                             f"{self.max_beat_frequency_hz:g} Hz exceeds the {chip.name} IF "
                             f"bandwidth limit {chip.if_bandwidth_hz:g} Hz")
        if self.start_freq_hz < chip.band_min_hz:
            raise ValueError(f"start_freq_hz={self.start_freq_hz:g} is below the {chip.name} "
                             f"band limit {chip.band_min_hz:g} Hz")
        ramp_top = self.start_freq_hz + self.slope_hz_per_s * self.ramp_end_time_s
        # TI profiles give the ramp end time to 10 ns (two decimals in us), so a ramp sized to
        # the band edge may pass it by up to one slope x 10 ns (TI Visualizer's 60 GHz
        # "profileCfg 0 60 ... 114.29 ... 35 ..." ends 0.15 MHz above 64 GHz).
        if ramp_top > chip.band_max_hz * (1 + 1e-12) + self.slope_hz_per_s * 10e-9:
            raise ValueError(f"start_freq_hz={self.start_freq_hz:g} + slope_hz_per_s="
                             f"{self.slope_hz_per_s:g} x ramp_end_time_s="
                             f"{self.ramp_end_time_s:g}: ramp end frequency {ramp_top:g} Hz "
                             f"exceeds the {chip.name} band limit {chip.band_max_hz:g} Hz")
        adc_end = self.adc_start_time_s + self.n_samples / self.adc_rate_sps
        if adc_end > self.ramp_end_time_s * (1 + 1e-9):
            raise ValueError(f"n_samples={self.n_samples}: ADC window ends at "
                             f"adc_start_time_s + n_samples / adc_rate_sps = {adc_end:g} s, "
                             f"after ramp_end_time_s={self.ramp_end_time_s:g} s")
        period = self.idle_time_s + self.ramp_end_time_s
        if not math.isclose(self.chirp_period_s, period, rel_tol=1e-6):
            raise ValueError(f"chirp_period_s={self.chirp_period_s:g} must equal idle_time_s + "
                             f"ramp_end_time_s = {period:g} s")
        # A chip without shifters has 0 bits: one code, 0 deg (TDMA/BPM signs need none).
        bits = chip.phase_shifter_bits or 0
        if self.phase_shifter_bits is None:
            _set("phase_shifter_bits", bits)
        elif not isinstance(self.phase_shifter_bits, (int, np.integer)) or \
                isinstance(self.phase_shifter_bits, bool) or self.phase_shifter_bits != bits:
            have = "has no phase shifter" if not bits else f"phase shifter has {bits} bits"
            raise ValueError(f"phase_shifter_bits={self.phase_shifter_bits!r}: the {chip.name} "
                             f"{have}")
        if scheme.needs_phase_shifter and self.phase_shifter_bits == 0:
            raise ValueError(f"mimo={self.mimo!r} needs per-Tx phase shifters; the {chip.name} "
                             "has none")
        if self.phase_quantization not in PHASE_QUANTIZATIONS:
            raise ValueError(f"phase_quantization={self.phase_quantization!r} is not one of "
                             f"{sorted(PHASE_QUANTIZATIONS)}")
        if self.antenna_pattern not in ANTENNA_PATTERNS:
            raise ValueError(f"antenna_pattern={self.antenna_pattern!r} is not one of "
                             f"{sorted(ANTENNA_PATTERNS)}")

        # MIMO schedule.
        if self.tx_order is None:
            order = scheme.default_tx_order(self.n_tx)
            if order == MimoScheme.default_tx_order(scheme, self.n_tx):
                # The R79 rule (horizontal Tx first, raised last) on this board's geometry.
                order = self._geometry_tx_order()
        else:
            order = _integers(self.tx_order, "tx_order", f"a permutation of Tx 1..{self.n_tx}")
        if sorted(order) != list(range(1, self.n_tx + 1)):
            raise ValueError(f"tx_order={order!r} must be a permutation of Tx 1..{self.n_tx}")
        _set("tx_order", order)
        if self.n_subbands is None:
            _set("n_subbands", scheme.default_n_subbands(self.n_tx))
        elif not isinstance(self.n_subbands, (int, np.integer)) or self.n_subbands < 1:
            raise ValueError(f"n_subbands={self.n_subbands!r} must be an integer >= 1")
        scheme.validate(self)
        for name, n, what in (("tx_phase_error_deg", self.n_tx, "Tx"),
                              ("tx_gain_error_db", self.n_tx, "Tx"),
                              ("rx_phase_error_deg", self.n_rx, "Rx"),
                              ("rx_gain_error_db", self.n_rx, "Rx")):
            val = getattr(self, name)
            if val is None:
                _set(name, (0.0,) * n)
                continue
            val = tuple(float(v) for v in val)
            if len(val) != n or not all(math.isfinite(v) for v in val):
                raise ValueError(f"{name} must hold {n} finite values (one per {what}), "
                                 f"got {val!r}")
            _set(name, val)
        if not (math.isfinite(self.range_bias_m) and abs(self.range_bias_m) <= MAX_RANGE_BIAS_M):
            raise ValueError(f"range_bias_m={self.range_bias_m!r} must be finite and within "
                             f"+/-{MAX_RANGE_BIAS_M:g} m")
        self._resolve_shifter_fields(_set)

    def _resolve_shifter_fields(self, _set) -> None:
        """Resolve and validate the shifter tables, the coupling and the calibration."""
        n_codes = 2 ** self.phase_shifter_bits  # 1 (code 0) on a chip without shifters
        _set("shifter_phase_error_deg", _shifter.resolve_table(
            "shifter_phase_error_deg", self.shifter_phase_error_deg, self.n_tx, n_codes,
            _shifter.MAX_SHIFTER_PHASE_ERROR_DEG))
        _set("shifter_gain_error_db", _shifter.resolve_table(
            "shifter_gain_error_db", self.shifter_gain_error_db, self.n_tx, n_codes,
            _shifter.MAX_SHIFTER_GAIN_ERROR_DB))
        eye = np.eye(self.n_tx, dtype=bool)
        lvl = np.where(eye, 0.0, -np.inf) if self.tx_coupling_db is None else \
            _shifter.check_table("tx_coupling_db", self.tx_coupling_db,
                                 (self.n_tx, self.n_tx), np.inf, allow_neg_inf=True)
        ph = np.zeros((self.n_tx, self.n_tx)) if self.tx_coupling_deg is None else \
            _shifter.check_table("tx_coupling_deg", self.tx_coupling_deg,
                                 (self.n_tx, self.n_tx), 360.0)
        if np.any(lvl[eye] != 0) or np.any(ph[eye] != 0):
            raise ValueError(f"tx_coupling_db / tx_coupling_deg diagonal must be 0 dB and "
                             f"0 deg (channel gains are tx_gain_error_db), got "
                             f"{lvl[eye].tolist()} dB, {ph[eye].tolist()} deg")
        if np.any(lvl[~eye] > _shifter.MAX_TX_COUPLING_DB):
            raise ValueError(f"tx_coupling_db off-diagonal level {lvl[~eye].max():g} dB "
                             f"exceeds the limit {_shifter.MAX_TX_COUPLING_DB:g} dB")
        _set("tx_coupling_db", tuple(tuple(float(v) for v in r) for r in lvl))
        _set("tx_coupling_deg", tuple(tuple(float(v) for v in r) for r in ph))
        cal = self.shifter_calibration_deg
        if cal is None:
            return
        if PHASE_QUANTIZATIONS[self.phase_quantization].ideal:
            raise ValueError(f"shifter_calibration_deg is set but phase_quantization="
                             f"{self.phase_quantization!r}: "
                             "an ideal shifter has no codes to choose; use 'floor' or 'round'")
        if isinstance(cal, Mapping):
            from .calibration import calibrate_shifters
            kw = dict(cal)
            seed = kw.pop("seed", 0)
            if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) or seed < 0:
                raise ValueError(f"shifter_calibration_deg: seed={seed!r} must be an "
                                 "integer >= 0")
            raw = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
            raw["shifter_calibration_deg"] = None
            try:
                res = calibrate_shifters(RadarConfig(**raw), rng=np.random.default_rng(seed),
                                         full_output=True, **kw)
            except TypeError as exc:
                raise ValueError(f"shifter_calibration_deg: bad calibration spec "
                                 f"{dict(cal)!r} ({exc})") from exc
            cal = res.measured_phase_error_deg
        _set("shifter_calibration_deg", _shifter.resolve_table(
            "shifter_calibration_deg", cal, self.n_tx, n_codes,
            _shifter.MAX_SHIFTER_PHASE_ERROR_DEG))

    def _geometry_tx_order(self) -> tuple[int, ...]:
        # Tx on the lowest row first (in channel order), raised Tx last, as the R79 demo's
        # Tx1, Tx3, Tx4, Tx2 (seed 000 3.3) and TI's "elevation antennas last" DDM rule.
        z = [self.tx_positions_wl[c - 1][1] for c in self.tx_channels]
        low = min(z)
        return tuple(sorted(range(1, self.n_tx + 1),
                            key=lambda k: (not math.isclose(z[k - 1], low, abs_tol=1e-9), k)))

    # ------------------------------------------------------------------ derived: chip
    @property
    def chip_spec(self):
        """The `radarsim.chips.Chip` record of `chip`."""
        return CHIPS[self.chip]

    @property
    def is_complex(self) -> bool:
        """True for the complex (I/Q) ADC modes."""
        return ADC_MODES[self.adc_mode].is_complex

    @property
    def adc_dtype(self) -> np.dtype:
        """dtype of an ADC frame: int16 (real) or complex64 with integer parts (complex)."""
        return np.dtype(np.complex64) if self.is_complex else np.dtype(np.int16)

    # ------------------------------------------------------------------ derived: waveform
    @property
    def wavelength_m(self) -> float:
        """Wavelength at the start frequency, m (77 GHz: 3.893 mm)."""
        return C_MPS / self.start_freq_hz

    @property
    def sampled_bandwidth_hz(self) -> float:
        """Bandwidth swept while the ADC samples, Hz (R79: 113.7 MHz)."""
        return self.slope_hz_per_s * self.n_samples / self.adc_rate_sps

    @property
    def n_range_bins(self) -> int:
        """Range bins kept after the range FFT: n_samples / 2 (real) or n_samples (complex)."""
        return self.n_samples if self.is_complex else self.n_samples // 2

    @property
    def range_resolution_m(self) -> float:
        """c / 2B, m (R79: 1.318 m)."""
        return C_MPS / (2 * self.sampled_bandwidth_hz)

    @property
    def max_range_m(self) -> float:
        """Range of the last kept bin edge, n_range_bins x resolution, m (R79: 253 m; a complex
        profile reaches twice as far for the same bandwidth)."""
        return self.n_range_bins * self.range_resolution_m

    @property
    def max_beat_frequency_hz(self) -> float:
        """Highest beat frequency the ADC represents: adc_rate / 2 (real) or adc_rate
        (complex, image band rejected), Hz."""
        return self.adc_rate_sps * ADC_MODES[self.adc_mode].span_per_rate

    @property
    def noise_bandwidth_hz(self) -> float:
        """Noise bandwidth of each real ADC channel (the real samples, or I and Q each): its
        Nyquist band adc_rate / 2, Hz."""
        return self.adc_rate_sps / 2

    @property
    def frame_time_s(self) -> float:
        """Duration of the chirp burst, n_chirps x chirp period, s (R79: 18.29 ms)."""
        return self.n_chirps * self.chirp_period_s

    @property
    def n_virtual(self) -> int:
        """Number of virtual antennas, n_tx x n_rx."""
        return self.n_tx * self.n_rx

    @property
    def scheme(self):
        """The `radarsim.mimo.MimoScheme` object of `mimo`."""
        return MIMO_SCHEMES[self.mimo]

    @property
    def n_doppler_bins(self) -> int:
        """Doppler bins per transmitter after separation: chirps per sub-band (DDMA) or per
        Tx (TDMA, BPM), from the scheme."""
        return self.scheme.n_doppler_bins(self)

    @property
    def velocity_resolution_mps(self) -> float:
        """lambda / (2 N Tc) with N the chirps of one Tx's slow-time sequence, m/s.

        DDMA: every Tx fires all 768 chirps at Tc (0.1065 m/s). TDMA: 192 chirps at 4 Tc,
        which spans the same frame time, so the resolution is the same. From the scheme
        (`MimoScheme.velocity_resolution_mps`; fast/slow: one chirp set's bin)."""
        return self.scheme.velocity_resolution_mps(self)

    @property
    def max_unambiguous_velocity_mps(self) -> float:
        """Radial velocity the chain reports without aliasing, +/- this value, m/s.

        From the scheme: DDMA lambda / (4 Tc) (40.9 m/s), recovered by empty-band demodulation
        (seed 000 3.3); TDMA and BPM lambda / (4 Nt Tc) (10.22 m/s for Nt = 4) before any
        disambiguation."""
        return self.scheme.max_unambiguous_velocity_mps(self)

    @property
    def subband_width_mps(self) -> float:
        """DDMA sub-band width in velocity, 2 Vmax / n_subbands (R79: 13.63 m/s)."""
        return 2 * self.wavelength_m / (4 * self.chirp_period_s) / self.n_subbands

    # ------------------------------------------------------------------ derived: MIMO
    @property
    def phase_lsb_deg(self) -> float:
        """Phase-shifter step, deg (6 bits: 5.625 deg)."""
        return 360.0 / 2 ** self.phase_shifter_bits

    @property
    def subband_of_tx(self) -> dict[int, int]:
        """DDMA sub-band (or TDMA slot) of each Tx, keyed by 1-based Tx number."""
        return {tx: i for i, tx in enumerate(self.tx_order)}

    def ideal_phase_step_rad(self) -> np.ndarray:
        """(n_tx,) DDMA phase step per chirp of Tx1..Tx{n_tx}: 2 pi p / N, p the sub-band."""
        p = np.array([self.subband_of_tx[t] for t in range(1, self.n_tx + 1)], dtype=float)
        return 2 * np.pi * p / self.n_subbands

    def programmed_phase_deg(self) -> np.ndarray:
        """(n_tx, n_subbands) ideal phase programmed into the shifters over one code period, deg.

        The shifter delays the signal, so the programmed phase is the negative of the step,
        wrapped to [0, 360) (seed 000 table 3)."""
        # Integer arithmetic: 360 (-p c mod N) / N is exact, so an exact multiple of the LSB
        # (180 deg = 32 codes) or of 360 deg never lands a rounding error below a code boundary.
        c = np.arange(self.n_subbands)
        p = np.array([self.subband_of_tx[t] for t in range(1, self.n_tx + 1)])
        return 360.0 * np.mod(-p[:, None] * c[None, :], self.n_subbands) / self.n_subbands

    def phase_codes(self) -> np.ndarray:
        """(n_tx, n_subbands) int shifter codes over one code period (seed 000 table 4).

        `floor` reproduces table 4 (Tx3: 0, 53, 42, 32, 21, 10); `round` is the SDK's rule;
        `none` returns the nearest code but `applied_phase_rad` then uses ideal phases. With a
        `shifter_calibration_deg` table: the code whose measured phase is closest to the
        programmed phase (`radarsim.shifter.select_codes`)."""
        cal = self.shifter_calibration_deg
        return _shifter.program_codes(self.programmed_phase_deg(), self.phase_lsb_deg,
                                      2 ** self.phase_shifter_bits, self.phase_quantization,
                                      None if cal is None else np.asarray(cal))

    def applied_phase_rad(self) -> np.ndarray:
        """(n_tx, n_subbands) phase actually imposed on each Tx's signal per chirp of one code
        period, rad, before static and random errors: the negative of the programmed shifter
        phase (ideal or quantised). Which schemes use it is theirs to say
        (`radarsim.mimo`)."""
        if PHASE_QUANTIZATIONS[self.phase_quantization].ideal:
            prog_deg = self.programmed_phase_deg()
        else:
            prog_deg = self.phase_codes() * self.phase_lsb_deg
        return -np.radians(prog_deg)

    def shifter_phase_residual_deg(self) -> np.ndarray:
        """(n_tx, P) phase the shifters really program over the first code period
        (P = `scheme.chirps_per_period`) minus the ideal programmed phase, relative to each
        Tx's code 0, deg: code-grid rounding plus the table error of the chosen code
        (`radarsim.shifter.phase_residual_deg`); NaN where a Tx is silent. The ideal phase is
        the scheme's code with an ideal shifter (`phase_quantization="none"`)."""
        from .frontend import programmed_codes, wanted_phase_deg
        p = self.scheme.chirps_per_period(self)
        wanted, gain = wanted_phase_deg(self)
        res = _shifter.phase_residual_deg(wanted[:, :p], programmed_codes(self)[:, :p],
                                          np.asarray(self.shifter_phase_error_deg),
                                          self.phase_lsb_deg)
        gain = gain[:, :p]
        return np.where(gain != 0, res, np.nan)

    # ------------------------------------------------------------------ derived: antenna
    @property
    def tx_positions_m(self) -> np.ndarray:
        """(n_tx, 3) positions of the active Tx (`tx_channels`) in the radar frame, m (board
        geometry, DESIGN 4.2 for the AWR2944 EVM)."""
        yz = np.array([self.tx_positions_wl[c - 1] for c in self.tx_channels])
        return self.wavelength_m * np.column_stack([np.zeros(self.n_tx), yz])

    @property
    def rx_positions_m(self) -> np.ndarray:
        """(n_rx, 3) positions of the active Rx (`rx_channels`) in the radar frame, m."""
        yz = np.array([self.rx_positions_wl[c - 1] for c in self.rx_channels])
        return self.wavelength_m * np.column_stack([np.zeros(self.n_rx), yz])

    @property
    def virtual_positions_m(self) -> np.ndarray:
        """(n_tx x n_rx, 3) virtual element positions t_k + r_r in the demodulated order:
        Tx in `tx_order` (Tx1, Tx3, Tx4, Tx2), Rx1..Rx{n_rx} within each, m."""
        t = self.tx_positions_m[np.array(self.tx_order) - 1]
        return (t[:, None, :] + self.rx_positions_m[None, :, :]).reshape(-1, 3)

    # ------------------------------------------------------------------ derived: RF budget
    @property
    def noise_power_w(self) -> float:
        """Thermal noise power of the real ADC samples, k T NF B with B = adc_rate / 2, W."""
        return K_BOLTZMANN * self.temperature_k * 10 ** (self.noise_figure_db / 10) * \
            self.noise_bandwidth_hz

    @property
    def adc_code_per_sqrt_w(self) -> float:
        """Scale from input-referred amplitude (sqrt(W), sine peak = sqrt(2 P)) to ADC codes:
        a sine of power `adc_full_scale_dbm` reaches the full-scale code 32767."""
        p_fs_w = 1e-3 * 10 ** (self.adc_full_scale_dbm / 10)
        return ADC_FULL_SCALE_CODE / math.sqrt(2 * p_fs_w)

    @property
    def noise_rms_lsb(self) -> float:
        """Standard deviation of the thermal noise at the ADC, LSB."""
        return math.sqrt(self.noise_power_w) * self.adc_code_per_sqrt_w

    # ------------------------------------------------------------------ (de)serialisation
    def to_dict(self) -> dict[str, Any]:
        """Plain dict of the fields (tuples as lists, tables as lists of lists), suitable for
        TOML/JSON; a field that is None (no shifter calibration) is left out. Absent coupling
        is -inf dB (TOML `-inf`)."""
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if v is None:
                continue
            out[f.name] = _as_lists(v)
        return out

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "RadarConfig":
        """Build from a dict; unknown keys raise ValueError naming them."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(data) - names)
        if unknown:
            raise ValueError(f"unknown RadarConfig field(s) {unknown}; known: {sorted(names)}")
        kw = {k: _as_tuples(v) for k, v in data.items()}
        return cls(**kw)

    def replace(self, **changes: Any) -> "RadarConfig":
        """A copy with some fields changed (validated again); unknown fields raise ValueError.

        Fields that follow another are re-derived when it changes and they are not given:
        `tx_order`, `n_subbands`, `tx_channels`, the per-Tx error tuples and the shifter and
        coupling tables follow `n_tx`; `tx_order` and `n_subbands` follow `mimo` (the new
        scheme's defaults); `rx_channels` follows `n_rx`; the board and its geometry and
        pattern follow `chip`."""
        names = {f.name for f in dataclasses.fields(self)}
        unknown = sorted(set(changes) - names)
        if unknown:
            raise ValueError(f"unknown RadarConfig field(s) {unknown}")
        data = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        for key in ("chip", "board", "n_tx", "n_rx", "mimo"):  # chip first: board follows it
            if key in changes and changes[key] != getattr(self, key):
                for k in _DEPENDENT_FIELDS[key]:
                    data[k] = None
        data.update(changes)
        return RadarConfig(**data)


def _as_lists(v: Any) -> Any:
    return [_as_lists(x) for x in v] if isinstance(v, tuple) else v


def _as_tuples(v: Any) -> Any:
    return tuple(_as_tuples(x) for x in v) if isinstance(v, list) else v
