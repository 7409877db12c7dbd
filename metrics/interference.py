"""Interference scores of one scheme: the noise floor with and without mitigation, and the
ghosts the mitigation adds.

An interference case exists to show three things (issue 21): the floor rise the interferers
cause without mitigation, how much of it the mitigation recovers, and that the mitigation adds
no ghosts (zeroing samples modulates every echo in slow time, which spreads strong echoes over
Doppler). The noise floors come per frame from the pipeline (`pipeline.chirp_level.
noise_floor_rise`, wired by the harness); these functions only reduce the tables.

References
----------
.. [1] TI SWRA725, "Interference Mitigation for AWR294x" (2021).
.. [2] DESIGN.md section 7 (noise-floor rise over thermal, interference-to-noise ratio).
"""
from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["floor_summary", "mitigation_stats", "MIN_RISE_TO_RECOVER_DB"]

#: Below this unmitigated floor rise, dB, there is nothing to recover: the recovered fraction
#: is NaN (a 0.1 dB rise measured to +/- 0.05 dB would make the fraction noise).
MIN_RISE_TO_RECOVER_DB = 0.5


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
        ``mitigation_floor_recovery_db`` (unmitigated minus mitigated median) and
        ``mitigation_floor_recovery_fraction`` (that over the unmitigated rise; NaN below
        `MIN_RISE_TO_RECOVER_DB`).

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
                    if raw >= MIN_RISE_TO_RECOVER_DB else float("nan")})
    return out


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
