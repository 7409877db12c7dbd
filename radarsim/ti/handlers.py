"""Command handlers: each reads one CLI line into the `ParseState` (argument meanings and
limits from TI's ``cli_mmwave.c`` / demo ``mmw_cli.c``; see `radarsim.ti` for the syntax)."""
from __future__ import annotations

import dataclasses
from decimal import Decimal
from typing import Callable

from ..chips import ADC_MODES, CHIPS
from .codes import CFAR_AVERAGE_MODES, CFAR_DIRECTIONS, CFAR_RANKED_CODES
from .parse_state import ParseState
from .profile import TiCfar
from .syntax import Line, LineError, channel_bits


def dfe_output_mode(st: ParseState, ln: Line) -> None:
    """``dfeDataOutputMode <modeType>``: 1 frame, 3 advanced frame (sub-frames, read by
    `radarsim.ti.advanced`); 2 continuous and 4/5 advanced chirp have no RadarConfig."""
    mode = ln.int(0, "modeType", 1, 5)
    if mode == 3 and not st.advanced:
        raise ln.fail("modeType=3 (advanced frame) needs an advFrameCfg and a subFrameCfg per "
                      "sub-frame")
    if mode not in (1, 3):
        raise ln.fail(f"modeType={mode}: only 1 (frame) and 3 (advanced frame) are supported; "
                      "continuous and advanced-chirp modes have no RadarConfig equivalent")
    if mode == 1 and st.advanced:
        raise ln.fail("modeType=1 (frame mode) contradicts advFrameCfg: use 3")


def channel_cfg(st: ParseState, ln: Line) -> None:
    chip = st.chip
    rx = ln.int(0, "rxChannelEn", 1, (1 << chip.n_rx) - 1, chip.name)
    tx = ln.int(1, "txChannelEn", 1, (1 << chip.n_tx) - 1, chip.name)
    ln.int(2, "cascading", 0, 0, chip.name)
    if len(ln.args) == 5:
        # <ethOscClkEn> <driveStrength>: the 25 MHz Ethernet clock output of the AWR2x44P /
        # AWR2544 (MCU+ SDK cli_mmwave.c). The MCU+ SDK 04.07 Visualizer writes this form for
        # every AWR294X-platform profile (its AWR294X demo covers the AWR2944P EVM): accepted on
        # the whole MCU+ family, no RF effect. The mmWave SDK 3.x demos take 3 arguments.
        if not chip.mcu_plus_sdk:
            raise ln.fail(f"the 5-argument form (ethOscClkEn, driveStrength) is MCU+ SDK "
                          f"AWR294x-family syntax; the {chip.name} demo takes 3 arguments")
        ln.int(3, "ethOscClkEn", 0, 1)
        ln.int(4, "driveStrength", 0, 15)
        if chip.channel_cfg_args != 5:
            st.notes.append(f"line {ln.no}: channelCfg ethOscClkEn/driveStrength (MCU+ SDK "
                            f"04.07 AWR294X form) read: Ethernet clock output, no effect on "
                            f"the {chip.name}'s radar")
    st.tx_mask, st.rx_mask = tx, rx
    chans = channel_bits(rx)
    st.set(ln, n_rx=len(chans), rx_channels=chans)


def adc_cfg(st: ParseState, ln: Line) -> None:
    bits = ln.int(0, "numADCBits", 0, 2)
    fmt = ln.int(1, "adcOutputFmt", 0, 2)
    if bits != 2:
        raise ln.fail(f"numADCBits={bits}: the captures are int16, use 2 (16 bit)")
    mode = next(m for m in ADC_MODES.values() if m.ti_code == fmt)
    if not st.chip.supports(mode.name):
        why = "real-only receiver " if len(st.chip.adc) == 1 else ""
        raise ln.fail(f"adcOutputFmt={fmt} ({mode.name}): the {st.chip.name} supports "
                      f"{sorted(st.chip.adc)} ({why}{st.chip.datasheet})")
    st.adc_complex = mode.is_complex
    st.set(ln, adc_mode=mode.name)


def adcbuf_cfg(st: ParseState, ln: Line) -> None:
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


def profile_cfg(st: ParseState, ln: Line) -> None:
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


def chirp_cfg(st: ParseState, ln: Line) -> None:
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


def frame_cfg(st: ParseState, ln: Line) -> None:
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


