"""TI mmWave SDK CLI profiles (.cfg) in and out, for every chip of `radarsim.chips.CHIPS`.

`parse_ti_cfg` reads the CLI commands of an mmWave SDK 2.x/3.x or MCU+ SDK configuration file
(the xwr16xx/18xx/68xx demos, the AWR294x/AWR2x44P/AWR2544 demos, the R79 demo's hard-coded
list, TI Visualizer output, toolbox labs) into a
`TiProfile`: the `RadarConfig` the commands define (channels, ADC format, chirp profile, chirp
table, frame, DDMA phase order), the CFAR settings (`cfarCfg`, kept pipeline-independent as
`TiCfar`), the frame period and every other demo command, kept and reported as ignored.
`from_ti_cfg` returns just the `RadarConfig`; `to_ti_cfg` writes one back, so that
``from_ti_cfg(to_ti_cfg(cfg)) == cfg`` for every valid config (the R79 preset is shipped as
``radarsim/data/r79_ddma.cfg``).

Units follow TI on the file side (GHz, us, MHz/us, ksps, ms, dB) and SI in `RadarConfig`; every
value is converted exactly once, through its decimal text (``"18.81"`` us becomes the float
nearest to 18.81e-6 s), so a write/read cycle is bit-exact.

Fields a TI file cannot express (RF budget, shifter error model, quantisation rule) travel as
structured comments, which TI's CLI skips like any ``%`` line::

    % radarsim: phase_quantization = "floor"

A file without them gets the `RadarConfig` defaults, except the shifter-code rule: TI's SDK
rounds phases to the nearest code, so a plain TI file means ``phase_quantization="round"``
(DESIGN section 4.3); the shipped R79 file carries ``"floor"`` to reproduce seed 000 table 4.

The chip comes from a ``% radarsim: chip = "..."`` directive, TI Visualizer's ``% Platform:``
header, or the commands themselves (`_infer_chip`); its limits (`radarsim.chips`) bound every
value. Commands the harness does not model (demo output, monitors, dither, calibration,
tracker and toolbox-lab commands, chirps and profiles the frame does not use) are kept and
reported as ignored (`TiProfile.ignored`, `TiProfile.notes`); an unknown command is ignored too,
unless it is a near-misspelling of a modelled command. ValueError naming the line is raised
only for what the chip would refuse or the harness cannot model: wrong argument counts for the
chip, malformed numbers, values outside the chip's limits, advanced frames, BPM, chirp patterns
that are neither DDMA nor TDMA, inconsistent numbers, missing required commands, and
`RadarConfig`'s own validation errors, re-raised with the line of the command that set the
offending field.

Command syntax (argument lists checked against TI sources, found with the code search)
--------------------------------------------------------------------------------------
mmWave MCU+ SDK 4.x ``ti/utils/cli/src/cli_mmwave.c`` (AWR294X build; help strings and argc
checks; same conversions as mmWave SDK 3.5 ``packages/ti/utils/cli/src/cli_mmwave.c``):

- ``dfeDataOutputMode <modeType>``: 1 frame, 2 continuous, 3 advanced frame (argc 2).
- ``channelCfg <rxChannelEn> <txChannelEn> <cascading>`` (argc 4; AWR2544/AWR2x44P add
  ``<ethOscClkEn> <driveStrength>``, argc 6). Any subset of channels (``txChannelEn 5`` = Tx1
  and Tx3) becomes `RadarConfig.tx_channels` / `rx_channels`.
- ``adcCfg <numADCBits> <adcOutputFmt>``: bits 0/1/2 = 12/14/16; fmt 0 real, 1 complex 1x,
  2 complex 2x (argc 3).
- ``profileCfg <profileId> <startFreq GHz> <idleTime us> <adcStartTime us> <rampEndTime us>
  <txOutPower> <txPhaseShifter> <freqSlopeConst MHz/us> <txStartTime us> <numAdcSamples>
  <digOutSampleRate ksps> <hpfCornerFreq1> <hpfCornerFreq2> <rxGain>`` (argc 15).
- ``chirpCfg <startIdx> <endIdx> <profileId> <startFreqVar> <freqSlopeVar> <idleTimeVar>
  <adcStartTimeVar> <txEnable>`` (argc 9).
- ``frameCfg <chirpStartIdx> <chirpEndIdx> <numLoops> <numFrames> <numAdcSamples>
  <framePeriodicity ms> <triggerSelect> <frameTriggerDelay ms>`` (argc 9 in the MCU+ SDK;
  mmWave SDK 3.x has no ``numAdcSamples``, argc 8 -- both accepted). ``numAdcSamples`` counts
  16-bit words per chirp and Rx (rlFrameCfg_t): the profile's samples, twice that for complex.

AWR2944 R79 corner-radar demo (TIDEP-01027) ``mss/mmw_cli.c``, whose hard-coded command list is
the R79 waveform of seed 000 table 2 (``profileCfg 0 77 5 5 18.81 0 0 8.883 0 384 30000 0 0
42``, ``chirpCfg 0 5 0 0 0 0 0 15``, ``frameCfg 0 5 128 0 384 250 1 0``):

- ``cfarCfg <subFrameIdx> <procDirection> <averageMode> <winLen> <guardLen> <noiseDiv>
  <cyclicMode> <thresholdScale dB> <peakGroupingEn> <osKvalue> <osEdgeKscaleEn>`` (argc 12;
  thresholdScale at most 100 dB). mmWave SDK 3.x / AWR294X TDM demo: the first 9 arguments;
  AWR2x44P DDM demo: + ``<isEnabled>`` (range) and + ``<variableThresholdMode>`` (Doppler).
  averageMode 0 CA, 1 CAGO, 2 CASO, 3 OS (HWA 2.0; seed 003 ``DPU_CFARProc_CfarCfg``);
  winLen and guardLen are one-sided.
- ``adcbufCfg <subFrameIdx> <adcOutputFmt> <SampleSwap> <ChanInterleave> <ChirpThreshold>``
  (argc 6, SDK 1.x without subFrameIdx; adcOutputFmt 0 complex, 1 real, must agree with
  ``adcCfg``; ChanInterleave 0 = interleaved buffer, `RadarConfig.adcbuf_interleaved`, which
  fixes the raw capture layout; chirpThreshold must be 1). The R79 firmware's hard-coded list
  has ``adcbufCfg -1 1 0 0 1``: interleaved, as seed 004 section 2 says of the AWR2944.

mmWave MCU+ SDK AWR2x44P DDM demo ``mmw_cli.c`` and its doxygen ``main.c`` (without the
command, as in the R79 firmware list, the R79 order: horizontal Tx first, elevation last):

- ``ddmPhaseShiftAntOrder <Tx0> <Tx1> ... <TxN>``: "antenna indices in increasing order of
  phase shift value, if all of them were enabled"; elevation antennas last, ``0 2 3 1`` for the
  AWR2944 (Tx0, Tx2, Tx3 azimuth, Tx1 elevation). TI's Tx k is our Tx k+1, so this is exactly
  `RadarConfig.tx_order` minus one (Tx1, Tx3, Tx4, Tx2).
- ``antGeometryCfg <Row(Tx0Rx0)> <Col(Tx0Rx0)> ... <Row(Tx3Rx3)> <Col(Tx3Rx3)> <xSpacebylambda>
  <zSpacebylambda>``: row 1 azimuth, row 0 elevation; the AWR2944 EVM is
  ``1 0 1 1 1 2 1 3 0 2 0 3 0 4 0 5 1 4 1 5 1 6 1 7 1 8 1 9 1 10 1 11 0.5 0.8`` (DESIGN 4.2).
  The grid defines the array (`RadarConfig.tx_positions_wl` / `rx_positions_wl`).

Chirp table to MIMO scheme: DDMA when every chirp of the frame enables the same two or more Tx
(as ``chirpCfg 0 5 ... 15`` + ``frameCfg 0 5 128``: 6 chirps per loop = 6 sub-bands, 128 loops
= 768 chirps); TDMA when each chirp enables one Tx and the loop repeats a sequence in which each
used Tx fires once (``Tx1, Tx3, Tx1, Tx3``: order Tx1, Tx3).

References
----------
.. [1] TI, mmWave SDK user guide, sec. "Configuration (.cfg) File Format".
.. [2] TI, AWR2944 DDMA application note (seed 000), table 2 (R79 waveform), sec. 3.3.
.. [3] TI, CFAR in the mmWave SDK (seed 003), ``DPU_CFARProc_CfarCfg``.
"""
from __future__ import annotations

import dataclasses
import difflib
import json
import os
import re
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from importlib import resources
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

from types import MappingProxyType

from .chips import ADC_MODES, CHIPS, Chip, get_chip
from .config import RadarConfig

__all__ = ["TiCfar", "TiProfile", "parse_ti_cfg", "from_ti_cfg", "to_ti_cfg", "r79_cfg_path",
           "r79_cfg_text", "TI_COMMANDS", "CFAR_AVERAGE_MODES", "DEFAULT_FRAME_PERIOD_S",
           "R79_CFAR", "R79_DEMO_LINES", "R79_FIRMWARE_LINES", "PLATFORMS"]

_MAX_CFAR_THRESHOLD_DB = 100.0  # R79 demo mmw_cli.c: "Maximum value for CFAR thresholdScale"

#: Frame period written when none is given, s: the R79 demo's ``frameCfg ... 250 1 0``.
DEFAULT_FRAME_PERIOD_S = 0.25

