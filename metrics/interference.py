"""Interference scores of one scheme: the noise floor with and without mitigation, and the
ghosts the mitigation adds.

An interference case exists to show three things: the floor rise the interferers
cause without mitigation, how much of it the mitigation recovers, and that the mitigation adds
no ghosts (zeroing samples modulates every echo in slow time, which spreads strong echoes over
Doppler). The noise floors come per frame from the pipeline (`pipeline.chirp_level.
noise_floor_rise`, wired by the harness); these functions only reduce the tables.

References
----------
.. [1] TI SWRA725, "Interference Mitigation for AWR294x" (2021).
.. [2] design.md section 7 (noise-floor rise over thermal, interference-to-noise ratio).
"""
from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["floor_summary", "mitigation_stats", "worst_window_recovery", "MIN_RISE_TO_RECOVER_DB",
           "WINDOW_S", "WINDOW_MIN_RISE_DB"]

#: Below this unmitigated floor rise, dB, there is nothing to recover: the recovered fraction
#: is NaN (a 0.1 dB rise measured to +/- 0.05 dB would make the fraction noise).
MIN_RISE_TO_RECOVER_DB = 0.5
#: Length of the windows the worst recovery is taken over, s: 20 frames at 20 Hz, long enough
#: for a window median, short enough to resolve an interferer's approach (the head-on case's
#: in-burst INR grows 5 dB in 3 s).
WINDOW_S = 1.0
#: A window counts for the worst recovery if its median unmitigated rise is at least this, dB
#: (twice `MIN_RISE_TO_RECOVER_DB`: a window has 10-20 frames, not a whole case).
WINDOW_MIN_RISE_DB = 1.0


def floor_summary(floors: pd.DataFrame) -> dict[str, float]:
    """Summary columns of one scheme from its per-frame floor table.

    Parameters
    ----------
    floors : DataFrame
        One row per frame: ``noise_floor_rise_db`` and ``noise_floor_rise_range_db`` (dB over
        thermal after the Doppler / range FFT, the scheme's chain as configured),
        ``interference_to_noise_db`` (NaN in frames without interferers) and optionally
        ``noise_floor_rise_unmitigated_db`` (the same frame with mitigation off).

    Returns
    -------
    dict
        Medians over frames: ``noise_floor_rise_db``, ``noise_floor_rise_range_db``,
        ``interference_to_noise_db`` (over frames with interferers; NaN if none); with the
        unmitigated column also ``noise_floor_rise_unmitigated_db``,
        ``mitigation_floor_recovery_db`` (unmitigated minus mitigated median),
        ``mitigation_floor_recovery_fraction`` (that over the unmitigated rise; NaN below
        `MIN_RISE_TO_RECOVER_DB`) and ``mitigation_floor_recovery_fraction_worst_1s``
        (`worst_window_recovery`; NaN without a ``time_s`` column).

    Examples
    --------
    >>> import pandas as pd
    >>> f = pd.DataFrame({"noise_floor_rise_db": [1.0, 1.2], "noise_floor_rise_range_db":
    ...                   [0.5, 0.5], "interference_to_noise_db": [20.0, float("nan")],
    ...                   "noise_floor_rise_unmitigated_db": [3.0, 3.2]})
    >>> s = floor_summary(f)
    >>> round(s["mitigation_floor_recovery_db"], 2), round(
    ...     s["mitigation_floor_recovery_fraction"], 3)
    (2.0, 0.645)
    """
    inr = floors["interference_to_noise_db"].to_numpy(dtype=float)
    out = {"noise_floor_rise_db": float(np.median(floors["noise_floor_rise_db"])),
           "noise_floor_rise_range_db": float(np.median(floors["noise_floor_rise_range_db"])),
           "interference_to_noise_db": float(np.nanmedian(inr)) if np.isfinite(inr).any()
           else float("nan")}
    if "noise_floor_rise_unmitigated_db" in floors:
        raw = float(np.median(floors["noise_floor_rise_unmitigated_db"]))
        rec = raw - out["noise_floor_rise_db"]
        out.update({"noise_floor_rise_unmitigated_db": raw, "mitigation_floor_recovery_db": rec,
                    "mitigation_floor_recovery_fraction": rec / raw
                    if raw >= MIN_RISE_TO_RECOVER_DB else float("nan"),
                    "mitigation_floor_recovery_fraction_worst_1s":
                    worst_window_recovery(floors) if "time_s" in floors else float("nan")})
    return out


def worst_window_recovery(floors: pd.DataFrame, window_s: float = WINDOW_S,
                          min_rise_db: float = WINDOW_MIN_RISE_DB) -> float:
    """The least recovered fraction of the floor rise over the run's `window_s` windows.

    A window starts at every processed frame and holds the frames within `window_s` of it; only
    windows the run covers whole count (the last frame at least `window_s` minus one frame
    spacing after the first), and of those the ones whose median unmitigated rise is at least
    `min_rise_db`. A window's recovery is (median unmitigated - median mitigated rise) /
    median unmitigated rise, in dB as `floor_summary`'s whole-run fraction.

    Parameters
    ----------
    floors : DataFrame
        ``time_s``, ``noise_floor_rise_db`` and ``noise_floor_rise_unmitigated_db`` per frame.
    window_s : float
        Window length, s.
    min_rise_db : float
        Least median unmitigated rise of a counted window, dB.

    Returns
    -------
    float
        NaN when no window counts.

    Examples
    --------
    >>> import pandas as pd
    >>> f = pd.DataFrame({"time_s": [0.0, 0.5, 1.0, 1.5],
    ...                   "noise_floor_rise_unmitigated_db": [3.0, 3.0, 3.0, 0.2],
    ...                   "noise_floor_rise_db": [2.0, 2.0, 0.0, 0.0]})
    >>> round(worst_window_recovery(f), 3)   # [0, 1) s: 1 dB of 3 recovered
    0.333
    """
    f = floors.sort_values("time_s")
    t = f["time_s"].to_numpy(dtype=float)
    raw = f["noise_floor_rise_unmitigated_db"].to_numpy(dtype=float)
    mit = f["noise_floor_rise_db"].to_numpy(dtype=float)
    if t.size < 2:
        return float("nan")
    dt = float(np.median(np.diff(t)))
    # frames of the window starting at frame i: [i, end[i]) (sorted times; a small tolerance
    # for times written as sums of frame periods)
    end = np.searchsorted(t, t + window_s - 1e-6 * window_s, side="left")
    whole = t + window_s - dt <= t[-1] + 1e-6 * window_s
    worst = float("nan")
    for i in np.flatnonzero(whole):  # one window per frame: tens, not samples or chirps
        u, m = float(np.median(raw[i:end[i]])), float(np.median(mit[i:end[i]]))
        if u >= min_rise_db:
            worst = min(worst, (u - m) / u) if np.isfinite(worst) else (u - m) / u
    return worst


def mitigation_stats(ghost_rate: float, ghost_rate_unmitigated: float) -> dict[str, float]:
    """``ghost_rate_unmitigated`` and ``mitigation_ghost_rate_added`` = ghost_rate minus it
    (the same frames processed with mitigation on and off).

    Examples
    --------
    >>> round(mitigation_stats(0.107, 0.003)["mitigation_ghost_rate_added"], 3)
    0.104
    """
    return {"ghost_rate_unmitigated": float(ghost_rate_unmitigated),
            "mitigation_ghost_rate_added": float(ghost_rate) - float(ghost_rate_unmitigated)}
