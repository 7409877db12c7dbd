"""TI mmWave SDK CLI profiles (.cfg) in and out: the waveform a radar engineer gives the AWR2944.

`parse_ti_cfg` reads the CLI commands of an mmWave (MCU+) SDK configuration file into a
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

Every problem raises ValueError naming the line: unknown commands (with a close-match hint),
wrong argument counts, malformed numbers, values outside the chip's limits, chirp patterns the
model cannot represent, missing required commands, and `RadarConfig`'s own validation errors,
re-raised with the line of the command that set the offending field.

Command syntax (argument lists checked against TI sources, found with the code search)
--------------------------------------------------------------------------------------
mmWave MCU+ SDK 4.x ``ti/utils/cli/src/cli_mmwave.c`` (AWR294X build; help strings and argc
checks; same conversions as mmWave SDK 3.5 ``packages/ti/utils/cli/src/cli_mmwave.c``):

- ``dfeDataOutputMode <modeType>``: 1 frame, 2 continuous, 3 advanced frame (argc 2).
- ``channelCfg <rxChannelEn> <txChannelEn> <cascading>`` (argc 4; AWR2544/AWR2x44P add
  ``<ethOscClkEn> <driveStrength>``, argc 6).
- ``adcCfg <numADCBits> <adcOutputFmt>``: bits 0/1/2 = 12/14/16; fmt 0 real, 1 complex 1x,
  2 complex 2x (argc 3).
- ``profileCfg <profileId> <startFreq GHz> <idleTime us> <adcStartTime us> <rampEndTime us>
  <txOutPower> <txPhaseShifter> <freqSlopeConst MHz/us> <txStartTime us> <numAdcSamples>
  <digOutSampleRate ksps> <hpfCornerFreq1> <hpfCornerFreq2> <rxGain>`` (argc 15).
- ``chirpCfg <startIdx> <endIdx> <profileId> <startFreqVar> <freqSlopeVar> <idleTimeVar>
  <adcStartTimeVar> <txEnable>`` (argc 9).
- ``frameCfg <chirpStartIdx> <chirpEndIdx> <numLoops> <numFrames> <numAdcSamples>
  <framePeriodicity ms> <triggerSelect> <frameTriggerDelay ms>`` (argc 9 in the MCU+ SDK;
  mmWave SDK 3.x has no ``numAdcSamples``, argc 8 -- both accepted).

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
  (argc 6; adcOutputFmt 1 = real; chirpThreshold must be 1).

mmWave MCU+ SDK AWR2x44P DDM demo ``mmw_cli.c`` and its doxygen ``main.c``:

- ``ddmPhaseShiftAntOrder <Tx0> <Tx1> ... <TxN>``: "antenna indices in increasing order of
  phase shift value, if all of them were enabled"; elevation antennas last, ``0 2 3 1`` for the
  AWR2944 (Tx0, Tx2, Tx3 azimuth, Tx1 elevation). TI's Tx k is our Tx k+1, so this is exactly
  `RadarConfig.tx_order` minus one (Tx1, Tx3, Tx4, Tx2).
- ``antGeometryCfg <Row(Tx0Rx0)> <Col(Tx0Rx0)> ... <Row(Tx3Rx3)> <Col(Tx3Rx3)> <xSpacebylambda>
  <zSpacebylambda>``: row 1 azimuth, row 0 elevation; the AWR2944 EVM is
  ``1 0 1 1 1 2 1 3 0 2 0 3 0 4 0 5 1 4 1 5 1 6 1 7 1 8 1 9 1 10 1 11 0.5 0.8`` (DESIGN 4.2).

Chirp table to MIMO scheme: DDMA when every chirp of the frame enables all active Tx (as
``chirpCfg 0 5 ... 15`` + ``frameCfg 0 5 128``: 6 chirps per loop = 6 sub-bands, 128 loops =
768 chirps); TDMA when each chirp enables one Tx and each Tx fires once per loop (the loop order
is `tx_order`).

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

from .config import BAND_MAX_HZ, BAND_MIN_HZ, RadarConfig

__all__ = ["TiCfar", "TiProfile", "parse_ti_cfg", "from_ti_cfg", "to_ti_cfg", "r79_cfg_path",
           "r79_cfg_text", "TI_COMMANDS", "CFAR_AVERAGE_MODES", "DEFAULT_FRAME_PERIOD_S",
           "R79_CFAR", "R79_DEMO_LINES"]

#: AWR2944 chip limits used by the parser (beyond those `RadarConfig` checks itself).
_N_TX_CHIP = 4
_N_RX_CHIP = 4
_MAX_CHIRP_INDEX = 511          # chirp RAM: 512 chirp definitions (rlChirpCfg_t)
_MAX_PROFILE_ID = 3             # RL_MAX_PROFILES_CNT = 4
_MAX_LOOPS = 255                # rlFrameCfg_t.numLoops: 1..255
_MAX_FRAMES = 65535             # rlFrameCfg_t.numFrames: 0 (infinite)..65535
_MAX_CFAR_THRESHOLD_DB = 100.0  # R79 demo mmw_cli.c: "Maximum value for CFAR thresholdScale"

#: Frame period written when none is given, s: the R79 demo's ``frameCfg ... 250 1 0``.
DEFAULT_FRAME_PERIOD_S = 0.25

#: TI ``averageMode`` code -> CFAR mode name (seed 003; the pipeline's CFAR_MODES keys).
CFAR_AVERAGE_MODES = {0: "ca", 1: "cago", 2: "caso", 3: "os"}
_CFAR_DIRECTIONS = {0: "range", 1: "doppler"}

# RadarConfig fields that TI commands define (a directive may not set them).
_TI_FIELDS = frozenset({"mimo", "n_tx", "n_rx", "start_freq_hz", "slope_hz_per_s",
                        "idle_time_s", "adc_start_time_s", "ramp_end_time_s", "n_samples",
                        "adc_rate_sps", "n_chirps", "tx_order"})
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
        if self.mode == "os":
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
        ``adcbufCfg`` ChanInterleave = 0 (interleaved ADC buffer); False when absent.
    profile_extras : dict
        profileCfg values the front-end model does not use: tx_start_time_s,
        hpf_corner_1_code, hpf_corner_2_code, rx_gain_code.
    chirp_level : dict
        The DDM demo's chirp-level settings as `pipeline.ProcessingConfig` field values:
        ``intfMitigCfg`` -> intf_mag_snr_db, intf_magdiff_snr_db; ``compressionCfg`` ->
        compression, compression_ratio, compression_range_bins_per_block (EGE only).
    ignored : tuple of (int, str)
        (line number, command) of every command kept but not used (demo, monitoring, tracker
        and calibration commands).
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
    profile_extras: dict[str, Any] = dataclasses.field(default_factory=dict)
    chirp_level: dict[str, Any] = dataclasses.field(default_factory=dict)
    ignored: tuple[tuple[int, str], ...] = ()
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

    def int(self, i: int, name: str, lo: int | None = None, hi: int | None = None) -> int:
        tok = self.args[i]
        if not re.fullmatch(r"[+-]?\d+", tok):
            raise self.fail(f"{name}={tok!r} is not an integer")
        val = int(tok)
        if (lo is not None and val < lo) or (hi is not None and val > hi):
            rng = f"{lo if lo is not None else '-inf'}..{hi if hi is not None else 'inf'}"
            raise self.fail(f"{name}={val} is outside {rng} (AWR2944 limit)")
        return val

    def flag(self, i: int, name: str) -> bool:
        return bool(self.int(i, name, 0, 1))


# ---------------------------------------------------------------------------- parser state
@dataclass(slots=True)
class _State:
    fields: dict[str, Any] = dataclasses.field(default_factory=dict)
    field_lines: dict[str, _Line] = dataclasses.field(default_factory=dict)
    seen: dict[str, _Line] = dataclasses.field(default_factory=dict)
    profile_id: int | None = None
    profile_samples: int | None = None
    chirps: dict[int, tuple[int, _Line]] = dataclasses.field(default_factory=dict)
    tx_mask: int | None = None
    frame: dict[str, Any] = dataclasses.field(default_factory=dict)
    cfar: dict[str, TiCfar] = dataclasses.field(default_factory=dict)
    ddm_order: tuple[int, ...] | None = None
    ant_geometry: tuple | None = None
    adc_interleaved: bool = False
    extras: dict[str, Any] = dataclasses.field(default_factory=dict)
    chirp_level: dict[str, Any] = dataclasses.field(default_factory=dict)
    ignored: list[tuple[int, str]] = dataclasses.field(default_factory=list)
    directives: dict[str, Any] = dataclasses.field(default_factory=dict)
    directive_lines: dict[str, _Line] = dataclasses.field(default_factory=dict)

    def set(self, line: _Line, **values: Any) -> None:
        for k, v in values.items():
            self.fields[k] = v
            self.field_lines[k] = line


def _contiguous_count(mask: int, what: str, label: str, line: _Line) -> int:
    n = mask.bit_length()
    if mask != (1 << n) - 1:
        raise line.fail(f"{what}={mask} (0b{mask:04b}): RadarConfig models {label}1..{label}N, "
                        "so enable channels from bit 0 without gaps")
    return n


def _require_frame_mode(st: _State, ln: _Line) -> None:
    # TI's CLI rejects profile/chirp/frame commands unless the DFE output mode is set first.
    if "dfeDataOutputMode" not in st.seen:
        raise ln.fail("needs 'dfeDataOutputMode 1' on an earlier line")


# ---------------------------------------------------------------------------- handlers
def _dfe_output_mode(st: _State, ln: _Line) -> None:
    mode = ln.int(0, "modeType", 1, 5)
    if mode != 1:
        raise ln.fail(f"modeType={mode}: only 1 (frame mode) is supported; advanced frame, "
                      "continuous and advanced-chirp modes have no RadarConfig equivalent")


def _channel_cfg(st: _State, ln: _Line) -> None:
    rx = ln.int(0, "rxChannelEn", 1, (1 << _N_RX_CHIP) - 1)
    tx = ln.int(1, "txChannelEn", 1, (1 << _N_TX_CHIP) - 1)
    ln.int(2, "cascading", 0, 0)
    if len(ln.args) == 5:  # AWR2x44P: <ethOscClkEn> <driveStrength>
        ln.int(3, "ethOscClkEn", 0, 1)
        ln.int(4, "driveStrength", 0, 15)
    st.tx_mask = tx
    st.set(ln, n_rx=_contiguous_count(rx, "rxChannelEn", "Rx", ln),
           n_tx=_contiguous_count(tx, "txChannelEn", "Tx", ln))


def _adc_cfg(st: _State, ln: _Line) -> None:
    bits = ln.int(0, "numADCBits", 0, 2)
    fmt = ln.int(1, "adcOutputFmt", 0, 2)
    if bits != 2:
        raise ln.fail(f"numADCBits={bits}: the captures are int16, use 2 (16 bit)")
    if fmt != 0:
        raise ln.fail(f"adcOutputFmt={fmt}: the AWR2944 chain modelled is real-only, use 0")


def _adcbuf_cfg(st: _State, ln: _Line) -> None:
    ln.int(0, "subFrameIdx", -1, 3)
    if ln.int(1, "adcOutputFmt", 0, 1) != 1:
        raise ln.fail("adcOutputFmt=0 (complex): the AWR2944 chain modelled is real-only, use 1")
    ln.flag(2, "SampleSwap")
    st.adc_interleaved = not ln.flag(3, "ChanInterleave")
    ln.int(4, "ChirpThreshold", 1, 1)


def _profile_cfg(st: _State, ln: _Line) -> None:
    _require_frame_mode(st, ln)
    pid = ln.int(0, "profileId", 0, _MAX_PROFILE_ID)
    if st.profile_id is not None:
        raise ln.fail(f"a second profile (profileId={pid}): RadarConfig describes one chirp "
                      f"profile, already given on line {st.seen['profileCfg'].no}")
    start_hz = ln.si(1, "startFreq", 9)
    if not BAND_MIN_HZ <= start_hz <= BAND_MAX_HZ:
        raise ln.fail(f"startFreq={ln.args[1]} GHz is outside the AWR2944 band "
                      f"{BAND_MIN_HZ / 1e9:g}..{BAND_MAX_HZ / 1e9:g} GHz")
    idle, ramp = ln.dec(2, "idleTime"), ln.dec(4, "rampEndTime")
    if ln.int(5, "txOutPower", 0, 255):
        raise ln.fail(f"txOutPower={ln.args[5]}: Tx back-off is not modelled; keep 0 and set "
                      "'% radarsim: tx_power_dbm = ...' instead")
    if ln.int(6, "txPhaseShifter", 0, 0xFFFFFFFF):
        raise ln.fail(f"txPhaseShifter={ln.args[6]}: static Tx phase offsets are not "
                      "modelled; keep 0 (errors go in '% radarsim: tx_phase_error_deg')")
    st.profile_id = pid
    st.profile_samples = ln.int(9, "numAdcSamples", 2, 65535)
    st.set(ln, start_freq_hz=start_hz, idle_time_s=float(idle.scaleb(-6)),
           adc_start_time_s=ln.si(3, "adcStartTime", -6), ramp_end_time_s=float(ramp.scaleb(-6)),
           slope_hz_per_s=ln.si(7, "freqSlopeConst", 12), n_samples=st.profile_samples,
           adc_rate_sps=float(Decimal(ln.int(10, "digOutSampleRate", 1, 65535)).scaleb(3)),
           # The chip's chirp period is idle + ramp end time; summed in decimal, so
           # "5" + "18.81" us is exactly 23.81e-6 s.
           chirp_period_s=float((idle + ramp).scaleb(-6)))
    st.extras.update(tx_start_time_s=ln.si(8, "txStartTime", -6),
                     hpf_corner_1_code=ln.int(11, "hpfCornerFreq1", 0, 3),
                     hpf_corner_2_code=ln.int(12, "hpfCornerFreq2", 0, 3),
                     rx_gain_code=ln.int(13, "rxGain", 0, 255))


def _chirp_cfg(st: _State, ln: _Line) -> None:
    _require_frame_mode(st, ln)
    start = ln.int(0, "startIdx", 0, _MAX_CHIRP_INDEX)
    end = ln.int(1, "endIdx", start, _MAX_CHIRP_INDEX)
    pid = ln.int(2, "profileId", 0, _MAX_PROFILE_ID)
    if st.profile_id is None or pid != st.profile_id:
        raise ln.fail(f"profileId={pid} is not defined by an earlier profileCfg")
    for i, name in enumerate(("startFreqVar", "freqSlopeVar", "idleTimeVar",
                              "adcStartTimeVar"), start=3):
        if ln.dec(i, name) != 0:
            raise ln.fail(f"{name}={ln.args[i]}: per-chirp variations are not modelled "
                          "(every chirp of a RadarConfig is the same); use 0")
    tx = ln.int(7, "txEnable", 1, (1 << _N_TX_CHIP) - 1)
    for idx in range(start, end + 1):
        if idx in st.chirps:
            raise ln.fail(f"chirp {idx} was already defined on line {st.chirps[idx][1].no}")
        st.chirps[idx] = (tx, ln)


def _frame_cfg(st: _State, ln: _Line) -> None:
    _require_frame_mode(st, ln)
    start = ln.int(0, "chirpStartIdx", 0, _MAX_CHIRP_INDEX)
    end = ln.int(1, "chirpEndIdx", start, _MAX_CHIRP_INDEX)
    loops = ln.int(2, "numLoops", 1, _MAX_LOOPS)
    frames = ln.int(3, "numFrames", 0, _MAX_FRAMES)
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
    order = tuple(ln.int(i, f"Tx{i}", 0, _N_TX_CHIP - 1) for i in range(len(ln.args)))
    if sorted(order) != list(range(_N_TX_CHIP)):
        raise ln.fail(f"order {' '.join(ln.args)} must list each of the AWR2944's Tx 0.."
                      f"{_N_TX_CHIP - 1} once (all Tx, even disabled ones, per TI)")
    st.ddm_order = order


def _evm_ant_geometry() -> tuple:
    """antGeometryCfg of the AWR2944 EVM array that RadarConfig models (DESIGN 4.2)."""
    full = RadarConfig(n_tx=_N_TX_CHIP, n_rx=_N_RX_CHIP)
    tx = full.tx_positions_m / full.wavelength_m
    rx = full.rx_positions_m / full.wavelength_m
    z_step = max(float(tx[:, 2].max()), 1e-12)
    pairs = tuple((1 if abs(tx[t, 2]) < 1e-9 else 0, int(round((tx[t, 1] + rx[r, 1]) / 0.5)))
                  for t in range(_N_TX_CHIP) for r in range(_N_RX_CHIP))
    return pairs, Decimal("0.5"), Decimal(_fmt_decimal(round(z_step, 9)))


def _ant_geometry_cfg(st: _State, ln: _Line) -> None:
    n = _N_TX_CHIP * _N_RX_CHIP
    pairs = tuple((ln.int(2 * i, f"row{i}", 0, 1), ln.int(2 * i + 1, f"col{i}", 0, 63))
                  for i in range(n))
    geometry = (pairs, ln.dec(2 * n, "xSpacebylambda"), ln.dec(2 * n + 1, "zSpacebylambda"))
    expected = _evm_ant_geometry()
    if geometry != expected:
        exp_text = " ".join(f"{r} {c}" for r, c in expected[0])
        raise ln.fail("array differs from the AWR2944 EVM array RadarConfig models "
                      f"(expected '{exp_text} {expected[1]} {expected[2]}')")
    st.ant_geometry = (pairs, float(geometry[1]), float(geometry[2]))


def _cfar_cfg(st: _State, ln: _Line) -> None:
    ln.int(0, "subFrameIdx", -1, 3)
    direction = _CFAR_DIRECTIONS[ln.int(1, "procDirection", 0, 1)]
    mode = CFAR_AVERAGE_MODES[ln.int(2, "averageMode", 0, 3)]
    n = len(ln.args)
    os_rank = ln.int(9, "osKvalue", 0, 255) if n >= 11 else None
    if mode == "os" and os_rank is None:
        raise ln.fail("averageMode=3 (OS) needs the osKvalue argument (11-argument syntax)")
    try:
        cfar = TiCfar(direction=direction, mode=mode,
                      window_cells=ln.int(3, "winLen", 1, 255),
                      guard_cells=ln.int(4, "guardLen", 0, 255),
                      noise_div_shift=ln.int(5, "noiseDiv", 0, 255),
                      cyclic=ln.flag(6, "cyclicMode"),
                      threshold_db=float(ln.dec(7, "thresholdScale")),
                      peak_grouping=ln.flag(8, "peakGroupingEn"),
                      os_rank=os_rank if mode == "os" else (os_rank or None),
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
    keep_ignored, keep_directives = st.ignored, (st.directives, st.directive_lines)
    fresh = _State()
    for f in dataclasses.fields(_State):
        setattr(st, f.name, getattr(fresh, f.name))
    st.ignored = keep_ignored
    st.directives, st.directive_lines = keep_directives


def _control(st: _State, ln: _Line) -> None:
    """sensorStop / sensorStart: no configuration content."""


def _unsupported(reason: str) -> Callable[[_State, _Line], None]:
    def handler(st: _State, ln: _Line) -> None:
        raise ln.fail(f"not supported: {reason}")
    return handler


@dataclass(frozen=True, slots=True)
class CommandSpec:
    """One CLI command: accepted argument counts (None: not checked), handler (None: kept and
    reported as ignored), one-line description."""

    n_args: frozenset[int] | None
    handler: Callable[[_State, _Line], None] | None
    help: str


def _spec(n_args, handler, help_text) -> CommandSpec:
    return CommandSpec(None if n_args is None else frozenset(n_args), handler, help_text)


#: Registry of the CLI commands the parser knows, by name (case-sensitive, as TI's CLI).
TI_COMMANDS: dict[str, CommandSpec] = {
    # --- used
    "sensorStop": _spec({0, 1}, _control, "stop the sensor"),
    "sensorStart": _spec({0, 1}, _control, "start the sensor"),
    "flushCfg": _spec({0}, _flush_cfg, "reset the configuration"),
    "dfeDataOutputMode": _spec({1}, _dfe_output_mode, "1 frame mode"),
    "channelCfg": _spec({3, 5}, _channel_cfg, "Rx/Tx enable masks"),
    "adcCfg": _spec({2}, _adc_cfg, "ADC bits and output format"),
    "adcbufCfg": _spec({5}, _adcbuf_cfg, "ADC buffer format and interleaving"),
    "profileCfg": _spec({14}, _profile_cfg, "chirp profile"),
    "chirpCfg": _spec({8}, _chirp_cfg, "chirp table entries"),
    "frameCfg": _spec({7, 8}, _frame_cfg, "frame: chirps, loops, period"),
    "ddmPhaseShiftAntOrder": _spec({_N_TX_CHIP}, _ddm_order, "DDMA Tx order"),
    "antGeometryCfg": _spec({2 * _N_TX_CHIP * _N_RX_CHIP + 2}, _ant_geometry_cfg,
                            "virtual array geometry"),
    "cfarCfg": _spec({9, 11, 12, 13}, _cfar_cfg, "CFAR settings"),
    # --- known but not representable
    "advFrameCfg": _spec({6}, _unsupported("advanced frames (sub-frames)"), "advanced frame"),
    "subFrameCfg": _spec({10}, _unsupported("advanced frames (sub-frames)"), "sub-frame"),
    "subDataFrameCfg": _spec({4}, _unsupported("advanced frames (sub-frames)"), "sub-frame"),
    "advChirpCfg": _spec({16}, _unsupported("advanced chirp LUTs"), "advanced chirp"),
    "LUTDataCfg": _spec(None, _unsupported("advanced chirp LUTs"), "advanced chirp LUT"),
    "contModeCfg": _spec({9}, _unsupported("continuous-wave mode"), "continuous mode"),
    "bpmCfgAdvanced": _spec({3}, _unsupported("BPM (binary phase) MIMO"), "BPM"),
    "bpmCfg": _spec(None, _unsupported("BPM (binary phase) MIMO"), "BPM"),
    # --- kept and reported as ignored (arg counts from the TI sources cited above)
    "version": _spec({0}, None, "print versions"),
    "lowPower": _spec({2}, None, "low-power ADC mode"),
    "guiMonitor": _spec({7}, None, "UART output selection"),
    "aoaFovCfg": _spec({5}, None, "angle field of view"),
    "cfarFovCfg": _spec({4}, None, "CFAR field of view"),
    "multiObjBeamForming": _spec({3}, None, "multi-object beamforming"),
    "calibDcRangeSig": _spec({5}, None, "DC range signature calibration"),
    "clutterRemoval": _spec({2}, None, "static clutter removal"),
    "extendedMaxVelocity": _spec({2}, None, "extended velocity"),
    "compRangeBiasAndRxChanPhase": _spec({1 + 2 * _N_TX_CHIP * _N_RX_CHIP}, None,
                                         "range bias and channel phase compensation"),
    "measureRangeBiasAndRxChanPhase": _spec({3}, None, "calibration measurement"),
    "antennaCalibParams": _spec({2 * _N_TX_CHIP * _N_RX_CHIP}, None, "antenna calibration"),
    "CQRxSatMonitor": _spec({5}, None, "Rx saturation monitor"),
    "CQSigImgMonitor": _spec({3}, None, "signal/image band monitor"),
    "analogMonitor": _spec({2}, None, "analog monitors"),
    "lvdsStreamCfg": _spec({4}, None, "LVDS streaming"),
    "configDataPort": _spec({2}, None, "data UART"),
    "queryDemoStatus": _spec({0}, None, "status query"),
    "calibData": _spec({3}, None, "calibration data save/restore"),
    "compressionCfg": _spec({5}, _compression_cfg, "DDM demo compression (EGE)"),
    "intfMitigCfg": _spec({3}, _intf_mitig_cfg, "interference mitigation thresholds"),
    "localMaxCfg": _spec({3}, None, "local-maximum thresholds"),
    "rangeProcCfg": _spec({5}, None, "range processing"),
    "procChain": _spec(None, None, "processing chain"),
    "procChainCfg": _spec(None, None, "processing chain"),
    "spreadSpectrumConfig": _spec({12}, None, "clock spread spectrum"),
    "adcDataDitherCfg": _spec({2}, None, "ADC dither (errata)"),
    "enableProgFiltCfg": _spec({1}, None, "programmable filter"),
    "powerMeasPerClockGating": _spec({1}, None, "power measurement"),
    "powerMeasHwaDynamicClockGating": _spec({1}, None, "power measurement"),
    "powerMeasHwaStateAfterFrameProc": _spec({1}, None, "power measurement"),
    "powerMeasDspStateAfterFrameProc": _spec({1}, None, "power measurement"),
    "anaTempRead": _spec({0}, None, "temperature"),
    "digTempRead": _spec({0}, None, "temperature"),
    "LdoBypassConfig": _spec({4}, None, "LDO bypass"),
    "ApllSynthBwConfig": _spec({7}, None, "APLL/synth bandwidth"),
    "appSceneryParams": _spec({11}, None, "R79 tracker scenery"),
    "appGatingParams": _spec({5}, None, "R79 tracker gating"),
    "appStateParams": _spec({6}, None, "R79 tracker state machine"),
    "appAllocParams": _spec({6}, None, "R79 tracker allocation"),
    "gtrack": _spec({11}, None, "R79 group tracker"),
    "ransac": _spec({3}, None, "R79 RANSAC static/moving split"),
    "rangeCfar": _spec({1}, None, "R79 range-CFAR enable"),
}


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
        if field.type in ("str", str):
            return raw
        raise ln.fail(f"value {raw!r} for {field.name} is not JSON") from None
    return tuple(value) if isinstance(value, list) else value


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
        With "line N (command): ..." for every unknown command, wrong argument count,
        malformed number, value outside the AWR2944's limits, unsupported feature, missing
        required command (reported at the end of the input) and `RadarConfig` validation
        error (at the line of the command that set the field).
    FileNotFoundError
        If a path was given and does not exist.
    """
    lines = _read_source(path_or_text).splitlines()
    st = _State()
    fields_by_name = {f.name: f for f in dataclasses.fields(RadarConfig)}
    for no, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text:
            continue
        if text.startswith("%"):
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
        ln = _Line(no, cmd, tuple(args))
        spec = TI_COMMANDS.get(cmd)
        if spec is None:
            close = difflib.get_close_matches(cmd, TI_COMMANDS, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise _LineError(f"line {no}: unknown command {cmd!r}{hint}")
        if spec.n_args is not None and len(args) not in spec.n_args:
            want = " or ".join(str(n) for n in sorted(spec.n_args))
            raise ln.fail(f"expects {want} arguments, got {len(args)}")
        if spec.handler is None:
            st.ignored.append((no, cmd))
        else:
            spec.handler(st, ln)
            st.seen[cmd] = ln
    return _finish(st, len(lines))


def _finish(st: _State, n_lines: int) -> TiProfile:
    end = f"line {n_lines} (end of input)"
    for cmd in ("dfeDataOutputMode", "channelCfg", "adcCfg", "profileCfg", "chirpCfg",
                "frameCfg"):
        if cmd not in st.seen:
            raise _LineError(f"{end}: missing required command {cmd!r}")
    fr = st.frame
    fln: _Line = fr["line"]
    if fr["samples"] is not None and fr["samples"] != st.profile_samples:
        raise fln.fail(f"numAdcSamples={fr['samples']} differs from profileCfg's "
                       f"numAdcSamples={st.profile_samples}")
    masks = []
    for idx in range(fr["start"], fr["end"] + 1):
        if idx not in st.chirps:
            raise fln.fail(f"chirp {idx} of the frame is not defined by any chirpCfg")
        tx, cln = st.chirps[idx]
        if tx & ~st.tx_mask:
            raise cln.fail(f"txEnable={tx} (0b{tx:04b}) enables a Tx that channelCfg "
                           f"txChannelEn={st.tx_mask} (0b{st.tx_mask:04b}) leaves off")
        masks.append(tx)
    n_tx = st.fields["n_tx"]
    per_loop = len(masks)
    # The MIMO scheme is the registered scheme that claims the chirp pattern (radarsim.mimo).
    from .mimo import MIMO_SCHEMES
    claim = None
    for scheme in MIMO_SCHEMES.values():
        try:
            claim = scheme.from_ti(tuple(masks), n_tx, st.tx_mask, st.ddm_order)
        except ValueError as exc:
            raise fln.fail(str(exc)) from None
        if claim is not None:
            break
    if claim is None:
        pattern = " ".join(f"0b{m:04b}" for m in masks)
        raise fln.fail(f"chirp Tx pattern [{pattern}] matches no MIMO scheme "
                       f"({', '.join(MIMO_SCHEMES)}): DDMA needs all {n_tx} Tx every chirp and "
                       f"at least {n_tx} chirps per loop, TDMA one Tx per chirp, each once per "
                       "loop")
    order = claim.pop("tx_order", None)
    st.set(fln, **claim, n_chirps=per_loop * fr["loops"])
    if "n_subbands" in claim:
        st.set(st.seen["ddmPhaseShiftAntOrder"], tx_order=order)
    else:
        if st.ddm_order is not None:
            st.ignored.append((st.seen["ddmPhaseShiftAntOrder"].no, "ddmPhaseShiftAntOrder"))
        st.set(fln, tx_order=order)
    if "n_subbands" in st.directives and "n_subbands" in claim:
        raise st.directive_lines["n_subbands"].fail(
            "n_subbands is set by chirpCfg/frameCfg (chirps per loop) for DDMA")

    kw = dict(_TI_DEFAULT_OVERRIDES)
    kw.update(st.directives)
    kw.update(st.fields)
    for name, value in st.directives.items():
        if name == "chirp_period_s":  # a directive refines the decimal idle + ramp sum
            kw[name] = value
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
                     adc_channel_interleaved=st.adc_interleaved, profile_extras=dict(st.extras),
                     chirp_level=dict(st.chirp_level),
                     ignored=tuple(st.ignored), directives=dict(st.directives))


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