#: TI ``averageMode`` code -> CFAR mode name (seed 003; the pipeline's CFAR_MODES keys).
CFAR_AVERAGE_MODES = {0: "ca", 1: "cago", 2: "caso", 3: "os"}
#: ``averageMode`` codes whose noise estimate is an order statistic (they need ``osKvalue``).
_CFAR_RANKED_CODES = frozenset({3})
_CFAR_RANKED_MODES = frozenset(CFAR_AVERAGE_MODES[c] for c in _CFAR_RANKED_CODES)
_CFAR_DIRECTIONS = {0: "range", 1: "doppler"}

# RadarConfig fields that TI commands define (a directive may not set them).
_TI_FIELDS = frozenset({"mimo", "n_tx", "n_rx", "start_freq_hz", "slope_hz_per_s",
                        "idle_time_s", "adc_start_time_s", "ramp_end_time_s", "n_samples",
                        "adc_rate_sps", "n_chirps", "tx_order", "tx_channels", "rx_channels",
                        "adc_mode", "adcbuf_interleaved"})
# Defaults of the fields a plain TI file leaves open: RadarConfig's, except the SDK's rounding.
_TI_DEFAULT_OVERRIDES = {"phase_quantization": "round"}
_DIRECTIVE_RE = re.compile(r"^%\s*radarsim\s*:\s*(\w+)\s*=\s*(.*?)\s*$")


# ---------------------------------------------------------------------------- public types
@dataclass(frozen=True, kw_only=True, slots=True)
class TiCfar:
    """One ``cfarCfg`` line, pipeline-independent (harness.cmd_ti maps it onto the pipeline).

    Parameters
    ----------
    direction : {"range", "doppler"}
        ``procDirection`` 0 / 1.
    mode : {"ca", "cago", "caso", "os"}
        ``averageMode`` 0..3.
    window_cells, guard_cells : int
        One-sided training window and guard lengths, cells.
    noise_div_shift : int
        TI's noise-sum divisor as a shift (fixed-point detail, kept for round trips).
    cyclic : bool
        Cyclic (wrap-around) window.
    threshold_db : float
        Threshold over the noise estimate, dB (0..100).
    peak_grouping : bool
        TI's peak grouping.
    os_rank : int or None
        OS-CFAR order statistic k (1-based among the 2 x window_cells training cells); None
        when the line has no ``osKvalue``.
    os_edge_k_scale : bool
        Scale k at the edges (non-cyclic OS only).
    enabled : bool
        ``isEnabled`` of the AWR2x44P DDM syntax (True when absent).
    variable_threshold_mode : int or None
        AWR2x44P DDM Doppler-CFAR extra argument, if given.
    line_no : int
        Line of the command (0 if built in code).
    """

    direction: str
    mode: str
    window_cells: int
    guard_cells: int
    noise_div_shift: int = 0
    cyclic: bool = True
    threshold_db: float
    peak_grouping: bool = False
    os_rank: int | None = None
    os_edge_k_scale: bool = False
    enabled: bool = True
    variable_threshold_mode: int | None = None
    line_no: int = dataclasses.field(default=0, compare=False)

    def __post_init__(self) -> None:
        if self.direction not in _CFAR_DIRECTIONS.values():
            raise ValueError(f"direction={self.direction!r} is not one of "
                             f"{sorted(_CFAR_DIRECTIONS.values())}")
        if self.mode not in CFAR_AVERAGE_MODES.values():
            raise ValueError(f"mode={self.mode!r} is not one of "
                             f"{sorted(CFAR_AVERAGE_MODES.values())}")
        if self.window_cells < 1:
            raise ValueError(f"window_cells={self.window_cells} must be >= 1")
        if self.guard_cells < 0:
            raise ValueError(f"guard_cells={self.guard_cells} must be >= 0")
        if not 0.0 <= self.threshold_db <= _MAX_CFAR_THRESHOLD_DB:
            raise ValueError(f"threshold_db={self.threshold_db:g} must be within 0.."
                             f"{_MAX_CFAR_THRESHOLD_DB:g} dB (TI CLI limit)")
        if self.mode in _CFAR_RANKED_MODES:
            if self.os_rank is None or not 1 <= self.os_rank <= 2 * self.window_cells:
                raise ValueError(f"os_rank={self.os_rank!r}: OS-CFAR needs 1 <= k <= 2 x "
                                 f"window_cells = {2 * self.window_cells}")

    def to_cli(self) -> str:
        """The ``cfarCfg`` line in the R79 demo's 11-argument syntax."""
        code = {v: k for k, v in CFAR_AVERAGE_MODES.items()}[self.mode]
        direction = {v: k for k, v in _CFAR_DIRECTIONS.items()}[self.direction]
        return (f"cfarCfg -1 {direction} {code} {self.window_cells} {self.guard_cells} "
                f"{self.noise_div_shift} {int(self.cyclic)} {_fmt_decimal(self.threshold_db)} "
                f"{int(self.peak_grouping)} {self.os_rank or 0} {int(self.os_edge_k_scale)}")


#: The R79 demo's CFAR (AWR2944 R79 mmw_cli.c): OS-CFAR along Doppler, 16 cells a side, no
#: guard, k = 24, cyclic, 12 dB; the range CFAR (15 dB) is disabled there by ``rangeCfar 0``.
R79_CFAR = {
    "doppler": TiCfar(direction="doppler", mode="os", window_cells=16, guard_cells=0,
                      noise_div_shift=0, cyclic=True, threshold_db=12.0, peak_grouping=False,
                      os_rank=24, os_edge_k_scale=False),
    "range": TiCfar(direction="range", mode="os", window_cells=16, guard_cells=0,
                    noise_div_shift=0, cyclic=True, threshold_db=15.0, peak_grouping=False,
                    os_rank=7, os_edge_k_scale=False),
}


@dataclass(frozen=True, kw_only=True, slots=True)
class TiProfile:
    """Everything a TI .cfg says, with the radar as a validated `RadarConfig`.

    Attributes
    ----------
    radar : RadarConfig
        Waveform, channels and MIMO schedule.
    frame_period_s : float
        ``framePeriodicity``, s (at least the chirp burst, n_chirps x chirp period).
    n_frames : int
        ``numFrames`` (0: run until stopped).
    trigger_select : int
        1 software, 2 hardware trigger.
    cfar : dict of str to TiCfar
        ``cfarCfg`` lines by direction ("range", "doppler").
    ddm_phase_order : tuple of int or None
        ``ddmPhaseShiftAntOrder`` (TI's 0-based Tx indices).
    ant_geometry : tuple or None
        ``antGeometryCfg``: ((row, col) x 16, x spacing, z spacing in wavelengths).
    adc_channel_interleaved : bool
        ``adcbufCfg`` ChanInterleave = 0 (interleaved ADC buffer); the chip demo's default when
        absent (= ``radar.adcbuf_interleaved``).
    sample_swap : bool or None
        ``adcbufCfg`` SampleSwap, if given.
    lvds_stream : tuple or None
        ``lvdsStreamCfg`` (enableHeader, dataFmt, enableSW), if given.
    profile_extras : dict
        profileCfg values the front-end model does not use: tx_start_time_s,
        hpf_corner_1_code, hpf_corner_2_code, rx_gain_code.
    chirp_level : dict
        The DDM demo's chirp-level settings as `pipeline.ProcessingConfig` field values:
        ``intfMitigCfg`` -> intf_mag_snr_db, intf_magdiff_snr_db; ``compressionCfg`` ->
        compression, compression_ratio, compression_range_bins_per_block (EGE only).
    ignored : tuple of (int, str)
        (line number, command) of every command kept but not used (demo, monitoring, tracker
        and calibration commands, unknown commands).
    notes : tuple of str
        How the chip was found, defaults taken, chirps/profiles/Tx defined but unused.
    directives : dict
        Fields set by ``% radarsim:`` comments.
    """

    radar: RadarConfig
    frame_period_s: float
    n_frames: int = 0
    trigger_select: int = 1
    cfar: dict[str, TiCfar] = dataclasses.field(default_factory=dict)
    ddm_phase_order: tuple[int, ...] | None = None
    ant_geometry: tuple | None = None
    adc_channel_interleaved: bool = False
    sample_swap: bool | None = None
    lvds_stream: tuple | None = None
    profile_extras: dict[str, Any] = dataclasses.field(default_factory=dict)
    chirp_level: dict[str, Any] = dataclasses.field(default_factory=dict)
    ignored: tuple[tuple[int, str], ...] = ()
    notes: tuple[str, ...] = ()
    directives: dict[str, Any] = dataclasses.field(default_factory=dict)

    @property
    def ignored_commands(self) -> list[str]:
        """Names of the ignored commands, in file order."""
        return [cmd for _, cmd in self.ignored]


# ---------------------------------------------------------------------------- number helpers
def _fmt_decimal(value: float | int | Decimal, exponent: int = 0) -> str:
    """Decimal text t with float(Decimal(t) x 10^exponent) == value exactly (shortest repr)."""
    d = value if isinstance(value, Decimal) else Decimal(repr(float(value)))
    d = d.scaleb(-exponent).normalize()
    text = format(d, "f")
    return "0" if text in ("-0", "0") else text


class _LineError(ValueError):
    pass


