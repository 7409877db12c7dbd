"""Suite-wide headline scores: pooling weights checked on hand-made tables."""
from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from metrics.suite import aliased_runs, headline_table


def _summary():
    return pd.DataFrame({
        "scenario": ["a", "a", "b", "b", "c"], "variant": "v", "seed": 0,
        "scheme": ["ddma", "tdma", "ddma", "tdma", "ddma"],
        "n_detections": [100, 80, 50, 40, 7], "n_ghost": [10, 4, 0, 4, 7],
        "n_true": [80, 60, 40, 30, 0], "n_velocity_ambiguous": [0, 20, 10, 0, 0],
        "velocity_unambiguity_rate": [1.0, 0.75, 0.8, 1.0, np.nan],
        "n_velocity_right": [80, 60, 40, 30, 0],
        "n_velocity_resolution_failures": [0, 20, 10, 0, 0],
        "range_error_rmse_m": [0.3, 0.4, 0.6, 0.2, np.nan],
        "radial_velocity_error_rmse_mps": [0.1, 0.1, 0.2, 0.2, np.nan],
        "n_error_samples": [80, 60, 40, 30, 0], "error": ["", "", "", "", "boom"]})


def _actor_summary():
    return pd.DataFrame({
        "scheme": ["ddma", "ddma", "ddma", "tdma", "tdma", "tdma"],
        "actor_class": ["car", "car", "guard_rail", "car", "car", "guard_rail"],
        "n_visible_frames": [10, 30, 50, 10, 30, 50], "n_detected_frames": [10, 20, 50, 5, 0, 50],
        "first_detection_range_m": [100.0, 50.0, 10.0, 90.0, np.nan, 10.0]})


def test_pooling_weights():
    t = headline_table(_summary(), _actor_summary(), baseline="tdma",
                       verdicts={"ddma": "PASS"}).set_index("scheme")
    assert list(t.index) == ["ddma", "tdma"]
    # detected / visible actor-frames; guard rails are not actors
    assert t.loc["ddma", "pd_car"] == pytest.approx(30 / 40)
    assert "pd_guard_rail" not in t
    assert t.loc["tdma", "first_detection_range_car_m"] == 90.0
    assert t.loc["ddma", "first_detection_range_car_m"] == 75.0
    # RMSE pooled by error samples; the failed run (error) is left out
    assert t.loc["ddma", "range_rmse_m"] == pytest.approx(math.sqrt((80 * 0.09 + 40 * 0.36) / 120))
    assert t.loc["ddma", "ghost_rate"] == pytest.approx(10 / 150)
    # right / (right + failures) velocities over every run
    assert t.loc["tdma", "velocity_unambiguity_rate"] == pytest.approx((60 + 30) / 110)
    assert t.loc["ddma", "gates"] == "PASS" and t.loc["tdma", "gates"] == "-"


def test_infrastructure_rate_pooled_apart_and_aliased_runs_listed():
    s = _summary().assign(n_infrastructure_velocity_right=[100, 10, 0, 30, 0],
                          n_infrastructure_velocity_failures=[0, 30, 0, 10, 0])
    t = headline_table(s, _actor_summary(), baseline="tdma").set_index("scheme")
    assert t.loc["tdma", "infrastructure_velocity_unambiguity_rate"] == pytest.approx(40 / 80)
    # the road users' rate is unchanged by the rail counts
    assert t.loc["tdma", "velocity_unambiguity_rate"] == pytest.approx((60 + 30) / 110)
    s.loc[1, "velocity_unambiguity_rate"] = 0.2
    al = aliased_runs(s)
    assert al[["scenario", "scheme"]].values.tolist() == [["a", "tdma"]]
    assert aliased_runs(s, below=0.1).empty


def test_snr_gain_is_median_of_noise_limited_pairs():
    rows = []
    for frame, (snr_d, snr_t) in enumerate([(20.0, 14.0), (22.0, 17.0), (60.0, 40.0)]):
        for scheme, snr in (("ddma", snr_d), ("tdma", snr_t)):
            rows.append({"scenario": "a", "variant": "v", "seed": 0, "scheme": scheme,
                         "frame": frame, "actor_id": 0, "actor_class": "car", "range_m": 50.0,
                         "detected": True, "max_snr_db": snr})
    t = headline_table(_summary(), _actor_summary(), pd.DataFrame(rows),
                       baseline="tdma").set_index("scheme")
    assert t.loc["ddma", "snr_gain_over_tdma_db"] == pytest.approx(5.5)  # 6 and 5; not 20
    assert t.loc["ddma", "snr_gain_pairs"] == 2 and np.isnan(t.loc["tdma",
                                                                   "snr_gain_over_tdma_db"])
