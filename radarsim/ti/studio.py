"""mmWave Studio setups read as profiles: the LogFile's ``API:...`` lines and the setup JSON.

Most public DCA1000 captures come with the mmWave Studio setup that recorded them (front ends
such as the AWR1243 / AWR2243 / xWR1443 have no SDK demo, so no CLI profile), in one of two
forms:

LogFile (``LogFile.txt``, one line per mmWaveLink call, values in mmWaveLink units)
    ``<time>: API:ChannelConfig,<rxChannelEn>,<txChannelEn>,<cascading>,`` (rlChanCfg_t);
    ``API:AdcOutConfig,<adcBits>,<adcOutFmt>,`` (rlAdcOutCfg_t);
    ``API:ProfileConfig,<profileId>,<startFreqConst>,<idleTimeConst>,<adcStartTimeConst>,
    <rampEndTime>,<txOutPowerBackoffCode>,<txPhaseShifter>,<freqSlopeConst>,<txStartTime>,
    <numAdcSamples>,<digOutSampleRate ksps>,<hpfCornerFreq1>,<hpfCornerFreq2>,<rxGain>,``
    (rlProfileCfg_t: start frequency in 3.6 GHz / 2^26 steps at 77 GHz, 2.7 GHz / 2^26 at
    60 GHz; times in 10 ns; slope in 3.6e9 x 900 / 2^26 Hz per us steps, 2.7e9 x 900 / 2^26 at
    60 GHz); ``API:ChirpConfig,<start>,<end>,<profileId>,<startFreqVar>,<freqSlopeVar>,
    <idleTimeVar>,<adcStartTimeVar>,<txEnable>,``; ``API:FrameConfig,<chirpStart>,<chirpEnd>,
    <numFrames>,<numLoops>,<framePeriodicity in 5 ns>,...`` (mmWave Studio ``ar1.FrameConfig``
    order); ``API:DataFmtConfig,<rxChannelEn>,<adcBits>,<adcFmt>,<iqSwap>,<chInterleave>,...``;
    ``API:select_chip_version,<chip>,``. mmWaveLink ``rl_sensor.h`` gives the units
    (mmWave Radar Interface Control Document, rlProfileCfg_t / rlFrameCfg_t).
Setup JSON (``*.mmwave.json``, what TI's ``rawDataReader.m`` reads)
    ``mmWaveDevices[0].rfConfig``: ``rlChanCfg_t`` (hex masks), ``rlAdcOutCfg_t.fmt``,
    ``rlProfiles[].rlProfileCfg_t`` (``startFreqConst_GHz``, ``idleTimeConst_usec``, ...,
    ``freqSlopeConst_MHz_usec``, ``digOutSampleRate`` ksps), ``rlChirps[].rlChirpCfg_t``,
    ``rlFrameCfg_t`` (``framePeriodicity_msec``), and ``rawDataCaptureConfig``'s
    ``rlDevDataFmtCfg_t.chInterleave``; an advanced frame as ``rlAdvFrameCfg_t.frameSeq``
    (``subFrameCfg[k].rlSubFrameCfg_t``, periods in ms; used when ``rlFrameCfg_t`` is absent
    or ``waveformType`` names an advanced frame); ``mmWaveDevices`` with several entries is a
    cascade.

Both are turned into the equivalent CLI commands and read by `parse_ti_cfg` (one reader, one
set of checks); an error names the LogFile line or the JSON key it came from. The chip comes
from ``select_chip_version`` / the JSON ``mmWaveDevice`` name when known, else from the
commands (`chip_inference`).
"""
from __future__ import annotations

import json
import os
import re
from decimal import Decimal
from typing import Any

from .reader import _read_source, parse_ti_cfg
from .profile import TiProfile
from .syntax import fmt_decimal

__all__ = ["parse_studio_log", "parse_studio_json", "parse_setup", "is_studio_log"]

_API_RE = re.compile(r"API:(\w+),([^\r\n]*)")
_LINE_RE = re.compile(r"^line (\d+)")
#: mmWaveLink start-frequency and slope steps: 3.6 GHz / 2^26 (76-81 GHz), 2.7 GHz / 2^26
#: (60-64 GHz devices); the slope step is 900 x that per us.
_FREQ_STEP = {77: Decimal("3.6e9") / 2 ** 26, 60: Decimal("2.7e9") / 2 ** 26}


def is_studio_log(text: str) -> bool:
    """Whether a text is an mmWave Studio LogFile (it holds ``API:ProfileConfig`` calls)."""
    return "API:ProfileConfig" in text