@dataclass(frozen=True, slots=True)
class _Line:
    no: int
    cmd: str
    args: tuple[str, ...]

    def fail(self, message: str) -> ValueError:
        return _LineError(f"line {self.no} ({self.cmd}): {message}")

    def dec(self, i: int, name: str) -> Decimal:
        tok = self.args[i]
        try:
            d = Decimal(tok)
        except InvalidOperation:
            raise self.fail(f"{name}={tok!r} is not a number") from None
        if not d.is_finite():
            raise self.fail(f"{name}={tok!r} must be finite")
        return d

    def si(self, i: int, name: str, exponent: int) -> float:
        # Through the decimal text, so "18.81" us is exactly the float nearest 18.81e-6 s.
        return float(self.dec(i, name).scaleb(exponent))

    def int(self, i: int, name: str, lo: int | None = None, hi: int | None = None,
            chip: str | None = None) -> int:
        tok = self.args[i]
        # TI's CLI reads integers with atoi: "2950.00" (TI toolbox profiles) is 2950; a
        # fractional value is refused rather than truncated.
        if not re.fullmatch(r"[+-]?\d+(\.0*)?|0[xX][0-9a-fA-F]+", tok):
            raise self.fail(f"{name}={tok!r} is not an integer")
        val = int(tok, 0) if tok.lower().startswith("0x") else int(tok.split(".")[0])
        if (lo is not None and val < lo) or (hi is not None and val > hi):
            rng = f"{lo if lo is not None else '-inf'}..{hi if hi is not None else 'inf'}"
            raise self.fail(f"{name}={val} is outside {rng}" +
                            (f" ({chip} limit)" if chip else ""))
        return val

    def flag(self, i: int, name: str) -> bool:
        return bool(self.int(i, name, 0, 1))


# ---------------------------------------------------------------------------- chip inference
#: Family spellings of the ``% Platform:`` header other TI tools and SDK releases write.
_PLATFORM_ALIASES = {
    "awr18xx": "AWR1843", "iwr18xx": "AWR1843", "xwr1843": "AWR1843", "iwr1843": "AWR1843",
    "awr16xx": "AWR1642", "iwr16xx": "AWR1642", "xwr1642": "AWR1642", "iwr1642": "AWR1642",
    "iwr68xx": "IWR6843", "xwr64xx": "IWR6843", "awr6843": "IWR6843", "xwr6843": "IWR6843",
    "xwr294x": "AWR2944", "xwr2544": "AWR2544",
}
#: TI visualizer ``% Platform:`` names -> chip: each chip's own name and its
#: `Chip.ti_platform` (the header TI's Visualizer writes), plus the aliases.
PLATFORMS = {**{name.lower(): name for name in CHIPS},
             **{c.ti_platform.lower(): name for name, c in CHIPS.items()}, **_PLATFORM_ALIASES}
_PLATFORM_RE = re.compile(r"^%\s*platform\s*:\s*(\S+)", re.IGNORECASE)


def _infer_chip(lines: list[str]) -> tuple[str, str]:
    """(chip, how it was found) from a ``% radarsim: chip`` directive, TI's ``% Platform:``
    header, or the commands: 60-64 GHz -> IWR6843; complex ADC -> AWR1843 with Tx3 enabled,
    else AWR1642; real ADC -> the AWR294x family (AWR2544 with ``procChainCfg``, AWR2944P
    with the 5-argument ``channelCfg``, else AWR2944)."""
    cmds: dict[str, list[str]] = {}
    for raw in lines:
        text = raw.strip()
        m = _DIRECTIVE_RE.match(text)
        if m and m.group(1) == "chip":
            try:
                return str(json.loads(m.group(2))), "directive"
            except json.JSONDecodeError:
                return m.group(2).strip('"\''), "directive"
        m = _PLATFORM_RE.match(text)
        if m:
            name = m.group(1).lower()
            base = name.split("_")[0]  # xWR68xx_AOP, xWR18xx_AOP: the chip of the base name
            if name in PLATFORMS or base in PLATFORMS:
                chip = PLATFORMS.get(name, PLATFORMS.get(base))
                how = f"'% Platform:{m.group(1)}' header"
                if name not in PLATFORMS:
                    how += (f" (the {m.group(1)} board is not in the board registry: the "
                            f"{chip}'s default board is assumed unless antGeometryCfg is given)")
                return chip, how
        if text and not text.startswith("%"):
            cmd, *args = text.split()
            cmds.setdefault(cmd, args)
    prof = cmds.get("profileCfg", [])
    try:
        start_ghz = float(prof[1])
    except (IndexError, ValueError):
        start_ghz = 77.0
    if start_ghz < 70.0:
        return "IWR6843", "start frequency in the 60-64 GHz band"
    adc = cmds.get("adcCfg", [])
    chan = cmds.get("channelCfg", [])
    if len(adc) >= 2 and adc[1] in ("1", "2"):
        tx = int(chan[1]) if len(chan) >= 2 and chan[1].isdigit() else 3
        if tx > 3:
            return "AWR1843", "complex ADC with Tx3 enabled"
        return "AWR1642", "complex ADC with Tx1/Tx2"
    if "procChainCfg" in cmds:
        return "AWR2544", "real ADC with procChainCfg (AWR2544 DDM demo)"
    if len(chan) == 5:
        return "AWR2944P", "real ADC with the 5-argument channelCfg (AWR2x44P)"
    return "AWR2944", "real ADC at 76-81 GHz"


# ---------------------------------------------------------------------------- parser state
@dataclass(slots=True)
class _State:
    chip: Chip
    fields: dict[str, Any] = dataclasses.field(default_factory=dict)
    field_lines: dict[str, _Line] = dataclasses.field(default_factory=dict)
    seen: dict[str, _Line] = dataclasses.field(default_factory=dict)
    profiles: dict[int, dict[str, Any]] = dataclasses.field(default_factory=dict)
    chirps: dict[int, tuple[int, int, _Line, bool]] = dataclasses.field(default_factory=dict)
    tx_mask: int | None = None
    rx_mask: int | None = None
    adc_complex: bool | None = None
    frame: dict[str, Any] = dataclasses.field(default_factory=dict)
    cfar: dict[str, TiCfar] = dataclasses.field(default_factory=dict)
    ddm_order: tuple[int, ...] | None = None
    bpm: tuple | None = None
    ant_geometry: tuple | None = None
    adcbuf: dict[str, Any] = dataclasses.field(default_factory=dict)
    lvds: tuple | None = None
    extras: dict[str, Any] = dataclasses.field(default_factory=dict)
    chirp_level: dict[str, Any] = dataclasses.field(default_factory=dict)
    ignored: list[tuple[int, str]] = dataclasses.field(default_factory=list)
    notes: list[str] = dataclasses.field(default_factory=list)
    directives: dict[str, Any] = dataclasses.field(default_factory=dict)
    directive_lines: dict[str, _Line] = dataclasses.field(default_factory=dict)

    def set(self, line: _Line, **values: Any) -> None:
        for k, v in values.items():
            self.fields[k] = v
            self.field_lines[k] = line


def _bits(mask: int) -> tuple[int, ...]:
    """1-based channel numbers of the set bits of a TI channel mask."""
    return tuple(i + 1 for i in range(mask.bit_length()) if mask >> i & 1)


# ---------------------------------------------------------------------------- handlers
def _dfe_output_mode(st: _State, ln: _Line) -> None:
    mode = ln.int(0, "modeType", 1, 5)
    if mode != 1:
        raise ln.fail(f"modeType={mode}: only 1 (frame mode) is supported; advanced frame, "
                      "continuous and advanced-chirp modes have no RadarConfig equivalent")


def _channel_cfg(st: _State, ln: _Line) -> None:
    chip = st.chip
    rx = ln.int(0, "rxChannelEn", 1, (1 << chip.n_rx) - 1, chip.name)
    tx = ln.int(1, "txChannelEn", 1, (1 << chip.n_tx) - 1, chip.name)
    ln.int(2, "cascading", 0, 0, chip.name)
    if len(ln.args) == 5:  # AWR2x44P / AWR2544: <ethOscClkEn> <driveStrength>
        if chip.channel_cfg_args != 5:
            raise ln.fail(f"the 5-argument form (ethOscClkEn, driveStrength) is AWR2x44P / "
                          f"AWR2544 syntax; the {chip.name} demo takes 3 arguments")
        ln.int(3, "ethOscClkEn", 0, 1)
        ln.int(4, "driveStrength", 0, 15)
    st.tx_mask, st.rx_mask = tx, rx
    chans = _bits(rx)
    st.set(ln, n_rx=len(chans), rx_channels=chans)


def _adc_cfg(st: _State, ln: _Line) -> None:
    bits = ln.int(0, "numADCBits", 0, 2)
    fmt = ln.int(1, "adcOutputFmt", 0, 2)
    if bits != 2:
        raise ln.fail(f"numADCBits={bits}: the captures are int16, use 2 (16 bit)")
    mode = next(m for m in ADC_MODES.values() if m.ti_code == fmt)
    if not st.chip.supports(mode.name):
        raise ln.fail(f"adcOutputFmt={fmt} ({mode.name}): the {st.chip.name} supports "
                      f"{sorted(st.chip.adc)} ({'real-only receiver' if len(st.chip.adc) == 1 else ''}"
                      f"{st.chip.datasheet})")
    st.adc_complex = mode.is_complex
    st.set(ln, adc_mode=mode.name)


def _adcbuf_cfg(st: _State, ln: _Line) -> None:
    # mmWave SDK 2.x/3.x and MCU+ SDK: <subFrameIdx> first; SDK 1.x: no subFrameIdx.
    k = 1 if len(ln.args) == 5 else 0
    if k:
        ln.int(0, "subFrameIdx", -1, 3)
    real = ln.flag(k, "adcOutputFmt")  # 0 complex, 1 real
    swap = ln.flag(k + 1, "SampleSwap")
    interleaved = not ln.flag(k + 2, "ChanInterleave")
    # SDK 2.0 Visualizer profiles write 0; the demos accept up to 8 chirps per ADC buffer
    # (the capture layout is per chirp either way: radarsim.capture).
    ln.int(k + 3, "ChirpThreshold", 0, 8)
    if interleaved not in st.chip.adcbuf_interleave:
        raise ln.fail(f"ChanInterleave=0 (interleaved): the {st.chip.name} demo supports only "
                      "the non-interleaved ADC buffer (1)")
    st.adcbuf = dict(real=real, sample_swap=swap, line=ln)
    st.set(ln, adcbuf_interleaved=interleaved)


