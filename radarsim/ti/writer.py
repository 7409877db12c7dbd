"""`to_ti_cfg`: a `RadarConfig` (or `TiProfile`) as the TI CLI profile of its chip, such that
``from_ti_cfg(to_ti_cfg(cfg)) == cfg`` exactly; what TI cannot say travels as directives."""
from __future__ import annotations

import json
from typing import Any, Iterable, Mapping

from core.errors import BadInput

from ..boards import get_board
from ..chips import ADC_MODES
from ..mimo import TiFrame
from ..radar_config import RadarConfig
from ..radar_parts import FIELDS
from . import fast_slow
from .families import DEMO_FAMILIES
from .parse_state import TI_DEFAULT_OVERRIDES, TI_FIELDS
from .profile import DEFAULT_FRAME_PERIOD_S, TiCfar, TiProfile
from .reader import parse_ti_cfg
from .syntax import fmt_decimal

__all__ = ["to_ti_cfg", "processing_lines"]


def to_channel_bits(line: str, radar: RadarConfig) -> str:
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


def _ti_default(name: str) -> Any:
    if name in TI_DEFAULT_OVERRIDES:
        return TI_DEFAULT_OVERRIDES[name]
    f = next(f for f in FIELDS.values() if f.name == name)
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
            + f" 0.5 {fmt_decimal(dz)}")


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
        The radar (a `TiProfile` also supplies frame period, frame count and CFAR; an
        advanced-frame profile is written with ``advFrameCfg`` and a ``subFrameCfg``, profile,
        chirps and ``cfarCfg`` lines per sub-frame).
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

    Examples
    --------
    >>> import radarsim
    >>> from radarsim.ti import from_ti_cfg, to_ti_cfg
    >>> cfg = radarsim.presets.r79_tdma()
    >>> text = to_ti_cfg(cfg, frame_period_s=0.1)
    >>> "frameCfg 0 3 192 0 384 100 1 0" in text, from_ti_cfg(text) == cfg
    (True, True)
    """
    profile = cfg if isinstance(cfg, TiProfile) else None
    if profile is not None and profile.is_advanced:
        return _advanced_text(profile, n_frames, extra_lines, comments)
    pair = None if profile else fast_slow.advanced_profile(cfg, frame_period_s, n_frames or 0)
    if pair is not None:  # two chirp periods: an advanced frame of two sub-frames
        text = _advanced_text(pair, n_frames, extra_lines, comments)
        if parse_ti_cfg(text).radar != cfg:
            raise BadInput(f"mimo={cfg.mimo!r}: idle times {cfg.scheme.idle_times_s(cfg)} s "
                           "do not survive TI's 10 ns idle-time grid as this scheme's pair")
        return text
    radar = profile.radar if profile else cfg
    if frame_period_s is None:
        frame_period_s = profile.frame_period_s if profile else DEFAULT_FRAME_PERIOD_S
    if n_frames is None:
        n_frames = profile.n_frames if profile else 0
    if cfar is None:
        cfar = profile.cfar if profile else {}
    cfars = list(cfar.values()) if isinstance(cfar, Mapping) else list(cfar)
    out = _header_lines(radar, comments)
    out += _command_lines(radar, frame_period_s, n_frames)
    out += [c.to_cli(sdk3=not radar.chip_spec.mcu_plus_sdk) for c in cfars]
    if profile is not None:
        out += processing_lines(profile)
    out += list(extra_lines)
    text = _with_directives(radar, out)
    back = parse_ti_cfg(text).radar
    if back != radar:  # pragma: no cover - guards the exact-round-trip promise
        raise RuntimeError(f"to_ti_cfg round trip failed: {back} != {radar}")
    return text


def _header_lines(radar: RadarConfig, comments: Iterable[str]) -> list[str]:
    """Comment header: writer, TI Visualizer's ``% Platform:`` line, a one-line summary."""
    chip = radar.chip_spec
    kind = "complex (I/Q)" if radar.is_complex else "real"
    return [
        f"% {chip.name} profile written by radarsim.ti.to_ti_cfg "
        f"({'mmWave MCU+ SDK' if chip.mcu_plus_sdk else 'mmWave SDK 3.x'} CLI).",
        f"% Platform:{get_board(radar.board).ti_platform or chip.ti_platform}",
        f"% {radar.mimo.upper()} {radar.n_tx} Tx x {radar.n_rx} Rx, {radar.n_chirps} chirps of "
        f"{radar.chirp_period_s * 1e6:.6g} us, {radar.n_samples} {kind} samples at "
        f"{radar.adc_rate_sps / 1e6:g} Msps: range resolution {radar.range_resolution_m:.3f} m, "
        f"max range {radar.max_range_m:.1f} m, Vmax +/-{radar.max_unambiguous_velocity_mps:.2f}"
        " m/s.",
        *(c if c.startswith("%") else f"% {c}" for c in comments),
    ]