def _ints(payload: str) -> list[int]:
    out = []
    for tok in payload.split(","):
        tok = tok.strip()
        if tok:
            out.append(int(tok, 0))
    return out


def _fail(msg: str) -> ValueError:
    return ValueError(msg)


def _chip_header(chip: str | None) -> list[str]:
    return [f"% Platform:{chip}"] if chip else []


def parse_studio_log(path_or_text: str | os.PathLike) -> TiProfile:
    """The profile of an mmWave Studio LogFile (its last configuration before a frame).

    Raises
    ------
    ValueError
        Naming the LogFile line (and the call) of a malformed or refused value, or the call
        that is missing.
    """
    text = _read_source(path_or_text)
    calls: list[tuple[int, str, list[int]]] = []
    chip = None
    for no, raw in enumerate(text.splitlines(), start=1):
        m = _API_RE.search(raw)
        if not m:
            continue
        name, payload = m.group(1), m.group(2)
        if name.lower() in ("select_chip_version", "selectchipversion"):
            chip = payload.split(",")[0].strip() or None
            continue
        if name in ("ChannelConfig", "AdcOutConfig", "ProfileConfig", "ChirpConfig",
                    "FrameConfig", "DataFmtConfig"):
            try:
                calls.append((no, name, _ints(payload)))
            except ValueError:
                raise _fail(f"LogFile line {no} (API:{name}): {payload.strip()!r} is not a "
                            "list of integers") from None
    # The last configuration: from the last ChannelConfig on.
    starts = [i for i, (_, name, _) in enumerate(calls) if name == "ChannelConfig"]
    if not starts:
        raise _fail("LogFile: no API:ChannelConfig call (not an mmWave Studio setup log?)")
    calls = calls[starts[-1]:]
    band = 60 if chip and "68" in chip else 77
    lines: list[tuple[str, str]] = []   # (CLI line, where it came from)
    for no, name, v in calls:
        where = f"LogFile line {no} (API:{name})"
        lines += [(s, where) for s in _log_call(name, v, band, where)]
    return _parse_lines(lines, chip, "LogFile")


def _log_call(name: str, v: list[int], band: int, where: str) -> list[str]:
    need = {"ChannelConfig": 3, "AdcOutConfig": 2, "ProfileConfig": 14, "ChirpConfig": 8,
            "FrameConfig": 5, "DataFmtConfig": 5}[name]
    if len(v) < need:
        raise _fail(f"{where}: {len(v)} values, expected at least {need}")
    if name == "ChannelConfig":
        return [f"channelCfg {v[0]} {v[1]} {v[2]}"]
    if name == "AdcOutConfig":
        return [f"adcCfg {v[0]} {v[1]}"]
    if name == "ProfileConfig":
        step = _FREQ_STEP[band]
        ghz = fmt_decimal(Decimal(v[1]) * step / Decimal(10) ** 9)
        slope = fmt_decimal(Decimal(v[7]) * step * 900 / Decimal(10) ** 6)  # Hz/us -> MHz/us
        us = [fmt_decimal(Decimal(x) / 100) for x in (v[2], v[3], v[4], v[8])]
        return [f"profileCfg {v[0]} {ghz} {us[0]} {us[1]} {us[2]} {v[5]} {v[6]} {slope} "
                f"{us[3]} {v[9]} {v[10]} {v[11]} {v[12]} {v[13]}"]
    if name == "ChirpConfig":
        if any(v[3:7]):
            raise _fail(f"{where}: per-chirp variations {v[3:7]} are not modelled; use 0")
        return [f"chirpCfg {v[0]} {v[1]} {v[2]} 0 0 0 0 {v[7]}"]
    if name == "FrameConfig":
        period_ms = fmt_decimal(Decimal(v[4]) * 5 / Decimal(10) ** 6)
        return [f"frameCfg {v[0]} {v[1]} {v[3]} {v[2]} {period_ms} 1 0"]
    # DataFmtConfig: rxChannelEn, adcBits, adcFmt, iqSwap, chInterleave (0 interleaved).
    real = 1 if v[2] == 0 else 0
    return [f"adcbufCfg -1 {real} {v[3]} {v[4]} 1"]