def _profile_cfg(st: _State, ln: _Line) -> None:
    chip = st.chip
    pid = ln.int(0, "profileId", 0, chip.max_profiles - 1, chip.name)
    if pid in st.profiles:
        raise ln.fail(f"profileId={pid} was already defined on line {st.profiles[pid]['line'].no}")
    start_hz = ln.si(1, "startFreq", 9)
    if not chip.band_min_hz <= start_hz <= chip.band_max_hz:
        raise ln.fail(f"startFreq={ln.args[1]} GHz is outside the {chip.name} band "
                      f"{chip.band_min_hz / 1e9:g}..{chip.band_max_hz / 1e9:g} GHz")
    idle, ramp = ln.dec(2, "idleTime"), ln.dec(4, "rampEndTime")
    tx_power = ln.int(5, "txOutPower", 0, 255)
    tx_phase = ln.int(6, "txPhaseShifter", 0, 0xFFFFFFFF)
    st.profiles[pid] = dict(
        line=ln, tx_power=tx_power, tx_phase=tx_phase,
        fields=dict(start_freq_hz=start_hz, idle_time_s=float(idle.scaleb(-6)),
                    adc_start_time_s=ln.si(3, "adcStartTime", -6),
                    ramp_end_time_s=float(ramp.scaleb(-6)),
                    slope_hz_per_s=ln.si(7, "freqSlopeConst", 12),
                    n_samples=ln.int(9, "numAdcSamples", 2, 65535),
                    adc_rate_sps=float(Decimal(ln.int(10, "digOutSampleRate", 1, 65535))
                                       .scaleb(3)),
                    # The chip's chirp period is idle + ramp end time; summed in decimal, so
                    # "5" + "18.81" us is exactly 23.81e-6 s.
                    chirp_period_s=float((idle + ramp).scaleb(-6))),
        extras=dict(tx_start_time_s=ln.si(8, "txStartTime", -6),
                    hpf_corner_1_code=ln.int(11, "hpfCornerFreq1", 0, 3),
                    hpf_corner_2_code=ln.int(12, "hpfCornerFreq2", 0, 3),
                    rx_gain_code=ln.int(13, "rxGain", 0, 255)))


def _chirp_cfg(st: _State, ln: _Line) -> None:
    chip = st.chip
    start = ln.int(0, "startIdx", 0, chip.max_chirp_defs - 1, chip.name)
    end = ln.int(1, "endIdx", start, chip.max_chirp_defs - 1, chip.name)
    pid = ln.int(2, "profileId", 0, chip.max_profiles - 1, chip.name)
    if pid not in st.profiles:
        raise ln.fail(f"profileId={pid} is not defined by an earlier profileCfg")
    varies = any(ln.dec(i, name) != 0 for i, name in enumerate(
        ("startFreqVar", "freqSlopeVar", "idleTimeVar", "adcStartTimeVar"), start=3))
    tx = ln.int(7, "txEnable", 0, (1 << chip.n_tx) - 1, chip.name)
    for idx in range(start, end + 1):
        if idx in st.chirps:
            raise ln.fail(f"chirp {idx} was already defined on line {st.chirps[idx][2].no}")
        st.chirps[idx] = (tx, pid, ln, varies)


def _frame_cfg(st: _State, ln: _Line) -> None:
    chip = st.chip
    start = ln.int(0, "chirpStartIdx", 0, chip.max_chirp_defs - 1, chip.name)
    end = ln.int(1, "chirpEndIdx", start, chip.max_chirp_defs - 1, chip.name)
    loops = ln.int(2, "numLoops", 1, chip.max_loops, chip.name)
    frames = ln.int(3, "numFrames", 0, 65535)
    k = 4
    samples = None
    if len(ln.args) == 8:  # MCU+ SDK syntax carries numAdcSamples
        samples = ln.int(4, "numAdcSamples", 2, 65535)
        k = 5
    period = ln.dec(k, "framePeriodicity")
    if period <= 0:
        raise ln.fail(f"framePeriodicity={ln.args[k]} ms must be > 0")
    trigger = ln.int(k + 1, "triggerSelect", 1, 2)
    if ln.dec(k + 2, "frameTriggerDelay") < 0:
        raise ln.fail(f"frameTriggerDelay={ln.args[k + 2]} ms must be >= 0")
    st.frame = dict(start=start, end=end, loops=loops, n_frames=frames, samples=samples,
                    period_s=float(period.scaleb(-3)), trigger=trigger, line=ln)


def _ddm_order(st: _State, ln: _Line) -> None:
    n = st.chip.n_tx
    order = tuple(ln.int(i, f"Tx{i}", 0, n - 1, st.chip.name) for i in range(len(ln.args)))
    if sorted(order) != list(range(n)):
        raise ln.fail(f"order {' '.join(ln.args)} must list each of the {st.chip.name}'s Tx 0.."
                      f"{n - 1} once (all Tx, even disabled ones, per TI)")
    st.ddm_order = order


def _ant_geometry_cfg(st: _State, ln: _Line) -> None:
    """Element positions from the virtual-array (row, col) grid: y = col x xSpacebylambda,
    z = (max row - row) x zSpacebylambda (row 1 azimuth, row 0 raised, as TI's AWR2944
    ``1 0 1 1 ... 0.5 0.8``); Rx1 at the origin, Tx k at its Rx1 element."""
    n_t, n_r = st.chip.n_tx, st.chip.n_rx
    n = n_t * n_r
    pairs = tuple((ln.int(2 * i, f"row{i}", 0, 255), ln.int(2 * i + 1, f"col{i}", 0, 255))
                  for i in range(n))
    dx, dz = ln.dec(2 * n, "xSpacebylambda"), ln.dec(2 * n + 1, "zSpacebylambda")
    top = max(r for r, _ in pairs)
    virt = [[(float(c * dx), float((top - r) * dz)) for r, c in pairs[t * n_r:(t + 1) * n_r]]
            for t in range(n_t)]
    rx = tuple((y - virt[0][0][0], z - virt[0][0][1]) for y, z in virt[0])
    tx = tuple(virt[t][0] for t in range(n_t))
    for t in range(n_t):
        for r in range(n_r):
            want = (tx[t][0] + rx[r][0], tx[t][1] + rx[r][1])
            if abs(want[0] - virt[t][r][0]) > 1e-9 or abs(want[1] - virt[t][r][1]) > 1e-9:
                raise ln.fail(f"virtual element Tx{t}Rx{r} at {virt[t][r]} is not Tx{t} + Rx{r} "
                              f"= {want}: the grid is not a transmit x receive array")
    st.ant_geometry = (pairs, float(dx), float(dz))
    st.set(ln, tx_positions_wl=tx, rx_positions_wl=rx)


#: cfarCfg argument counts the parser reads, by chip family: mmWave SDK 3.x (9) everywhere, the
#: R79 / AWR2x44P DDM syntax (11, 12, 13) on the AWR294x family. Other counts (SDK 1.x/2.0
#: with linear thresholds, toolbox-lab firmwares) are kept and ignored.
_CFAR_ARGS = {**{name: {9, 11, 12, 13} for name, c in CHIPS.items() if c.mcu_plus_sdk},
              None: {9}}


def _cfar_cfg(st: _State, ln: _Line) -> None:
    if len(ln.args) not in _CFAR_ARGS.get(st.chip.name, _CFAR_ARGS[None]):
        st.ignored.append((ln.no, ln.cmd))
        st.notes.append(f"line {ln.no}: cfarCfg with {len(ln.args)} arguments (SDK 1.x/2.0 "
                        f"linear threshold or a lab firmware's syntax) ignored")
        return
    ln.int(0, "subFrameIdx", -1, 3)
    direction = _CFAR_DIRECTIONS[ln.int(1, "procDirection", 0, 1)]
    code = ln.int(2, "averageMode", 0, 3)
    mode = CFAR_AVERAGE_MODES[code]
    ranked = code in _CFAR_RANKED_CODES
    n = len(ln.args)
    os_rank = ln.int(9, "osKvalue", 0, 255) if n >= 11 else None
    if ranked and os_rank is None:
        raise ln.fail(f"averageMode={code} ({mode.upper()}) needs the osKvalue argument "
                      f"(11-argument syntax)")
    try:
        cfar = TiCfar(direction=direction, mode=mode,
                      window_cells=ln.int(3, "winLen", 1, 255),
                      guard_cells=ln.int(4, "guardLen", 0, 255),
                      noise_div_shift=ln.int(5, "noiseDiv", 0, 255),
                      cyclic=ln.flag(6, "cyclicMode"),
                      threshold_db=float(ln.dec(7, "thresholdScale")),
                      peak_grouping=ln.flag(8, "peakGroupingEn"),
                      os_rank=os_rank if ranked else (os_rank or None),
                      os_edge_k_scale=ln.flag(10, "osEdgeKscaleEn") if n >= 11 else False,
                      enabled=ln.flag(11, "isEnabled") if n >= 12 else True,
                      variable_threshold_mode=ln.int(12, "variableThresholdMode", 0, 255)
                      if n >= 13 else None,
                      line_no=ln.no)
    except _LineError:
        raise
    except ValueError as exc:
        raise ln.fail(str(exc)) from exc
    st.cfar[direction] = cfar


