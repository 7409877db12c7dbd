"""`parse_ti_cfg`: a TI mmWave SDK CLI profile (path or text) to a `TiProfile`."""
from __future__ import annotations

import dataclasses
import difflib
import json
import os
import re
from pathlib import Path
from typing import Any, Mapping

from ..chips import get_chip
from ..config import RadarConfig
from .chip_inference import infer_chip
from .commands import MODELLED_COMMANDS, TI_COMMANDS
from .profile import TiProfile
from .schedule import frame_masks, schedule
from .state import TI_DEFAULT_OVERRIDES, TI_FIELDS, ParseState
from .syntax import DIRECTIVE_RE, Line, LineError, as_tuples

__all__ = ["parse_ti_cfg", "from_ti_cfg"]


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


def _directive_value(field: dataclasses.Field, raw: str, ln: Line) -> Any:
    try:
        value = json.loads(raw)
    except json.JSONDecodeError:
        if "str" in str(field.type):
            return raw
        raise ln.fail(f"value {raw!r} for {field.name} is not JSON") from None
    return as_tuples(value)


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
        With "line N (command): ..." for every wrong argument count, malformed number, value
        outside the chip's limits, unsupported feature, near-misspelled modelled command,
        missing required command (reported at the end of the input) and `RadarConfig`
        validation error (at the line of the command that set the field).
    FileNotFoundError
        If a path was given and does not exist.
    """
    lines = _read_source(path_or_text).splitlines()
    chip_name, how = infer_chip(lines)
    try:
        chip = get_chip(chip_name)
    except ValueError as exc:
        raise LineError(f"line 1: {exc}") from None
    st = ParseState(chip=chip)
    st.notes.append(f"chip {chip.name} from the {how}")
    fields_by_name = {f.name: f for f in dataclasses.fields(RadarConfig)}
    for no, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text:
            continue
        if text.startswith("%") or text.startswith("#"):
            m = DIRECTIVE_RE.match(text)
            if m:
                ln = Line(no, "% radarsim", (m.group(1), m.group(2)))
                name = m.group(1)
                if name not in fields_by_name:
                    raise ln.fail(f"unknown RadarConfig field {name!r}")
                if name in TI_FIELDS:
                    raise ln.fail(f"{name} is set by TI commands, not by a directive")
                st.directives[name] = _directive_value(fields_by_name[name], m.group(2), ln)
                st.directive_lines[name] = ln
            continue
        cmd, *args = text.split()
        # A trailing "% ..." or "# ..." note after the arguments (seen in users' files).
        cut = next((i for i, a in enumerate(args) if a[:1] in "%#"), len(args))
        args = args[:cut]
        ln = Line(no, cmd, tuple(args))
        spec = TI_COMMANDS.get(cmd)
        if spec is None:
            close = difflib.get_close_matches(cmd, MODELLED_COMMANDS, n=1, cutoff=0.85)
            if close:
                raise LineError(f"line {no}: unknown command {cmd!r}; did you mean "
                                 f"{close[0]!r}?")
            st.ignored.append((no, cmd))
            st.notes.append(f"line {no}: {cmd!r} is not a command of the SDK demos the harness "
                            "knows; kept and ignored")
            continue
        counts = spec.counts(chip.name)
        if counts is not None and len(args) not in counts:
            want = " or ".join(str(n) for n in sorted(counts))
            raise ln.fail(f"expects {want} arguments, got {len(args)}")
        if spec.handler is None:
            st.ignored.append((no, cmd))
        else:
            spec.handler(st, ln)
            st.seen[cmd] = ln
    return _finish(st, len(lines))


def _finish(st: ParseState, n_lines: int) -> TiProfile:
    end = f"line {n_lines} (end of input)"
    for cmd in ("channelCfg", "adcCfg", "profileCfg", "chirpCfg", "frameCfg"):
        if cmd not in st.seen:
            raise LineError(f"{end}: missing required command {cmd!r}")
    fr = st.frame
    fln: Line = fr["line"]
    masks, pid = frame_masks(st)
    prof = st.profiles[pid]
    pln: Line = prof["line"]
    if prof["tx_power"]:
        raise pln.fail(f"txOutPower={prof['tx_power']}: Tx back-off is not modelled; keep 0 and "
                       "set '% radarsim: tx_power_dbm = ...' instead")
    if prof["tx_phase"]:
        raise pln.fail(f"txPhaseShifter={prof['tx_phase']}: static Tx phase offsets are not "
                       "modelled; keep 0 (errors go in '% radarsim: tx_phase_error_deg')")
    st.set(pln, **prof["fields"])
    st.extras.update(prof["extras"])
    n_samples = prof["fields"]["n_samples"]
    if fr["samples"] is not None:
        # rlFrameCfg_t.numAdcSamples counts 16-bit words per chirp and Rx: 2 per complex sample.
        words = n_samples * (2 if st.adc_complex else 1)
        if fr["samples"] != words:
            raise fln.fail(f"numAdcSamples={fr['samples']} differs from profileCfg's "
                           f"numAdcSamples={n_samples}"
                           + (" x 2 (complex: 16-bit words per chirp)" if st.adc_complex
                              else ""))
    if st.adcbuf and st.adc_complex is not None and st.adcbuf["real"] == st.adc_complex:
        aln: Line = st.adcbuf["line"]
        raise aln.fail(f"adcOutputFmt={int(st.adcbuf['real'])} "
                       f"({'real' if st.adcbuf['real'] else 'complex'}) contradicts adcCfg's "
                       f"{'complex' if st.adc_complex else 'real'} output")
    claim = schedule(st, masks)
    if "n_subbands" in st.directives and "n_subbands" in claim:
        raise st.directive_lines["n_subbands"].fail(
            "n_subbands is set by chirpCfg/frameCfg (chirps per loop) for DDMA")

    kw = dict(TI_DEFAULT_OVERRIDES)
    kw["chip"] = st.chip.name
    kw.update(st.directives)
    kw.update(st.fields)
    if "chirp_period_s" in st.directives:  # a directive refines the decimal idle + ramp sum
        kw["chirp_period_s"] = st.directives["chirp_period_s"]
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
                     adc_channel_interleaved=radar.adcbuf_interleaved,
                     sample_swap=st.adcbuf.get("sample_swap"), lvds_stream=st.lvds,
                     profile_extras=dict(st.extras), chirp_level=dict(st.chirp_level),
                     ignored=tuple(st.ignored), notes=tuple(st.notes),
                     directives=dict(st.directives))


def _relabel(exc: Exception, lines: Mapping[str, Line], st: ParseState) -> ValueError:
    """RadarConfig's error, prefixed with the line of the command that set the field."""
    msg = str(exc)
    m = re.match(r"\s*(\w+)\s*=", msg)
    names = [m.group(1)] if m and m.group(1) in lines else []
    names += [n for n in lines if re.search(rf"\b{n}\b", msg) and n not in names]
    ln = lines[names[0]] if names else st.seen["profileCfg"]
    return LineError(f"line {ln.no} ({ln.cmd}): {msg}")


def from_ti_cfg(path_or_text: str | os.PathLike) -> RadarConfig:
    """`RadarConfig` of a TI mmWave SDK .cfg (path or text); see `parse_ti_cfg`."""
    return parse_ti_cfg(path_or_text).radar
