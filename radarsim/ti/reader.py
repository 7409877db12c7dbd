"""`parse_ti_cfg`: a TI mmWave SDK CLI profile (path or text) to a `TiProfile`."""
from __future__ import annotations

import dataclasses
import difflib
import json
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from core.errors import BadInput
from core.fileio import read_input_bytes

from ..chips import Chip, get_chip
from ..radar_config import RadarConfig
from ..radar_parts import FIELDS
from . import advanced, fast_slow
from .advanced import MAX_SUBFRAMES
from .board_calibration import antenna_calib_pairs, is_identity
from .chip_inference import infer_chip, platform_board
from .commands import MODELLED_COMMANDS, TI_COMMANDS
from .families import PROCESSING_COMMANDS, family_of
from .mimo_schedule import frame_masks, schedule
from .parse_state import TI_DEFAULT_OVERRIDES, TI_FIELDS, ParseState
from .profile import TiProfile
from .syntax import DIRECTIVE_RE, Line, LineError, as_tuples, is_comment

__all__ = ["parse_ti_cfg", "from_ti_cfg", "read_source", "MAX_PROFILE_BYTES"]


#: Largest profile read, bytes. A TI CLI profile is a few kB (the demos' CLI reads lines of
#: at most 256 characters over a 115200 baud UART); a bigger file is not a profile.
MAX_PROFILE_BYTES = 4 * 2**20
#: Distinct unknown command names for which close matches to the modelled commands are sought
#: (difflib costs ~50 us a name); further unknown names are only counted.
MAX_SUGGESTIONS = 64
#: Unknown commands listed by line in the notes; the rest are counted in one note.
MAX_UNKNOWN_NOTES = 20


def read_source(path_or_text: str | os.PathLike) -> str:
    """The profile text: a path is read as UTF-8 (a BOM is skipped), any str with a newline is
    the text itself."""
    if isinstance(path_or_text, os.PathLike):
        return _read_file(Path(path_or_text))
    if not isinstance(path_or_text, str):
        raise TypeError(f"path_or_text must be a path or the .cfg text, got "
                        f"{type(path_or_text).__name__}")
    text = path_or_text
    if "\n" in text:
        if len(text) > MAX_PROFILE_BYTES:
            raise BadInput(f"profile text of {len(text)} characters exceeds the "
                           f"{MAX_PROFILE_BYTES} limit (a TI CLI profile is a few kB)")
        return text
    if os.path.lexists(text):  # a file, or a special one the input check names
        return _read_file(Path(text))
    if text.strip().endswith(".cfg") or not any(c.isspace() for c in text.strip()):
        raise BadInput(f"TI .cfg file {text!r} not found")
    return text


def _read_file(path: Path) -> str:
    # A regular file only (a FIFO would block, /dev/zero never end): the shared input check.
    raw = read_input_bytes(path, "profile", max_bytes=MAX_PROFILE_BYTES)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        raise BadInput(f"profile {str(path)!r} is not UTF-8 text: byte 0x{raw[exc.start]:02x} "
                       f"at offset {exc.start} (line {line}); TI profiles are ASCII") from None


def _directive_value(field: dataclasses.Field, raw: str, ln: Line) -> Any:
    try:
        value = json.loads(raw)
    except json.JSONDecodeError:
        if "str" in str(field.type):
            return raw
        raise ln.fail(f"value {raw!r} for {field.name} is not JSON") from None
    return as_tuples(value)


@dataclass(slots=True)
class _Tokens:
    """A profile split into lines: directives, the commands after the last ``flushCfg`` (with
    whether their first argument is a sub-frame index), ignored records and notes."""

    directives: list[Line] = dataclasses.field(default_factory=list)
    commands: list[tuple[Line, bool]] = dataclasses.field(default_factory=list)
    ignored: list[tuple[int, str]] = dataclasses.field(default_factory=list)
    notes: list[str] = dataclasses.field(default_factory=list)
    board: str | None = None