def _lvds_stream_cfg(st: _State, ln: _Line) -> None:
    """``lvdsStreamCfg <subFrameIdx> <enableHeader> <dataFmt> <enableSW>``: dataFmt 1 streams
    the ADC samples (the raw capture); kept for the capture layout, otherwise ignored."""
    ln.int(0, "subFrameIdx", -1, 3)
    st.lvds = (ln.flag(1, "enableHeader"), ln.int(2, "dataFmt", 0, 4), ln.flag(3, "enableSW"))
    st.ignored.append((ln.no, ln.cmd))


#: TI commands that select a MIMO scheme of `radarsim.mimo.MIMO_SCHEMES` by themselves.
_TI_SCHEME_COMMANDS = {"bpmCfg": "bpm"}


def _bpm_cfg(st: _State, ln: _Line) -> None:
    """``bpmCfg <subFrameIdx> <isEnabled> <chirp0Idx> <chirp1Idx>`` (mmWave SDK demos): with
    isEnabled 1 the two chirps carry the 2 x 2 Hadamard code (chirp0 +,+; chirp1 +,-), the
    harness's BPM scheme; with 0 it is kept and ignored."""
    ln.int(0, "subFrameIdx", -1, 3)
    if ln.flag(1, "isEnabled"):
        st.bpm = (ln.int(2, "chirp0Idx", 0, st.chip.max_chirp_defs - 1),
                  ln.int(3, "chirp1Idx", 0, st.chip.max_chirp_defs - 1), ln)
    else:
        st.bpm = None
        st.ignored.append((ln.no, ln.cmd))


def _intf_mitig_cfg(st: _State, ln: _Line) -> None:
    """intfMitigCfg <subFrameIdx> <magSNRdB> <magDiffSNRdB> (MCU+ SDK DDM demo, integers)."""
    ln.int(0, "subFrameIdx", -1, 3)
    st.chirp_level.update(intf_mag_snr_db=float(ln.int(1, "magSNRdB", 1, 60)),
                          intf_magdiff_snr_db=float(ln.int(2, "magDiffSNRdB", 1, 60)))


def _compression_cfg(st: _State, ln: _Line) -> None:
    """compressionCfg <subFrameIdx> <enabled> <method 0 EGE / 1 BFP> <ratio> <rangeBinsPerBlock>
    (MCU+ SDK DDM demo)."""
    ln.int(0, "subFrameIdx", -1, 3)
    enabled = ln.flag(1, "enabled")
    if ln.int(2, "compressionMethod", 0, 1) == 1 and enabled:
        raise ln.fail("compressionMethod=1 (BFP) is not modelled; use 0 (EGE)")
    st.chirp_level.update(compression=enabled,
                          compression_ratio=float(ln.dec(3, "compressionRatio")),
                          compression_range_bins_per_block=ln.int(4, "rangeBinsPerBlock", 1, 32))


def _flush_cfg(st: _State, ln: _Line) -> None:
    # TI's flushCfg resets the configuration given so far; ignored-command records are kept.
    keep = (st.ignored, st.notes, st.directives, st.directive_lines)
    fresh = _State(chip=st.chip)
    for f in dataclasses.fields(_State):
        setattr(st, f.name, getattr(fresh, f.name))
    st.ignored, st.notes, st.directives, st.directive_lines = keep


def _control(st: _State, ln: _Line) -> None:
    """sensorStop / sensorStart: no configuration content."""


def _unsupported(reason: str) -> Callable[[_State, _Line], None]:
    def handler(st: _State, ln: _Line) -> None:
        raise ln.fail(f"not supported: {reason}")
    return handler


@dataclass(frozen=True, slots=True)
class CommandSpec:
    """One CLI command: accepted argument counts (None: not checked; a mapping: per chip, with
    the key None for the others), handler (None: kept and reported as ignored), description."""

    n_args: frozenset[int] | Mapping[str | None, frozenset[int]] | None
    handler: Callable[[_State, _Line], None] | None
    help: str

    def counts(self, chip: str) -> frozenset[int] | None:
        if isinstance(self.n_args, Mapping):
            return self.n_args.get(chip, self.n_args[None])
        return self.n_args


def _spec(n_args, handler, help_text) -> CommandSpec:
    if isinstance(n_args, Mapping):
        n_args = MappingProxyType({k: frozenset(v) for k, v in n_args.items()})
    elif n_args is not None:
        n_args = frozenset(n_args)
    return CommandSpec(n_args, handler, help_text)


def _odd_counts(lo: int, hi: int) -> range:
    return range(lo, hi + 1, 2)


#: Registry of the CLI commands the parser knows, by name (case-sensitive, as TI's CLI).
#: Argument counts from the demos' ``mmw_cli.c`` (mmWave SDK 2.x/3.x xwr16xx/18xx/68xx, MCU+
#: SDK AWR294x/AWR2x44P/AWR2544, the R79 demo) and TI's profiles found with the code search.
TI_COMMANDS: dict[str, CommandSpec] = {
    # --- used
    "sensorStop": _spec({0, 1}, _control, "stop the sensor"),
    "sensorStart": _spec({0, 1, 4}, _control, "start the sensor"),
    "flushCfg": _spec({0}, _flush_cfg, "reset the configuration"),
    "dfeDataOutputMode": _spec({1}, _dfe_output_mode, "1 frame mode"),
    "channelCfg": _spec({3, 5}, _channel_cfg, "Rx/Tx enable masks"),
    "adcCfg": _spec({2}, _adc_cfg, "ADC bits and output format"),
    "adcbufCfg": _spec({4, 5}, _adcbuf_cfg, "ADC buffer format and interleaving"),
    "profileCfg": _spec({14}, _profile_cfg, "chirp profile"),
    "chirpCfg": _spec({8}, _chirp_cfg, "chirp table entries"),
    "frameCfg": _spec({7, 8}, _frame_cfg, "frame: chirps, loops, period"),
    "ddmPhaseShiftAntOrder": _spec({"AWR1843": {3}, "IWR6843": {3}, "AWR1642": {2},
                                    None: {4}}, _ddm_order, "DDMA Tx order"),
    "antGeometryCfg": _spec({None: {34}, "AWR1843": {26}, "IWR6843": {26}, "AWR1642": {18}},
                            _ant_geometry_cfg, "virtual array geometry"),
    "cfarCfg": _spec(None, _cfar_cfg, "CFAR settings (counts: _CFAR_ARGS)"),
    "lvdsStreamCfg": _spec({4}, _lvds_stream_cfg, "LVDS streaming (raw capture)"),
    "bpmCfg": _spec({4}, _bpm_cfg, "BPM MIMO (2 Tx Hadamard)"),
    # --- known but not representable
    "advFrameCfg": _spec(None, _unsupported("advanced frames (sub-frames)"), "advanced frame"),
    "subFrameCfg": _spec(None, _unsupported("advanced frames (sub-frames)"), "sub-frame"),
    "subDataFrameCfg": _spec(None, _unsupported("advanced frames (sub-frames)"), "sub-frame"),
    "advChirpCfg": _spec(None, _unsupported("advanced chirp LUTs"), "advanced chirp"),
    "LUTDataCfg": _spec(None, _unsupported("advanced chirp LUTs"), "advanced chirp LUT"),
    "contModeCfg": _spec(None, _unsupported("continuous-wave mode"), "continuous mode"),
    "bpmCfgAdvanced": _spec(None, _unsupported("BPM (binary phase) MIMO"), "BPM"),
    # --- kept and reported as ignored (SDK demo, monitoring, dither, calibration, tracker)
    "version": _spec({0}, None, "print versions"),
    "lowPower": _spec({2}, None, "low-power ADC mode"),
    "guiMonitor": _spec(None, None, "UART output selection (differs per demo and lab)"),
    "aoaFovCfg": _spec({4, 5}, None, "angle field of view"),
    "cfarFovCfg": _spec({3, 4}, None, "CFAR field of view"),
    "multiObjBeamForming": _spec({2, 3}, None, "multi-object beamforming"),
    "calibDcRangeSig": _spec({4, 5}, None, "DC range signature calibration"),
    "clutterRemoval": _spec({1, 2}, None, "static clutter removal"),
    "extendedMaxVelocity": _spec({1, 2}, None, "extended velocity"),
    "nearFieldCfg": _spec({4}, None, "near-field correction"),
    # 1 range bias + (re, im) per virtual antenna, any Tx x Rx size.
    "compRangeBiasAndRxChanPhase": _spec(_odd_counts(3, 1 + 2 * 16), None,
                                         "range bias and channel phase compensation"),
    "measureRangeBiasAndRxChanPhase": _spec({3}, None, "calibration measurement"),
    "antennaCalibParams": _spec(range(2, 33, 2), None, "antenna calibration"),
    "CQRxSatMonitor": _spec({5}, None, "Rx saturation monitor"),
    "CQSigImgMonitor": _spec({3}, None, "signal/image band monitor"),
    "analogMonitor": _spec({None: {2}, "AWR2544": {3}}, None, "analog monitors"),
    "configDataPort": _spec({2}, None, "data UART"),
    "queryDemoStatus": _spec({0}, None, "status query"),
    "calibData": _spec({3}, None, "calibration data save/restore"),
    "compressionCfg": _spec({5}, _compression_cfg, "DDM demo compression (EGE)"),
    "intfMitigCfg": _spec({3}, _intf_mitig_cfg, "interference mitigation thresholds"),
    "localMaxCfg": _spec({3}, None, "local-maximum thresholds"),
    "rangeProcCfg": _spec(None, None, "range processing"),
    "procChain": _spec(None, None, "processing chain"),
    "procChainCfg": _spec(None, None, "processing chain"),
    "spreadSpectrumConfig": _spec(None, None, "clock spread spectrum"),
    "adcDataDitherCfg": _spec({None: {2}, "AWR2544": {3}}, None, "ADC dither (errata)"),
    "enableProgFiltCfg": _spec({1}, None, "programmable filter"),
    "powerMeasPerClockGating": _spec({1}, None, "power measurement"),
    "powerMeasHwaDynamicClockGating": _spec({1}, None, "power measurement"),
    "powerMeasHwaStateAfterFrameProc": _spec({1}, None, "power measurement"),
    "powerMeasDspStateAfterFrameProc": _spec({1}, None, "power measurement"),
    "anaTempRead": _spec({0}, None, "temperature"),
    "digTempRead": _spec({0}, None, "temperature"),
    "LdoBypassConfig": _spec(None, None, "LDO bypass"),
    "ApllSynthBwConfig": _spec(None, None, "APLL/synth bandwidth"),
    "appSceneryParams": _spec({11}, None, "R79 tracker scenery"),
    "appGatingParams": _spec({5}, None, "R79 tracker gating"),
    "appStateParams": _spec({6}, None, "R79 tracker state machine"),
    "appAllocParams": _spec({6}, None, "R79 tracker allocation"),
    "gtrack": _spec({11}, None, "R79 group tracker"),
    "ransac": _spec({3}, None, "R79 RANSAC static/moving split"),
    "rangeCfar": _spec({1}, None, "R79 range-CFAR enable"),
    # mmWave industrial toolbox labs (people counting, tracking, vital signs): demo only.
    **{name: _spec(None, None, "toolbox lab command") for name in (
        "SceneryParam", "GatingParam", "AllocationParam", "StateParam", "FilterParam",
        "TrackingCfg", "trackingCfg", "SensorPosition", "sensorPosition", "BoundaryBox",
        "boundaryBox", "StaticBoundaryBox", "staticBoundaryBox", "PresenceBoundaryBox",
        "presenceBoundaryBox", "dynamicRACfarCfg", "staticRACfarCfg", "dynamicRangeAngleCfg",
        "dynamic2DAngleCfg", "staticRangeAngleCfg", "fineMotionCfg", "maxAcceleration",
        "sceneryParam", "gatingParam", "allocationParam", "stateParam", "fovCfg",
        "antGeometry0", "antGeometry1", "antPhaseRot", "vitalSignsCfg", "motionDetection",
        "VitalSignsCfg", "MotionDetection", "clusterCfg", "mpdBoundaryBox", "zoneDef",
        "occStateMach", "intrThresh", "sensorSelection", "radarSelection")},
}
#: Commands whose near-misspellings are refused with a suggestion (modelled commands only).
_MODELLED = tuple(name for name, spec in TI_COMMANDS.items() if spec.handler not in (None,))