def parse_studio_json(path_or_text: str | os.PathLike, chip: str | None = None) -> TiProfile:
    """The profile of an mmWave Studio setup JSON (``mmWaveDevices[0]``). The JSON does not
    name the chip: give `chip` (e.g. "AWR1243"), else it is inferred from the commands.

    Raises
    ------
    ValueError
        Naming the JSON key of a missing or malformed value; for a cascade setup (several
        devices), which has no single-chip `RadarConfig`.
    """
    text = _read_source(path_or_text)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise _fail(f"setup JSON: not JSON ({exc})") from None
    try:
        devices = data["mmWaveDevices"]
        dev = devices[0]
        rf = dev["rfConfig"]
    except (KeyError, IndexError, TypeError):
        raise _fail("setup JSON: no mmWaveDevices[0].rfConfig (not an mmWave Studio setup?)") \
            from None
    if len(devices) > 1:
        raise _fail(f"setup JSON: mmWaveDevices has {len(devices)} devices (a cascade); a "
                    "cascade of chips has no single-chip RadarConfig")
    chip = chip or _json_chip(dev)
    lines: list[tuple[str, str]] = []

    def get(obj: Any, key: str, where: str) -> Any:
        try:
            return obj[key]
        except (KeyError, TypeError):
            raise _fail(f"setup JSON: missing {where}.{key}") from None

    def num(x: Any) -> int:
        return int(x, 16) if isinstance(x, str) and x.lower().startswith("0x") else int(x)

    ch = get(rf, "rlChanCfg_t", "rfConfig")
    lines.append((f"channelCfg {num(get(ch, 'rxChannelEn', 'rlChanCfg_t'))} "
                  f"{num(get(ch, 'txChannelEn', 'rlChanCfg_t'))} 0", "rfConfig.rlChanCfg_t"))
    fmt = get(get(rf, "rlAdcOutCfg_t", "rfConfig"), "fmt", "rlAdcOutCfg_t")
    lines.append((f"adcCfg {num(get(fmt, 'b2AdcBits', 'fmt'))} "
                  f"{num(get(fmt, 'b2AdcOutFmt', 'fmt'))}", "rfConfig.rlAdcOutCfg_t"))
    data_fmt = (dev.get("rawDataCaptureConfig") or {}).get("rlDevDataFmtCfg_t")
    if isinstance(data_fmt, dict) and "chInterleave" in data_fmt:
        real = 1 if num(get(fmt, "b2AdcOutFmt", "fmt")) == 0 else 0
        lines.append((f"adcbufCfg -1 {real} {num(data_fmt.get('iqSwapSel', 0))} "
                      f"{num(data_fmt['chInterleave'])} 1", "rlDevDataFmtCfg_t"))
    for k, item in enumerate(get(rf, "rlProfiles", "rfConfig")):
        p = get(item, "rlProfileCfg_t", f"rlProfiles[{k}]")
        w = f"rlProfiles[{k}].rlProfileCfg_t"

        def d(key: str) -> str:
            return fmt_decimal(Decimal(str(get(p, key, w))))
        lines.append((f"profileCfg {num(get(p, 'profileId', w))} {d('startFreqConst_GHz')} "
                      f"{d('idleTimeConst_usec')} {d('adcStartTimeConst_usec')} "
                      f"{d('rampEndTime_usec')} {num(get(p, 'txOutPowerBackoffCode', w))} "
                      f"{num(get(p, 'txPhaseShifter', w))} {d('freqSlopeConst_MHz_usec')} "
                      f"{d('txStartTime_usec')} {num(get(p, 'numAdcSamples', w))} "
                      f"{int(Decimal(str(get(p, 'digOutSampleRate', w))))} "
                      f"{num(get(p, 'hpfCornerFreq1', w))} {num(get(p, 'hpfCornerFreq2', w))} "
                      f"{num(get(p, 'rxGain_dB', w))}", w))
    for k, item in enumerate(get(rf, "rlChirps", "rfConfig")):
        c = get(item, "rlChirpCfg_t", f"rlChirps[{k}]")
        w = f"rlChirps[{k}].rlChirpCfg_t"
        var = [Decimal(str(c.get(key, 0))) for key in ("startFreqVar_MHz",
                                                       "freqSlopeVar_KHz_usec",
                                                       "idleTimeVar_usec",
                                                       "adcStartTimeVar_usec")]
        if any(var):
            raise _fail(f"setup JSON {w}: per-chirp variations are not modelled; use 0")
        lines.append((f"chirpCfg {num(get(c, 'chirpStartIdx', w))} "
                      f"{num(get(c, 'chirpEndIdx', w))} {num(get(c, 'profileId', w))} 0 0 0 0 "
                      f"{num(get(c, 'txEnable', w))}", w))
    advanced = "rlAdvFrameCfg_t" in rf and (
        "rlFrameCfg_t" not in rf or "advanced" in str(rf.get("waveformType", "")).lower())
    if advanced:
        lines += _json_advanced_frame(get(rf, "rlAdvFrameCfg_t", "rfConfig"), get, num)
        return _parse_lines(lines, chip, "setup JSON", mode=3)
    f = get(rf, "rlFrameCfg_t", "rfConfig")
    w = "rfConfig.rlFrameCfg_t"
    lines.append((f"frameCfg {num(get(f, 'chirpStartIdx', w))} {num(get(f, 'chirpEndIdx', w))} "
                  f"{num(get(f, 'numLoops', w))} {num(get(f, 'numFrames', w))} "
                  f"{fmt_decimal(Decimal(str(get(f, 'framePeriodicity_msec', w))))} 1 0", w))
    return _parse_lines(lines, chip, "setup JSON")


