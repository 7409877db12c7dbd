"""Handlers of the demos' processing commands (`radarsim.ti.families` says which family has
which and what an absent one means). Each writes `ProcessingConfig` field values into
``ParseState.processing`` and records the command in ``ParseState.processing_commands``; a
command the harness reads but does not model is recorded in ``ParseState.unmodelled`` when it
asks for something, and listed in one note.

Syntax: mmWave SDK 3.x user guide, sec. "Configuration (.cfg) File Format" (the MCU+ SDK TDM
demo takes the same arguments).
"""
from __future__ import annotations

import math

from .parse_state import ParseState
from .syntax import Line

__all__ = ["ONE_PEAK_DB", "extended_max_velocity", "multi_obj_beamforming", "cfar_fov_cfg",
           "aoa_fov_cfg", "clutter_removal", "calib_dc_range_sig", "measure_range_bias",
           "rx_sat_monitor"]


def _record(st: ParseState, ln: Line, **fields) -> None:
    st.processing.update(fields)
    st.processing_commands[ln.cmd] = ln


def _sub(ln: Line) -> int:
    """Index of the first argument after the optional subFrameIdx (SDK 1.x/2.0 forms lack it)."""
    return 1 if len(ln.args) in {"extendedMaxVelocity": {2}, "clutterRemoval": {2},
                                 "multiObjBeamForming": {3}, "calibDcRangeSig": {5},
                                 "cfarFovCfg": {4}, "aoaFovCfg": {5}}[ln.cmd] else 0


def extended_max_velocity(st: ParseState, ln: Line) -> None:
    """``extendedMaxVelocity <subFrameIdx> <enabled>``: TDM/BPM velocity disambiguation beyond
    +/-Vmax (`ProcessingConfig.tdma_disambiguation`)."""
    _record(st, ln, tdma_disambiguation=ln.flag(_sub(ln), "enabled"))


#: `ProcessingConfig.azimuth_sidelobe_db` that keeps only the strongest azimuth peak of a cell
#: (TI's multiObjBeamForming disabled, or a threshold of 1).
ONE_PEAK_DB = 1e-6


def multi_obj_beamforming(st: ParseState, ln: Line) -> None:
    """``multiObjBeamForming <subFrameIdx> <enabled> <threshold>``: a second azimuth peak of a
    (range, Doppler) cell is reported when its magnitude exceeds threshold x the first peak's
    (SDK 3.x AoAProcHWA compares magnitudes), i.e. within -20 log10(threshold) dB in power:
    `ProcessingConfig.azimuth_sidelobe_db`. Disabled: the strongest peak only (`ONE_PEAK_DB`).
    Chains that report one peak per cell anyway (`pipeline.MimoChain.multi_azimuth_peaks`
    False) cannot follow "enabled": ``harness.cell.ti_profile`` notes it."""
    k = _sub(ln)
    enabled = ln.flag(k, "enabled")
    thr = float(ln.dec(k + 1, "threshold"))
    if not 0.0 <= thr <= 1.0:
        raise ln.fail(f"threshold={ln.args[k + 1]} is outside 0..1 (a fraction of the first "
                      "peak's magnitude)")
    if not enabled or thr == 1.0:
        _record(st, ln, azimuth_sidelobe_db=ONE_PEAK_DB)
        return
    _record(st, ln, azimuth_sidelobe_db=None if thr == 0.0 else -20.0 * math.log10(thr))


def cfar_fov_cfg(st: ParseState, ln: Line) -> None:
    """``cfarFovCfg <subFrameIdx> <procDirection> <min> <max>``: detections outside [min, max]
    are dropped; direction 0 range (m), 1 Doppler (radial velocity, m/s)."""
    k = _sub(ln)
    direction = ln.int(k, "procDirection", 0, 1)
    lo, hi = float(ln.dec(k + 1, "min")), float(ln.dec(k + 2, "max"))
    if lo > hi:
        raise ln.fail(f"min={ln.args[k + 1]} is above max={ln.args[k + 2]}")
    if direction == 0:
        if lo < 0:
            raise ln.fail(f"min={ln.args[k + 1]} m: a range field of view starts at >= 0")
        _record(st, ln, range_fov_m=(lo, hi))
    else:
        _record(st, ln, velocity_fov_mps=(lo, hi))
    st.processing_commands[f"cfarFovCfg {direction}"] = ln


