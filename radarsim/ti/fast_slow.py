"""Fast/slow chirp frames (`radarsim.mimo.fast_slow`) as TI profiles: an advanced frame of two
sub-frames, each a TDMA loop on its own ``profileCfg``, the two profiles differing only in
their idle time ([TI-VEXT] table 2: TI's SRR chirps of 59 and 70.8 us share a 56 us ramp, idle
3 and 14.8 us).

Written (`advanced_profile`, used by `to_ti_cfg`): sub-frame 0 holds the first set's
n_chirps / 2 chirps (``profileCfg 0``), sub-frame 1 the second set's (``profileCfg 1``); sub-frame
0's ``subFramePeriodicity`` equals its burst, so the second set starts right after the first,
as the scheme's timing has it. TI programs idle time in 10 ns steps (``profileCfg``
idleTime, two decimals in us): the fast idle is rounded to that grid and the slow idle takes
the rest of twice the mean, so the mean chirp (`RadarConfig.idle_time_s`, `chirp_period_s`)
is kept exactly and T_s / T_f moves by a few 1e-4 (R79 preset: idle 2.84 and 7.16 us,
T_f = 21.65 us, T_s = 25.97 us, ratio 1.19954 for the scheme's 1.2).

Read (`pair_radar`, used by `from_ti_cfg`): two sub-frames whose radars are the same TDMA loop
but for the idle time are a fast/slow pair; the registered `FastSlowScheme` whose split of
the mean chirp lands on both idle times within half a 10 ns step (and whose set order
matches) names the scheme. Unequal chirp counts, or a ratio no registered scheme has, raise
`ValueError` naming the sub-frames, the values and the limit.

References
----------
.. [1] [TI-VEXT] section 3, table 2 (fast/slow chirp profiles of the SRR demo).
.. [2] TI mmWave SDK user guide, ``advFrameCfg`` / ``subFrameCfg`` (see `radarsim.ti.advanced`).
"""
from __future__ import annotations

import dataclasses
from decimal import Decimal

from core.errors import BadInput

from ..mimo.fast_slow import FastSlowScheme
from ..mimo.schemes import MIMO_SCHEMES, TdmaScheme
from ..radar_config import RadarConfig
from ..radar_parts import FIELDS
from .profile import DEFAULT_FRAME_PERIOD_S, TiProfile

__all__ = ["advanced_profile", "pair_radar", "IDLE_STEP_S"]

#: ``profileCfg`` idleTime resolution, s (10 ns: two decimals in us).
IDLE_STEP_S = 10e-9
#: Fields the two sub-frames of a fast/slow pair may differ in.
_SET_FIELDS = ("idle_time_s", "chirp_period_s")


def _us(x_s: float) -> Decimal:
    """A time in s as its decimal text in us (the TI file's unit)."""
    return Decimal(repr(x_s)).scaleb(6)


def _s(x_us: Decimal) -> float:
    return float(x_us.scaleb(-6))


def advanced_profile(cfg: RadarConfig, frame_period_s: float | None = None,
                     n_frames: int = 0) -> TiProfile | None:
    """The two-sub-frame `TiProfile` of a fast/slow config, or None for any other scheme.

    Parameters
    ----------
    cfg : RadarConfig
        A config whose scheme is a `FastSlowScheme`.
    frame_period_s : float, optional
        Frame period, s (default `DEFAULT_FRAME_PERIOD_S`); sub-frame 1's periodicity is the
        rest of it after sub-frame 0's burst.
    n_frames : int
        ``numFrames``.

    Raises
    ------
    ValueError
        If the frame period is shorter than the two bursts.
    """
    sch = cfg.scheme
    if not isinstance(sch, FastSlowScheme):
        return None
    period = DEFAULT_FRAME_PERIOD_S if frame_period_s is None else frame_period_s
    ramp = _us(cfg.ramp_end_time_s)
    idle_f = _us(sch.idle_times_s(cfg)[0]).quantize(Decimal("0.01"))
    idle_s = 2 * _us(cfg.idle_time_s) - idle_f
    half = cfg.n_chirps // 2
    idles = (idle_s, idle_f) if sch.slow_first else (idle_f, idle_s)
    # Each set is read back as the registry's TDMA loop (the pattern TdmaScheme.from_ti claims).
    subs = [cfg.replace_fields(mimo="tdma", n_chirps=half, tx_order=cfg.tx_order,
                               idle_time_s=_s(i), chirp_period_s=_s(i + ramp)) for i in idles]
    bursts = [_s((i + ramp) * half) for i in idles]
    rest = period - bursts[0]
    if rest < bursts[1]:
        raise BadInput(f"frame_period_s={period:g} is shorter than the two chirp sets "
                       f"({bursts[0]:g} + {bursts[1]:g} s)")
    parts = tuple(TiProfile(radar=r, frame_period_s=period, n_frames=n_frames,
                            subframe_index=k, subframe_start_s=0.0 if k == 0 else bursts[0],
                            burst_period_s=b, subframe_period_s=b if k == 0 else rest)
                  for k, (r, b) in enumerate(zip(subs, bursts)))
    return dataclasses.replace(parts[0], subframe_index=None, burst_period_s=None,
                               subframe_period_s=None, subframes=parts)


