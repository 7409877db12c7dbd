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

import dataclasses
import json
import math
import os
import re
from decimal import Decimal
from typing import Any

from core.errors import BadInput

from .chip_inference import PLATFORMS
from .profile import TiProfile
from .reader import parse_ti_cfg, read_source
from .syntax import code_part, fmt_decimal

__all__ = ["parse_studio_log", "parse_studio_json", "parse_setup", "is_studio_log",
           "setup_kind"]

_API_RE = re.compile(r"API:(\w+),([^\r\n]*)")
_LINE_RE = re.compile(r"^line (\d+)")
#: mmWaveLink start-frequency and slope steps: 3.6 GHz / 2^26 (76-81 GHz), 2.7 GHz / 2^26
#: (60-64 GHz devices); the slope step is 900 x that per us.
_FREQ_STEP = {77: Decimal("3.6e9") / 2 ** 26, 60: Decimal("2.7e9") / 2 ** 26}


def setup_kind(text: str) -> str:
    r"""What a setup text is, decided here only and from what is read, never from comments:
    ``"studio_json"`` (a JSON object), ``"studio_log"`` (a line that is no comment makes an
    ``API:<call>,`` call: a LogFile that lacks its ProfileConfig is still one, and
    `parse_studio_log` names what it lacks) or ``"cli_profile"`` (a TI CLI .cfg). An SDK
    profile whose ``%`` comments quote the LogFile it was written from stays a CLI profile.

    Examples
    --------
    >>> setup_kind("% API:ProfileConfig,0,1435384036 (source)\nsensorStop\n")
    'cli_profile'
    >>> setup_kind("10:00:00:003: API:ProfileConfig,0,1435384036,\n")
    'studio_log'
    """
    if text.lstrip().startswith("{"):
        return "studio_json"
    for raw in text.splitlines():
        if _API_RE.search(code_part(raw)):
            return "studio_log"
    return "cli_profile"


def is_studio_log(text: str) -> bool:
    """Whether a text is an mmWave Studio LogFile (`setup_kind`)."""
    return setup_kind(text) == "studio_log"


def _ints(payload: str) -> list[int]:
    out = []
    for tok in payload.split(","):
        tok = tok.strip()
        if tok:
            out.append(int(tok, 0))
    return out


def _fail(msg: str) -> BadInput:
    return BadInput(msg)


def _get(obj: Any, key: str, where: str) -> Any:
    """``obj[key]`` of a setup JSON, or a ValueError naming the missing key."""
    try:
        return obj[key]
    except (KeyError, TypeError):
        raise _fail(f"setup JSON: missing {where}.{key}") from None


def _bad(where: str, key: str, value: Any, want: str) -> BadInput:
    text = repr(value)
    text = text if len(text) <= 40 else text[:37] + "..."
    return _fail(f"setup JSON: {where}.{key}={text} must be {want}")


def _int(obj: Any, key: str, where: str, default: Any = None) -> int:
    """``obj[key]``: a JSON integer (an integral number such as 10000.0 too) or a "0x..." hex
    string as Studio writes masks and codes; anything else (null, a list, true, 64.7, "abc")
    is refused naming the key, never truncated."""
    x = _get(obj, key, where) if default is None else obj.get(key, default)
    if isinstance(x, str) and re.fullmatch(r"0[xX][0-9a-fA-F]+", x.strip()):
        return int(x, 16)
    if isinstance(x, int) and not isinstance(x, bool):
        return x
    if isinstance(x, float) and math.isfinite(x) and x == int(x):
        return int(x)
    raise _bad(where, key, x, 'an integer (or a "0x..." hex string)')


def _dec(obj: Any, key: str, where: str, default: Any = None) -> str:
    """``obj[key]``, a finite JSON number, as exact decimal text (no float rounding on the
    way to the reader); anything else is refused naming the key."""
    x = _get(obj, key, where) if default is None else obj.get(key, default)
    if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
        raise _bad(where, key, x, "a finite number")
    return fmt_decimal(Decimal(str(x)))


def _list(obj: Any, key: str, where: str) -> list:
    """``obj[key]``, a JSON list (of the setup's profiles, chirps, sub-frames)."""
    x = _get(obj, key, where)
    if not isinstance(x, list):
        raise _bad(where, key, x, "a list")
    return x


