"""Radar configuration: waveform, chip, board, ADC mode, DDMA/TDMA schedule and RF budget.

`RadarConfig` is the single description of a radar that every stage reads. It is a frozen
dataclass with units in its field names; it names its chip (`radarsim.chips.CHIPS`) and board
(`radarsim.boards.BOARDS`), and every chip or method limit (design.md section 4.4, each chip's own
values) is checked at construction and named in the error. Derived quantities (resolutions,
unambiguous velocity, phase codes, virtual array) are read-only properties.

References
----------
.. [1] TI, "AWR2944 DDMA waveform for corner radar" [TI-DDMA], tables 2-4, figure 20, eq. 1-10.
.. [2] TI, "AWR1642 velocity disambiguation" [TI-VEXT], TDMA Vmax = lambda / (4 Nt Tc).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from core.config import add_flat_properties, dotted_changes
from core.errors import BadInput

from . import shifter as _shifter
from .boards import get_board
from .chips import ADC_MODES, CHIPS, get_chip
from .config_rules import ADC_FULL_SCALE_CODE, channel_errors, check_timing, integers
from .mimo.schemes import MIMO_SCHEMES, MimoScheme, scheme_of
from .radar_parts import (
    ANTENNA_PATTERNS,
    FIELD_PART,
    PARTS,
    ArrayConfig,
    Impairments,
    MimoSchedule,
    RfBudget,
    ShifterConfig,
    Waveform,
)

__all__ = [
    "RadarConfig", "Waveform", "ArrayConfig", "MimoSchedule", "ShifterConfig", "Impairments",
    "RfBudget", "FLAT_KEYS", "radar_paths", "radar_fields", "MIMO_SCHEMES", "PHASE_QUANTIZATIONS",
    "ANTENNA_PATTERNS", "ADC_MODES", "C_MPS", "K_BOLTZMANN", "MAX_ADC_RATE_SPS",
    "MAX_IF_BANDWIDTH_HZ", "BAND_MIN_HZ", "BAND_MAX_HZ",
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

#: How a programmed phase is mapped onto the shifter's codes (`radarsim.shifter`).
PHASE_QUANTIZATIONS = _shifter.PHASE_QUANTIZATIONS
#: Flat key of the previous release -> its dotted path (``"n_chirps"`` -> ``"waveform.n_chirps"``).
FLAT_KEYS = {name: f"{part}.{name}" for name, part in FIELD_PART.items()}

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


# Not slotted: the fields' read-only properties are set on the class after it is made, and a
# slotted frozen class of Python 3.11 raises TypeError, not FrozenInstanceError, on them.
@dataclass(frozen=True, kw_only=True)
class RadarConfig:
    """One radar: chip, board, waveform, ADC mode, MIMO schedule, antenna and RF budget.

    Parameters
    ----------
    waveform : Waveform
        Ramp, timing, ADC sampling and frame length.
    array : ArrayConfig
        Chip, board, active channels, element positions and pattern.
    schedule : MimoSchedule
        MIMO scheme, DDMA sub-bands, Tx order.
    shifter : ShifterConfig
        Phase-shifter resolution, quantisation, per-code errors and calibration.
    impairments : Impairments
        Static channel errors, range bias, phase noise, Tx coupling, DC offset, leakage.
    budget : RfBudget
        Tx power, element gains, noise figure, losses, temperature, ADC full scale.

    Build one from parts (``RadarConfig(waveform=Waveform(n_chirps=256))``), from fields by
    their own names (`from_fields`), or change one (`replace`, dotted keys such as
    ``"waveform.n_chirps"``). Every field below is read by its own name too
    (``cfg.n_chirps`` is ``cfg.waveform.n_chirps``).

    Fields (all SI, unit in the name)
    ------
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
        ([TI-DDMA] 3.3), Nt for classic DDMA. Ignored by schemes without sub-bands.
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
        the wanted phase instead of the `phase_quantization` rule. None: uncalibrated. A
        config is a value and never measures: a calibration request {seed[, range_m, rcs_m2,
        n_repeats, thermal_noise]} is resolved by whoever asks for it
        (`radarsim.calibration.resolve_calibration`; a sweep's radar table per cell).
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
        R79 demo removes it per chirp and Rx before the range FFT ([TI-DAZ] section 2).
    tx_leakage_dbfs : float or None
        Tx-to-Rx leakage (antenna coupling, bumper) as a tone from a 0.1 m path at this level
        relative to a full-scale sine, dBFS; None = none (default).

    Raises
    ------
    ValueError
        For every limit of design.md 4.4 (with the chip's values) and every out-of-domain value;
        the message names the field, the value and the limit.
    """

    waveform: Waveform = Waveform()
    array: ArrayConfig = ArrayConfig()
    schedule: MimoSchedule = MimoSchedule()
    shifter: ShifterConfig = ShifterConfig()
    impairments: Impairments = Impairments()
    budget: RfBudget = RfBudget()

    def __post_init__(self) -> None:
        for part, cls in PARTS.items():
            if not isinstance(getattr(self, part), cls):
                raise BadInput(f"{part}={getattr(self, part)!r} must be a {cls.__name__}")
        scheme = scheme_of(self.mimo)
        chip = get_chip(self.chip)
        board = get_board(chip.default_board if self.board is None else self.board)
        board.validate(self)
        self._set(board=board.name, **board.defaults(self))
        chip.validate(self)
        self._set(**chip.defaults(self))
        check_timing(self)
        if scheme.needs_phase_shifter and self.phase_shifter_bits == 0:
            raise BadInput(f"mimo={self.mimo!r} needs per-Tx phase shifters; the {chip.name} "
                           "has none")
        self._resolve_schedule(scheme)
        self._set(**channel_errors(self))
        self._set(**_shifter.resolve_config_tables(self))

    def _set(self, **fields: Any) -> None:
        """Set resolved fields (by their own names) while the frozen instance is being built:
        each part is replaced by a copy, which checks its values again."""
        for part, changes in _by_part(fields).items():
            object.__setattr__(self, part, dataclasses.replace(getattr(self, part), **changes))
        self.__dict__.pop("_hash", None)  # a hash taken while building is stale now

    def __hash__(self) -> int:
        """The hash of the six parts, computed once: the instance is immutable once built, and
        hashing its parts' forty-odd fields costs ~15 us, which the chain's configuration
        caches (`functools.lru_cache`) would otherwise pay several times a frame. Equal
        configurations hash alike (the generated `__eq__` compares the same parts)."""
        h = self.__dict__.get("_hash")
        if h is None:
            h = hash(tuple(getattr(self, f.name) for f in dataclasses.fields(self)))
            object.__setattr__(self, "_hash", h)
        return h

    def __getstate__(self) -> dict:
        """The parts, without the cached hash: string hashes differ between processes, so a
        pickled hash would not match an equal configuration built in the receiving one."""
        state = self.__dict__.copy()
        state.pop("_hash", None)
        return state

    @classmethod
    def from_fields(cls, **fields: Any) -> "RadarConfig":
        """Build from fields given by their own names (``n_chirps=256``), each sent to its part:
        the bridge for a vocabulary that names the fields (TI profiles, `to_dict`).

        Raises
        ------
        BadInput
            An unknown field name (with the known ones), or a value its part refuses.
        """
        unknown = sorted(set(fields) - set(FIELD_PART))
        if unknown:
            raise BadInput(f"unknown RadarConfig field(s) {unknown}; known: "
                           f"{sorted(FIELD_PART)}")
        return cls(**{part: PARTS[part](**kw) for part, kw in _by_part(fields).items()})

    def _resolve_schedule(self, scheme: MimoScheme) -> None:
        """Tx order and sub-bands (the scheme's defaults when None), then the scheme's rules."""
        if self.tx_order is None:
            order = scheme.default_tx_order(self.n_tx)
            if order == MimoScheme.default_tx_order(scheme, self.n_tx):
                # The R79 rule (horizontal Tx first, raised last) on this board's geometry.
                order = self._geometry_tx_order()
        else:
            order = integers(self.tx_order, "tx_order", f"a permutation of Tx 1..{self.n_tx}")
        if sorted(order) != list(range(1, self.n_tx + 1)):
            raise BadInput(f"tx_order={order!r} must be a permutation of Tx 1..{self.n_tx}")
        self._set(tx_order=order)
        if self.n_subbands is None:
            self._set(n_subbands=scheme.default_n_subbands(self.n_tx))
        elif not isinstance(self.n_subbands, (int, np.integer)) or self.n_subbands < 1:
            raise BadInput(f"n_subbands={self.n_subbands!r} must be an integer >= 1")
        scheme.validate(self)

    def _geometry_tx_order(self) -> tuple[int, ...]:
        # Tx on the lowest row first (in channel order), raised Tx last, as the R79 demo's
        # Tx1, Tx3, Tx4, Tx2 ([TI-DDMA] 3.3) and TI's "elevation antennas last" DDM rule.
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
        ([TI-DDMA] 3.3); TDMA and BPM lambda / (4 Nt Tc) (10.22 m/s for Nt = 4) before any
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
        wrapped to [0, 360) ([TI-DDMA] table 3)."""
        # Integer arithmetic: 360 (-p c mod N) / N is exact, so an exact multiple of the LSB
        # (180 deg = 32 codes) or of 360 deg never lands a rounding error below a code boundary.
        c = np.arange(self.n_subbands)
        p = np.array([self.subband_of_tx[t] for t in range(1, self.n_tx + 1)])
        return 360.0 * np.mod(-p[:, None] * c[None, :], self.n_subbands) / self.n_subbands

    def phase_codes(self) -> np.ndarray:
        """(n_tx, n_subbands) int shifter codes over one code period ([TI-DDMA] table 4).

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

    # ------------------------------------------------------------------ derived: antenna
    @property
    def tx_positions_m(self) -> np.ndarray:
        """(n_tx, 3) positions of the active Tx (`tx_channels`) in the radar frame, m (board
        geometry, design.md 4.2 for the AWR2944 EVM)."""
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
        """Plain dict of the fields by their own names (tuples as lists, tables as lists of
        lists), suitable for TOML/JSON; a field that is None (no shifter calibration) is left
        out. Absent coupling is -inf dB (TOML `-inf`)."""
        out = {}
        for name in FIELD_PART:
            v = getattr(self, name)
            if v is None:
                continue
            out[name] = _as_lists(v)
        return out

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "RadarConfig":
        """Build from a dict of fields by their own names (`to_dict`); unknown keys raise
        BadInput naming them."""
        return cls.from_fields(**{k: _as_tuples(v) for k, v in data.items()})

    def replace(self, **changes: Any) -> "RadarConfig":
        """A copy with some fields changed (validated again), by dotted key
        (``**{"waveform.n_chirps": 256}``), by part (``waveform={"n_chirps": 256}`` or a
        `Waveform`); the flat keys of the previous release (``n_chirps=256``) still work and
        warn (`DeprecationWarning`) with the new key. Unknown fields raise BadInput.

        Fields that follow another are re-derived when it changes and they are not given:
        `tx_order`, `n_subbands`, `tx_channels`, the per-Tx error tuples and the shifter and
        coupling tables follow `n_tx`; `tx_order` and `n_subbands` follow `mimo` (the new
        scheme's defaults); `rx_channels` follows `n_rx`; the board and its geometry and
        pattern follow `chip`."""
        return self.replace_fields(**_fields_of(radar_paths(changes, stacklevel=4)))

    def replace_fields(self, **changes: Any) -> "RadarConfig":
        """`replace` with fields given by their own names, without a warning: the bridge for a
        vocabulary that names the fields (a TI profile's board, a chain's own settings)."""
        unknown = sorted(set(changes) - set(FIELD_PART))
        if unknown:
            raise BadInput(f"unknown RadarConfig field(s) {unknown}")
        data = {name: getattr(self, name) for name in FIELD_PART}
        for key in ("chip", "board", "n_tx", "n_rx", "mimo"):  # chip first: board follows it
            if key in changes and changes[key] != getattr(self, key):
                for k in _DEPENDENT_FIELDS[key]:
                    data[k] = None
        data.update(changes)
        return RadarConfig.from_fields(**data)


def radar_paths(changes: dict[str, Any], *, warn: bool = True,
                stacklevel: int = 3) -> dict[str, Any]:
    """`RadarConfig` changes as dotted paths and whole parts (`core.config.dotted_changes`):
    a part's table becomes its dotted keys, a flat key its dotted path (with a
    `DeprecationWarning` unless `warn` is False).

    Raises
    ------
    BadInput
        A key that names no part, field of a part, or flat field.
    """
    paths = dotted_changes(changes, PARTS, FLAT_KEYS, "RadarConfig", warn=warn,
                           stacklevel=stacklevel)
    for path in paths:
        part, _, name = path.partition(".")
        if name and FIELD_PART.get(name) != part:
            raise BadInput(f"unknown RadarConfig field(s) [{path!r}]; {part} holds "
                           f"{sorted(f.name for f in dataclasses.fields(PARTS[part]))}")
    return paths


def radar_fields(changes: dict[str, Any], *, warn: bool = True) -> dict[str, Any]:
    """`RadarConfig` changes in any accepted form (dotted keys, part tables, whole parts, flat
    keys) as fields by their own names: how a reader of a sweep's radar table finds a field
    whatever form the file used (``radar_fields(v)["phase_noise_deg_rms"]``)."""
    return _fields_of(radar_paths(changes, warn=warn, stacklevel=4))


def _by_part(fields: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Fields by their own names, grouped by the part that holds them."""
    out: dict[str, dict[str, Any]] = {}
    for name, value in fields.items():
        out.setdefault(FIELD_PART[name], {})[name] = value
    return out


def _fields_of(paths: dict[str, Any]) -> dict[str, Any]:
    """Dotted paths and whole parts (`radar_paths`) as fields by their own names."""
    out: dict[str, Any] = {}
    for path, value in paths.items():
        part, _, name = path.partition(".")
        if name:
            out[name] = value
        else:
            out.update({f.name: getattr(value, f.name) for f in dataclasses.fields(value)})
    return out


# Every field of a part is also read by its own name: cfg.n_chirps is cfg.waveform.n_chirps.
add_flat_properties(RadarConfig, FIELD_PART)


def _as_lists(v: Any) -> Any:
    return [_as_lists(x) for x in v] if isinstance(v, tuple) else v


def _as_tuples(v: Any) -> Any:
    return tuple(_as_tuples(x) for x in v) if isinstance(v, list) else v