# ---------------------------------------------------------------------------- reading
def _read_source(path_or_text: str | os.PathLike) -> str:
    if isinstance(path_or_text, os.PathLike):
        return Path(path_or_text).read_text(encoding="utf-8")
    if not isinstance(path_or_text, str):
        raise TypeError(f"path_or_text must be a path or the .cfg text, got "
                        f"{type(path_or_text).__name__}")
    text = path_or_text
    if "\n" in text:
        return text
    if Path(text).is_file():
        return Path(text).read_text(encoding="utf-8")
    if text.strip().endswith(".cfg") or not any(c.isspace() for c in text.strip()):
        raise FileNotFoundError(f"TI .cfg file {text!r} not found")
    return text


def _directive_value(field: dataclasses.Field, raw: str, ln: _Line) -> Any:
    try:
        value = json.loads(raw)
    except json.JSONDecodeError:
        if "str" in str(field.type):
            return raw
        raise ln.fail(f"value {raw!r} for {field.name} is not JSON") from None
    return _as_tuples(value)


def _as_tuples(v: Any) -> Any:
    return tuple(_as_tuples(x) for x in v) if isinstance(v, list) else v


def parse_ti_cfg(path_or_text: str | os.PathLike) -> TiProfile:
    """Parse a TI mmWave SDK CLI configuration into a `TiProfile`.

    Parameters
    ----------
    path_or_text : str or path-like
        A .cfg file path, or the text itself (any string with a newline is text).

    Returns
    -------
    TiProfile
        ``.radar`` is the validated `RadarConfig`.

    Raises
    ------
    ValueError
        With "line N (command): ..." for every wrong argument count, malformed number, value
        outside the chip's limits, unsupported feature, near-misspelled modelled command,
        missing required command (reported at the end of the input) and `RadarConfig`
        validation error (at the line of the command that set the field).
    FileNotFoundError
        If a path was given and does not exist.
    """
    lines = _read_source(path_or_text).splitlines()
    chip_name, how = _infer_chip(lines)
    try:
        chip = get_chip(chip_name)
    except ValueError as exc:
        raise _LineError(f"line 1: {exc}") from None
    st = _State(chip=chip)
    st.notes.append(f"chip {chip.name} from the {how}")
    fields_by_name = {f.name: f for f in dataclasses.fields(RadarConfig)}
    for no, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text:
            continue
        if text.startswith("%") or text.startswith("#"):
            m = _DIRECTIVE_RE.match(text)
            if m:
                ln = _Line(no, "% radarsim", (m.group(1), m.group(2)))
                name = m.group(1)
                if name not in fields_by_name:
                    raise ln.fail(f"unknown RadarConfig field {name!r}")
                if name in _TI_FIELDS:
                    raise ln.fail(f"{name} is set by TI commands, not by a directive")
                st.directives[name] = _directive_value(fields_by_name[name], m.group(2), ln)
                st.directive_lines[name] = ln
            continue
        cmd, *args = text.split()
        # A trailing "% ..." or "# ..." note after the arguments (seen in users' files).
        cut = next((i for i, a in enumerate(args) if a[:1] in "%#"), len(args))
        args = args[:cut]
        ln = _Line(no, cmd, tuple(args))
        spec = TI_COMMANDS.get(cmd)
        if spec is None:
            close = difflib.get_close_matches(cmd, _MODELLED, n=1, cutoff=0.85)
            if close:
                raise _LineError(f"line {no}: unknown command {cmd!r}; did you mean "
                                 f"{close[0]!r}?")
            st.ignored.append((no, cmd))
            st.notes.append(f"line {no}: {cmd!r} is not a command of the SDK demos the harness "
                            "knows; kept and ignored")
            continue
        counts = spec.counts(chip.name)
        if counts is not None and len(args) not in counts:
            want = " or ".join(str(n) for n in sorted(counts))
            raise ln.fail(f"expects {want} arguments, got {len(args)}")
        if spec.handler is None:
            st.ignored.append((no, cmd))
        else:
            spec.handler(st, ln)
            st.seen[cmd] = ln
    return _finish(st, len(lines))


def _frame_masks(st: _State) -> tuple[list[int], int]:
    """Tx masks of the frame's chirps (one loop) and their profile; unused chirps noted."""
    fr = st.frame
    fln: _Line = fr["line"]
    masks, pids = [], set()
    for idx in range(fr["start"], fr["end"] + 1):
        if idx not in st.chirps:
            raise fln.fail(f"chirp {idx} of the frame is not defined by any chirpCfg")
        tx, pid, cln, varies = st.chirps[idx]
        if varies:
            raise cln.fail("startFreqVar/freqSlopeVar/idleTimeVar/adcStartTimeVar: per-chirp "
                           "variations are not modelled (every chirp of a RadarConfig is the "
                           "same); use 0")
        if tx == 0:
            raise cln.fail(f"txEnable=0: chirp {idx} of the frame transmits on no Tx")
        if tx & ~st.tx_mask:
            raise cln.fail(f"txEnable={tx} (0b{tx:04b}) enables a Tx that channelCfg "
                           f"txChannelEn={st.tx_mask} (0b{st.tx_mask:04b}) leaves off")
        masks.append(tx)
        pids.add(pid)
    if len(pids) > 1:
        raise fln.fail(f"the frame's chirps use profiles {sorted(pids)}: RadarConfig describes "
                       "one chirp profile")
    unused = sorted(set(st.chirps) - set(range(fr["start"], fr["end"] + 1)))
    if unused:
        st.notes.append(f"chirps {unused} are defined but not used by the frame (ignored)")
    unused_p = sorted(set(st.profiles) - pids)
    if unused_p:
        st.notes.append(f"profiles {unused_p} are not used by the frame's chirps (ignored)")
    return masks, pids.pop()