def _known_chip(name: str, where: str) -> str:
    """The registered chip a setup names (Studio's ``select_chip_version`` spellings such as
    AR1243 too, `radarsim.ti.chip_inference.PLATFORMS`); an unknown name is refused, never
    replaced by a chip inferred from the commands."""
    key = name.strip().lower()
    chip = PLATFORMS.get(key) or PLATFORMS.get(key.split("_")[0])
    if chip is None:
        raise _fail(f"{where}: chip {name!r} is not one the harness knows (known: "
                    f"{', '.join(sorted(set(PLATFORMS.values())))})")
    return chip


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
    text = read_source(path_or_text)
    calls: list[tuple[int, str, list[int]]] = []
    chip = None
    for no, raw in enumerate(text.splitlines(), start=1):
        m = _API_RE.search(code_part(raw))  # a commented-out call is not a call
        if not m:
            continue
        name, payload = m.group(1), m.group(2)
        if name.lower() in ("select_chip_version", "selectchipversion"):
            named = payload.split(",")[0].strip()
            chip = _known_chip(named, f"LogFile line {no} (API:{name})") if named else None
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
    have = {name for _, name, _ in calls}
    lacking = [n for n in ("ProfileConfig", "ChirpConfig", "FrameConfig") if n not in have]
    if lacking:
        first = calls[0][0]
        raise _fail(f"LogFile: its last configuration (from line {first}, API:ChannelConfig) "
                    f"has no {', '.join('API:' + n for n in lacking)} call")
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
    text = read_source(path_or_text)
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
    chip = _known_chip(chip, "chip") if chip else _json_chip(dev)
    lines = _json_channels(rf, dev) + _json_chirps(rf)
    if "rlAdvFrameCfg_t" in rf and ("rlFrameCfg_t" not in rf
                                    or "advanced" in str(rf.get("waveformType", "")).lower()):
        lines += _json_advanced_frame(_get(rf, "rlAdvFrameCfg_t", "rfConfig"))
        return _parse_lines(lines, chip, "setup JSON", mode=3)
    f = _get(rf, "rlFrameCfg_t", "rfConfig")
    w = "rfConfig.rlFrameCfg_t"
    counts = " ".join(str(_int(f, key, w))
                      for key in ("chirpStartIdx", "chirpEndIdx", "numLoops", "numFrames"))
    lines.append((f"frameCfg {counts} {_dec(f, 'framePeriodicity_msec', w)} 1 0", w))
    return _parse_lines(lines, chip, "setup JSON")


def _json_channels(rf: dict, dev: dict) -> list[tuple[str, str]]:
    """channelCfg, adcCfg, adcbufCfg (from ``rawDataCaptureConfig``) and the profiles."""
    ch = _get(rf, "rlChanCfg_t", "rfConfig")
    out = [(f"channelCfg {_int(ch, 'rxChannelEn', 'rlChanCfg_t')} "
            f"{_int(ch, 'txChannelEn', 'rlChanCfg_t')} 0", "rfConfig.rlChanCfg_t")]
    fmt = _get(_get(rf, "rlAdcOutCfg_t", "rfConfig"), "fmt", "rlAdcOutCfg_t")
    adc_fmt = _int(fmt, "b2AdcOutFmt", "fmt")
    out.append((f"adcCfg {_int(fmt, 'b2AdcBits', 'fmt')} {adc_fmt}",
                "rfConfig.rlAdcOutCfg_t"))
    capture = dev.get("rawDataCaptureConfig")
    data_fmt = capture.get("rlDevDataFmtCfg_t") if isinstance(capture, dict) else None
    if isinstance(data_fmt, dict) and "chInterleave" in data_fmt:
        w = "rlDevDataFmtCfg_t"
        out.append((f"adcbufCfg -1 {1 if adc_fmt == 0 else 0} "
                    f"{_int(data_fmt, 'iqSwapSel', w, 0)} {_int(data_fmt, 'chInterleave', w)} 1",
                    w))
    for k, item in enumerate(_list(rf, "rlProfiles", "rfConfig")):
        out.append(_json_profile(_get(item, "rlProfileCfg_t", f"rlProfiles[{k}]"),
                                 f"rlProfiles[{k}].rlProfileCfg_t"))
    return out


def _json_chirps(rf: dict) -> list[tuple[str, str]]:
    """One chirpCfg per ``rlChirps[k].rlChirpCfg_t`` (per-chirp variations refused)."""
    out = []
    for k, item in enumerate(_list(rf, "rlChirps", "rfConfig")):
        c = _get(item, "rlChirpCfg_t", f"rlChirps[{k}]")
        w = f"rlChirps[{k}].rlChirpCfg_t"
        if any(Decimal(_dec(c, key, w, 0)) for key in (
                "startFreqVar_MHz", "freqSlopeVar_KHz_usec", "idleTimeVar_usec",
                "adcStartTimeVar_usec")):
            raise _fail(f"setup JSON {w}: per-chirp variations are not modelled; use 0")
        idx = " ".join(str(_int(c, key, w))
                       for key in ("chirpStartIdx", "chirpEndIdx", "profileId"))
        out.append((f"chirpCfg {idx} 0 0 0 0 {_int(c, 'txEnable', w)}", w))
    return out


