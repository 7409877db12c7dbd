"""Track metrics on hand-built track and truth tables with values worked out by hand."""
from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from metrics.tracks import (
    TRACK_METRIC_COLUMNS,
    TrackMetricsConfig,
    gospa,
    gospa_per_frame,
    match_tracks,
    per_actor_track_metrics,
    track_metrics,
    track_metrics_long,
)

# ---------------------------------------------------------------------------------------------
# GOSPA (Rahmathullah et al. 2017, alpha = 2)


def test_gospa_empty_sets_is_zero():
    assert gospa(np.zeros((0, 2)), np.zeros((0, 2)))["gospa_m"] == 0.0


@pytest.mark.parametrize("c, p", [(10.0, 2.0), (5.0, 1.0), (3.0, 3.0)])
def test_gospa_one_missed_target(c, p):
    # One miss costs c^p / 2: d = c / 2^(1/p).
    out = gospa([[1.0, 2.0]], np.zeros((0, 2)), c, p)
    assert out["gospa_m"] == pytest.approx(c / 2 ** (1 / p))
    assert (out["n_missed"], out["n_false"], out["n_assigned"]) == (1, 0, 0)
    # A false track alone costs the same.
    assert gospa(np.zeros((0, 2)), [[1.0, 2.0]], c, p)["gospa_m"] == pytest.approx(c / 2 ** (1 / p))


@pytest.mark.parametrize("p", [1.0, 2.0])
def test_gospa_single_pair_is_euclidean_distance(p):
    out = gospa([[0.0, 0.0]], [[3.0, 4.0]], 10.0, p)
    assert out["gospa_m"] == pytest.approx(5.0) and out["localization_m"] == pytest.approx(5.0)


def test_gospa_pair_beyond_cutoff_is_miss_plus_false():
    out = gospa([[0.0, 0.0]], [[20.0, 0.0]], 10.0, 2.0)
    assert out["gospa_m"] == pytest.approx(10.0)      # (c^2/2 + c^2/2)^(1/2)
    assert (out["n_missed"], out["n_false"]) == (1, 1)


def test_gospa_optimal_assignment_and_cardinality():
    # Truth at 0 and 10, one estimate at 1: assigned to 0 at distance 1, one miss.
    out = gospa([[0.0, 0.0], [10.0, 0.0]], [[1.0, 0.0]], c_m=4.0, p=2.0)
    assert out["gospa_m"] == pytest.approx(math.sqrt(1.0 + 16.0 / 2))   # = 3
    # Swapped estimate order: the same optimal assignment.
    x, y = [[0.0, 0.0], [10.0, 0.0]], [[10.5, 0.0], [0.0, 1.0]]
    assert gospa(x, y, 4.0, 1.0)["gospa_m"] == pytest.approx(1.5)
    assert gospa(x, y[::-1], 4.0, 1.0)["gospa_m"] == pytest.approx(1.5)


def test_gospa_validation():
    with pytest.raises(ValueError, match="c_m"):
        gospa([[0.0, 0.0]], [[1.0, 0.0]], c_m=0.0)
    with pytest.raises(ValueError, match="p="):
        gospa([[0.0, 0.0]], [[1.0, 0.0]], p=0.5)


# ---------------------------------------------------------------------------------------------
# A hand-built run: one car approaching over 10 frames (0.1 s), a guard rail, three tracks.


def _truth() -> pd.DataFrame:
    f = np.arange(10)
    car = pd.DataFrame({"frame": f, "time_s": 0.1 * f, "actor_id": 0, "actor_class": "car",
                        "length_m": 4.5, "width_m": 1.8, "yaw_deg": 0.0,
                        "x_m": 50.0 - f, "y_m": 0.0, "vx_mps": -10.0, "vy_mps": 0.0,
                        "range_m": 50.0 - f + 2.0})
    rail = pd.DataFrame({"frame": f, "time_s": 0.1 * f, "actor_id": 5,
                         "actor_class": "guard_rail", "length_m": 100.0, "width_m": 0.3,
                         "yaw_deg": 0.0, "x_m": 20.0, "y_m": -8.0, "vx_mps": -10.0,
                         "vy_mps": 0.0, "range_m": 21.5})
    return pd.concat([car, rail], ignore_index=True)


def _tracks() -> pd.DataFrame:
    rows = []

    def add(frame, tid, state, x, y, vx=-9.0, vy=0.0):
        rows.append({"frame": frame, "time_s": 0.1 * frame, "track_id": tid, "state": state,
                     "x_m": x, "y_m": y, "vx_mps": vx, "vy_mps": vy})

    for f in range(10):
        car_x = 50.0 - f
        if f <= 5:       # track 3: DETECT 0-1, ACTIVE 2-5, offset (0.3, 0.4), dv = (1, 0)
            add(f, 3, "DETECT" if f < 2 else "ACTIVE", car_x + 0.3, 0.4)
        if f >= 7:       # frame 6 missed; track 9 takes over
            add(f, 9, "ACTIVE", car_x + 0.3, 0.4)
        add(f, 20, "ACTIVE", 20.0, -8.0)          # on the guard rail: false
        if f in (3, 4):
            add(f, 21, "ACTIVE", 100.0, 50.0)     # nowhere: false
    return pd.DataFrame(rows)


