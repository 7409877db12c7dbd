"""The parts of a `radarsim.RadarConfig`: waveform, array, MIMO schedule, shifter, front-end
impairments and RF budget, each a frozen dataclass that checks its own values.

A part checks what it can know alone (types, finiteness, bounds, its own registry names); the
rules that join parts (the chip's limits on the waveform and the array, the board's geometry,
the scheme's rules, tables sized by the Tx count) are `RadarConfig`'s, which also fills in the
defaults that follow the chip, the board and the scheme. Field names are the flat names of the
previous release, so every field keeps its one name (``cfg.n_chirps`` is
``cfg.waveform.n_chirps``; the key ``"waveform.n_chirps"``).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from core.checks import one_of, require
from core.errors import BadInput

from . import shifter as _shifter
from .chips import ADC_MODES
from .config_rules import (
    ADC_FULL_SCALE_CODE,
    MAX_RANGE_BIAS_M,
    RF_BUDGET_LIMITS,
    TX_ERROR_LIMITS,
    check_numbers,
    is_number,
)
from .mimo.schemes import scheme_of

__all__ = ["Waveform", "ArrayConfig", "MimoSchedule", "ShifterConfig", "Impairments",
           "RfBudget", "PARTS", "FIELD_PART", "FIELDS", "ANTENNA_PATTERNS"]

#: Element gain patterns.
ANTENNA_PATTERNS = {
    "cosine": "power gain G0 cos(az)^n_az cos(el)^n_el inside +/-90 deg, 0 behind",
    "isotropic": "G0 in every direction (tests)",
}


def _check_limits(part, names) -> None:
    for name in names:
        lo, hi = (RF_BUDGET_LIMITS | TX_ERROR_LIMITS)[name]
        v = getattr(part, name)
        if not (math.isfinite(v) and lo <= v <= hi):
            raise BadInput(f"{name}={v!r} is outside the plausible range [{lo:g}, {hi:g}]")


@dataclass(frozen=True, kw_only=True, slots=True)
class Waveform:
    """Chirp ramp, timing, ADC sampling and frame length (SI, unit in the name).

    Parameters are those of `RadarConfig` of the same names: `start_freq_hz`,
    `slope_hz_per_s`, `idle_time_s`, `adc_start_time_s`, `ramp_end_time_s`, `chirp_period_s`,
    `n_samples`, `adc_rate_sps`, `n_chirps` and `adc_mode`. The chip's limits and the ramp
    timing rule (ADC window inside the ramp, period = idle + ramp end) are checked by the
    `RadarConfig` that holds it, after the chip's."""

    start_freq_hz: float = 77e9
    slope_hz_per_s: float = 8.883e12
    idle_time_s: float = 5e-6
    adc_start_time_s: float = 5e-6
    ramp_end_time_s: float = 18.81e-6
    chirp_period_s: float = 23.81e-6
    n_samples: int = 384
    adc_rate_sps: float = 30e6
    n_chirps: int = 768
    adc_mode: str = "real"

    def __post_init__(self) -> None:
        check_numbers(self)
        one_of("adc_mode", self.adc_mode, ADC_MODES)
        require(self, ("n_samples", "n_chirps"), "integer", ge=2)
        if self.n_samples % 2 and not ADC_MODES[self.adc_mode].is_complex:
            raise BadInput(f"n_samples={self.n_samples} must be even (real ADC: "
                           "n_samples/2 range bins)")
        require(self, ("start_freq_hz", "slope_hz_per_s", "idle_time_s", "ramp_end_time_s",
                       "chirp_period_s", "adc_rate_sps"), gt=0)
        if not (math.isfinite(self.adc_start_time_s) and self.adc_start_time_s >= 0):
            raise BadInput(f"adc_start_time_s={self.adc_start_time_s!r} must be >= 0")


