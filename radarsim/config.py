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
from dataclasses import dataclass
from typing import Any

import numpy as np

from .boards import get_board
from .chips import ADC_MODES, CHIPS, get_chip
from .mimo import MIMO_SCHEMES, scheme_of

__all__ = [
    "RadarConfig", "MIMO_SCHEMES", "PHASE_QUANTIZATIONS", "ANTENNA_PATTERNS", "ADC_MODES",
    "C_MPS", "K_BOLTZMANN", "MAX_ADC_RATE_SPS", "MAX_IF_BANDWIDTH_HZ", "BAND_MIN_HZ",
    "BAND_MAX_HZ", "from_ti_cfg", "to_ti_cfg",
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

#: How a programmed phase is mapped onto the shifter's codes.
PHASE_QUANTIZATIONS = {
    "floor": "code = floor(phase / lsb), as seed 000 table 4",
    "round": "code = round(phase / lsb), as TI's SDK",
    "none": "ideal shifter (no quantisation)",
}
#: Element gain patterns.
ANTENNA_PATTERNS = {
    "cosine": "power gain G0 cos(az)^n_az cos(el)^n_el inside +/-90 deg, 0 behind",
    "isotropic": "G0 in every direction (tests)",
}

# Fields re-derived by `replace` when the field they depend on changes and they are not given.
_DEPENDENT_FIELDS = {
    "n_tx": ("tx_order", "n_subbands", "tx_phase_error_deg", "tx_gain_error_db", "tx_channels"),
    "n_rx": ("rx_channels",),
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


def _channels(value, n: int, n_chip: int, name: str, chip: str) -> tuple[int, ...]:
    if value is None:
        return tuple(range(1, n + 1))
    chans = tuple(int(c) for c in value)
    if len(chans) != n or len(set(chans)) != n or not all(1 <= c <= n_chip for c in chans):
        raise ValueError(f"{name}={value!r} must list {n} distinct channel numbers in "
                         f"1..{n_chip} ({chip})")
    return chans


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
        Default (1, 3, 4, 2) restricted to the active Tx.
    phase_shifter_bits : int or None
        Shifter resolution, must be the chip's (AWR2944: 6 bits, 5.625 deg per LSB; None for a
        chip without shifters, which cannot run DDMA); default the chip's.
    phase_quantization : {"floor", "round", "none"}
        How programmed phases map to codes, see `PHASE_QUANTIZATIONS`.
    tx_phase_error_deg, tx_gain_error_db : tuple of float or None
        Static per-Tx phase and gain errors (uncalibrated shifters: > +/-10 deg).
    phase_noise_deg_rms : float
        Random per-chirp, per-Tx phase error, deg rms (independent Gaussian).
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
    phase_noise_deg_rms: float = 0.0
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

    def __post_init__(self) -> None:
        _set = lambda name, value: object.__setattr__(self, name, value)  # noqa: E731
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
        for name in ("n_samples", "n_chirps"):
            val = getattr(self, name)
            if not isinstance(val, (int, np.integer)) or val < 2:
                raise ValueError(f"{name}={val!r} must be an integer >= 2")
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
        for name in ("start_freq_hz", "slope_hz_per_s", "idle_time_s", "ramp_end_time_s",
                     "chirp_period_s", "adc_rate_sps", "temperature_k"):
            val = getattr(self, name)
            if not (math.isfinite(val) and val > 0):
                raise ValueError(f"{name}={val!r} must be a finite positive number")
        if not (math.isfinite(self.adc_start_time_s) and self.adc_start_time_s >= 0):
            raise ValueError(f"adc_start_time_s={self.adc_start_time_s!r} must be >= 0")
        for name in ("tx_power_dbm", "tx_antenna_gain_dbi", "rx_antenna_gain_dbi",
                     "noise_figure_db", "system_loss_db", "adc_full_scale_dbm",
                     "phase_noise_deg_rms", "pattern_exponent_az", "pattern_exponent_el"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name}={getattr(self, name)!r} must be finite")
        for name in ("noise_figure_db", "system_loss_db", "phase_noise_deg_rms",
                     "pattern_exponent_az", "pattern_exponent_el"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name}={getattr(self, name)!r} must be >= 0")

        # DESIGN 4.4: chip limits, the chip's values.
        max_rate = chip.adc[self.adc_mode].max_rate_sps
        if self.adc_rate_sps > max_rate:
            raise ValueError(f"adc_rate_sps={self.adc_rate_sps:g} exceeds the {chip.name} "
                             f"{self.adc_mode} limit {max_rate:g} sps")
        if not self.is_complex and \
                self.max_beat_frequency_hz > chip.if_bandwidth_hz * (1 + 1e-9):
            raise ValueError(f"adc_rate_sps={self.adc_rate_sps:g}: beat (IF) frequency span "
                             f"{self.max_beat_frequency_hz:g} Hz exceeds the {chip.name} IF "
                             f"bandwidth limit {chip.if_bandwidth_hz:g} Hz")
        if self.start_freq_hz < chip.band_min_hz:
            raise ValueError(f"start_freq_hz={self.start_freq_hz:g} is below the {chip.name} "
                             f"band limit {chip.band_min_hz:g} Hz")
        ramp_top = self.start_freq_hz + self.slope_hz_per_s * self.ramp_end_time_s
        if ramp_top > chip.band_max_hz * (1 + 1e-12):
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
        if self.phase_shifter_bits is None:
            _set("phase_shifter_bits", chip.phase_shifter_bits)
        elif not isinstance(self.phase_shifter_bits, (int, np.integer)) or \
                self.phase_shifter_bits != chip.phase_shifter_bits:
            have = "has no phase shifter" if chip.phase_shifter_bits is None else \
                f"phase shifter has {chip.phase_shifter_bits} bits"
            raise ValueError(f"phase_shifter_bits={self.phase_shifter_bits!r}: the {chip.name} "
                             f"{have}")
        if scheme.needs_phase_shifter and self.phase_shifter_bits is None:
            raise ValueError(f"mimo={self.mimo!r} needs per-Tx phase shifters; the {chip.name} "
                             "has none")
        if self.phase_quantization not in PHASE_QUANTIZATIONS:
            raise ValueError(f"phase_quantization={self.phase_quantization!r} is not one of "
                             f"{sorted(PHASE_QUANTIZATIONS)}")
        if self.antenna_pattern not in ANTENNA_PATTERNS:
            raise ValueError(f"antenna_pattern={self.antenna_pattern!r} is not one of "
                             f"{sorted(ANTENNA_PATTERNS)}")

        # MIMO schedule.
        order = self._default_tx_order() if self.tx_order is None else \
            tuple(int(t) for t in self.tx_order)
        if sorted(order) != list(range(1, self.n_tx + 1)):
            raise ValueError(f"tx_order={order!r} must be a permutation of Tx 1..{self.n_tx}")
        _set("tx_order", order)
        if self.n_subbands is None:
            _set("n_subbands", scheme.default_n_subbands(self.n_tx))
        elif not isinstance(self.n_subbands, (int, np.integer)) or self.n_subbands < 1:
            raise ValueError(f"n_subbands={self.n_subbands!r} must be an integer >= 1")
        scheme.validate(self)
        for name in ("tx_phase_error_deg", "tx_gain_error_db"):
            val = getattr(self, name)
            if val is None:
                _set(name, (0.0,) * self.n_tx)
                continue
            val = tuple(float(v) for v in val)
            if len(val) != self.n_tx or not all(math.isfinite(v) for v in val):
                raise ValueError(f"{name} must hold {self.n_tx} finite values (one per Tx), "
                                 f"got {val!r}")
            _set(name, val)

    def _default_tx_order(self) -> tuple[int, ...]:
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
        which spans the same frame time, so the resolution is the same."""
        return self.wavelength_m / (2 * self.frame_time_s)

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
        `none` returns the nearest code but `applied_phase_rad` then uses ideal phases."""
        prog = self.programmed_phase_deg() / self.phase_lsb_deg
        n_codes = 2 ** self.phase_shifter_bits
        if self.phase_quantization == "floor":
            # A tiny tolerance keeps exact multiples (e.g. 180/5.625 = 32) from flooring down.
            codes = np.floor(prog + 1e-9)
        else:
            codes = np.round(prog)
        return np.mod(codes, n_codes).astype(np.int64)

    def applied_phase_rad(self) -> np.ndarray:
        """(n_tx, n_subbands) phase actually imposed on each Tx's signal per chirp of one code
        period, rad, before static and random errors: the negative of the programmed shifter
        phase (ideal or quantised). Which schemes use it is theirs to say
        (`radarsim.mimo`)."""
        if self.phase_quantization == "none":
            prog_deg = self.programmed_phase_deg()
        else:
            prog_deg = self.phase_codes() * self.phase_lsb_deg
        return -np.radians(prog_deg)

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
        """Plain dict of the fields (tuples as lists), suitable for TOML/JSON."""
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
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
        `tx_order`, `n_subbands`, `tx_channels` and the per-Tx error tuples follow `n_tx`,
        `rx_channels` follows `n_rx`, the board and its geometry and pattern follow `chip`."""
        names = {f.name for f in dataclasses.fields(self)}
        unknown = sorted(set(changes) - names)
        if unknown:
            raise ValueError(f"unknown RadarConfig field(s) {unknown}")
        data = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        for key in ("chip", "board", "n_tx", "n_rx"):  # chip before board: board follows chip
            if key in changes and changes[key] != getattr(self, key):
                for k in _DEPENDENT_FIELDS[key]:
                    data[k] = None
        data.update(changes)
        return RadarConfig(**data)


def _as_lists(v: Any) -> Any:
    return [_as_lists(x) for x in v] if isinstance(v, tuple) else v


def _as_tuples(v: Any) -> Any:
    return tuple(_as_tuples(x) for x in v) if isinstance(v, list) else v


def from_ti_cfg(path_or_text):
    """`RadarConfig` of a TI mmWave .cfg; see `radarsim.ti_cfg.parse_ti_cfg`.

    Imported on call: ti_cfg builds on this module, so config does not import it at load
    time (no import cycle)."""
    from .ti_cfg import from_ti_cfg as _from
    return _from(path_or_text)


def to_ti_cfg(cfg, **kwargs):
    """TI mmWave .cfg text for a `RadarConfig`; see `radarsim.ti_cfg.to_ti_cfg`."""
    from .ti_cfg import to_ti_cfg as _to
    return _to(cfg, **kwargs)