def _command_lines(radar: RadarConfig, frame_period_s: float, n_frames: int) -> list[str]:
    """The CLI commands from sensorStop to the frame (and antGeometryCfg on MCU+ chips)."""
    chip = radar.chip_spec
    # The scheme's loop over the logical Tx 1..n_tx (radarsim.mimo), mapped onto the chip
    # channels `tx_channels` below.
    ti_frame = _fitted_loop(radar, radar.scheme.to_ti(radar, radar.n_tx))
    per_loop = ti_frame.chirps_per_loop
    loops = radar.n_chirps // per_loop
    if loops > chip.max_loops:
        raise BadInput(f"n_chirps={radar.n_chirps}: {loops} loops of {per_loop} chirps "
                       f"exceed the {chip.name} frame limit of {chip.max_loops} loops")
    rx_mask = sum(1 << (c - 1) for c in radar.rx_channels)
    tx_mask = sum(1 << (c - 1) for c in radar.tx_channels)  # logical Tx k -> TI txEnable bit
    mcu_plus = chip.mcu_plus_sdk
    idle_us = fmt_decimal(radar.idle_time_s, -6)
    ramp_us = fmt_decimal(radar.ramp_end_time_s, -6)
    fmt = ADC_MODES[radar.adc_mode].ti_code
    words = radar.n_samples * (2 if radar.is_complex else 1)  # rlFrameCfg_t: 16-bit words
    out = [
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
        f"profileCfg 0 {fmt_decimal(radar.start_freq_hz, 9)} {idle_us} "
        f"{fmt_decimal(radar.adc_start_time_s, -6)} {ramp_us} 0 0 "
        f"{fmt_decimal(radar.slope_hz_per_s, 12)} 0 {radar.n_samples} "
        f"{fmt_decimal(radar.adc_rate_sps, 3)} 0 0 42",
    ]
    out += [to_channel_bits(line, radar) for line in ti_frame.chirp_lines]
    out.append(f"frameCfg 0 {per_loop - 1} {loops} {n_frames} "
               + (f"{words} " if mcu_plus else "")
               + f"{fmt_decimal(frame_period_s, -3)} 1 0")
    out += [to_channel_bits(line, radar) for line in ti_frame.extra_lines]
    geometry = _ant_geometry_line(radar)
    if geometry is not None and mcu_plus:
        out.append(geometry)
    return out


