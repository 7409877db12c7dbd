"""The registry of TI CLI commands the reader knows: argument counts per chip family, the
handler that models the command (or None: kept and reported as ignored) and a description."""
from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Callable, Mapping

from . import handlers as h
from . import processing_handlers as ph
from .board_calibration import antenna_calib_params, comp_range_bias_and_rx_chan_phase
from .parse_state import ParseState
from .syntax import Line

__all__ = ["CommandSpec", "TI_COMMANDS", "MODELLED_COMMANDS"]


@dataclass(frozen=True, slots=True)
class CommandSpec:
    """One CLI command.

    Attributes
    ----------
    n_args : frozenset of int, mapping or None
        Accepted argument counts (None: not checked; a mapping: per chip, key None for the
        others).
    handler : callable or None
        Models the command (None: kept and reported as ignored).
    help : str
    subframe_counts : frozenset of int or mapping
        Argument counts whose first argument is ``subFrameIdx`` (-1: every sub-frame); a
        mapping: per chip, as `n_args`.
    key_args : int or None
        The command configures one thing: a second line with the same first `key_args`
        arguments (and sub-frame) is a duplicate, refused (TI's CLI silently keeps the last).
        None: the command may repeat (chirpCfg, monitors, demo output).
    """

    n_args: frozenset[int] | Mapping[str | None, frozenset[int]] | None
    handler: Callable[[ParseState, Line], None] | None
    help: str
    subframe_counts: frozenset[int] | Mapping[str | None, frozenset[int]] = frozenset()
    key_args: int | None = None

    def counts(self, chip: str) -> frozenset[int] | None:
        if isinstance(self.n_args, Mapping):
            return self.n_args.get(chip, self.n_args[None])
        return self.n_args

    def has_subframe(self, line: Line, chip: str) -> bool:
        """Whether the line's first argument is its ``subFrameIdx`` (for that chip's demo)."""
        counts = self.subframe_counts
        if isinstance(counts, Mapping):
            counts = counts.get(chip, counts[None])
        return len(line.args) in counts

    def instance_key(self, line: Line, chip: str) -> tuple | None:
        """What the line configures (duplicates share it), or None if it may repeat."""
        if self.key_args is None:
            return None
        n = self.key_args + (1 if self.has_subframe(line, chip) else 0)
        return (line.cmd, *line.args[:n])


def _counts(n_args):
    if isinstance(n_args, Mapping):
        return MappingProxyType({k: frozenset(v) for k, v in n_args.items()})
    return None if n_args is None else frozenset(n_args)


def _spec(n_args, handler, help_text, *, sub=(), key=None) -> CommandSpec:
    return CommandSpec(_counts(n_args), handler, help_text, _counts(sub), key)