def _json_advanced_frame(adv: dict, get, num) -> list[tuple[str, str]]:
    """``rlAdvFrameCfg_t`` (``frameSeq`` with ``subFrameCfg[k].rlSubFrameCfg_t``) as
    advFrameCfg / subFrameCfg lines (`radarsim.ti.advanced`)."""
    w = "rlAdvFrameCfg_t.frameSeq"
    seq = get(adv, "frameSeq", "rlAdvFrameCfg_t")
    subs = get(seq, "subFrameCfg", w)
    n_sub = num(seq.get("numOfSubFrames", len(subs)))
    out = [(f"advFrameCfg {n_sub} {num(seq.get('forceProfile', 0))} "
            f"{num(get(seq, 'numFrames', w))} 1 0", w)]
    for k, item in enumerate(subs[:n_sub]):
        ws = f"{w}.subFrameCfg[{k}].rlSubFrameCfg_t"
        s = get(item, "rlSubFrameCfg_t", f"{w}.subFrameCfg[{k}]")

        def ms(key: str) -> str:
            return fmt_decimal(Decimal(str(get(s, key, ws))))
        out.append((f"subFrameCfg {k} {num(get(s, 'forceProfileIdx', ws))} "
                    f"{num(get(s, 'chirpStartIdx', ws))} {num(get(s, 'numOfChirps', ws))} "
                    f"{num(get(s, 'numLoops', ws))} {ms('burstPeriodicity_msec')} "
                    f"{num(get(s, 'chirpStartIdxOffset', ws))} {num(get(s, 'numOfBurst', ws))} "
                    f"{num(get(s, 'numOfBurstLoops', ws))} {ms('subFramePeriodicity_msec')}",
                    ws))
    return out


def _json_chip(dev: dict) -> str | None:
    """A device name some setup writers add to the device entry (not TI's own field)."""
    val = dev.get("mmWaveDevice")
    return val if isinstance(val, str) and val else None


def _parse_lines(lines: list[tuple[str, str]], chip: str | None, kind: str,
                 mode: int = 1) -> TiProfile:
    """Read the CLI lines made from a setup (`mode`: dfeDataOutputMode, 3 for advanced
    frames); an error names the setup line or key."""
    head = _chip_header(chip)
    cli = head + ["sensorStop", "flushCfg", f"dfeDataOutputMode {mode}"] + \
        [s for s, _ in lines] + ["sensorStart"]
    try:
        prof = parse_ti_cfg("\n".join(cli) + "\n")
    except ValueError as exc:
        msg = str(exc)
        m = _LINE_RE.match(msg)
        if m:
            k = int(m.group(1)) - len(head) - 4
            where = lines[k][1] if 0 <= k < len(lines) else kind
            msg = f"{where}: {msg.split(': ', 1)[-1]}"
        raise ValueError(f"mmWave Studio {kind}: {msg}") from None
    note = f"read from an mmWave Studio {kind} (converted to CLI commands)"
    return _with_note(prof, note)


def _with_note(prof: TiProfile, note: str) -> TiProfile:
    import dataclasses
    return dataclasses.replace(prof, notes=prof.notes + (note,),
                               subframes=tuple(dataclasses.replace(p, notes=p.notes + (note,))
                                               for p in prof.subframes))


def parse_setup(path_or_text: str | os.PathLike) -> TiProfile:
    """Any setup a user brings: a TI CLI profile (.cfg), an mmWave Studio LogFile or an
    mmWave Studio setup JSON, told apart by content."""
    text = _read_source(path_or_text)
    if text.lstrip().startswith("{"):
        return parse_studio_json(text)
    if is_studio_log(text):
        return parse_studio_log(text)
    return parse_ti_cfg(text)
