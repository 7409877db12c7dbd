"""Detection metrics on hand-built labelled tables with known answers."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from metrics.association import CLUTTER, GHOST, TRUE, AssociationConfig
from metrics.detection import (
    actor_detection,
    error_stats,
    ghost_stats,
    max_range_pd90,
    pd_vs_range,
    snr_gain_pairs,
    snr_gain_stats,
    summarize_scheme,
    target_first_detection_range_m,
    velocity_stats,
)


def labelled(labels, range_err=None, vel_err=None, v_true=None):
    n = len(labels)
    return pd.DataFrame({
        "frame": np.arange(n), "label": labels, "snr_db": 20.0,
        "range_error_m": np.full(n, np.nan) if range_err is None else range_err,
        "radial_velocity_error_mps": np.full(n, np.nan) if vel_err is None else vel_err,
        "truth_radial_velocity_mps": np.zeros(n) if v_true is None else v_true})


def test_error_stats_rmse_and_p95():
    er = np.array([0.1, -0.2, 0.3, -0.4, np.nan])
    ev = np.array([0.01, 0.02, -0.03, 0.04, np.nan])
    lab = labelled([TRUE] * 4 + [GHOST], er, ev)
    s = error_stats(lab)
    assert s["range_error_rmse_m"] == pytest.approx(np.sqrt(np.mean(er[:4] ** 2)))
    assert s["range_error_p95_m"] == pytest.approx(np.percentile(np.abs(er[:4]), 95))
    assert s["radial_velocity_error_rmse_mps"] == pytest.approx(np.sqrt(np.mean(ev[:4] ** 2)))
    assert s["n_error_samples"] == 4
    assert np.isnan(error_stats(labelled([GHOST]))["range_error_rmse_m"])


def test_velocity_stats_count_every_checked_detection_and_the_window():
    v = np.r_[np.full(99, 30.0), 35.0, 60.0]
    lab = labelled([TRUE] * 99 + [GHOST, GHOST], v_true=v)
    # The velocity check, not the 2D label, decides: the two ghosts are aliased echoes.
    lab["velocity_check"] = ["right"] * 99 + ["failure", "failure"]
    lab["velocity_truth_mps"] = v
    s = velocity_stats(lab, 40.8)
    assert s["velocity_unambiguity_rate"] == pytest.approx(99 / 101)
    # The 60 m/s failure lies outside the +/-40.8 m/s window of the in-span rate.
    assert s["velocity_unambiguity_rate_in_span"] == pytest.approx(0.99)
    assert s["n_velocity_resolution_failures"] == 2
    none = labelled([GHOST]).assign(velocity_check="", velocity_truth_mps=np.nan)
    assert np.isnan(velocity_stats(none, 40.8)["velocity_unambiguity_rate"])


def test_velocity_stats_keep_infrastructure_out_of_the_road_user_rate():
    lab = labelled([TRUE, TRUE, CLUTTER, CLUTTER, CLUTTER], v_true=np.zeros(5))
    lab["velocity_check"] = ["failure", "right", "right", "right", "failure"]
    lab["velocity_truth_mps"] = [50.0, 10.0, -25.0, -25.0, -25.0]
    lab["velocity_on_infrastructure"] = [False, False, True, True, True]
    s = velocity_stats(lab, 40.8)
    assert s["velocity_unambiguity_rate"] == 0.5
    assert (s["n_velocity_right"], s["n_velocity_resolution_failures"]) == (1, 1)
    assert s["infrastructure_velocity_unambiguity_rate"] == pytest.approx(2 / 3)
    assert (s["n_infrastructure_velocity_right"], s["n_infrastructure_velocity_failures"]) \
        == (2, 1)


def test_ghost_stats():
    lab = labelled([TRUE, GHOST, GHOST, CLUTTER, TRUE])
    s = ghost_stats(lab, n_frames=4)
    assert s["ghost_rate"] == pytest.approx(2 / 5)
    assert s["ghosts_per_frame"] == pytest.approx(0.5)
    assert s["clutter_per_frame"] == pytest.approx(0.25)
    assert s["detections_per_frame"] == pytest.approx(1.25)


def actor_frames_table():
    # Actor 1 approaches from 100 m, visible in 4 frames, detected in frames 1, 2, 3;
    # actor 2 is never detected.
    return pd.DataFrame({
        "frame": [0, 1, 2, 3, 0, 1], "time_s": [0, .05, .1, .15, 0, .05],
        "actor_id": [1, 1, 1, 1, 2, 2], "actor_class": ["motorcycle"] * 4 + ["car"] * 2,
        "range_m": [100.0, 98.0, 96.0, 94.0, 30.0, 30.0],
        "visible": [True, True, True, True, True, False],
        "detected": [False, True, True, True, False, False],
        "max_snr_db": [np.nan, 20, 21, 22, np.nan, np.nan]})


def test_actor_detection_pd_and_first_range():
    a = actor_detection(actor_frames_table()).set_index("actor_id")
    assert a.loc[1, "detection_probability"] == pytest.approx(0.75)
    assert a.loc[1, "first_detection_range_m"] == pytest.approx(98.0)
    assert a.loc[1, "first_detection_time_s"] == pytest.approx(0.05)
    assert a.loc[2, "detection_probability"] == 0.0
    assert np.isnan(a.loc[2, "first_detection_range_m"])
    assert target_first_detection_range_m(a.reset_index(), target_classes=["motorcycle"]) == 98.0
    # Every target must be detected: an undetected one makes the case value NaN.
    assert np.isnan(target_first_detection_range_m(a.reset_index()))


def test_first_detection_range_needs_a_true_detection():
    af = actor_frames_table().assign(n_ambiguous=[1, 0, 0, 0, 0, 0])
    a = actor_detection(af).set_index("actor_id")
    # Frame 0 has only a velocity-aliased detection: the first detection is at 98 m.
    assert a.loc[1, "first_detection_range_m"] == 98.0
    assert "first_association_range_m" not in a


def test_pd_vs_range_and_max_range_pd90():
    rng_m = np.r_[np.full(10, 5.0), np.full(20, 15.0), np.full(10, 25.0), np.full(2, 35.0)]
    det = np.r_[np.ones(10, bool), np.arange(20) < 19, np.arange(10) < 5, np.ones(2, bool)]
    af = pd.DataFrame({"actor_class": "car", "range_m": rng_m, "visible": True,
                       "detected": det})
    t = pd_vs_range(af, 10.0)
    assert list(t["range_lo_m"]) == [0, 10, 20, 30]
    assert list(t["detection_probability"]) == pytest.approx([1.0, 0.95, 0.5, 1.0])
    # The 30-40 m bin has only 2 frames (< 5): the farthest bin with Pd >= 0.9 is 10-20 m.
    assert max_range_pd90(t, min_count=5) == {"car": 20.0}
    assert max_range_pd90(t, min_count=1) == {"car": 40.0}


def test_snr_gain_pairs_same_actor_and_frame():
    af = actor_frames_table()
    both = pd.concat([af.assign(scheme="ddma", max_snr_db=af["max_snr_db"] + 5.4),
                      af.assign(scheme="tdma").iloc[:3]])
    pairs = snr_gain_pairs(both, "ddma", "tdma")
    # Frames 1 and 2 are detected by both (frame 3 is missing in TDMA).
    assert list(pairs["frame"]) == [1, 2]
    s = snr_gain_stats(pairs, min_pairs=2)
    assert s["snr_gain_median_db"] == pytest.approx(5.4)
    assert s["snr_gain_std_db"] == pytest.approx(0.0, abs=1e-12)
    assert s["snr_gain_n"] == 2
    assert list(pairs["reference_snr_db"]) == [20, 21]
    assert s["snr_gain_noise_limited_median_db"] == pytest.approx(5.4)
    one = snr_gain_stats(pairs, noise_limited_snr_db=20.5, min_pairs=2)
    assert one["snr_gain_noise_limited_n"] == 1
    assert np.isnan(one["snr_gain_noise_limited_median_db"])  # too few pairs for a median
    assert np.isnan(snr_gain_stats(pairs.iloc[:0])["snr_gain_median_db"])


def test_summarize_scheme_columns_have_units():
    lab = labelled([TRUE, GHOST], np.array([0.1, np.nan]), np.array([0.02, np.nan]))
    lab["actor_id"] = [1, -1]
    lab["velocity_check"] = ["right", ""]
    lab["velocity_truth_mps"] = [5.0, np.nan]
    row = summarize_scheme(lab, actor_frames_table(), 4, AssociationConfig(pd_min_count=1),
                           target_classes=["motorcycle"])
    assert row["n_true"] == 1 and row["n_ghost"] == 1
    assert row["target_first_detection_range_m"] == 98.0
    assert row["detection_probability_min"] == 0.0
    unitless = {"velocity_unambiguity_rate", "velocity_unambiguity_rate_in_span", "ghost_rate",
                "infrastructure_velocity_unambiguity_rate",
                "ghosts_per_frame",
                "clutter_per_frame", "detections_per_frame", "detection_probability_mean",
                "detection_probability_min"}
    for k in row:
        assert k.startswith("n_") or k in unitless or k.endswith(("_m", "_mps", "_db",
                                                                 "_deg")), k