@dataclass(frozen=True, kw_only=True, slots=True)
class ArrayConfig:
    """Chip, board, active channels, element positions and pattern (`RadarConfig`'s fields
    `chip`, `board`, `n_tx`, `n_rx`, `tx_channels`, `rx_channels`, `tx_positions_wl`,
    `rx_positions_wl`, `adcbuf_interleaved`, `antenna_pattern`, `pattern_exponent_az`,
    `pattern_exponent_el`). None: the chip's or board's default, filled in by `RadarConfig`,
    which also checks the counts and channels against the chip."""

    chip: str = "AWR2944"
    board: str | None = None
    n_tx: int = 4
    n_rx: int = 4
    tx_channels: tuple[int, ...] | None = None
    rx_channels: tuple[int, ...] | None = None
    tx_positions_wl: tuple[tuple[float, float], ...] | None = None
    rx_positions_wl: tuple[tuple[float, float], ...] | None = None
    adcbuf_interleaved: bool | None = None
    antenna_pattern: str = "cosine"
    pattern_exponent_az: float | None = None
    pattern_exponent_el: float | None = None

    def __post_init__(self) -> None:
        check_numbers(self)
        one_of("antenna_pattern", self.antenna_pattern, ANTENNA_PATTERNS)
        require(self, ("pattern_exponent_az", "pattern_exponent_el"), ge=0, none_ok=True)


@dataclass(frozen=True, kw_only=True, slots=True)
class MimoSchedule:
    """The MIMO scheme (a name of `radarsim.MIMO_SCHEMES`), its DDMA sub-bands and the Tx
    order (`RadarConfig`'s `mimo`, `n_subbands`, `tx_order`); None: the scheme's default,
    filled in by `RadarConfig`, which runs the scheme's rules."""

    mimo: str = "ddma"
    n_subbands: int | None = None
    tx_order: tuple[int, ...] | None = None

    def __post_init__(self) -> None:
        scheme_of(self.mimo)


@dataclass(frozen=True, kw_only=True, slots=True)
class ShifterConfig:
    """Phase shifters: resolution, quantisation rule, per-code error tables and calibration
    (`RadarConfig`'s `phase_shifter_bits`, `phase_quantization`, `shifter_phase_error_deg`,
    `shifter_gain_error_db`, `shifter_calibration_deg`). The tables are sized by the Tx count
    and the bits, so `RadarConfig` resolves and checks them (`radarsim.shifter`)."""

    phase_shifter_bits: int | None = None
    phase_quantization: str = "floor"
    shifter_phase_error_deg: Any = None
    shifter_gain_error_db: Any = None
    shifter_calibration_deg: Any = None

    def __post_init__(self) -> None:
        one_of("phase_quantization", self.phase_quantization, _shifter.PHASE_QUANTIZATIONS)


@dataclass(frozen=True, kw_only=True, slots=True)
class Impairments:
    """Front-end errors of chip and board: static per-channel phase and gain, range bias,
    per-chirp phase noise, Tx coupling, ADC DC offset and Tx-to-Rx leakage (`RadarConfig`'s
    fields of the same names). Per-channel tuples are sized by `RadarConfig`."""

    tx_phase_error_deg: tuple[float, ...] | None = None
    tx_gain_error_db: tuple[float, ...] | None = None
    rx_phase_error_deg: tuple[float, ...] | None = None
    rx_gain_error_db: tuple[float, ...] | None = None
    range_bias_m: float = 0.0
    phase_noise_deg_rms: float = 0.0
    tx_coupling_db: Any = None
    tx_coupling_deg: Any = None
    adc_dc_offset_lsb: float = 0.0
    tx_leakage_dbfs: float | None = None

    def __post_init__(self) -> None:
        check_numbers(self)
        require(self, "phase_noise_deg_rms", ge=0)
        _check_limits(self, ("phase_noise_deg_rms",))
        for name, (lo, hi) in TX_ERROR_LIMITS.items():
            v = getattr(self, name)
            if v is None:
                continue
            if isinstance(v, (str, bytes)) or not hasattr(v, "__len__") or not all(
                    is_number(x) and math.isfinite(x) and lo <= x <= hi for x in v):
                raise BadInput(f"{name}={v!r} must be a list of finite numbers in "
                               f"[{lo:g}, {hi:g}] (one per {name[:2].capitalize()})")
        if not (math.isfinite(self.adc_dc_offset_lsb)
                and abs(self.adc_dc_offset_lsb) <= ADC_FULL_SCALE_CODE):
            raise BadInput(f"adc_dc_offset_lsb={self.adc_dc_offset_lsb!r} must be finite and "
                           f"within +/-{ADC_FULL_SCALE_CODE} LSB")
        if self.tx_leakage_dbfs is not None and not (math.isfinite(self.tx_leakage_dbfs)
                                                     and self.tx_leakage_dbfs <= 0):
            raise BadInput(f"tx_leakage_dbfs={self.tx_leakage_dbfs!r} must be <= 0 dBFS or "
                           "None")
        if not (math.isfinite(self.range_bias_m) and abs(self.range_bias_m) <= MAX_RANGE_BIAS_M):
            raise BadInput(f"range_bias_m={self.range_bias_m!r} must be finite and within "
                           f"+/-{MAX_RANGE_BIAS_M:g} m")