def _tokenize(lines: list[str], chip: Chip, n_subframes: int) -> _Tokens:
    """Split and check every line once: argument counts, sub-frame indices against
    `n_subframes`, duplicated commands, unknown commands (near-misspellings of modelled ones
    refused with a suggestion, for at most `MAX_SUGGESTIONS` distinct names)."""
    tok = _Tokens()
    seen: dict[tuple, Line] = {}
    suggest: dict[str, str | None] = {}
    n_unknown = 0
    for no, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text:
            continue
        if is_comment(text):
            m = DIRECTIVE_RE.match(text)
            if m:
                tok.directives.append(Line(no, "% radarsim", (m.group(1), m.group(2))))
            continue
        cmd, *args = text.split()
        # A trailing "% ..." or "# ..." note after the arguments (seen in users' files).
        cut = next((i for i, a in enumerate(args) if is_comment(a)), len(args))
        ln = Line(no, cmd, tuple(args[:cut]))
        spec = TI_COMMANDS.get(cmd)
        if spec is None:
            if cmd not in suggest:
                suggest[cmd] = (difflib.get_close_matches(cmd, MODELLED_COMMANDS, n=1,
                                                          cutoff=0.85) or [None])[0] \
                    if len(suggest) < MAX_SUGGESTIONS else None
            if suggest[cmd]:
                raise LineError(f"line {no}: unknown command {cmd!r}; did you mean "
                                f"{suggest[cmd]!r}?")
            tok.ignored.append((no, cmd))
            n_unknown += 1
            if n_unknown <= MAX_UNKNOWN_NOTES:
                tok.notes.append(f"line {no}: {cmd!r} is not a command of the SDK demos the "
                                 "harness knows; kept and ignored")
            continue
        counts = spec.counts(chip.name)
        if counts is not None and len(ln.args) not in counts:
            want = " or ".join(str(n) for n in sorted(counts))
            raise ln.fail(f"expects {want} arguments, got {len(ln.args)}")
        if cmd == "flushCfg":  # TI's flushCfg resets everything given before it
            tok.ignored += [(c.no, c.cmd) for c, _ in tok.commands]
            tok.commands.clear()
            seen.clear()
        has_sub = spec.has_subframe(ln, chip.name)
        if has_sub:
            where = (f"advFrameCfg numOfSubFrames={n_subframes}" if n_subframes > 1 else
                     "a frame-mode profile has one sub-frame")
            ln.int(0, "subFrameIdx", -1, n_subframes - 1, where)
        key = spec.instance_key(ln, chip.name)
        if key is not None:
            if key in seen:
                first = seen[key]
                raise ln.fail(f"duplicate of line {first.no} ({first.cmd} "
                              f"{' '.join(first.args)}): TI's CLI would silently keep the later "
                              "one; remove one of them")
            seen[key] = ln
        tok.commands.append((ln, has_sub))
    if n_unknown > MAX_UNKNOWN_NOTES:
        tok.notes.append(f"{n_unknown - MAX_UNKNOWN_NOTES} more unknown commands kept and "
                         "ignored")
    return tok


def _n_subframes(lines: list[str]) -> int:
    """numOfSubFrames of the profile's advFrameCfg (1 without one; checked later)."""
    for raw in lines:
        parts = raw.split()
        if parts[:1] == ["advFrameCfg"] and len(parts) > 1 and parts[1].isdigit():
            return max(1, min(int(parts[1]), MAX_SUBFRAMES))
    return 1


