"""Registry of TI mmWave radar chips: the limits a `RadarConfig` is validated against.

Every value carries its source in a comment. Datasheets (ti.com document viewer):

- AWR2944: SWRS273D, sec. 8 "Detailed Description", receive subsystem ("real-only receiver ...
  bandwidths up to 15 MHz"), Features (76-81 GHz, 4 Tx, 4 Rx); ADC rate 37.5 Msps as design.md 4.4
  ([TI-DDMA] section 1); 6-bit phase shifter: [TI-DDMA] section 3.3 / table 4.
- AWR2944P: SWRS318A, same receive subsystem and RF front end as the AWR2944 (sec. 8).
- AWR2544: SWRS314B, receive subsystem ("real-only receiver ... up to 15 MHz"), 4 Tx 4 Rx,
  76-81 GHz; DDM demo (mmWave MCU+ SDK AWR2544 ``ddmPhaseShiftAntOrder``): 6-bit shifter.
- AWR1843: SWRS222D, receive subsystem ("complex baseband architecture ... up to 10 MHz" as
  the IWR1843AOP sheet), 3 Tx, 4 Rx, 76-81 GHz, "6-bit phase shifter" (Features).
- AWR1642: SWRS203D, receive subsystem ("complex baseband ... up to 5 MHz"), 2 Tx, 4 Rx,
  76-81 GHz; binary phase modulation only (Features), no phase shifter.
- IWR6843: SWRS219F, receive subsystem ("complex baseband ... up to 10 MHz"), 3 Tx, 4 Rx,
  60-64 GHz, 6-bit phase shifter (Features).
- AWR1443 (xWR1443): SWRS207, receive subsystem ("complex baseband ... up to 15 MHz"), 3 Tx,
  4 Rx, 76-81 GHz, binary phase modulation (no shifter); mmWave SDK xwr14xx demo: the ADC
  buffer is interleaved only (SDK user guide ``adcbufCfg``: "0 - interleaved (only supported
  for XWR14xx)"), 4 LVDS lanes (DCA1000 lvdsMode 1).
- AWR1243: SWRS188 (JAJSEW2D) sec. 8 receive subsystem ("complex baseband ... up to 15 MHz"),
  3 Tx, 4 Rx, 76-81 GHz, a front end without a processor (mmWave Studio / mmWaveLink, no SDK
  demo), 4 LVDS lanes.
- AWR2243: SWRS223D sec. 8 receive subsystem ("complex baseband ... up to 20 MHz"), 3 Tx, 4 Rx,
  76-81 GHz, 6-bit phase shifter (Features), front end only (mmWave Studio, the MMWCAS cascade
  boards), 4 LVDS lanes / CSI-2; ADC up to 45 Msps real / 22.5 Msps complex 1x (mmWaveLink
  ``rlProfileCfg_t.digOutSampleRate`` of the AWR2243 DFP).

ADC rates per output mode (``adcCfg <bits> <fmt>``: 0 real, 1 complex 1x, 2 complex 2x) for the
complex-baseband xWR16/18/68 family follow mmWaveLink ``rlProfileCfg_t.digOutSampleRate`` and the
mmWave SDK user guide (real and complex 2x up to 25 Msps, complex 1x up to 12.5 Msps). TI's own
demo profiles sample complex 1x above the IF bandwidth (xWR16xx ``profile_2d.cfg``: 5209 ksps
with a 5 MHz IF band), so for complex modes the ADC rate binds and echoes beyond the IF band are
attenuated by the IF low-pass (`Chip.if_lowpass_hz`) rather than refused; for the real mode the
Nyquist band must lie inside the IF band (design.md 4.4).

ADC buffer and capture: ``adcbufCfg ... <ChanInterleave>``: the AWR2944 demo buffer is
interleaved ([TI-DAZ] section 2; the R79 firmware's ``adcbufCfg -1 1 0 0 1``), the xWR16/18/68
SDK demos support only the non-interleaved buffer (mmWave SDK 3.x user guide, ``adcbufCfg``:
"only non-interleaved (1) supported"). LVDS lanes: 2 on xWR16/18/68 with the SDK (DCA1000 user
guide SPRUIJ4, "lvdsMode 2"), 4 on the AWR294x (MCU+ SDK ``lvdsStreamCfg``, 4-lane HSI).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Mapping, NamedTuple

import numpy as np

from core.errors import BadInput
from core.registry import Registry

from .config_rules import integers

__all__ = ["AdcMode", "ADC_MODES", "AdcLimits", "Chip", "CHIPS", "get_chip", "register_chip",
           "MAX_CHIP_ADC_SAMPLES"]


class AdcMode(NamedTuple):
    """One ADC output format (``adcCfg <numADCBits> <adcOutputFmt>``)."""

    name: str
    ti_code: int          # adcCfg adcOutputFmt
    is_complex: bool
    #: beat-frequency span the samples represent, in units of the ADC rate: real fs/2 (the
    #: upper half of the spectrum is the mirror image), complex fs (image band rejected).
    span_per_rate: float
    description: str
    #: The receiver rejects negative beat frequencies (complex 1x: its image band is filtered,
    #: so an interferer sweeping through 0 Hz is heard on one side only).
    image_rejected: bool = False


#: ADC output formats by name; complex 2x has the complex 1x signal model (its image band is
#: passed rather than filtered, which point targets with positive beat frequencies never use).
#: TI's formats, a closed (frozen) vocabulary.
ADC_MODES: Registry[AdcMode] = Registry("ADC mode", field="adc_mode", kind=AdcMode).register_all((
    AdcMode("real", 0, False, 0.5, "real samples: n_samples/2 range bins"),
    AdcMode("complex1x", 1, True, 1.0, "I/Q, image band filtered: n_samples range bins",
            image_rejected=True),
    AdcMode("complex2x", 2, True, 1.0,
            "I/Q at the real-mode rate, image band kept: n_samples range bins"),
)).freeze()


class AdcLimits(NamedTuple):
    """ADC limits of one output mode."""

    max_rate_sps: float


#: ADC samples per chirp no chip exceeds: rlProfileCfg_t.numAdcSamples is a 16-bit field.
MAX_CHIP_ADC_SAMPLES = 65535
#: Upper limits of a chip record's counts: the mmWaveLink fields every device is programmed
#: through (mmWave Radar Interface Control Document). Beyond them a "limit" would let a config
#: allocate frames no chip can hold (max_loops=1e9 let n_chirps=1e9 through to a MemoryError).
_COUNT_LIMITS = {
    "max_loops": (255, "rlFrameCfg_t.numLoops is 1..255"),
    "max_chirp_defs": (512, "the chirp RAM holds 512 rlChirpCfg_t entries"),
    "max_profiles": (4, "RL_MAX_PROFILES_CNT"),
    "max_adc_samples": (MAX_CHIP_ADC_SAMPLES, "rlProfileCfg_t.numAdcSamples is 16 bits"),
}


@dataclass(frozen=True, slots=True)
class Chip:
    """Limits of one chip (see the module docstring for every source).

    Attributes
    ----------
    band_min_hz, band_max_hz : float
        RF band of the synthesizer.
    n_tx, n_rx : int
        Transmit / receive channels.
    adc : mapping of ADC mode name to AdcLimits
        Supported ADC output modes and their maximum rates.
    if_bandwidth_hz : float
        IF (beat) bandwidth of the receive chain.
    if_lowpass_hz : float
        -3 dB corner of the modelled IF anti-alias low-pass.
    phase_shifter_bits : int or None
        Per-Tx phase-shifter resolution; None: no shifter (no DDMA).
    max_adc_samples : int
        ``profileCfg numAdcSamples`` upper limit (ADC ping-pong buffer).
    max_chirp_defs, max_loops, max_profiles : int
        Chirp RAM entries, ``frameCfg numLoops`` and profile limits (rlChirpCfg_t,
        rlFrameCfg_t, rlProfileCfg_t).
    adcbuf_interleave : frozenset of bool
        Interleaved ADC buffer settings the demo firmware accepts (True = ChanInterleave 0).
    adcbuf_interleaved_default : bool
        The demo's setting, used when a config does not say.
    lvds_lanes : int
        LVDS lanes streamed to a DCA1000.
    ti_platform : str
        The ``% Platform:`` name of TI's mmWave Visualizer profiles (e.g. xWR18xx, AWR294X).
    mcu_plus_sdk : bool
        The demo CLI is the mmWave MCU+ SDK's (AWR294x family: DDM demo syntax); otherwise the
        mmWave SDK 3.x's.
    channel_cfg_args : int
        Arguments of the demo's ``channelCfg``: 3, or 5 on the AWR2x44P / AWR2544 (adds
        ``<ethOscClkEn> <driveStrength>``, MCU+ SDK AWR2x44P demo user guide).
    """

    name: str
    band_min_hz: float
    band_max_hz: float
    n_tx: int
    n_rx: int
    adc: Mapping[str, AdcLimits]
    if_bandwidth_hz: float
    if_lowpass_hz: float
    phase_shifter_bits: int | None
    max_adc_samples: int
    max_chirp_defs: int
    max_loops: int
    max_profiles: int
    adcbuf_interleave: frozenset
    adcbuf_interleaved_default: bool
    lvds_lanes: int
    default_board: str
    datasheet: str
    ti_platform: str
    mcu_plus_sdk: bool
    channel_cfg_args: int

    def __post_init__(self) -> None:
        # A lab's own chip is checked as the shipped ones were written: the limits a config is
        # validated against must themselves be sane.
        if not isinstance(self.name, str) or not self.name:
            raise BadInput(f"chip name={self.name!r} must be a non-empty string")
        if not 0 < self.band_min_hz < self.band_max_hz < math.inf:
            raise BadInput(f"chip {self.name}: band_min_hz={self.band_min_hz:g} and "
                           f"band_max_hz={self.band_max_hz:g} must be finite, > 0, min < max")
        for fld in ("n_tx", "n_rx", "max_adc_samples", "max_chirp_defs", "max_loops",
                    "max_profiles", "lvds_lanes"):
            v = getattr(self, fld)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                raise BadInput(f"chip {self.name}: {fld}={v!r} must be an integer >= 1")
        for fld, (hi, why) in _COUNT_LIMITS.items():
            if getattr(self, fld) > hi:
                raise BadInput(f"chip {self.name}: {fld}={getattr(self, fld)!r} exceeds {hi} "
                               f"({why})")
        if not isinstance(self.adc, Mapping):
            raise BadInput(f"chip {self.name}: adc={self.adc!r} must map ADC mode names to "
                           "AdcLimits")
        bad = sorted(str(m) for m in set(self.adc) - set(ADC_MODES))
        if not self.adc or bad:
            raise BadInput(f"chip {self.name}: adc modes {sorted(map(str, self.adc))} must be "
                           f"a non-empty subset of {sorted(ADC_MODES)}")
        for mode, lim in self.adc.items():
            rate = getattr(lim, "max_rate_sps", None)
            if not (isinstance(lim, AdcLimits) and isinstance(rate, (int, float, np.number))
                    and not isinstance(rate, bool) and 0 < rate < math.inf):
                raise BadInput(f"chip {self.name}: adc[{mode!r}]={lim!r} must be AdcLimits with "
                               "max_rate_sps a finite number > 0 (sps)")
        for fld in ("if_bandwidth_hz", "if_lowpass_hz"):
            v = getattr(self, fld)
            if not (isinstance(v, (int, float)) and 0 < v < math.inf):
                raise BadInput(f"chip {self.name}: {fld}={v!r} must be a finite number > 0")
        if self.phase_shifter_bits is not None and (
                isinstance(self.phase_shifter_bits, bool)
                or not isinstance(self.phase_shifter_bits, (int, np.integer))
                or not 1 <= self.phase_shifter_bits <= 16):
            raise BadInput(f"chip {self.name}: phase_shifter_bits="
                           f"{self.phase_shifter_bits!r} must be None or an integer in 1..16")
        if not self.adcbuf_interleave or self.adcbuf_interleaved_default not in \
                self.adcbuf_interleave:
            raise BadInput(f"chip {self.name}: adcbuf_interleaved_default="
                           f"{self.adcbuf_interleaved_default!r} must be one of "
                           f"adcbuf_interleave={sorted(self.adcbuf_interleave)}")

    @property
    def max_chirps(self) -> int:
        """Chirps per frame the chirp RAM and loop counter allow: max_chirp_defs x max_loops."""
        return self.max_chirp_defs * self.max_loops

    def supports(self, adc_mode: str) -> bool:
        return adc_mode in self.adc

    # ------------------------------------------------------------------ configs
    def validate(self, cfg) -> None:
        """Check a `radarsim.RadarConfig` against this chip's limits (design.md 4.4 with this
        chip's values): ADC mode, active channels, ADC samples and chirps, ADC rate, IF band,
        RF band, phase-shifter bits, ADC-buffer interleaving. Fields left None take the
        chip's defaults (`defaults`) and are valid by definition.

        Raises
        ------
        ValueError
            Naming the field, the value and this chip's limit.
        """
        if not self.supports(cfg.adc_mode):
            raise BadInput(f"adc_mode={cfg.adc_mode!r}: the {self.name} supports "
                           f"{sorted(self.adc)} ({self.datasheet}, receive subsystem)")
        for name, hi in (("n_tx", self.n_tx), ("n_rx", self.n_rx)):
            val = getattr(cfg, name)
            if not isinstance(val, (int, np.integer)) or not 1 <= val <= hi:
                raise BadInput(f"{name}={val!r} must be an integer in 1..{hi} ({self.name})")
        self.channels(cfg.tx_channels, cfg.n_tx, "tx")
        self.channels(cfg.rx_channels, cfg.n_rx, "rx")
        if cfg.n_samples > self.max_adc_samples:
            raise BadInput(f"n_samples={cfg.n_samples} exceeds the {self.name} limit of "
                           f"{self.max_adc_samples} ADC samples per chirp")
        if cfg.n_chirps > self.max_chirps:
            raise BadInput(f"n_chirps={cfg.n_chirps} exceeds the {self.name} limit of "
                           f"{self.max_chirps} chirps per frame ({self.max_chirp_defs} chirp "
                           f"definitions x {self.max_loops} loops)")
        self._validate_rf(cfg)
        self.shifter_bits(cfg.phase_shifter_bits)
        self.adcbuf_interleaved(cfg.adcbuf_interleaved)

    def _validate_rf(self, cfg) -> None:
        """ADC rate, IF band and RF band of a config (design.md 4.4)."""
        max_rate = self.adc[cfg.adc_mode].max_rate_sps
        if cfg.adc_rate_sps > max_rate:
            raise BadInput(f"adc_rate_sps={cfg.adc_rate_sps:g} exceeds the {self.name} "
                           f"limit {max_rate:g} sps ({cfg.adc_mode} ADC)")
        if not cfg.is_complex and \
                cfg.max_beat_frequency_hz > self.if_bandwidth_hz * (1 + 1e-9):
            raise BadInput(f"adc_rate_sps={cfg.adc_rate_sps:g}: beat (IF) frequency span "
                           f"{cfg.max_beat_frequency_hz:g} Hz exceeds the {self.name} IF "
                           f"bandwidth limit {self.if_bandwidth_hz:g} Hz")
        if cfg.start_freq_hz < self.band_min_hz:
            raise BadInput(f"start_freq_hz={cfg.start_freq_hz:g} is below the {self.name} "
                           f"band limit {self.band_min_hz:g} Hz")
        ramp_top = cfg.start_freq_hz + cfg.slope_hz_per_s * cfg.ramp_end_time_s
        # TI profiles give the ramp end time to 10 ns (two decimals in us), so a ramp sized to
        # the band edge may pass it by up to one slope x 10 ns (TI Visualizer's 60 GHz
        # "profileCfg 0 60 ... 114.29 ... 35 ..." ends 0.15 MHz above 64 GHz).
        if ramp_top > self.band_max_hz * (1 + 1e-12) + cfg.slope_hz_per_s * 10e-9:
            raise BadInput(f"start_freq_hz={cfg.start_freq_hz:g} + slope_hz_per_s="
                           f"{cfg.slope_hz_per_s:g} x ramp_end_time_s="
                           f"{cfg.ramp_end_time_s:g}: ramp end frequency {ramp_top:g} Hz "
                           f"exceeds the {self.name} band limit {self.band_max_hz:g} Hz")

    def channels(self, value, n: int, side: str) -> tuple[int, ...]:
        """Chip channels (1-based) of the `n` active Tx or Rx (`side` "tx" / "rx"): `value`,
        or 1..n when None.

        Raises
        ------
        ValueError
            Not `n` distinct channel numbers of this chip.
        """
        if value is None:
            return tuple(range(1, n + 1))
        n_chip = self.n_tx if side == "tx" else self.n_rx
        chans = integers(value, f"{side}_channels",
                         f"{n} distinct channel numbers in 1..{n_chip}")
        if len(chans) != n or len(set(chans)) != n or not all(1 <= c <= n_chip for c in chans):
            raise BadInput(f"{side}_channels={value!r} must list {n} distinct channel numbers "
                           f"in 1..{n_chip} ({self.name})")
        return chans

    def shifter_bits(self, value) -> int:
        """Phase-shifter bits of a config: the chip's (0 without a shifter: one code, 0 deg;
        TDMA / BPM signs need none) when `value` is None, else `value` if it is the chip's.

        Raises
        ------
        ValueError
            Any other value.
        """
        bits = self.phase_shifter_bits or 0
        if value is None:
            return bits
        if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value != bits:
            have = "has no phase shifter" if not bits else f"phase shifter has {bits} bits"
            raise BadInput(f"phase_shifter_bits={value!r}: the {self.name} {have}")
        return int(value)

    def adcbuf_interleaved(self, value) -> bool:
        """ADC-buffer interleaving of a config: the demo's when `value` is None.

        Raises
        ------
        ValueError
            A setting the chip's demo firmware does not accept.
        """
        if value is None:
            return self.adcbuf_interleaved_default
        if bool(value) not in self.adcbuf_interleave:
            raise BadInput(f"adcbuf_interleaved={value!r}: the {self.name} "
                           "demo firmware accepts only a "
                           f"{'non-' if False in self.adcbuf_interleave else ''}interleaved "
                           "ADC buffer")
        return bool(value)

    def defaults(self, cfg) -> dict[str, Any]:
        """The chip-derived fields of a validated config, None resolved: active channels,
        phase-shifter bits, ADC-buffer interleaving."""
        return {"tx_channels": self.channels(cfg.tx_channels, cfg.n_tx, "tx"),
                "rx_channels": self.channels(cfg.rx_channels, cfg.n_rx, "rx"),
                "phase_shifter_bits": self.shifter_bits(cfg.phase_shifter_bits),
                "adcbuf_interleaved": self.adcbuf_interleaved(cfg.adcbuf_interleaved)}


def _awr294x(name: str, board: str, datasheet: str, platform: str,
             interleaved_default: bool = True, channel_cfg_args: int = 3) -> Chip:
    return Chip(
        name=name,
        band_min_hz=76e9, band_max_hz=81e9,           # Features: 76- to 81-GHz
        n_tx=4, n_rx=4,                                # Features: four Tx, four Rx
        adc=MappingProxyType({"real": AdcLimits(37.5e6)}),  # real-only receiver; design.md 4.4
        if_bandwidth_hz=15e6,                          # receive subsystem: up to 15 MHz
        # Just above the usable IF band: < 0.2 dB loss to ~240 m at the R79 slope, echoes
        # beyond the 253 m Nyquist range attenuated instead of aliasing at full strength.
        if_lowpass_hz=16.5e6,
        phase_shifter_bits=6,                          # [TI-DDMA] 3.3, table 4: 5.625 deg LSB
        max_adc_samples=1024,                          # rlProfileCfg_t numAdcSamples
        max_chirp_defs=512,                            # rlChirpCfg_t: chirp RAM of 512
        max_loops=255,                                 # rlFrameCfg_t.numLoops 1..255
        max_profiles=4,                                # RL_MAX_PROFILES_CNT
        adcbuf_interleave=frozenset({True, False}),    # MCU+ SDK adcbufCfg: both
        # AWR2944: [TI-DAZ] sec. 2 and the R79 firmware's adcbufCfg -1 1 0 0 1; AWR2544: its
        # DDM demo profile's adcbufCfg -1 1 0 1 1.
        adcbuf_interleaved_default=interleaved_default,
        lvds_lanes=4,                                  # MCU+ SDK lvdsStreamCfg: 4-lane HSI
        default_board=board,
        datasheet=datasheet,
        ti_platform=platform, mcu_plus_sdk=True, channel_cfg_args=channel_cfg_args,
    )


def _xwr1x6x(name: str, band: tuple[float, float], n_tx: int, if_bw: float,
             shifter: int | None, board: str, datasheet: str, platform: str, *,
             interleaved: bool = False, lanes: int = 2, max_rate_sps: float = 25e6) -> Chip:
    return Chip(
        name=name, band_min_hz=band[0], band_max_hz=band[1], n_tx=n_tx, n_rx=4,
        adc=MappingProxyType({
            "real": AdcLimits(max_rate_sps),  # mmWave SDK / rlProfileCfg_t: real up to 25 Msps
            "complex1x": AdcLimits(max_rate_sps / 2),  # complex 1x up to 12.5 Msps
            "complex2x": AdcLimits(max_rate_sps),      # complex 2x up to 25 Msps
        }),
        if_bandwidth_hz=if_bw,
        if_lowpass_hz=1.1 * if_bw,
        phase_shifter_bits=shifter,
        max_adc_samples=1024,               # 32 KB ping-pong ADC buffer: 4 Rx x 1024 x 4 B
        max_chirp_defs=512, max_loops=255, max_profiles=4,
        # SDK 3.x xWR16/18/68: only non-interleaved; xWR14xx: only interleaved.
        adcbuf_interleave=frozenset({interleaved}),
        adcbuf_interleaved_default=interleaved,
        lvds_lanes=lanes,                   # SDK LVDS streaming, DCA1000 lvdsMode 2 (1: 4 lanes)
        default_board=board, datasheet=datasheet,
        ti_platform=platform, mcu_plus_sdk=False, channel_cfg_args=3,
    )


#: Chips by the name users type (TI part number); `register_chip` adds a lab's own.
CHIPS: Registry[Chip] = Registry("chip", kind=Chip)
CHIPS.register_all((
    _awr294x("AWR2944", "AWR2944EVM", "SWRS273D", "AWR294X"),
    _awr294x("AWR2944P", "AWR2944PEVM", "SWRS318A", "AWR2X44P", channel_cfg_args=5),
    _awr294x("AWR2544", "AWR2544LOPEVM", "SWRS314B", "AWR2544",
             interleaved_default=False, channel_cfg_args=5),
    # Complex-baseband family: IF bandwidths from each receive-subsystem section.
    _xwr1x6x("AWR1843", (76e9, 81e9), 3, 10e6, 6, "AWR1843BOOST", "SWRS222D", "xWR18xx"),
    _xwr1x6x("AWR1642", (76e9, 81e9), 2, 5e6, None, "AWR1642BOOST", "SWRS203D", "xWR16xx"),
    _xwr1x6x("IWR6843", (60e9, 64e9), 3, 10e6, 6, "IWR6843ISK", "SWRS219F", "xWR68xx"),
    _xwr1x6x("AWR1443", (76e9, 81e9), 3, 15e6, None, "AWR1443BOOST", "SWRS207", "xWR14xx",
             interleaved=True, lanes=4),
    # Front ends (mmWave Studio setups; no SDK demo of their own).
    _xwr1x6x("AWR1243", (76e9, 81e9), 3, 15e6, None, "AWR1243BOOST", "SWRS188", "AWR1243",
             lanes=4),
    _xwr1x6x("AWR2243", (76e9, 81e9), 3, 20e6, 6, "AWR2243BOOST", "SWRS223D", "AWR2243",
             lanes=4, max_rate_sps=45e6),
))


def get_chip(name: str) -> Chip:
    """The chip of that name; ValueError naming the known chips otherwise.

    Examples
    --------
    >>> from radarsim.chips import get_chip
    >>> chip = get_chip("AWR1843")
    >>> chip.n_tx, chip.if_bandwidth_hz, sorted(chip.adc)
    (3, 10000000.0, ['complex1x', 'complex2x', 'real'])
    """
    return CHIPS.lookup(name)


def register_chip(chip: Chip, *, replace: bool = False) -> Chip:
    """Register a lab's own chip (a `Chip` record) under ``chip.name`` and return it.

    A config then names it in ``RadarConfig.chip``; give it a board too (`register_board`,
    ``default_board`` names it).

    Raises
    ------
    ValueError
        A name already taken (without ``replace``), or not a `Chip`.

    Examples
    --------
    >>> import dataclasses, radarsim
    >>> lab = dataclasses.replace(radarsim.CHIPS["AWR2944"], name="LAB2944",
    ...                           default_board="AWR2944EVM_LAB")
    >>> _ = radarsim.register_chip(lab)
    >>> _ = radarsim.register_board(dataclasses.replace(radarsim.BOARDS["AWR2944EVM"],
    ...                                                 name="AWR2944EVM_LAB", chip="LAB2944"))
    >>> radarsim.presets.r79_ddma(**{"array.chip": "LAB2944"}).board
    'AWR2944EVM_LAB'
    >>> _ = radarsim.BOARDS.unregister("AWR2944EVM_LAB"), radarsim.CHIPS.unregister("LAB2944")
    """
    return CHIPS.register(chip, replace=replace)