def test_per_actor_confirmation_and_continuity():
    out = per_actor_track_metrics(_tracks(), _truth())
    assert out.actor_id.tolist() == [0]            # the guard rail is not an actor
    row = out.iloc[0]
    assert row.actor_class == "car"
    assert row.track_confirm_time_s == pytest.approx(0.2)
    assert row.track_confirm_latency_s == pytest.approx(0.2)
    assert row.track_confirm_range_m == pytest.approx(50.0)   # truth range_m at frame 2
    assert row.n_track_ids == 2
    assert row.track_id_switches == 1
    assert row.track_fragmentations == 1
    assert row.track_coverage == pytest.approx(0.7)


def test_run_summary_values():
    m = track_metrics(_tracks(), _truth())
    assert list(m) == list(TRACK_METRIC_COLUMNS)
    assert m["n_frames"] == 10 and m["duration_s"] == pytest.approx(1.0)
    assert (m["n_actors"], m["n_actors_confirmed"]) == (1, 1)
    assert m["track_confirm_range_m_max"] == pytest.approx(50.0)
    assert (m["track_id_switches"], m["track_fragmentations"]) == (1, 1)
    assert m["n_false_tracks"] == 2
    assert m["false_tracks_per_min"] == pytest.approx(120.0)
    assert m["track_pos_rmse_m"] == pytest.approx(0.5)
    assert m["track_vel_rmse_mps"] == pytest.approx(1.0)
    # GOSPA (c = 10, p = 2): frames 0, 1, 6 miss the car and carry track 20 (10 m each);
    # frames 2, 5, 7-9 one match at 0.5 m plus track 20; frames 3-4 also track 21.
    want = (3 * 10.0 + 5 * math.sqrt(0.25 + 50) + 2 * math.sqrt(0.25 + 100)) / 10
    assert m["gospa_mean_m"] == pytest.approx(want)
    assert m["gospa_missed_per_frame"] == pytest.approx(0.3)
    assert m["gospa_false_per_frame"] == pytest.approx(1.2)
    assert m["gospa_localization_mean_m"] == pytest.approx(0.35)


def test_gospa_per_frame_table():
    g = gospa_per_frame(_tracks(), _truth(), TrackMetricsConfig(gospa_c_m=10.0, gospa_p=1.0))
    assert g.frame.tolist() == list(range(10))
    assert g.gospa_m.iloc[0] == pytest.approx(10.0)          # miss + false at p = 1: c/2 + c/2
    assert g.gospa_m.iloc[3] == pytest.approx(0.5 + 10.0)    # match + two false: 0.5 + 2 c/2


def test_including_detect_tracks_changes_confirmation():
    cfg = TrackMetricsConfig(confirmed_states=("DETECT", "ACTIVE"))
    row = per_actor_track_metrics(_tracks(), _truth(), cfg).iloc[0]
    assert row.track_confirm_time_s == pytest.approx(0.0)
    assert row.track_coverage == pytest.approx(0.9)


def test_truth_outside_field_of_view_cannot_be_missed():
    truth = _truth().assign(azimuth_deg=0.0)
    truth.loc[(truth.actor_id == 0) & (truth.frame < 3), "azimuth_deg"] = 95.0   # beyond 80
    row = per_actor_track_metrics(_tracks(), truth).iloc[0]
    assert row.n_frames == 7 and row.first_time_s == pytest.approx(0.3)
    # Confirmed at frame 2, just outside the nominal field of view: still the confirmation.
    assert row.track_confirm_time_s == pytest.approx(0.2)
    assert row.track_confirm_latency_s == pytest.approx(-0.1)
    assert row.track_coverage == pytest.approx(6 / 7)
    m = track_metrics(_tracks(), truth)
    assert m["n_false_tracks"] == 2                       # the track at frame 2 is not false
    assert m["gospa_missed_per_frame"] == pytest.approx(0.1)   # only frame 6 (0, 1 unseen)
    far = truth.assign(range_m=250.0)                      # everything beyond 200 m
    assert track_metrics(_tracks(), far)["n_actors"] == 0
    full = TrackMetricsConfig(fov_azimuth_deg=None, max_range_m=None)
    assert track_metrics(_tracks(), far, full)["n_actors"] == 1