def _schedule(st: _State, masks: list[int]) -> dict:
    """MIMO scheme, Tx channels and order from the frame's chirp Tx masks.

    The chip channels the chirps use become the logical Tx 1..n (`RadarConfig.tx_channels`);
    the registered scheme that claims the logical pattern (`radarsim.mimo.MimoScheme.from_ti`)
    gives mimo, sub-bands and order: DDMA when every chirp enables the same two or more Tx
    (without ``ddmPhaseShiftAntOrder`` the R79 demo's order, horizontal Tx first), TDMA when
    each chirp enables one Tx and the loop repeats a sequence in which each fires once."""
    from .mimo import MIMO_SCHEMES
    fr, fln = st.frame, st.frame["line"]
    used = 0
    for m in masks:
        used |= m
    chans = _bits(used)
    unused = sorted(set(_bits(st.tx_mask)) - set(chans))
    if unused:
        st.notes.append(f"Tx {unused} enabled by channelCfg but not by the frame's chirps")
    logical = tuple(sum(1 << chans.index(c) for c in _bits(m)) for m in masks)
    n_tx = len(chans)
    order = None if st.ddm_order is None else \
        tuple(chans.index(t + 1) for t in st.ddm_order if t + 1 in chans)
    claim = None
    if st.bpm is not None:  # bpmCfg names its scheme: both Tx on the two coded chirps
        c0, c1, bln = st.bpm
        if n_tx != 2 or len(masks) != 2 or set(logical) != {3} or \
                (c0, c1) != (fr["start"], fr["start"] + 1):
            raise bln.fail(f"chirp0Idx={c0}, chirp1Idx={c1}: BPM needs a loop of exactly these "
                           "two chirps, both enabling the same two Tx")
        claim = {"mimo": MIMO_SCHEMES[_TI_SCHEME_COMMANDS["bpmCfg"]].name, "tx_order": (1, 2)}
    for scheme in () if claim is not None else MIMO_SCHEMES.values():
        try:
            claim = scheme.from_ti(logical, n_tx, (1 << n_tx) - 1, order)
        except ValueError as exc:
            raise fln.fail(str(exc)) from None
        if claim is not None:
            break
    if claim is None:
        pattern = " ".join(f"0b{m:04b}" for m in masks)
        raise fln.fail(f"chirp Tx pattern [{pattern}] matches no MIMO scheme "
                       f"({', '.join(MIMO_SCHEMES)}): DDMA needs the same {n_tx} Tx every chirp "
                       f"and more than {n_tx} chirps per loop (classic DDMA exactly {n_tx}), "
                       "TDMA one Tx per chirp in a repeated sequence in which each Tx fires once")
    claim = dict(claim)
    tx_order = claim.pop("tx_order", None)
    st.set(fln, **claim, n_tx=n_tx, tx_channels=chans, n_chirps=len(masks) * fr["loops"])
    if "n_subbands" in claim:
        if st.ddm_order is None:
            st.notes.append("no ddmPhaseShiftAntOrder: the R79 demo's default order "
                            "(horizontal Tx first, elevation Tx last)")
    elif st.ddm_order is not None:
        st.ignored.append((st.seen["ddmPhaseShiftAntOrder"].no, "ddmPhaseShiftAntOrder"))
    if tx_order is not None:
        ln = st.seen["ddmPhaseShiftAntOrder"] if "n_subbands" in claim else fln
        st.set(ln, tx_order=tx_order)
    return claim


def _to_channel_bits(line: str, radar: RadarConfig) -> str:
    """A scheme's TI line over logical Tx 1..n_tx (`MimoScheme.to_ti`) on the config's chip
    channels: ``chirpCfg`` txEnable masks and the ``ddmPhaseShiftAntOrder`` list (all chip Tx,
    the active ones first, as TI requires)."""
    cmd, *args = line.split()
    chans = radar.tx_channels
    if cmd == "chirpCfg":
        mask = int(args[7])
        args[7] = str(sum(1 << (chans[k] - 1) for k in range(radar.n_tx) if mask >> k & 1))
    elif cmd == "ddmPhaseShiftAntOrder":
        order = [chans[int(t)] - 1 for t in args if int(t) < radar.n_tx]
        order += [t for t in range(radar.chip_spec.n_tx) if t not in order]
        args = [str(t) for t in order]
    return " ".join([cmd, *args])


def _finish(st: _State, n_lines: int) -> TiProfile:
    end = f"line {n_lines} (end of input)"
    for cmd in ("channelCfg", "adcCfg", "profileCfg", "chirpCfg", "frameCfg"):
        if cmd not in st.seen:
            raise _LineError(f"{end}: missing required command {cmd!r}")
    fr = st.frame
    fln: _Line = fr["line"]
    masks, pid = _frame_masks(st)
    prof = st.profiles[pid]
    pln: _Line = prof["line"]
    if prof["tx_power"]:
        raise pln.fail(f"txOutPower={prof['tx_power']}: Tx back-off is not modelled; keep 0 and "
                       "set '% radarsim: tx_power_dbm = ...' instead")
    if prof["tx_phase"]:
        raise pln.fail(f"txPhaseShifter={prof['tx_phase']}: static Tx phase offsets are not "
                       "modelled; keep 0 (errors go in '% radarsim: tx_phase_error_deg')")
    st.set(pln, **prof["fields"])
    st.extras.update(prof["extras"])
    n_samples = prof["fields"]["n_samples"]
    if fr["samples"] is not None:
        # rlFrameCfg_t.numAdcSamples counts 16-bit words per chirp and Rx: 2 per complex sample.
        words = n_samples * (2 if st.adc_complex else 1)
        if fr["samples"] != words:
            raise fln.fail(f"numAdcSamples={fr['samples']} differs from profileCfg's "
                           f"numAdcSamples={n_samples}"
                           + (" x 2 (complex: 16-bit words per chirp)" if st.adc_complex
                              else ""))
    if st.adcbuf and st.adc_complex is not None and st.adcbuf["real"] == st.adc_complex:
        aln: _Line = st.adcbuf["line"]
        raise aln.fail(f"adcOutputFmt={int(st.adcbuf['real'])} "
                       f"({'real' if st.adcbuf['real'] else 'complex'}) contradicts adcCfg's "
                       f"{'complex' if st.adc_complex else 'real'} output")
    claim = _schedule(st, masks)
    if "n_subbands" in st.directives and "n_subbands" in claim:
        raise st.directive_lines["n_subbands"].fail(
            "n_subbands is set by chirpCfg/frameCfg (chirps per loop) for DDMA")

    kw = dict(_TI_DEFAULT_OVERRIDES)
    kw["chip"] = st.chip.name
    kw.update(st.directives)
    kw.update(st.fields)
    if "chirp_period_s" in st.directives:  # a directive refines the decimal idle + ramp sum
        kw["chirp_period_s"] = st.directives["chirp_period_s"]
    lines = {**st.field_lines, **st.directive_lines}
    try:
        radar = RadarConfig(**kw)
    except (ValueError, TypeError) as exc:
        raise _relabel(exc, lines, st) from exc
    burst_s = radar.n_chirps * radar.chirp_period_s
    if fr["period_s"] < burst_s * (1 - 1e-9):
        raise fln.fail(f"framePeriodicity={fr['period_s'] * 1e3:g} ms is shorter than the "
                       f"chirp burst n_chirps x chirp period = {burst_s * 1e3:g} ms")
    return TiProfile(radar=radar, frame_period_s=fr["period_s"], n_frames=fr["n_frames"],
                     trigger_select=fr["trigger"], cfar=dict(st.cfar),
                     ddm_phase_order=st.ddm_order, ant_geometry=st.ant_geometry,
                     adc_channel_interleaved=radar.adcbuf_interleaved,
                     sample_swap=st.adcbuf.get("sample_swap"), lvds_stream=st.lvds,
                     profile_extras=dict(st.extras), chirp_level=dict(st.chirp_level),
                     ignored=tuple(st.ignored), notes=tuple(st.notes),
                     directives=dict(st.directives))


def _relabel(exc: Exception, lines: Mapping[str, _Line], st: _State) -> ValueError:
    """RadarConfig's error, prefixed with the line of the command that set the field."""
    msg = str(exc)
    m = re.match(r"\s*(\w+)\s*=", msg)
    names = [m.group(1)] if m and m.group(1) in lines else []
    names += [n for n in lines if re.search(rf"\b{n}\b", msg) and n not in names]
    ln = lines[names[0]] if names else st.seen["profileCfg"]
    return _LineError(f"line {ln.no} ({ln.cmd}): {msg}")


def from_ti_cfg(path_or_text: str | os.PathLike) -> RadarConfig:
    """`RadarConfig` of a TI mmWave SDK .cfg (path or text); see `parse_ti_cfg`."""
    return parse_ti_cfg(path_or_text).radar


# ---------------------------------------------------------------------------- writing
def _ti_default(name: str) -> Any:
    if name in _TI_DEFAULT_OVERRIDES:
        return _TI_DEFAULT_OVERRIDES[name]
    f = next(f for f in dataclasses.fields(RadarConfig) if f.name == name)
    return f.default


def _json_value(value: Any) -> str:
    return json.dumps(list(value) if isinstance(value, tuple) else value)


def _ant_geometry_line(radar: RadarConfig) -> str | None:
    """``antGeometryCfg`` of the config's array on a lambda/2 x (one height) grid, or None when
    the positions are not on such a grid (they then travel as directives)."""
    tx = radar.tx_positions_wl
    rx = radar.rx_positions_wl
    heights = sorted({round(z, 9) for _, z in tx + rx} - {0.0})
    dz = heights[0] if len(heights) == 1 else 0.8 if not heights else None
    if dz is None:
        return None
    pairs = []
    for ty, tz in tx:
        for ry, rz in rx:
            col = (ty + ry) / 0.5
            row_f = (tz + rz) / dz
            if abs(col - round(col)) > 1e-9 or round(row_f, 9) not in (0.0, 1.0) or col < 0:
                return None
            pairs.append((1 - int(round(row_f)), int(round(col))))
    return ("antGeometryCfg " + " ".join(f"{r} {c}" for r, c in pairs)
            + f" 0.5 {_fmt_decimal(dz)}")