@dataclass(frozen=True, kw_only=True, slots=True)
class RfBudget:
    """Radar-equation terms: Tx power, element gains, receiver noise figure, losses, noise
    temperature and the ADC's full-scale input (`RadarConfig`'s fields of the same names),
    each within `radarsim.config_rules.RF_BUDGET_LIMITS`."""

    tx_power_dbm: float = 12.0
    tx_antenna_gain_dbi: float = 10.0
    rx_antenna_gain_dbi: float = 10.0
    noise_figure_db: float = 12.0
    system_loss_db: float = 3.0
    temperature_k: float = 290.0
    adc_full_scale_dbm: float = -20.0

    def __post_init__(self) -> None:
        check_numbers(self)
        require(self, "temperature_k", gt=0)
        require(self, ("tx_power_dbm", "tx_antenna_gain_dbi", "rx_antenna_gain_dbi",
                       "adc_full_scale_dbm"))
        require(self, ("noise_figure_db", "system_loss_db"), ge=0)
        _check_limits(self, [f.name for f in dataclasses.fields(self)])


#: Part name of `RadarConfig` -> its dataclass, in the order `RadarConfig` builds them.
PARTS: dict[str, type] = {"waveform": Waveform, "array": ArrayConfig, "schedule": MimoSchedule,
                          "shifter": ShifterConfig, "impairments": Impairments,
                          "budget": RfBudget}
# The fields in the order of the flat config of the previous release: `to_dict` and the TI
# writer's directives keep their order.
_ORDER = (
    "chip", "board", "adc_mode", "mimo", "n_tx", "n_rx", "start_freq_hz", "slope_hz_per_s",
    "idle_time_s", "adc_start_time_s", "ramp_end_time_s", "chirp_period_s", "n_samples",
    "adc_rate_sps", "n_chirps", "n_subbands", "tx_order", "tx_channels", "rx_channels",
    "tx_positions_wl", "rx_positions_wl", "adcbuf_interleaved", "phase_shifter_bits",
    "phase_quantization", "tx_phase_error_deg", "tx_gain_error_db", "rx_phase_error_deg",
    "rx_gain_error_db", "range_bias_m", "phase_noise_deg_rms", "shifter_phase_error_deg",
    "shifter_gain_error_db", "tx_coupling_db", "tx_coupling_deg", "shifter_calibration_deg",
    "tx_power_dbm", "tx_antenna_gain_dbi", "rx_antenna_gain_dbi", "antenna_pattern",
    "pattern_exponent_az", "pattern_exponent_el", "noise_figure_db", "system_loss_db",
    "temperature_k", "adc_full_scale_dbm", "adc_dc_offset_lsb", "tx_leakage_dbfs",
)
_BY_NAME = {f.name: (part, f) for part, cls in PARTS.items() for f in dataclasses.fields(cls)}
assert set(_BY_NAME) == set(_ORDER) and len(_BY_NAME) == len(_ORDER), "a part field is unnamed"
#: Field name -> the part that holds it (every field name is unique across the parts).
FIELD_PART: dict[str, str] = {name: _BY_NAME[name][0] for name in _ORDER}
#: Field name -> its `dataclasses.Field` (type, default) in its part.
FIELDS: dict[str, dataclasses.Field] = {name: _BY_NAME[name][1] for name in _ORDER}