def test_match_uses_footprint_gate():
    truth = pd.DataFrame({"frame": [0], "time_s": [0.0], "actor_id": [1], "x_m": [0.0],
                          "y_m": [0.0], "yaw_deg": [90.0], "length_m": [4.5], "width_m": [1.8],
                          "vx_mps": [0.0], "vy_mps": [0.0]})

    def matched(x, y, gate):
        trk = pd.DataFrame({"frame": [0], "time_s": [0.0], "track_id": [4], "state": ["ACTIVE"],
                            "x_m": [x], "y_m": [y], "vx_mps": [0.0], "vy_mps": [0.0]})
        return len(match_tracks(trk, truth, TrackMetricsConfig(match_gate_m=gate)))

    assert matched(0.0, 2.0, 0.1) == 1     # inside the box (length along y at yaw 90 deg)
    assert matched(2.0, 0.0, 1.2) == 1     # 2.0 - 0.9 = 1.1 m from the side
    assert matched(2.0, 0.0, 1.0) == 0


def test_id_swap_between_two_actors_counts_two_switches():
    f = np.repeat(np.arange(4), 2)
    truth = pd.DataFrame({"frame": f, "time_s": 0.1 * f, "actor_id": np.tile([0, 1], 4),
                          "x_m": np.tile([20.0, 40.0], 4), "y_m": 0.0, "vx_mps": 0.0,
                          "vy_mps": 0.0})
    tracks = pd.DataFrame({"frame": f, "time_s": 0.1 * f, "state": "ACTIVE",
                           "track_id": [1, 2, 1, 2, 2, 1, 2, 1],
                           "x_m": np.tile([20.0, 40.0], 4), "y_m": 0.0, "vx_mps": 0.0,
                           "vy_mps": 0.0})
    m = track_metrics(tracks, truth)
    assert m["track_id_switches"] == 2 and m["track_fragmentations"] == 0
    assert m["n_false_tracks"] == 0 and m["gospa_mean_m"] == 0.0


def test_two_actors_each_with_its_own_track_have_no_switch():
    """Per-actor identity counts stop at the actor boundary: the first match of actor 1 (track
    2) follows actor 0's matches (track 1) in the sorted table and is no switch, nor is it a
    resumed match (actor 1 is first matched at frame 1, after actor 0's hits); its gap at
    frame 2 is one fragmentation."""
    f = np.repeat(np.arange(5), 2)
    truth = pd.DataFrame({"frame": f, "time_s": 0.1 * f, "actor_id": np.tile([0, 1], 5),
                          "x_m": np.tile([20.0, 40.0], 5), "y_m": 0.0, "vx_mps": 0.0,
                          "vy_mps": 0.0})
    keep = ~(np.isin(f, [0, 2]) & (np.tile([0, 1], 5) == 1))  # actor 1 unmatched at 0, 2
    tracks = pd.DataFrame({"frame": f, "time_s": 0.1 * f, "state": "ACTIVE",
                           "track_id": np.tile([1, 2], 5), "x_m": np.tile([20.0, 40.0], 5),
                           "y_m": 0.0, "vx_mps": 0.0, "vy_mps": 0.0})[keep]
    out = per_actor_track_metrics(tracks, truth)
    assert out.track_id_switches.tolist() == [0, 0]
    assert out.n_track_ids.tolist() == [1, 1]
    assert out.track_fragmentations.tolist() == [0, 1]
    assert out.track_coverage.tolist() == [1.0, 0.6]


def test_no_tracks_gives_nan_scores_and_full_misses():
    tracks = _tracks().iloc[0:0]
    m = track_metrics(tracks, _truth())
    assert m["n_actors_confirmed"] == 0 and math.isnan(m["track_pos_rmse_m"])
    assert math.isnan(m["track_confirm_range_m_max"])
    assert m["gospa_mean_m"] == pytest.approx(10 / math.sqrt(2))
    assert m["n_false_tracks"] == 0 and m["false_tracks_per_min"] == 0.0


def test_long_form():
    long = track_metrics_long(_tracks(), _truth(), scenario="r79_motorcycle", seed=3,
                              scheme="ddma")
    assert list(long.columns) == ["scenario", "seed", "scheme", "metric", "value"]
    assert long.metric.tolist() == list(TRACK_METRIC_COLUMNS)
    assert long.set_index("metric").value["n_false_tracks"] == 2.0
    assert (long.scheme == "ddma").all()


def test_missing_columns_are_reported():
    with pytest.raises(ValueError, match="tracks is missing columns"):
        track_metrics(_tracks().drop(columns="state"), _truth())
    with pytest.raises(ValueError, match="truth is missing columns"):
        track_metrics(_tracks(), _truth().drop(columns="vx_mps"))


@pytest.mark.parametrize("field, value, match", [
    ("match_gate_m", 0.0, "match_gate_m"),
    ("gospa_c_m", float("nan"), "gospa_c_m"),
    ("gospa_p", 0.9, "gospa_p"),
    ("false_track_max_match_fraction", 1.5, "false_track_max_match_fraction"),
    ("frame_period_s", -0.1, "frame_period_s"),
    ("confirmed_states", "ACTIVE", "confirmed_states"),
    ("fov_azimuth_deg", 0.0, "fov_azimuth_deg"),
    ("max_range_m", -1.0, "max_range_m"),
])
def test_config_validation(field, value, match):
    with pytest.raises(ValueError, match=match):
        TrackMetricsConfig(**{field: value})
