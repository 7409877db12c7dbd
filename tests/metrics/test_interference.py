"""metrics.interference: the worst 1-second window's recovery beside the case median."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from metrics.interference import floor_summary, worst_window_recovery


def _floors(raw, mit, dt=0.05):
    n = len(raw)
    return pd.DataFrame({"time_s": np.arange(n) * dt, "noise_floor_rise_unmitigated_db": raw,
                         "noise_floor_rise_db": mit, "noise_floor_rise_range_db": 0.0,
                         "interference_to_noise_db": 15.0})


def test_a_weak_first_second_shows_beside_a_good_median():
    """The head-on pattern: 2.8 dB rise half recovered in the first second, fully later."""
    raw = np.r_[np.full(20, 2.8), np.full(40, 4.0)]
    mit = np.r_[np.full(20, 1.4), np.full(40, 0.0)]
    s = floor_summary(_floors(raw, mit))
    assert s["mitigation_floor_recovery_fraction"] == pytest.approx(1.0)
    assert s["mitigation_floor_recovery_fraction_worst_1s"] == pytest.approx(0.5)


def test_windows_below_the_rise_limit_and_partial_windows_do_not_count():
    raw = np.r_[np.full(20, 0.8), np.full(20, 3.0), np.full(10, 3.0)]
    mit = np.r_[np.full(20, 0.8), np.full(20, 0.3), np.full(10, 3.0)]
    # first second: 0.8 dB, nothing to recover; the last 10 frames (none recovered) start no
    # whole window of their own: the worst window is frames 30-49, mitigated median
    # (0.3 + 3.0) / 2
    got = worst_window_recovery(_floors(raw, mit))
    assert got == pytest.approx((3.0 - 1.65) / 3.0)
    # a 0.8 dB window alone would count 0 recovered, were the limit below its rise
    assert worst_window_recovery(_floors(raw, mit), min_rise_db=0.5) == pytest.approx(0.0)
    assert np.isnan(worst_window_recovery(_floors(np.full(30, 0.5), np.zeros(30))))


def test_a_run_shorter_than_a_window_has_no_worst_window():
    assert np.isnan(worst_window_recovery(_floors(np.full(10, 3.0), np.zeros(10))))


def test_without_frame_times_the_column_is_nan():
    f = _floors(np.full(30, 3.0), np.zeros(30)).drop(columns="time_s")
    assert np.isnan(floor_summary(f)["mitigation_floor_recovery_fraction_worst_1s"])