def aoa_fov_cfg(st: ParseState, ln: Line) -> None:
    """``aoaFovCfg <subFrameIdx> <minAzimuthDeg> <maxAzimuthDeg> <minElevationDeg>
    <maxElevationDeg>``: detections outside the angles are dropped."""
    k = _sub(ln)
    vals = [float(ln.dec(k + i, name)) for i, name in enumerate(
        ("minAzimuthDeg", "maxAzimuthDeg", "minElevationDeg", "maxElevationDeg"))]
    for (lo, hi), what in (((vals[0], vals[1]), "azimuth"), ((vals[2], vals[3]), "elevation")):
        if not -90.0 <= lo <= hi <= 90.0:
            raise ln.fail(f"{what} field of view {lo:g}..{hi:g} deg must be ordered within "
                          "-90..90")
    _record(st, ln, azimuth_fov_deg=(vals[0], vals[1]), elevation_fov_deg=(vals[2], vals[3]))


def clutter_removal(st: ParseState, ln: Line) -> None:
    """``clutterRemoval <subFrameIdx> <enabled>``: static clutter removal (each virtual
    channel's mean over the frame's chirps subtracted), `ProcessingConfig.clutter_removal`."""
    _record(st, ln, clutter_removal=ln.flag(_sub(ln), "enabled"))


#: TI's DC_RANGE_SIGNATURE_COMP_MAX_BIN_SIZE (mmw_config.h): bins the signature may span.
DC_SIGNATURE_MAX_BINS = 32


def calib_dc_range_sig(st: ParseState, ln: Line) -> None:
    """``calibDcRangeSig <subFrameIdx> <enabled> <negativeBinIdx> <positiveBinIdx> <numAvg>``:
    the antenna-coupling signature of the bins negativeBinIdx..positiveBinIdx around DC,
    averaged over the first numAvg loops and then subtracted (`pipeline.dc_range_signature`;
    ``radar-harness process`` runs it over a capture). Checks of ``MmwDemo_CLICalibDcRangeSig``
    (SDK 3.x ``mmw_cli.c``): negativeBinIdx <= 0, at most 32 bins, numAvg a power of two."""
    k = _sub(ln)
    st.processing_commands[ln.cmd] = ln
    if not ln.flag(k, "enabled"):
        return
    neg = ln.int(k + 1, "negativeBinIdx", -DC_SIGNATURE_MAX_BINS, 0)
    pos = ln.int(k + 2, "positiveBinIdx", -1, DC_SIGNATURE_MAX_BINS - 1)
    if pos - neg + 1 > DC_SIGNATURE_MAX_BINS:
        raise ln.fail(f"bins {neg}..{pos} are {pos - neg + 1}; the demo takes at most "
                      f"{DC_SIGNATURE_MAX_BINS} (DC_RANGE_SIGNATURE_COMP_MAX_BIN_SIZE)")
    num_avg = ln.int(k + 3, "numAvg", 1, 65535)
    if num_avg & (num_avg - 1):
        raise ln.fail(f"numAvg={num_avg} is not a power of two (the demo's CLI refuses it)")
    st.dc_range_sig = (ln, neg, pos, num_avg)


def measure_range_bias(st: ParseState, ln: Line) -> None:
    """``measureRangeBiasAndRxChanPhase <enabled> <targetDistance m> <searchWin m>``: kept as
    `TiProfile.measure_range_bias` (``radar-harness calibrate`` does the measurement)."""
    enabled = ln.flag(0, "enabled")
    target, window = float(ln.dec(1, "targetDistance")), float(ln.dec(2, "searchWin"))
    if target <= 0 or window <= 0:
        raise ln.fail(f"targetDistance={ln.args[1]} m and searchWin={ln.args[2]} m must be > 0")
    st.measure = (enabled, target, window)
    st.processing_commands[ln.cmd] = ln
    if enabled:
        st.unmodelled.append(f"line {ln.no} measureRangeBiasAndRxChanPhase enabled (run "
                             "radar-harness calibrate)")


def rx_sat_monitor(st: ParseState, ln: Line) -> None:
    """``CQRxSatMonitor``: the chip's analog saturation monitor; the chain flags saturation
    from the ADC codes instead (`pipeline.saturation`)."""
    st.processing_commands[ln.cmd] = ln
    st.unmodelled.append(f"line {ln.no} CQRxSatMonitor (saturation is flagged from ADC codes)")
