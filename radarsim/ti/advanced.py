"""Advanced frames (``dfeDataOutputMode 3``): a frame of up to four sub-frames, each with its own
chirps, loops, profile and processing commands.

`plan` reads ``advFrameCfg`` / ``subFrameCfg`` (/ ``subDataFrameCfg`` on the MCU+ SDK) into an
`AdvancedFrame`; the reader then reads the profile once per sub-frame (`subframe_commands`:
the commands whose ``subFrameIdx`` is -1 or that sub-frame), as if the sub-frame were a frame
of its own, and `combine` joins the per-sub-frame `TiProfile` values. A sub-frame starts when
the previous one's ``subFramePeriodicity`` ends; the frame period is their sum.

Command syntax (mmWave SDK 3.x user guide, sec. "Configuration (.cfg) File Format"; MCU+ SDK
``cli_mmwave.c`` ``CLI_MMWaveAdvFrameCfg`` / ``CLI_MMWaveSubFrameCfg`` /
``CLI_MMWaveAdvFrameDataCfg``; mmWaveLink ``rlAdvFrameCfg_t`` / ``rlSubFrameCfg_t``):

- ``advFrameCfg <numOfSubFrames> <forceProfile> <numFrames> <triggerSelect> <frameTrigDelay ms>``
  (+ ``<numOfSubFrames>`` of the frame data on the MCU+ SDK): 1..4 sub-frames
  (RL_MAX_SUBFRAMES).
- ``subFrameCfg <subFrameNum> <forceProfileIdx> <chirpStartIdx> <numOfChirps> <numLoops>
  <burstPeriodicity ms> <chirpStartIdxOffset> <numOfBurst> <numOfBurstLoops>
  <subFramePeriodicity ms>``.
- ``subDataFrameCfg <subFrameNum> <numAdcSamples> <totalChirps> <numChirpsInDataPacket>``.

A sub-frame of several bursts (``numOfBurst`` or ``numOfBurstLoops`` > 1) or with
``forceProfile`` 1 has no `RadarConfig` (one chirp profile, evenly spaced chirps) and is
refused, naming the line.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Iterable, Sequence

from ..chips import Chip
from .profile import TiProfile
from .syntax import Line

__all__ = ["AdvancedFrame", "SubFrameSpec", "MAX_SUBFRAMES", "plan", "subframe_commands",
           "combine"]

#: mmWaveLink RL_MAX_SUBFRAMES.
MAX_SUBFRAMES = 4
_ADVANCED_COMMANDS = ("advFrameCfg", "subFrameCfg", "subDataFrameCfg")


@dataclass(frozen=True, slots=True)
class SubFrameSpec:
    """One ``subFrameCfg``: chirps ``chirp_start .. chirp_start + n_chirps - 1`` repeated
    `n_loops` times, in a slot of `period_s`; `samples` from ``subDataFrameCfg`` if given."""

    index: int
    chirp_start: int
    n_chirps: int
    n_loops: int
    burst_period_s: float
    period_s: float
    samples: int | None
    line: Line


@dataclass(frozen=True, slots=True)
class AdvancedFrame:
    """``advFrameCfg`` and its sub-frames."""

    n_subframes: int
    n_frames: int
    trigger: int
    subframes: tuple[SubFrameSpec, ...]
    line: Line

    @property
    def frame_period_s(self) -> float:
        """Frame period, s: the sum of the sub-frame periodicities."""
        return sum(s.period_s for s in self.subframes)

    def start_s(self, k: int) -> float:
        """Start of sub-frame k within the frame, s."""
        return sum(s.period_s for s in self.subframes[:k])


def _sub_frame(ln: Line, chip: Chip, n_sub: int, data: dict[int, Line]) -> SubFrameSpec:
    k = ln.int(0, "subFrameNum", 0, n_sub - 1, f"advFrameCfg numOfSubFrames={n_sub}")
    start = ln.int(2, "chirpStartIdx", 0, chip.max_chirp_defs - 1, chip.name)
    n_chirps = ln.int(3, "numOfChirps", 1, chip.max_chirp_defs - start, chip.name)
    loops = ln.int(4, "numLoops", 1, chip.max_loops, chip.name)
    burst = ln.dec(5, "burstPeriodicity")
    bursts = ln.int(7, "numOfBurst", 1, 512)
    burst_loops = ln.int(8, "numOfBurstLoops", 1, 64)
    if bursts != 1 or burst_loops != 1:
        raise ln.fail(f"numOfBurst={bursts}, numOfBurstLoops={burst_loops}: a sub-frame of "
                      "several bursts is not modelled (a RadarConfig is one evenly spaced "
                      "burst); use 1 and 1")
    period = ln.dec(9, "subFramePeriodicity")
    if burst <= 0 or period < burst:
        raise ln.fail(f"subFramePeriodicity={ln.args[9]} ms must be >= burstPeriodicity="
                      f"{ln.args[5]} ms > 0")
    samples = None
    if k in data:
        dln = data[k]
        samples = dln.int(1, "numAdcSamples", 2, 65535)
        total = dln.int(2, "totalChirps", 1, 65535)
        if total != n_chirps * loops:
            raise dln.fail(f"totalChirps={total} differs from subFrameCfg's numOfChirps x "
                           f"numLoops = {n_chirps * loops} (line {ln.no})")
    return SubFrameSpec(index=k, chirp_start=start, n_chirps=n_chirps, n_loops=loops,
                        burst_period_s=float(burst.scaleb(-3)),
                        period_s=float(period.scaleb(-3)), samples=samples, line=ln)


def plan(commands: Sequence[Line], chip: Chip) -> AdvancedFrame | None:
    """The advanced frame of a profile's commands, or None for a frame-mode profile.

    Raises
    ------
    ValueError
        "line N (command): ..." for an out-of-range count or index, a missing ``subFrameCfg``,
        sub-frames of several bursts, ``forceProfile`` 1, or ``frameCfg`` in advanced mode.
    """
    adv = [ln for ln in commands if ln.cmd == "advFrameCfg"]
    if not adv:
        stray = next((ln for ln in commands if ln.cmd in _ADVANCED_COMMANDS), None)
        if stray is not None:
            raise stray.fail("sub-frame command without advFrameCfg (and dfeDataOutputMode 3)")
        return None
    aln = adv[0]
    n_sub = aln.int(0, "numOfSubFrames", 1, MAX_SUBFRAMES, "RL_MAX_SUBFRAMES")
    if aln.int(1, "forceProfile", 0, 1):
        raise aln.fail("forceProfile=1 (every chirp forced to one profile) is not modelled; "
                       "use 0")
    n_frames = aln.int(2, "numFrames", 0, 65535)
    trigger = aln.int(3, "triggerSelect", 1, 2)
    if aln.dec(4, "frameTrigDelay") < 0:
        raise aln.fail(f"frameTrigDelay={aln.args[4]} ms must be >= 0")
    if len(aln.args) == 6 and aln.int(5, "numOfSubFrames (data)", 1, MAX_SUBFRAMES) != n_sub:
        raise aln.fail(f"the frame data's numOfSubFrames={aln.args[5]} differs from "
                       f"numOfSubFrames={n_sub}")
    frame = next((ln for ln in commands if ln.cmd == "frameCfg"), None)
    if frame is not None:
        raise frame.fail("frameCfg in an advanced-frame profile: sub-frames are defined by "
                         "subFrameCfg")
    data = {ln.int(0, "subFrameNum", 0, n_sub - 1, f"advFrameCfg numOfSubFrames={n_sub}"): ln
            for ln in commands if ln.cmd == "subDataFrameCfg"}
    subs = {}
    for ln in commands:
        if ln.cmd == "subFrameCfg":
            spec = _sub_frame(ln, chip, n_sub, data)
            subs[spec.index] = spec
    missing = [k for k in range(n_sub) if k not in subs]
    if missing:
        raise aln.fail(f"numOfSubFrames={n_sub} but no subFrameCfg for sub-frame(s) {missing}")
    return AdvancedFrame(n_subframes=n_sub, n_frames=n_frames, trigger=trigger,
                         subframes=tuple(subs[k] for k in range(n_sub)), line=aln)


def subframe_commands(commands: Iterable[tuple[Line, bool]], k: int) -> list[Line]:
    """The commands that configure sub-frame k: (line, has_subframe_arg) pairs whose
    ``subFrameIdx`` is -1 or k, and every command without one."""
    out = []
    for ln, has_sub in commands:
        if has_sub and int(ln.args[0]) not in (-1, k):
            continue
        out.append(ln)
    return out


def combine(subs: Sequence[TiProfile], adv: AdvancedFrame) -> TiProfile:
    """One `TiProfile` for the whole advanced frame: sub-frame 0's radar and CFAR at the top
    (what a frame-mode caller sees), every sub-frame in `TiProfile.subframes` (each with the
    frame period, its index and its start), notes and ignored commands merged."""
    period = adv.frame_period_s
    parts = tuple(dataclasses.replace(p, frame_period_s=period, n_frames=adv.n_frames,
                                      trigger_select=adv.trigger, subframe_index=k,
                                      subframe_start_s=adv.start_s(k),
                                      burst_period_s=adv.subframes[k].burst_period_s,
                                      subframe_period_s=adv.subframes[k].period_s)
                  for k, p in enumerate(subs))
    ignored = tuple(dict.fromkeys(i for p in subs for i in p.ignored))
    notes = tuple(dict.fromkeys(n for p in subs for n in p.notes))
    notes += (f"advanced frame (line {adv.line.no}): {adv.n_subframes} sub-frame(s), frame "
              f"period {period * 1e3:g} ms",)
    return dataclasses.replace(parts[0], subframe_index=None, subframe_start_s=0.0,
                               burst_period_s=None, subframe_period_s=None,
                               subframes=parts, ignored=ignored, notes=notes)