def to_ti_cfg(cfg: RadarConfig | TiProfile, *, frame_period_s: float | None = None,
              n_frames: int | None = None,
              cfar: Mapping[str, TiCfar] | Iterable[TiCfar] | None = None,
              extra_lines: Iterable[str] = (), comments: Iterable[str] = ()) -> str:
    """Write a TI mmWave SDK CLI configuration for an AWR2944 running `cfg`.

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

    ti_frame = radar.scheme.to_ti(radar, _N_TX_CHIP)  # the scheme's loop (radarsim.mimo)
    per_loop = ti_frame.chirps_per_loop
    loops = radar.n_chirps // per_loop
    if loops > _MAX_LOOPS:
        raise ValueError(f"n_chirps={radar.n_chirps}: {loops} loops of {per_loop} chirps "
                         f"exceed the AWR2944 frame limit of {_MAX_LOOPS} loops")
    rx_mask, tx_mask = (1 << radar.n_rx) - 1, (1 << radar.n_tx) - 1
    idle_us = _fmt_decimal(radar.idle_time_s, -6)
    ramp_us = _fmt_decimal(radar.ramp_end_time_s, -6)
    out = [
        "% AWR2944 profile written by radarsim.ti_cfg.to_ti_cfg (mmWave MCU+ SDK CLI).",
        f"% {radar.mimo.upper()} {radar.n_tx} Tx x {radar.n_rx} Rx, {radar.n_chirps} chirps of "
        f"{radar.chirp_period_s * 1e6:.6g} us, {radar.n_samples} real samples at "
        f"{radar.adc_rate_sps / 1e6:g} Msps: range resolution {radar.range_resolution_m:.3f} m, "
        f"max range {radar.max_range_m:.1f} m, Vmax +/-{radar.max_unambiguous_velocity_mps:.2f}"
        " m/s.",
        *(c if c.startswith("%") else f"% {c}" for c in comments),
        "sensorStop",
        "flushCfg",
        "dfeDataOutputMode 1",
        f"channelCfg {rx_mask} {tx_mask} 0",
        "adcCfg 2 0",
        "adcbufCfg -1 1 0 1 1",
        "lowPower 0 0",
        # txOutPower, txPhaseShifter, txStartTime 0; HPF codes 0 0 and rxGain 42 as in the R79
        # demo (the front-end model has no HPF or gain setting).
        f"profileCfg 0 {_fmt_decimal(radar.start_freq_hz, 9)} {idle_us} "
        f"{_fmt_decimal(radar.adc_start_time_s, -6)} {ramp_us} 0 0 "
        f"{_fmt_decimal(radar.slope_hz_per_s, 12)} 0 {radar.n_samples} "
        f"{_fmt_decimal(radar.adc_rate_sps, 3)} 0 0 42",
    ]
    out += list(ti_frame.chirp_lines)
    out.append(f"frameCfg 0 {per_loop - 1} {loops} {n_frames} {radar.n_samples} "
               f"{_fmt_decimal(frame_period_s, -3)} 1 0")
    out += list(ti_frame.extra_lines)
    pairs, dx, dz = _evm_ant_geometry()
    out.append("antGeometryCfg " + " ".join(f"{r} {c}" for r, c in pairs) + f" {dx} {dz}")
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
