"""Slow time from frames: recordings with one chirp per frame (vibration, vital signs).

Vital-sign and vibration setups (TI's mmWave Industrial Toolbox labs, most DCA1000 vibration
datasets) transmit ONE chirp per frame and sample the target's phase at the frame rate: their
slow time is the frame sequence, not the chirps of a frame. A chain that needs a Doppler axis
reads such a capture by regrouping N consecutive frames into one frame of N chirps whose chirp
period is the frame period (`regroup_profile`): the DCA1000 stores frames chirp after chirp
with no header, so N one-chirp frames are byte for byte one N-chirp frame
(`radarsim.capture`), and only the radar description changes:

- n_chirps = N, chirp period = framePeriodicity (idle time = period - ramp end time), so the
  Doppler resolution is lambda / (2 N T_frame) and the unambiguous velocity lambda / (4 T_frame);
- the regrouped frame period is N x framePeriodicity (its timestamps).

Regrouping is explicit (``radar-harness process --regroup-frames N``): the profile alone
cannot say how long the slow-time window of the user's analysis is. A capture whose frame count
N does not divide is refused (`check_regroup`).
"""
from __future__ import annotations

import dataclasses
import os
from pathlib import Path

from core.errors import BadInput
from core.fileio import check_input_file, read_input_bytes

from ..ti.studio import setup_kind
from ..ti.syntax import code_part
from .dca1000 import MAX_CAPTURE_BYTES, frame_nbytes

__all__ = ["chirps_per_frame", "regroup_profile", "check_regroup", "one_chirp_frames"]


def _text(path_or_text: str | os.PathLike) -> str:
    if isinstance(path_or_text, os.PathLike) or (isinstance(path_or_text, str)
                                                 and "\n" not in path_or_text):
        # A FIFO or device is named, not read; bad UTF-8 stays a UnicodeDecodeError for the
        # caller that leaves it to the profile reader.
        return read_input_bytes(path_or_text, "profile").decode()
    return path_or_text


def _frame_cfg(text: str) -> tuple[int, list[str]] | None:
    """(line index, tokens) of the last ``frameCfg`` line, or None."""
    found = None
    for i, line in enumerate(text.splitlines()):
        tok = code_part(line).split()
        if tok[:1] == ["frameCfg"]:
            found = (i, tok)
    return found


def chirps_per_frame(path_or_text: str | os.PathLike) -> int | None:
    """Chirps per frame of a CLI profile's ``frameCfg <chirpStartIdx> <chirpEndIdx>
    <numLoops> ...``: (end - start + 1) x loops; None without a readable frameCfg (advanced
    frames, mmWave Studio setups)."""
    found = _frame_cfg(_text(path_or_text))
    if found is None or len(found[1]) < 4:
        return None
    try:
        start, end, loops = (int(float(v)) for v in found[1][1:4])
    except ValueError:
        return None
    return (end - start + 1) * loops


def one_chirp_frames(path_or_text: str | os.PathLike) -> bool:
    """True for a profile whose frames hold one chirp (which the chain cannot process
    without regrouping)."""
    return chirps_per_frame(path_or_text) == 1


def regroup_profile(path_or_text: str | os.PathLike, n_frames: int):
    """The `radarsim.ti.TiProfile` of N one-chirp frames read as one frame of N chirps.

    Parameters
    ----------
    path_or_text : path or str
        TI CLI profile (one chirp per frame).
    n_frames : int
        Frames per regrouped frame, >= 2.

    Raises
    ------
    ValueError
        The profile's frames hold more than one chirp, N < 2, or the regrouped frame breaks a
        limit of the radar (e.g. the chip's chirps per frame), each naming value and limit.
    """
    from ..ti import parse_ti_cfg

    if isinstance(n_frames, bool) or not isinstance(n_frames, int) or n_frames < 2:
        raise BadInput(f"--regroup-frames={n_frames!r} must be an integer >= 2")
    text = _text(path_or_text)
    kind = setup_kind(text)
    if kind != "cli_profile":
        raise BadInput(f"--regroup-frames {n_frames}: the profile is an mmWave Studio "
                       f"{'setup JSON' if kind == 'studio_json' else 'LogFile'}; regrouping "
                       "reads TI CLI profiles (.cfg)")
    k = chirps_per_frame(text)
    if k != 1:
        raise BadInput(f"--regroup-frames {n_frames}: the profile's frames hold "
                       f"{'no readable frameCfg' if k is None else f'{k} chirps'}; "
                       "regrouping builds slow time from one-chirp frames only")
    i, tok = _frame_cfg(text)
    tok = list(tok)
    tok[3] = "2"  # parse as a two-chirp frame (the chain's minimum), then set the real timing
    lines = text.splitlines()
    lines[i] = " ".join(tok)
    prof = parse_ti_cfg("\n".join(lines) + "\n")
    period = prof.frame_period_s
    radar = prof.radar
    if period <= radar.ramp_end_time_s:
        raise BadInput(f"framePeriodicity {period * 1e3:g} ms is not longer than the chirp's "
                       f"ramp end time {radar.ramp_end_time_s * 1e6:g} us")
    try:
        radar = radar.replace_fields(n_chirps=n_frames, chirp_period_s=period,
                                     idle_time_s=period - radar.ramp_end_time_s)
    except ValueError as exc:
        raise BadInput(f"--regroup-frames {n_frames}: {exc}") from None
    n_out = prof.n_frames // n_frames if prof.n_frames else 0
    return dataclasses.replace(prof, radar=radar, frame_period_s=n_frames * period,
                               n_frames=n_out)


def check_regroup(path: str | os.PathLike, regrouped_radar, n_frames: int) -> int:
    """Number of regrouped frames in a capture of one-chirp frames.

    Raises
    ------
    ValueError
        If the capture is not a whole number of one-chirp frames, or N does not divide its
        frame count (naming both).
    """
    check_input_file(path, "capture", max_bytes=MAX_CAPTURE_BYTES)  # FIFO, device: named
    size = Path(path).stat().st_size
    per_chirp = frame_nbytes(regrouped_radar) // n_frames
    n_recorded, rest = divmod(size, per_chirp)
    if size == 0 or rest:
        raise BadInput(f"capture {str(path)!r}: {size} bytes is not a whole number of "
                       f"{per_chirp}-byte one-chirp frames")
    groups, left = divmod(n_recorded, n_frames)
    if left:
        raise BadInput(f"--regroup-frames {n_frames} does not divide the capture's "
                       f"{n_recorded} frames ({groups} x {n_frames} + {left})")
    return groups