def _fitted_loop(radar: RadarConfig, frame: TiFrame) -> TiFrame:
    """`frame` with its sequence repeated the fewest times per loop that bring the loop count
    within the chip's (`TiFrame.repeatable` schemes only; 512 TDMA chirps of 2 Tx: 4 chirps x
    128 loops, the form of TI's own xWR18xx occupancy-detection profile)."""
    chip = radar.chip_spec
    per_loop = frame.chirps_per_loop
    if not frame.repeatable or radar.n_chirps // per_loop <= chip.max_loops:
        return frame
    fits = [k for k in range(2, chip.max_chirp_defs // per_loop + 1)
            if radar.n_chirps % (k * per_loop) == 0
            and radar.n_chirps // (k * per_loop) <= chip.max_loops]
    if not fits:
        return frame
    k = fits[0]
    lines = []
    for rep in range(k):
        for line in frame.chirp_lines:
            cmd, start, end, *rest = line.split()
            lines.append(" ".join([cmd, str(int(start) + rep * per_loop),
                                   str(int(end) + rep * per_loop), *rest]))
    return frame._replace(chirps_per_loop=k * per_loop, chirp_lines=tuple(lines))


def _with_directives(radar: RadarConfig, out: list[str]) -> str:
    """The profile text with ``% radarsim:`` directives after the header for every field a
    plain read of the commands gets wrong (what TI cannot say)."""
    body = out + ["sensorStart"]
    plain = parse_ti_cfg("\n".join(body) + "\n").parts[0].radar  # advanced: sub-frame 0's
    directives = []
    for f in FIELDS.values():
        if f.name in TI_FIELDS:
            continue
        if getattr(plain, f.name) != getattr(radar, f.name):
            directives.append(f"% radarsim: {f.name} = {_json_value(getattr(radar, f.name))}")
    n_head = next(i for i, line in enumerate(out) if not line.startswith("%"))
    return "\n".join(out[:n_head] + directives + body[n_head:]) + "\n"


def _advanced_text(profile: TiProfile, n_frames: int | None, extra_lines: Iterable[str],
                   comments: Iterable[str]) -> str:
    """An advanced-frame profile (``dfeDataOutputMode 3``): sub-frame k's chirp profile is
    profileCfg k, its chirps follow the previous sub-frames' in the chirp table, its
    ``subFrameCfg`` keeps its burst and sub-frame periods, its CFAR lines carry index k."""
    parts = profile.parts
    shared = [f.name for f in FIELDS.values()
              if f.name not in TI_FIELDS | _SUBFRAME_FIELDS]
    for part in parts[1:]:
        differ = [n for n in shared + ["tx_channels", "rx_channels", "adc_mode"]
                  if getattr(part.radar, n) != getattr(parts[0].radar, n)]
        if differ:
            raise BadInput(f"sub-frame {part.subframe_index} differs from sub-frame 0 in "
                           f"{differ}: sub-frames share the chip's channels, ADC format and "
                           "model settings")
    n_frames = profile.n_frames if n_frames is None else n_frames
    head, body, tail = [], [], []
    next_chirp = 0
    for k, part in enumerate(parts):
        lines = _command_lines(part.radar, profile.frame_period_s, 0)
        i_prof = next(i for i, s in enumerate(lines) if s.startswith("profileCfg"))
        i_frame = next(i for i, s in enumerate(lines) if s.startswith("frameCfg"))
        if k == 0:
            head = [s.replace("dfeDataOutputMode 1", "dfeDataOutputMode 3")
                    for s in lines[:i_prof] if not s.startswith("adcbufCfg")]
            tail = lines[i_frame + 1:]
        adcbuf = next(s for s in lines if s.startswith("adcbufCfg")).split()
        body.append(" ".join(["adcbufCfg", str(k), *adcbuf[2:]]))
        prof = lines[i_prof].split()
        body.append(" ".join(["profileCfg", str(k), *prof[2:]]))
        chirps = [s.split() for s in lines[i_prof + 1:i_frame]]
        for c in chirps:
            a, b = int(c[1]) + next_chirp, int(c[2]) + next_chirp
            body.append(" ".join(["chirpCfg", str(a), str(b), str(k), *c[4:]]))
        n_per_loop = int(lines[i_frame].split()[2]) + 1
        loops = part.radar.n_chirps // n_per_loop
        burst = part.burst_period_s or part.subframe_period_s
        body.append(f"subFrameCfg {k} 0 {next_chirp} {n_per_loop} {loops} "
                    f"{fmt_decimal(burst, -3)} 0 1 1 {fmt_decimal(part.subframe_period_s, -3)}")
        sdk3 = not part.radar.chip_spec.mcu_plus_sdk
        body += [c.to_cli(sdk3=sdk3).replace("cfarCfg -1 ", f"cfarCfg {k} ", 1)
                 for c in part.cfar.values()]
        body += ["%proc " + s for s in processing_lines(part, k)]
        next_chirp += n_per_loop
    adv = f"advFrameCfg {len(parts)} 0 {n_frames} 1 0"
    if parts[0].radar.chip_spec.mcu_plus_sdk:
        adv += f" {len(parts)}"
    out = _header_lines(parts[0].radar, comments) + head
    out += [s for s in body if not s.startswith(("subFrameCfg", "cfarCfg", "%proc "))]
    out += [adv] + [s for s in body if s.startswith("subFrameCfg")] + tail
    out += [s for s in body if s.startswith("cfarCfg")]
    out += [s[len("%proc "):] for s in body if s.startswith("%proc ")] + list(extra_lines)
    text = _with_directives(parts[0].radar, out)
    back = parse_ti_cfg(text)
    if tuple(p.radar for p in back.parts) != tuple(p.radar for p in parts):  # pragma: no cover
        raise RuntimeError("to_ti_cfg round trip of the advanced frame failed")
    return text


# RadarConfig fields a sub-frame's own profileCfg / chirps set (they may differ by sub-frame).
_SUBFRAME_FIELDS = frozenset({"chirp_period_s"})


def processing_lines(profile: TiProfile, subframe: int = -1) -> list[str]:
    """The processing commands of a profile's demo family that express its `processing`
    values (`radarsim.ti.families`): what the file said, so a written profile means the same.
    A value at the family's default when absent is written too (explicit is clearer)."""
    fam = DEMO_FAMILIES[profile.demo_family] if profile.demo_family else None
    p = profile.processing
    if fam is None:
        return []
    sf = str(subframe)
    out = []
    if fam.has("extendedMaxVelocity") and "tdma_disambiguation" in p:
        out.append(f"extendedMaxVelocity {sf} {int(bool(p['tdma_disambiguation']))}")
    if fam.has("clutterRemoval") and "clutter_removal" in p:
        out.append(f"clutterRemoval {sf} {int(bool(p['clutter_removal']))}")
    if fam.has("compressionCfg") and "compression" in p:
        out.append(f"compressionCfg {sf} {int(bool(p['compression']))} 0 "
                   f"{fmt_decimal(p.get('compression_ratio', 0.5))} "
                   f"{p.get('compression_range_bins_per_block', 8)}")
    if fam.has("intfMitigCfg") and p.get("interference_mitigation"):
        out.append(f"intfMitigCfg {sf} {int(p['intf_mag_snr_db'])} "
                   f"{int(p['intf_magdiff_snr_db'])}")
    db = p.get("azimuth_sidelobe_db")
    if fam.has("multiObjBeamForming") and "azimuth_sidelobe_db" in p:
        # threshold = magnitude ratio, 6 significant digits (TI's profiles give 1-2).
        out.append(f"multiObjBeamForming {sf} 1 "
                   f"{'0' if db is None else format(10 ** (-db / 20), '.6g')}")
    for name, direction in (("range_fov_m", 0), ("velocity_fov_mps", 1)):
        if fam.has("cfarFovCfg") and p.get(name) is not None:
            lo, hi = p[name]
            out.append(f"cfarFovCfg {sf} {direction} {fmt_decimal(lo)} {fmt_decimal(hi)}")
    if fam.has("aoaFovCfg") and p.get("azimuth_fov_deg") is not None:
        (a0, a1), (e0, e1) = p["azimuth_fov_deg"], p["elevation_fov_deg"]
        out.append("aoaFovCfg " + " ".join([sf] + [fmt_decimal(v) for v in (a0, a1, e0, e1)]))
    if fam.has("calibDcRangeSig") and profile.dc_range_signature is not None:
        neg, pos, num_avg, _ = profile.dc_range_signature
        out.append(f"calibDcRangeSig {sf} 1 {neg} {pos} {num_avg}")
    if subframe in (-1, 0):  # one line for the whole frame, written with sub-frame 0's
        out += _calibration_lines(fam, p)
    return out


def _calibration_lines(fam, p) -> list[str]:
    """The channel correction as the family's demo takes it (`radarsim.ti.board_calibration`): the
    DDM demo's ``antennaCalibParams`` (Im, Re per virtual antenna), a range bias then in a
    ``compRangeBiasAndRxChanPhase`` with identity coefficients; the TDM demos'
    ``compRangeBiasAndRxChanPhase`` for both. Nothing without coefficients (as before)."""
    comp, bias = p.get("channel_comp"), p.get("range_bias_m", 0.0)
    if comp is None:
        return []
    out = []
    if fam.has("antennaCalibParams"):
        out.append("antennaCalibParams " + " ".join(
            fmt_decimal(v) for re, im in comp for v in (im, re)))
        if not bias:
            return out
        comp = tuple((1.0, 0.0) for _ in comp)
    if fam.has("compRangeBiasAndRxChanPhase"):
        out.append("compRangeBiasAndRxChanPhase " + " ".join(
            [fmt_decimal(bias)] + [fmt_decimal(v) for pair in comp for v in pair]))
    return out