def pair_radar(profile: TiProfile) -> RadarConfig | None:
    """The fast/slow `RadarConfig` of a two-sub-frame profile, or None if its sub-frames are
    not a fast/slow pair (then each sub-frame is a radar of its own).

    Raises
    ------
    ValueError
        If the sub-frames are a pair (same TDMA loop, different idle times) with unequal chirp
        counts, or with a T_s / T_f that no registered `FastSlowScheme` has.
    """
    if len(profile.subframes) != 2:
        return None
    a, b = (p.radar for p in profile.subframes)
    same = all(getattr(a, f.name) == getattr(b, f.name) for f in FIELDS.values()
               if f.name not in _SET_FIELDS + ("n_chirps",))
    if not same or a.idle_time_s == b.idle_time_s or not isinstance(a.scheme, TdmaScheme) \
            or isinstance(a.scheme, FastSlowScheme):
        return None  # not two TDMA loops differing in idle time only
    if a.n_chirps != b.n_chirps:
        raise BadInput(f"subFrameCfg: sub-frames 0 and 1 are a fast/slow chirp pair (idle "
                       f"{_us(a.idle_time_s)} and {_us(b.idle_time_s)} us) with n_chirps="
                       f"{a.n_chirps} and {b.n_chirps}: the association compares the two "
                       "sets' peaks, so their chirp counts (numOfChirps x numLoops) must be "
                       "equal")
    slow_first = a.chirp_period_s > b.chirp_period_s
    fast, slow = (b, a) if slow_first else (a, b)
    mean_idle = _s((_us(a.idle_time_s) + _us(b.idle_time_s)) / 2)
    mean_period = _s((_us(a.chirp_period_s) + _us(b.chirp_period_s)) / 2)
    merged = {f.name: getattr(a, f.name) for f in FIELDS.values()}
    merged.update(n_chirps=2 * a.n_chirps, idle_time_s=mean_idle, chirp_period_s=mean_period)
    tol = IDLE_STEP_S / 2 * (1 + 1e-6)
    known = []
    for sch in MIMO_SCHEMES.values():
        if not isinstance(sch, FastSlowScheme) or sch.slow_first != slow_first:
            continue
        known.append(f"{sch.name}: {sch.slow_period_ratio:g}")
        t_f = 2 * mean_period / (1 + sch.slow_period_ratio)
        if abs(t_f - fast.chirp_period_s) <= tol and \
                abs(sch.slow_period_ratio * t_f - slow.chirp_period_s) <= tol:
            return RadarConfig.from_fields(**{**merged, "mimo": sch.name})
    ratio = slow.chirp_period_s / fast.chirp_period_s
    raise BadInput(f"profileCfg: sub-frames 0 and 1 are a fast/slow chirp pair with T_s / T_f "
                   f"= {_us(slow.chirp_period_s)} / {_us(fast.chirp_period_s)} us = "
                   f"{ratio:.6g}, which no registered fast/slow scheme "
                   f"({', '.join(known) or 'none'}) matches within TI's 10 ns idle-time step; "
                   f"register a FastSlowScheme with slow_period_ratio={ratio:.6g}")