def _json_advanced_frame(adv: dict) -> list[tuple[str, str]]:
    """``rlAdvFrameCfg_t`` (``frameSeq`` with ``subFrameCfg[k].rlSubFrameCfg_t``) as
    advFrameCfg / subFrameCfg lines (`radarsim.ti.advanced`)."""
    w = "rlAdvFrameCfg_t.frameSeq"
    seq = _get(adv, "frameSeq", "rlAdvFrameCfg_t")
    subs = _list(seq, "subFrameCfg", w)
    n_sub = _int(seq, "numOfSubFrames", w, len(subs))
    out = [(f"advFrameCfg {n_sub} {_int(seq, 'forceProfile', w, 0)} "
            f"{_int(seq, 'numFrames', w)} 1 0", w)]
    keys = ("forceProfileIdx", "chirpStartIdx", "numOfChirps", "numLoops")
    for k, item in enumerate(subs[:n_sub]):
        ws = f"{w}.subFrameCfg[{k}].rlSubFrameCfg_t"
        s = _get(item, "rlSubFrameCfg_t", f"{w}.subFrameCfg[{k}]")
        head = " ".join(str(_int(s, key, ws)) for key in keys)
        bursts = " ".join(str(_int(s, key, ws))
                          for key in ("chirpStartIdxOffset", "numOfBurst", "numOfBurstLoops"))
        out.append((f"subFrameCfg {k} {head} {_dec(s, 'burstPeriodicity_msec', ws)} {bursts} "
                    f"{_dec(s, 'subFramePeriodicity_msec', ws)}", ws))
    return out


def _json_profile(p: dict, w: str) -> tuple[str, str]:
    """One ``rlProfileCfg_t`` (times in us, GHz, MHz/us, ksps) as a profileCfg line."""
    ints = [_int(p, key, w) for key in ("profileId", "txOutPowerBackoffCode",
                                               "txPhaseShifter", "numAdcSamples",
                                               "hpfCornerFreq1", "hpfCornerFreq2", "rxGain_dB")]
    return (f"profileCfg {ints[0]} {_dec(p, 'startFreqConst_GHz', w)} "
            f"{_dec(p, 'idleTimeConst_usec', w)} {_dec(p, 'adcStartTimeConst_usec', w)} "
            f"{_dec(p, 'rampEndTime_usec', w)} {ints[1]} {ints[2]} "
            f"{_dec(p, 'freqSlopeConst_MHz_usec', w)} {_dec(p, 'txStartTime_usec', w)} "
            f"{ints[3]} {_int(p, 'digOutSampleRate', w)} "
            f"{ints[4]} {ints[5]} {ints[6]}", w)


def _json_chip(dev: dict) -> str | None:
    """A device name some setup writers add to the device entry (not TI's own field)."""
    val = dev.get("mmWaveDevice")
    if val is None or val == "":
        return None
    if not isinstance(val, str):
        raise _bad("mmWaveDevices[0]", "mmWaveDevice", val, "a chip name")
    return _known_chip(val, "setup JSON: mmWaveDevices[0].mmWaveDevice")


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
        raise BadInput(f"mmWave Studio {kind}: {msg}") from None
    note = f"read from an mmWave Studio {kind} (converted to CLI commands)"
    return _with_note(prof, note)


def _with_note(prof: TiProfile, note: str) -> TiProfile:
    return dataclasses.replace(prof, notes=prof.notes + (note,),
                               subframes=tuple(dataclasses.replace(p, notes=p.notes + (note,))
                                               for p in prof.subframes))


def parse_setup(path_or_text: str | os.PathLike) -> TiProfile:
    r"""Any setup a user brings: a TI CLI profile (.cfg), an mmWave Studio LogFile or an
    mmWave Studio setup JSON, told apart by content.

    Examples
    --------
    >>> from radarsim.ti import parse_setup
    >>> log = "\n".join([
    ...     "10:00:00:000: API:select_chip_version,AWR2243,0,",
    ...     "10:00:00:001: API:ChannelConfig,15,1,0,0,",
    ...     "10:00:00:002: API:AdcOutConfig,2,1,0,",
    ...     "10:00:00:003: API:ProfileConfig,0,1435384036,700,600,5800,0,0,1243,0,256,10000,"
    ...     "0,0,30,",
    ...     "10:00:00:004: API:ChirpConfig,0,0,0,0,0,0,0,1,0,",
    ...     "10:00:00:005: API:FrameConfig,0,0,10,64,8000000,0,512,1,"])
    >>> prof = parse_setup(log)
    >>> prof.radar.chip, prof.radar.n_chirps, round(prof.radar.slope_hz_per_s / 1e12, 3)
    ('AWR2243', 64, 60.012)
    """
    text = read_source(path_or_text)
    if not text.strip():
        where = f"setup {os.fspath(path_or_text)!r}" if isinstance(path_or_text, os.PathLike) \
            else "setup text"
        raise _fail(f"{where} is empty: no TI CLI commands, mmWave Studio LogFile calls or "
                    "setup JSON")
    return _SETUP_READERS[setup_kind(text)](text)


#: The reader of each `setup_kind`.
_SETUP_READERS = {"studio_json": parse_studio_json, "studio_log": parse_studio_log,
                  "cli_profile": parse_ti_cfg}