def to_ti_cfg(cfg: RadarConfig | TiProfile, *, frame_period_s: float | None = None,
              n_frames: int | None = None,
              cfar: Mapping[str, TiCfar] | Iterable[TiCfar] | None = None,
              extra_lines: Iterable[str] = (), comments: Iterable[str] = ()) -> str:
    """Write a TI mmWave SDK CLI configuration for the config's chip running `cfg` (MCU+ SDK
    syntax for the AWR294x family, mmWave SDK 3.x syntax for xWR16/18/68; the chip is named in
    TI Visualizer's ``% Platform:`` header).

    Parameters
    ----------
    cfg : RadarConfig or TiProfile
        The radar (a `TiProfile` also supplies frame period, frame count and CFAR).
    frame_period_s : float, optional
        ``framePeriodicity``, s; default the profile's, else `DEFAULT_FRAME_PERIOD_S`.
    n_frames : int, optional
        ``numFrames`` (0: until stopped); default the profile's, else 0.
    cfar : mapping or iterable of TiCfar, optional
        ``cfarCfg`` lines to write (none by default for a bare RadarConfig).
    extra_lines : iterable of str
        Further commands appended before ``sensorStart`` (validated by the round trip).
    comments : iterable of str
        Extra header comment lines (a leading ``%`` is added when missing).

    Returns
    -------
    str
        The .cfg text; ``from_ti_cfg(text) == cfg`` exactly.

    Raises
    ------
    ValueError
        If the config cannot be programmed on the chip (e.g. more than 255 loops per frame,
        or a frame period shorter than the chirp burst).
    """
    profile = cfg if isinstance(cfg, TiProfile) else None
    radar = profile.radar if profile else cfg
    if frame_period_s is None:
        frame_period_s = profile.frame_period_s if profile else DEFAULT_FRAME_PERIOD_S
    if n_frames is None:
        n_frames = profile.n_frames if profile else 0
    if cfar is None:
        cfar = profile.cfar if profile else {}
    cfars = list(cfar.values()) if isinstance(cfar, Mapping) else list(cfar)

    chip = radar.chip_spec
    # The scheme's loop over the logical Tx 1..n_tx (radarsim.mimo), mapped onto the chip
    # channels `tx_channels` below.
    ti_frame = radar.scheme.to_ti(radar, radar.n_tx)
    per_loop = ti_frame.chirps_per_loop
    loops = radar.n_chirps // per_loop
    if loops > chip.max_loops:
        raise ValueError(f"n_chirps={radar.n_chirps}: {loops} loops of {per_loop} chirps "
                         f"exceed the {chip.name} frame limit of {chip.max_loops} loops")
    rx_mask = sum(1 << (c - 1) for c in radar.rx_channels)
    tx_bits = [1 << (c - 1) for c in radar.tx_channels]  # logical Tx k -> TI txEnable bit
    tx_mask = sum(tx_bits)
    mcu_plus = chip.mcu_plus_sdk
    idle_us = _fmt_decimal(radar.idle_time_s, -6)
    ramp_us = _fmt_decimal(radar.ramp_end_time_s, -6)
    fmt = ADC_MODES[radar.adc_mode].ti_code
    kind = "complex (I/Q)" if radar.is_complex else "real"
    words = radar.n_samples * (2 if radar.is_complex else 1)  # rlFrameCfg_t: 16-bit words
    out = [
        f"% {chip.name} profile written by radarsim.ti_cfg.to_ti_cfg "
        f"({'mmWave MCU+ SDK' if mcu_plus else 'mmWave SDK 3.x'} CLI).",
        f"% Platform:{chip.ti_platform}",
        f"% {radar.mimo.upper()} {radar.n_tx} Tx x {radar.n_rx} Rx, {radar.n_chirps} chirps of "
        f"{radar.chirp_period_s * 1e6:.6g} us, {radar.n_samples} {kind} samples at "
        f"{radar.adc_rate_sps / 1e6:g} Msps: range resolution {radar.range_resolution_m:.3f} m, "
        f"max range {radar.max_range_m:.1f} m, Vmax +/-{radar.max_unambiguous_velocity_mps:.2f}"
        " m/s.",
        *(c if c.startswith("%") else f"% {c}" for c in comments),
        "sensorStop",
        "flushCfg",
        "dfeDataOutputMode 1",
        f"channelCfg {rx_mask} {tx_mask} 0" + " 0" * (chip.channel_cfg_args - 3),
        f"adcCfg 2 {fmt}",
        # adcbufCfg <subFrameIdx> <adcOutputFmt 0 complex / 1 real> <SampleSwap>
        # <ChanInterleave> <ChirpThreshold>: TI's demo values (SampleSwap 1 for complex).
        f"adcbufCfg -1 {0 if radar.is_complex else 1} {1 if radar.is_complex else 0} "
        f"{0 if radar.adcbuf_interleaved else 1} 1",
        "lowPower 0 0",
        # txOutPower, txPhaseShifter, txStartTime 0; HPF codes 0 0 and rxGain 42 as in the R79
        # demo (the front-end model has no HPF or gain setting).
        f"profileCfg 0 {_fmt_decimal(radar.start_freq_hz, 9)} {idle_us} "
        f"{_fmt_decimal(radar.adc_start_time_s, -6)} {ramp_us} 0 0 "
        f"{_fmt_decimal(radar.slope_hz_per_s, 12)} 0 {radar.n_samples} "
        f"{_fmt_decimal(radar.adc_rate_sps, 3)} 0 0 42",
    ]
    out += [_to_channel_bits(line, radar) for line in ti_frame.chirp_lines]
    out.append(f"frameCfg 0 {per_loop - 1} {loops} {n_frames} "
               + (f"{words} " if mcu_plus else "")
               + f"{_fmt_decimal(frame_period_s, -3)} 1 0")
    out += [_to_channel_bits(line, radar) for line in ti_frame.extra_lines]
    geometry = _ant_geometry_line(radar)
    if geometry is not None and mcu_plus:
        out.append(geometry)
    out += [c.to_cli() for c in cfars]
    out += list(extra_lines)

    # Directives for what TI cannot say: find the fields a plain read gets wrong.
    body = out + ["sensorStart"]
    plain = parse_ti_cfg("\n".join(body) + "\n").radar
    directives = []
    for f in dataclasses.fields(RadarConfig):
        if f.name in _TI_FIELDS:
            continue
        if getattr(plain, f.name) != getattr(radar, f.name):
            directives.append(f"% radarsim: {f.name} = {_json_value(getattr(radar, f.name))}")
    n_head = next(i for i, line in enumerate(out) if not line.startswith("%"))
    text = "\n".join(out[:n_head] + directives + body[n_head:]) + "\n"
    back = parse_ti_cfg(text).radar
    if back != radar:  # pragma: no cover - guards the exact-round-trip promise
        raise RuntimeError(f"to_ti_cfg round trip failed: {back} != {radar}")
    return text


#: Commands of the AWR2944 R79 demo (TIDEP-01027 mmw_cli.c) that configure its on-chip
#: processing, UART output and tracker: shipped in r79_ddma.cfg, reported as ignored here.
R79_DEMO_LINES = (
    "guiMonitor -1 1 0 0 0 0 0",
    "compressionCfg -1 1 0 0.5 8",
    "intfMitigCfg -1 15 18",
    "localMaxCfg -1 4 40",
    "antennaCalibParams " + " ".join(["0 1"] * 16),
    "analogMonitor 0 0",
    "calibData 0 0 0",
    "appSceneryParams 0.0 0.0 1.0 -25.0 0.0 -14.0 14.0 1.0 231.0 -5.0 5.0",
    "appGatingParams 8.0 10.0 8.0 4.0 40.0",
    "appStateParams 3 2 10 100 10 0",
    "appAllocParams 20.0 20.0 1.0 6 4.0 20.0",
    "gtrack 1 800 30 0.0 40.8781 0.1065 1.0 10.0 0.0 0.250 0",
    "ransac 1 200 1.0",
    "rangeCfar 0",
)
#: The command list the R79 demo firmware hard-codes (TIDEP-01027 ``mss/mmw_cli.c``,
#: ``gHardcodedCliConfigs``): no ddmPhaseShiftAntOrder (the firmware's DDM order is Tx1, Tx3,
#: Tx4, Tx2), no antGeometryCfg (the EVM array), an interleaved ADC buffer.
R79_FIRMWARE_LINES = (
    "sensorStop", "flushCfg", "dfeDataOutputMode 1", "channelCfg 15 15 0", "adcCfg 2 0",
    "adcbufCfg -1 1 0 0 1", "lowPower 0 0",
    "profileCfg 0 77 5 5 18.81 0 0 8.883 0 384 30000 0 0 42",
    "chirpCfg 0 5 0 0 0 0 0 15", "frameCfg 0 5 128 0 384 250 1 0",
    "guiMonitor -1 3 0 0 0 0 0",
    "cfarCfg -1 1 3 16 0 0 1 12.0 0 24 0", "cfarCfg -1 0 3 16 0 0 1 15.0 0 7 0",
    *R79_DEMO_LINES[1:10],
    "appSceneryParams 0.0 0.0 1.0 0.0 0.0 -14.0 14.0 1.0 231.0 -5.0 5.0",
    *R79_DEMO_LINES[11:],
    "sensorStart",
)
R79_COMMENTS = (
    "TI R79 corner-radar DDMA waveform (TIDEP-01027; seed 000 table 2): the R79 demo's",
    "profileCfg/chirpCfg/frameCfg/cfarCfg and demo commands, plus ddmPhaseShiftAntOrder and",
    "antGeometryCfg of the MCU+ SDK DDM demo. Phase codes floor-quantised as seed 000 table 4.",
)


def r79_cfg_text() -> str:
    """The text of ``radarsim/data/r79_ddma.cfg``, regenerated from the R79 preset."""
    from .presets import r79_ddma  # presets imports config, which imports this module
    return to_ti_cfg(r79_ddma(), cfar=R79_CFAR, extra_lines=R79_DEMO_LINES,
                     comments=R79_COMMENTS)


def r79_cfg_path() -> Path:
    """Path of the shipped R79 DDMA profile, ``radarsim/data/r79_ddma.cfg``."""
    return Path(str(resources.files("radarsim") / "data" / "r79_ddma.cfg"))