def ddm_order(st: ParseState, ln: Line) -> None:
    n = st.chip.n_tx
    order = tuple(ln.int(i, f"Tx{i}", 0, n - 1, st.chip.name) for i in range(len(ln.args)))
    if sorted(order) != list(range(n)):
        raise ln.fail(f"order {' '.join(ln.args)} must list each of the {st.chip.name}'s Tx 0.."
                      f"{n - 1} once (all Tx, even disabled ones, per TI)")
    st.ddm_order = order


def ant_geometry_cfg(st: ParseState, ln: Line) -> None:
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
CFAR_ARGS = {**{name: {9, 11, 12, 13} for name, c in CHIPS.items() if c.mcu_plus_sdk},
              None: {9}}


def cfar_cfg(st: ParseState, ln: Line) -> None:
    if len(ln.args) not in CFAR_ARGS.get(st.chip.name, CFAR_ARGS[None]):
        st.ignored.append((ln.no, ln.cmd))
        st.notes.append(f"line {ln.no}: cfarCfg with {len(ln.args)} arguments (SDK 1.x/2.0 "
                        f"linear threshold or a lab firmware's syntax) ignored")
        return
    ln.int(0, "subFrameIdx", -1, 3)
    direction = CFAR_DIRECTIONS[ln.int(1, "procDirection", 0, 1)]
    code = ln.int(2, "averageMode", 0, 3)
    mode = CFAR_AVERAGE_MODES[code]
    ranked = code in CFAR_RANKED_CODES
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
    except LineError:
        raise
    except ValueError as exc:
        raise ln.fail(str(exc)) from exc
    st.cfar[direction] = cfar
    st.processing_commands[ln.cmd] = ln


def lvds_stream_cfg(st: ParseState, ln: Line) -> None:
    """``lvdsStreamCfg <subFrameIdx> <enableHeader> <dataFmt> <enableSW>``: dataFmt 1 streams
    the ADC samples (the raw capture); kept for the capture layout, otherwise ignored."""
    ln.int(0, "subFrameIdx", -1, 3)
    st.lvds = (ln.flag(1, "enableHeader"), ln.int(2, "dataFmt", 0, 4), ln.flag(3, "enableSW"))
    st.ignored.append((ln.no, ln.cmd))


#: TI commands that select a MIMO scheme of `radarsim.mimo.MIMO_SCHEMES` by themselves.
TI_SCHEME_COMMANDS = {"bpmCfg": "bpm"}


def bpm_cfg(st: ParseState, ln: Line) -> None:
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


def intf_mitig_cfg(st: ParseState, ln: Line) -> None:
    """intfMitigCfg <subFrameIdx> <magSNRdB> <magDiffSNRdB> (MCU+ SDK DDM demo, integers)."""
    ln.int(0, "subFrameIdx", -1, 3)
    st.processing.update(interference_mitigation=True,
                         intf_mag_snr_db=float(ln.int(1, "magSNRdB", 1, 60)),
                         intf_magdiff_snr_db=float(ln.int(2, "magDiffSNRdB", 1, 60)))
    st.processing_commands[ln.cmd] = ln


def compression_cfg(st: ParseState, ln: Line) -> None:
    """compressionCfg <subFrameIdx> <enabled> <method 0 EGE / 1 BFP> <ratio> <rangeBinsPerBlock>
    (MCU+ SDK DDM demo)."""
    ln.int(0, "subFrameIdx", -1, 3)
    enabled = ln.flag(1, "enabled")
    if ln.int(2, "compressionMethod", 0, 1) == 1 and enabled:
        raise ln.fail("compressionMethod=1 (BFP) is not modelled; use 0 (EGE)")
    st.processing.update(compression=enabled,
                         compression_ratio=float(ln.dec(3, "compressionRatio")),
                         compression_range_bins_per_block=ln.int(4, "rangeBinsPerBlock", 1, 32))
    st.processing_commands[ln.cmd] = ln


def flush_cfg(st: ParseState, ln: Line) -> None:
    # TI's flushCfg resets the configuration given so far; ignored-command records, notes,
    # directives and the header's board are kept (they are not configuration commands).
    keep = (st.ignored, st.notes, st.directives, st.directive_lines, st.board)
    fresh = ParseState(chip=st.chip, subframe=st.subframe, advanced=st.advanced)
    for f in dataclasses.fields(ParseState):
        setattr(st, f.name, getattr(fresh, f.name))
    st.ignored, st.notes, st.directives, st.directive_lines, st.board = keep


def control(st: ParseState, ln: Line) -> None:
    """sensorStop / sensorStart: no configuration content."""


def unsupported(reason: str) -> Callable[[ParseState, Line], None]:
    def handler(st: ParseState, ln: Line) -> None:
        raise ln.fail(f"not supported: {reason}")
    return handler
