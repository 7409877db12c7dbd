"""What a TI profile says, as typed values: `TiProfile` (the radar as a validated
`RadarConfig`, plus the frame, CFAR and demo commands) and `TiCfar` (one ``cfarCfg`` line,
pipeline-independent)."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from core.errors import BadInput

from ..radar_config import RadarConfig
from .codes import (
    CFAR_AVERAGE_MODES,
    CFAR_DIRECTIONS,
    CFAR_RANKED_MODES,
    MAX_CFAR_THRESHOLD_DB,
    cfar_code,
)
from .syntax import fmt_decimal

__all__ = ["TiCfar", "TiProfile", "DEFAULT_FRAME_PERIOD_S"]

#: Frame period written when none is given, s: the R79 demo's ``frameCfg ... 250 1 0``.
DEFAULT_FRAME_PERIOD_S = 0.25


@dataclass(frozen=True, kw_only=True, slots=True)
class TiCfar:
    """One ``cfarCfg`` line, pipeline-independent (harness.cli.cmd_ti maps it onto the pipeline).

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
        if self.direction not in CFAR_DIRECTIONS.values():
            raise BadInput(f"direction={self.direction!r} is not one of "
                           f"{sorted(CFAR_DIRECTIONS.values())}")
        if self.mode not in CFAR_AVERAGE_MODES.values():
            raise BadInput(f"mode={self.mode!r} is not one of "
                           f"{sorted(CFAR_AVERAGE_MODES.values())}")
        if self.window_cells < 1:
            raise BadInput(f"window_cells={self.window_cells} must be >= 1")
        if self.guard_cells < 0:
            raise BadInput(f"guard_cells={self.guard_cells} must be >= 0")
        if not 0.0 <= self.threshold_db <= MAX_CFAR_THRESHOLD_DB:
            raise BadInput(f"threshold_db={self.threshold_db:g} must be within 0.."
                           f"{MAX_CFAR_THRESHOLD_DB:g} dB (TI CLI limit)")
        if self.mode in CFAR_RANKED_MODES:
            if self.os_rank is None or not 1 <= self.os_rank <= 2 * self.window_cells:
                raise BadInput(f"os_rank={self.os_rank!r}: OS-CFAR needs 1 <= k <= 2 x "
                               f"window_cells = {2 * self.window_cells}")

    def to_cli(self, *, sdk3: bool = False) -> str:
        """The ``cfarCfg`` line: the R79 / MCU+ SDK demo's 11-argument syntax (12/13 with the
        AWR2x44P DDM demo's isEnabled / variableThresholdMode when they are set), or with
        `sdk3` the mmWave SDK 3.x demos' 9 arguments (which have no OS-CFAR).

        Raises
        ------
        ValueError
            If `sdk3` and the mode needs ``osKvalue``.
        """
        code = cfar_code(self.mode)
        direction = {v: k for k, v in CFAR_DIRECTIONS.items()}[self.direction]
        head = (f"cfarCfg -1 {direction} {code} {self.window_cells} {self.guard_cells} "
                f"{self.noise_div_shift} {int(self.cyclic)} {fmt_decimal(self.threshold_db)} "
                f"{int(self.peak_grouping)}")
        if sdk3:
            if self.mode in CFAR_RANKED_MODES:
                raise BadInput(f"mode={self.mode!r}: the mmWave SDK 3.x cfarCfg (9 arguments) "
                               "has no OS-CFAR (osKvalue)")
            return head
        line = f"{head} {self.os_rank or 0} {int(self.os_edge_k_scale)}"
        if not self.enabled or self.variable_threshold_mode is not None:  # AWR2x44P DDM form
            line += f" {int(self.enabled)}"
            if self.variable_threshold_mode is not None:
                line += f" {self.variable_threshold_mode}"
        return line


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
    processing : dict
        `pipeline.ProcessingConfig` field values the profile's processing commands define
        (`radarsim.ti.families`): ``cfarCfg`` is in `cfar`; ``extendedMaxVelocity`` ->
        tdma_disambiguation; ``compressionCfg`` -> compression, compression_ratio,
        compression_range_bins_per_block; ``intfMitigCfg`` -> interference_mitigation,
        intf_mag_snr_db, intf_magdiff_snr_db; ``multiObjBeamForming`` -> azimuth_sidelobe_db;
        ``cfarFovCfg`` -> range_fov_m, velocity_fov_mps; ``aoaFovCfg`` -> azimuth_fov_deg,
        elevation_fov_deg; ``compRangeBiasAndRxChanPhase`` -> range_bias_m, channel_comp. A
        command the profile leaves out is at its demo family's default.
    demo_family : str
        The TI demo the profile is for (`radarsim.ti.families.DEMO_FAMILIES`).
    measure_range_bias : tuple or None
        ``measureRangeBiasAndRxChanPhase`` (enabled, target distance m, search window m).
    dc_range_signature : tuple or None
        An enabled ``calibDcRangeSig`` the demo runs: (negativeBinIdx, positiveBinIdx, numAvg
        loops, chirps per loop); `pipeline.dc_range_signature` over a capture's frames.
    ignored : tuple of (int, str)
        (line number, command) of every command kept but not used (demo, monitoring, tracker
        and calibration commands, unknown commands).
    notes : tuple of str
        How the chip was found, defaults taken, chirps/profiles/Tx defined but unused.
    directives : dict
        Fields set by ``% radarsim:`` comments.
    subframes : tuple of TiProfile
        Advanced frames (``dfeDataOutputMode 3``): one profile per sub-frame, each with its
        own radar, CFAR and processing commands (the top-level fields are sub-frame 0's);
        empty in frame mode.
    subframe_index : int or None
        Which sub-frame this profile is (None: a whole frame).
    subframe_start_s : float
        Start of the sub-frame within the frame, s (the earlier sub-frames' periodicities).
    burst_period_s, subframe_period_s : float or None
        ``subFrameCfg`` burstPeriodicity and subFramePeriodicity, s (sub-frames only).
    command_lines : dict of str to int
        Line number of each modelled command read (the last one), for notes that cite it.
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
    processing: dict[str, Any] = dataclasses.field(default_factory=dict)
    demo_family: str = ""
    measure_range_bias: tuple | None = None
    dc_range_signature: tuple | None = None
    ignored: tuple[tuple[int, str], ...] = ()
    notes: tuple[str, ...] = ()
    directives: dict[str, Any] = dataclasses.field(default_factory=dict)
    subframes: tuple["TiProfile", ...] = ()
    subframe_index: int | None = None
    subframe_start_s: float = 0.0
    command_lines: dict[str, int] = dataclasses.field(default_factory=dict, compare=False)
    burst_period_s: float | None = None
    subframe_period_s: float | None = None

    @property
    def is_advanced(self) -> bool:
        """True for an advanced-frame profile (several sub-frames, `subframes`)."""
        return bool(self.subframes)

    @property
    def is_joined(self) -> bool:
        """True for an advanced frame whose sub-frames are one radar (a fast/slow chirp pair,
        `radarsim.ti.fast_slow`): `radar` is none of the sub-frames' radars."""
        return bool(self.subframes) and all(p.radar != self.radar for p in self.subframes)

    @property
    def parts(self) -> tuple["TiProfile", ...]:
        """The sub-frame profiles, or (self,) for a frame-mode profile."""
        return self.subframes or (self,)

    @property
    def ignored_commands(self) -> list[str]:
        """Names of the ignored commands, in file order."""
        return [cmd for _, cmd in self.ignored]
