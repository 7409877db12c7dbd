"""TI mmWave SDK CLI profiles (.cfg) in and out, for every chip of `radarsim.chips.CHIPS`.

Modules: `reader` (`parse_ti_cfg`), `writer` (`to_ti_cfg`), `commands` (the command registry)
with `handlers` (one per modelled command), `codes` (TI's numeric codes, one table),
`chip_inference`, `schedule` (chirp table -> MIMO scheme), `profile` (`TiProfile`, `TiCfar`),
`r79` (the R79 demo's profile).

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
(design.md section 4.3); the shipped R79 file carries ``"floor"`` to reproduce [TI-DDMA] table 4.

The chip comes from a ``% radarsim: chip = "..."`` directive, TI Visualizer's ``% Platform:``
header, or the commands themselves (`infer_chip`); its limits (`radarsim.chips`) bound every
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
the R79 waveform of [TI-DDMA] table 2 (``profileCfg 0 77 5 5 18.81 0 0 8.883 0 384 30000 0 0
42``, ``chirpCfg 0 5 0 0 0 0 0 15``, ``frameCfg 0 5 128 0 384 250 1 0``):

- ``cfarCfg <subFrameIdx> <procDirection> <averageMode> <winLen> <guardLen> <noiseDiv>
  <cyclicMode> <thresholdScale dB> <peakGroupingEn> <osKvalue> <osEdgeKscaleEn>`` (argc 12;
  thresholdScale at most 100 dB). mmWave SDK 3.x / AWR294X TDM demo: the first 9 arguments;
  AWR2x44P DDM demo: + ``<isEnabled>`` (range) and + ``<variableThresholdMode>`` (Doppler).
  averageMode 0 CA, 1 CAGO, 2 CASO, 3 OS (HWA 2.0; [TI-DPC] ``DPU_CFARProc_CfarCfg``);
  winLen and guardLen are one-sided.
- ``adcbufCfg <subFrameIdx> <adcOutputFmt> <SampleSwap> <ChanInterleave> <ChirpThreshold>``
  (argc 6, SDK 1.x without subFrameIdx; adcOutputFmt 0 complex, 1 real, must agree with
  ``adcCfg``; ChanInterleave 0 = interleaved buffer, `RadarConfig.adcbuf_interleaved`, which
  fixes the raw capture layout; chirpThreshold must be 1). The R79 firmware's hard-coded list
  has ``adcbufCfg -1 1 0 0 1``: interleaved, as [TI-DAZ] section 2 says of the AWR2944.

mmWave MCU+ SDK AWR2x44P DDM demo ``mmw_cli.c`` and its doxygen ``main.c`` (without the
command, as in the R79 firmware list, the R79 order: horizontal Tx first, elevation last):

- ``ddmPhaseShiftAntOrder <Tx0> <Tx1> ... <TxN>``: "antenna indices in increasing order of
  phase shift value, if all of them were enabled"; elevation antennas last, ``0 2 3 1`` for the
  AWR2944 (Tx0, Tx2, Tx3 azimuth, Tx1 elevation). TI's Tx k is our Tx k+1, so this is exactly
  `RadarConfig.tx_order` minus one (Tx1, Tx3, Tx4, Tx2).
- ``antGeometryCfg <Row(Tx0Rx0)> <Col(Tx0Rx0)> ... <Row(Tx3Rx3)> <Col(Tx3Rx3)> <xSpacebylambda>
  <zSpacebylambda>``: row 1 azimuth, row 0 elevation; the AWR2944 EVM is
  ``1 0 1 1 1 2 1 3 0 2 0 3 0 4 0 5 1 4 1 5 1 6 1 7 1 8 1 9 1 10 1 11 0.5 0.8`` (design.md 4.2).
  The grid defines the array (`RadarConfig.tx_positions_wl` / `rx_positions_wl`).

Chirp table to MIMO scheme: DDMA when every chirp of the frame enables the same two or more Tx
(as ``chirpCfg 0 5 ... 15`` + ``frameCfg 0 5 128``: 6 chirps per loop = 6 sub-bands, 128 loops
= 768 chirps); TDMA when each chirp enables one Tx and the loop repeats a sequence in which each
used Tx fires once (``Tx1, Tx3, Tx1, Tx3``: order Tx1, Tx3).

References
----------
.. [1] TI, mmWave SDK user guide, sec. "Configuration (.cfg) File Format".
.. [2] TI, AWR2944 DDMA application note [TI-DDMA], table 2 (R79 waveform), sec. 3.3.
.. [3] TI, CFAR in the mmWave SDK [TI-DPC], ``DPU_CFARProc_CfarCfg``.
"""
from __future__ import annotations

from .chip_inference import PLATFORMS
from .codes import CFAR_AVERAGE_MODES
from .commands import TI_COMMANDS
from .profile import DEFAULT_FRAME_PERIOD_S, TiCfar, TiProfile
from .r79_profile import R79_CFAR, R79_DEMO_LINES, R79_FIRMWARE_LINES, r79_cfg_path, r79_cfg_text
from .reader import from_ti_cfg, parse_ti_cfg
from .studio import parse_setup, parse_studio_json, parse_studio_log, setup_kind
from .writer import to_ti_cfg

__all__ = ["TiCfar", "TiProfile", "parse_ti_cfg", "from_ti_cfg", "to_ti_cfg", "r79_cfg_path",
           "r79_cfg_text", "TI_COMMANDS", "CFAR_AVERAGE_MODES", "DEFAULT_FRAME_PERIOD_S",
           "R79_CFAR", "R79_DEMO_LINES", "R79_FIRMWARE_LINES", "PLATFORMS", "parse_setup",
           "parse_studio_log", "parse_studio_json", "setup_kind"]