def parse_ti_cfg(path_or_text: str | os.PathLike) -> TiProfile:
    """Parse a TI mmWave SDK CLI configuration into a `TiProfile`.

    Parameters
    ----------
    path_or_text : str or path-like
        A .cfg file path, or the text itself (any string with a newline is text).

    Returns
    -------
    TiProfile
        ``.radar`` is the validated `RadarConfig`; an advanced-frame profile has one
        `TiProfile` per sub-frame in ``.subframes`` (its ``.radar`` is sub-frame 0's, or, for
        two sub-frames that are one TDMA loop at two idle times, the fast/slow radar of both:
        `radarsim.ti.fast_slow.pair_radar`).

    Raises
    ------
    ValueError
        With "line N (command): ..." for every wrong argument count, malformed number, value
        outside the chip's limits, sub-frame index out of range, duplicated command,
        unsupported feature, near-misspelled modelled command, missing required command
        (reported at the end of the input) and `RadarConfig` validation error (at the line of
        the command that set the field); for a file that is not UTF-8 text or is larger than
        `MAX_PROFILE_BYTES`.
    FileNotFoundError
        If a path was given and does not exist.

    Examples
    --------
    >>> from radarsim.ti import parse_ti_cfg, r79_cfg_path
    >>> prof = parse_ti_cfg(r79_cfg_path())
    >>> prof.radar.mimo, prof.radar.n_chirps, prof.frame_period_s
    ('ddma', 768, 0.25)
    """
    lines = read_source(path_or_text).splitlines()
    chip_name, how = infer_chip(lines)
    try:
        chip = get_chip(chip_name)
    except ValueError as exc:
        raise LineError(f"line 1: {exc}") from None
    tok = _tokenize(lines, chip, _n_subframes(lines))
    tok.notes.insert(0, f"chip {chip.name} from the {how}")
    tok.board = platform_board(lines, chip.name)
    if tok.board is not None:
        tok.notes.insert(1, f"board {tok.board} from the '% Platform:' header")
    adv = advanced.plan([ln for ln, _ in tok.commands], chip)
    if adv is None:
        return _read_pass([ln for ln, _ in tok.commands], tok, chip, len(lines))
    parts = [_read_pass(advanced.subframe_commands(tok.commands, k), tok, chip, len(lines),
                        sub=adv.subframes[k])
             for k in range(adv.n_subframes)]
    profile = advanced.combine(parts, adv)
    # Two sub-frames that are one TDMA loop at two idle times are one fast/slow radar.
    pair = fast_slow.pair_radar(profile)
    return profile if pair is None else dataclasses.replace(profile, radar=pair)


def _read_pass(commands: list[Line], tok: _Tokens, chip: Chip, n_lines: int,
               sub: advanced.SubFrameSpec | None = None) -> TiProfile:
    """Run the handlers of `commands` (a frame, or sub-frame `sub` of an advanced frame)."""
    st = ParseState(chip=chip, subframe=None if sub is None else sub.index,
                    advanced=sub is not None)
    st.ignored, st.notes = list(tok.ignored), list(tok.notes)
    st.board = tok.board
    fields_by_name = {f.name: f for f in FIELDS.values()}
    for ln in tok.directives:
        name = ln.args[0]
        if name not in fields_by_name:
            raise ln.fail(f"unknown RadarConfig field {name!r}")
        if name in TI_FIELDS:
            raise ln.fail(f"{name} is set by TI commands, not by a directive")
        st.directives[name] = _directive_value(fields_by_name[name], ln.args[1], ln)
        st.directive_lines[name] = ln
    for ln in commands:
        spec = TI_COMMANDS[ln.cmd]
        if spec.handler is None:
            st.ignored.append((ln.no, ln.cmd))
            continue
        spec.handler(st, ln)
        st.seen[ln.cmd] = ln
    if sub is not None:
        _install_subframe(st, sub)
    return _finish(st, n_lines)


def _install_subframe(st: ParseState, sub: advanced.SubFrameSpec) -> None:
    """The sub-frame's chirps and loops as the pass's frame: its burst must fit
    ``burstPeriodicity``."""
    st.frame = dict(start=sub.chirp_start, end=sub.chirp_start + sub.n_chirps - 1,
                    loops=sub.n_loops, n_frames=0, samples=sub.samples,
                    period_s=sub.burst_period_s, trigger=1, line=sub.line,
                    period_name="burstPeriodicity")
    st.seen["frameCfg"] = sub.line
    for idx in range(sub.chirp_start, sub.chirp_start + sub.n_chirps):
        if idx not in st.chirps:
            raise sub.line.fail(f"chirp {idx} of sub-frame {sub.index} is not defined by any "
                                "chirpCfg")


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
    if st.board is not None:
        kw["board"] = st.board
    kw.update(st.directives)
    kw.update(st.fields)
    if "chirp_period_s" in st.directives:  # a directive refines the decimal idle + ramp sum
        kw["chirp_period_s"] = st.directives["chirp_period_s"]
    lines = {**st.field_lines, **st.directive_lines}
    try:
        radar = RadarConfig.from_fields(**kw)
    except (ValueError, TypeError) as exc:
        raise _relabel(exc, lines, st) from exc
    burst_s = radar.n_chirps * radar.chirp_period_s
    if fr["period_s"] < burst_s * (1 - 1e-9):
        name = fr.get("period_name", "framePeriodicity")
        raise fln.fail(f"{name}={fr['period_s'] * 1e3:g} ms is shorter than the chirp burst "
                       f"n_chirps x chirp period = {burst_s * 1e3:g} ms")
    family = family_of(st.chip, radar.scheme)
    processing = _family_processing(st, family)
    dc_sig = _dc_range_signature(st, family, radar)
    return TiProfile(radar=radar, frame_period_s=fr["period_s"], n_frames=fr["n_frames"],
                     trigger_select=fr["trigger"], cfar=dict(st.cfar),
                     ddm_phase_order=st.ddm_order, ant_geometry=st.ant_geometry,
                     adc_channel_interleaved=radar.adcbuf_interleaved,
                     sample_swap=st.adcbuf.get("sample_swap"), lvds_stream=st.lvds,
                     profile_extras=dict(st.extras), processing=processing,
                     demo_family=family.name, measure_range_bias=st.measure,
                     dc_range_signature=dc_sig,
                     ignored=tuple(st.ignored), notes=tuple(st.notes),
                     directives=dict(st.directives),
                     command_lines={cmd: ln.no for cmd, ln in st.seen.items()})