#: Registry of the CLI commands the parser knows, by name (case-sensitive, as TI's CLI).
#: Argument counts from the demos' ``mmw_cli.c`` (mmWave SDK 2.x/3.x xwr16xx/18xx/68xx, MCU+
#: SDK AWR294x/AWR2x44P/AWR2544, the R79 demo) and TI's profiles found with the code search.
TI_COMMANDS: dict[str, CommandSpec] = {
    # --- used
    "sensorStop": _spec({0, 1}, h.control, "stop the sensor"),
    "sensorStart": _spec({0, 1, 4}, h.control, "start the sensor"),
    "flushCfg": _spec({0}, h.flush_cfg, "reset the configuration"),
    "dfeDataOutputMode": _spec({1}, h.dfe_output_mode, "1 frame, 3 advanced frame", key=0),
    "channelCfg": _spec({3, 5}, h.channel_cfg, "Rx/Tx enable masks", key=0),
    "adcCfg": _spec({2}, h.adc_cfg, "ADC bits and output format", key=0),
    "adcbufCfg": _spec({4, 5}, h.adcbuf_cfg, "ADC buffer format and interleaving",
                       sub={5}, key=0),
    "profileCfg": _spec({14}, h.profile_cfg, "chirp profile"),
    "chirpCfg": _spec({8}, h.chirp_cfg, "chirp table entries"),
    "frameCfg": _spec({7, 8}, h.frame_cfg, "frame: chirps, loops, period", key=0),
    "ddmPhaseShiftAntOrder": _spec({"AWR1843": {3}, "IWR6843": {3}, "AWR1642": {2},
                                    None: {4}}, h.ddm_order, "DDMA Tx order", key=0),
    "antGeometryCfg": _spec({None: {34}, "AWR1843": {26}, "IWR6843": {26}, "AWR1642": {18}},
                            h.ant_geometry_cfg, "virtual array geometry", key=0),
    "cfarCfg": _spec(None, h.cfar_cfg, "CFAR settings (counts: CFAR_ARGS)",
                     sub={n: {8, 11} | c for n, c in h.CFAR_ARGS.items()}, key=1),
    "lvdsStreamCfg": _spec({4}, h.lvds_stream_cfg, "LVDS streaming (raw capture)", sub={4},
                           key=0),
    "bpmCfg": _spec({4}, h.bpm_cfg, "BPM MIMO (2 Tx Hadamard)", sub={4}, key=0),
    # --- known but not representable
    # Advanced frames: read by radarsim.ti.advanced before the per-sub-frame passes.
    "advFrameCfg": _spec({5, 6}, h.control, "advanced frame", key=0),
    "subFrameCfg": _spec({10}, h.control, "sub-frame chirps, loops, period", key=1),
    "subDataFrameCfg": _spec({4}, h.control, "sub-frame data (MCU+ SDK)", key=1),
    "advChirpCfg": _spec(None, h.unsupported("advanced chirp LUTs"), "advanced chirp"),
    "LUTDataCfg": _spec(None, h.unsupported("advanced chirp LUTs"), "advanced chirp LUT"),
    "contModeCfg": _spec(None, h.unsupported("continuous-wave mode"), "continuous mode"),
    "bpmCfgAdvanced": _spec(None, h.unsupported("BPM (binary phase) MIMO"), "BPM"),
    # --- kept and reported as ignored (SDK demo, monitoring, dither, calibration, tracker)
    "version": _spec({0}, None, "print versions"),
    "lowPower": _spec({2}, None, "low-power ADC mode"),
    "guiMonitor": _spec(None, None, "UART output selection (differs per demo and lab)",
                        sub={7}),
    "aoaFovCfg": _spec({4, 5}, ph.aoa_fov_cfg, "angle field of view", sub={5}, key=0),
    "cfarFovCfg": _spec({3, 4}, ph.cfar_fov_cfg, "CFAR field of view", sub={4}, key=1),
    "multiObjBeamForming": _spec({2, 3}, ph.multi_obj_beamforming, "multi-object beamforming",
                                 sub={3}, key=0),
    "calibDcRangeSig": _spec({4, 5}, ph.calib_dc_range_sig, "DC range signature calibration",
                             sub={5},
                             key=0),
    "clutterRemoval": _spec({1, 2}, ph.clutter_removal, "static clutter removal", sub={2}, key=0),
    "extendedMaxVelocity": _spec({1, 2}, ph.extended_max_velocity, "extended velocity",
                                 sub={2}, key=0),
    "nearFieldCfg": _spec({4}, None, "near-field correction"),
    # 1 range bias + (re, im) per chip Tx x Rx pair: the count is the chip's (handler).
    "compRangeBiasAndRxChanPhase": _spec(None, comp_range_bias_and_rx_chan_phase,
                                         "range bias and channel phase compensation", key=0),
    "measureRangeBiasAndRxChanPhase": _spec({3}, ph.measure_range_bias,
                                            "calibration measurement", key=0),
    # One (Im, Re) pair per chip virtual antenna: the count is the chip's (reader).
    "antennaCalibParams": _spec(range(2, 33, 2), antenna_calib_params,
                                "DDM demo virtual-antenna calibration", key=0),
    "CQRxSatMonitor": _spec({5}, ph.rx_sat_monitor, "Rx saturation monitor", key=1),
    "CQSigImgMonitor": _spec({3}, None, "signal/image band monitor"),
    "analogMonitor": _spec({None: {2}, "AWR2544": {3}}, None, "analog monitors"),
    "configDataPort": _spec({2}, None, "data UART"),
    "queryDemoStatus": _spec({0}, None, "status query"),
    "calibData": _spec({3}, None, "calibration data save/restore"),
    "compressionCfg": _spec({5}, h.compression_cfg, "DDM demo compression (EGE)", sub={5},
                            key=0),
    "intfMitigCfg": _spec({3}, h.intf_mitig_cfg, "interference mitigation thresholds",
                          sub={3}, key=0),
    "localMaxCfg": _spec({3}, None, "local-maximum thresholds", sub={3}, key=0),
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
    "peakGrouping": _spec(None, None, "SDK 1.x/2.x peak grouping (CFAR output)"),
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
MODELLED_COMMANDS = tuple(name for name, spec in TI_COMMANDS.items() if spec.handler is not None)
