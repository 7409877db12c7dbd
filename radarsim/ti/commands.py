"""The registry of TI CLI commands the reader knows: argument counts per chip family, the
handler that models the command (or None: kept and reported as ignored) and a description."""
from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Callable, Mapping

from . import handlers as h
from .calibration import comp_range_bias_and_rx_chan_phase
from .state import ParseState
from .syntax import Line

__all__ = ["CommandSpec", "TI_COMMANDS", "MODELLED_COMMANDS"]


@dataclass(frozen=True, slots=True)
class CommandSpec:
    """One CLI command: accepted argument counts (None: not checked; a mapping: per chip, with
    the key None for the others), handler (None: kept and reported as ignored), description."""

    n_args: frozenset[int] | Mapping[str | None, frozenset[int]] | None
    handler: Callable[[ParseState, Line], None] | None
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


#: Registry of the CLI commands the parser knows, by name (case-sensitive, as TI's CLI).
#: Argument counts from the demos' ``mmw_cli.c`` (mmWave SDK 2.x/3.x xwr16xx/18xx/68xx, MCU+
#: SDK AWR294x/AWR2x44P/AWR2544, the R79 demo) and TI's profiles found with the code search.
TI_COMMANDS: dict[str, CommandSpec] = {
    # --- used
    "sensorStop": _spec({0, 1}, h.control, "stop the sensor"),
    "sensorStart": _spec({0, 1, 4}, h.control, "start the sensor"),
    "flushCfg": _spec({0}, h.flush_cfg, "reset the configuration"),
    "dfeDataOutputMode": _spec({1}, h.dfe_output_mode, "1 frame mode"),
    "channelCfg": _spec({3, 5}, h.channel_cfg, "Rx/Tx enable masks"),
    "adcCfg": _spec({2}, h.adc_cfg, "ADC bits and output format"),
    "adcbufCfg": _spec({4, 5}, h.adcbuf_cfg, "ADC buffer format and interleaving"),
    "profileCfg": _spec({14}, h.profile_cfg, "chirp profile"),
    "chirpCfg": _spec({8}, h.chirp_cfg, "chirp table entries"),
    "frameCfg": _spec({7, 8}, h.frame_cfg, "frame: chirps, loops, period"),
    "ddmPhaseShiftAntOrder": _spec({"AWR1843": {3}, "IWR6843": {3}, "AWR1642": {2},
                                    None: {4}}, h.ddm_order, "DDMA Tx order"),
    "antGeometryCfg": _spec({None: {34}, "AWR1843": {26}, "IWR6843": {26}, "AWR1642": {18}},
                            h.ant_geometry_cfg, "virtual array geometry"),
    "cfarCfg": _spec(None, h.cfar_cfg, "CFAR settings (counts: CFAR_ARGS)"),
    "lvdsStreamCfg": _spec({4}, h.lvds_stream_cfg, "LVDS streaming (raw capture)"),
    "bpmCfg": _spec({4}, h.bpm_cfg, "BPM MIMO (2 Tx Hadamard)"),
    # --- known but not representable
    "advFrameCfg": _spec(None, h.unsupported("advanced frames (sub-frames)"), "advanced frame"),
    "subFrameCfg": _spec(None, h.unsupported("advanced frames (sub-frames)"), "sub-frame"),
    "subDataFrameCfg": _spec(None, h.unsupported("advanced frames (sub-frames)"), "sub-frame"),
    "advChirpCfg": _spec(None, h.unsupported("advanced chirp LUTs"), "advanced chirp"),
    "LUTDataCfg": _spec(None, h.unsupported("advanced chirp LUTs"), "advanced chirp LUT"),
    "contModeCfg": _spec(None, h.unsupported("continuous-wave mode"), "continuous mode"),
    "bpmCfgAdvanced": _spec(None, h.unsupported("BPM (binary phase) MIMO"), "BPM"),
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
    # 1 range bias + (re, im) per chip Tx x Rx pair: the count is the chip's (handler).
    "compRangeBiasAndRxChanPhase": _spec(None, comp_range_bias_and_rx_chan_phase,
                                         "range bias and channel phase compensation"),
    "measureRangeBiasAndRxChanPhase": _spec({3}, None, "calibration measurement"),
    "antennaCalibParams": _spec(range(2, 33, 2), None, "antenna calibration"),
    "CQRxSatMonitor": _spec({5}, None, "Rx saturation monitor"),
    "CQSigImgMonitor": _spec({3}, None, "signal/image band monitor"),
    "analogMonitor": _spec({None: {2}, "AWR2544": {3}}, None, "analog monitors"),
    "configDataPort": _spec({2}, None, "data UART"),
    "queryDemoStatus": _spec({0}, None, "status query"),
    "calibData": _spec({3}, None, "calibration data save/restore"),
    "compressionCfg": _spec({5}, h.compression_cfg, "DDM demo compression (EGE)"),
    "intfMitigCfg": _spec({3}, h.intf_mitig_cfg, "interference mitigation thresholds"),
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
MODELLED_COMMANDS = tuple(name for name, spec in TI_COMMANDS.items() if spec.handler not in (None,))