def _family_processing(st: ParseState, family) -> dict[str, Any]:
    """`ProcessingConfig` field values of the profile: what its processing commands set, a
    command of another demo family dropped (noted), an absent one at the family's default;
    the commands read but not modelled are listed in one note."""
    processing = dict(st.processing)
    for cmd, ln in st.processing_commands.items():
        name = cmd.split()[0]
        if not family.has(name):
            for f in PROCESSING_COMMANDS[name].fields:
                if st.processing_origin.get(f, name) == name:
                    processing.pop(f, None)
            st.cfar.clear() if name == "cfarCfg" else None
            st.ignored.append((ln.no, name))
            st.notes.append(f"line {ln.no}: {name} is not a command of the {family.description}"
                            "; ignored")
    _apply_antenna_calib(st, family, processing)
    present = {cmd.split()[0] for cmd in st.processing_commands}
    for cmd, defaults in family.defaults.items():
        if cmd not in present:
            for f, v in defaults.items():
                processing.setdefault(f, v)
    if st.unmodelled:
        st.notes.append("read but not modelled: " + "; ".join(st.unmodelled))
    return processing


def _dc_range_signature(st: ParseState, family, radar: RadarConfig) -> tuple | None:
    """An enabled ``calibDcRangeSig`` as the demo runs it: (negativeBinIdx, positiveBinIdx,
    numAvg, chirps per loop), or None. A numAvg below the loops per frame (the Doppler bins)
    makes the demo disable it (``MmwDemo_dataPathTask``: ``dcRangeForcedDisableCntr``):
    None, with a note. Not a command of the family's demo: ignored there (noted)."""
    if st.dc_range_sig is None or not family.has("calibDcRangeSig"):
        return None
    ln, neg, pos, num_avg = st.dc_range_sig
    loops = st.frame["loops"]
    if num_avg < loops:
        st.notes.append(f"line {ln.no}: calibDcRangeSig numAvg={num_avg} is below the "
                        f"{loops} Doppler bins (loops per frame): the demo disables it")
        return None
    return (neg, pos, num_avg, radar.n_chirps // loops)


def _apply_antenna_calib(st: ParseState, family, processing: dict[str, Any]) -> None:
    """The DDM demo's ``antennaCalibParams`` as ``channel_comp`` (`radarsim.ti.board_calibration`).
    A ``compRangeBiasAndRxChanPhase`` of the same profile that also corrects the channels (not
    the identity) is refused naming both lines: one board, one correction."""
    ln = st.antenna_calib
    if ln is None or not family.has(ln.cmd):
        return
    pairs = antenna_calib_pairs(ln, st.chip)
    if pairs is None:
        return
    other = st.processing_commands.get("compRangeBiasAndRxChanPhase")
    if other is not None and family.has(other.cmd) and not is_identity(
            processing.get("channel_comp") or ()):
        raise ln.fail(f"line {other.no} compRangeBiasAndRxChanPhase already corrects the "
                      "channels; keep one of the two (or make the other the identity)")
    processing["channel_comp"] = pairs


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
