"""Association of detections with truth actors on hand-built frames with known answers."""
from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from metrics.association import (
    CLUTTER,
    GHOST,
    TRUE,
    VELOCITY_AMBIGUOUS,
    AssociationConfig,
    _pairs,
    actor_frames,
    associate,
    detection_errors,
)

DDMA_SPAN = 2 * 40.88   # 2 Vmax of the R79 DDMA preset, m/s
TDMA_SPAN = 2 * 10.22


def actor(frame=0, actor_id=1, cls="car", x=50.0, y=0.0, yaw=0.0, length=4.0, width=2.0,
          vx=-20.0, vy=0.0):
    r = math.hypot(x, y)
    return dict(frame=frame, time_s=0.05 * frame, actor_id=actor_id, actor_class=cls,
                length_m=length, width_m=width, height_m=1.5, x_radar_m=x, y_radar_m=y,
                z_radar_m=0.0, yaw_radar_deg=yaw, vx_radar_mps=vx, vy_radar_mps=vy, range_m=r,
                azimuth_deg=math.degrees(math.atan2(y, x)),
                radial_velocity_mps=(vx * x + vy * y) / r)


def dets(rows):
    """rows of (frame, x, y, radial_velocity, snr)."""
    d = pd.DataFrame(rows, columns=["frame", "x_m", "y_m", "radial_velocity_mps", "snr_db"])
    d["range_m"] = np.hypot(d["x_m"], d["y_m"])
    d["azimuth_deg"] = np.degrees(np.arctan2(d["y_m"], d["x_m"]))
    return d


def labels(d, truth, span=DDMA_SPAN, **kw):
    return list(associate(d, pd.DataFrame(truth), velocity_span_mps=span, **kw)["label"])


def test_near_face_true_and_range_gate_one_cell():
    truth = [actor()]           # near face at x = 48 m
    d = dets([(0, 48.0, 0.0, -20.0, 20), (0, 46.6, 0.0, -20.0, 20), (0, 46.4, 0.0, -20.0, 20)])
    # 1.4 m in front of the face is inside the 1.5 m range gate, 1.6 m is not.
    assert labels(d, truth) == [TRUE, TRUE, GHOST]
    out = associate(d, pd.DataFrame(truth), velocity_span_mps=DDMA_SPAN)
    assert out["box_distance_m"].iloc[0] == pytest.approx(0.0)
    assert out["box_distance_m"].iloc[1] == pytest.approx(1.4)
    assert list(out["actor_id"]) == [1, 1, -1]


def test_cross_range_gate_grows_with_range():
    truth = [actor(x=50.0)]     # side face at y = +1 m; gate across = 50 tan(3 deg) = 2.62 m
    d = dets([(0, 50.0, 1.0 + 2.5, -20.0, 20), (0, 50.0, 1.0 + 2.8, -20.0, 20)])
    assert labels(d, truth) == [TRUE, GHOST]


def test_velocity_gate_and_ambiguity_multiples():
    truth = [actor()]
    d = dets([(0, 48.0, 0.0, -20.0 + 0.9, 20),        # inside the 1 m/s gate
              (0, 48.0, 0.0, -20.0 + 1.1, 20),        # wrong, not a multiple of 2 Vmax
              (0, 48.0, 0.0, -20.0 + DDMA_SPAN, 20),  # aliased by one DDMA span
              (0, 48.0, 0.0, -20.0 + 5.0, 20)])
    assert labels(d, truth) == [TRUE, GHOST, VELOCITY_AMBIGUOUS, GHOST]
    # TDMA: aliased by -2 spans of 20.44 m/s.
    d2 = dets([(0, 48.0, 0.0, -20.0 - 2 * TDMA_SPAN + 0.3, 20)])
    out = associate(d2, pd.DataFrame(truth), velocity_span_mps=TDMA_SPAN)
    assert out["label"].iloc[0] == VELOCITY_AMBIGUOUS
    assert out["velocity_alias_k"].iloc[0] == -2


def test_truth_velocity_at_nearest_box_point():
    # Car crossing at (30, 10) with vx = -10: radial velocity at the point (28, 9) of the box
    # nearest a detection at (27, 9) is (-10 * 28) / hypot(28, 9).
    truth = [actor(x=30.0, y=10.0, vx=-10.0, length=4.0, width=2.0)]
    d = dets([(0, 27.0, 9.5, -10 * 28 / math.hypot(28, 9.5), 20)])
    out = associate(d, pd.DataFrame(truth), velocity_span_mps=DDMA_SPAN)
    assert out["label"].iloc[0] == TRUE
    assert out["truth_radial_velocity_mps"].iloc[0] == pytest.approx(
        -10 * 28 / math.hypot(28, 9.5))


def test_rotated_footprint():
    # A 10 m long truck turned 90 deg at (30, 0) covers y in [-5, 5]; unrotated it would not.
    d = dets([(0, 30.0, 4.5, 0.0, 20)])
    assert labels(d, [actor(x=30, yaw=90, length=10, vx=0.0)]) == [TRUE]
    assert labels(d, [actor(x=30, yaw=0, length=10, vx=0.0)]) == [GHOST]


def test_guard_rail_is_clutter_and_road_user_wins():
    rail = actor(actor_id=9, cls="guard_rail", x=50.0, y=-3.0, length=200.0, width=0.3,
                 vx=-25.0)
    car = actor(x=50.0, y=-1.0, vx=-20.0)
    d = dets([(0, 60.0, -3.0, 7.0, 20),          # on the rail, any velocity -> CLUTTER
              (0, 48.5, -2.1, -20.0, 20),        # in both gates, car velocity -> TRUE
              (0, 90.0, 30.0, -20.0, 20)])       # nowhere -> GHOST
    out = associate(d, pd.DataFrame([rail, car]), velocity_span_mps=DDMA_SPAN)
    assert list(out["label"]) == [CLUTTER, TRUE, GHOST]
    assert list(out["actor_class"]) == ["guard_rail", "car", ""]


def test_nearest_of_two_actors_and_frames_do_not_mix():
    truth = [actor(actor_id=1, x=50, y=0), actor(actor_id=2, x=50, y=3.0),
             actor(frame=1, actor_id=1, x=49, y=0)]
    d = dets([(0, 48.0, 2.6, -20.0, 20), (0, 48.0, 0.2, -20.0, 20), (1, 60.0, 3.0, -20.0, 20)])
    out = associate(d, pd.DataFrame(truth), velocity_span_mps=DDMA_SPAN)
    assert list(out["actor_id"]) == [2, 1, -1]
    assert out["label"].iloc[2] == GHOST   # actor 2 exists in frame 0 only


def test_ground_clutter_from_scatterers():
    sc = pd.DataFrame({"frame": [0], "actor_id": [-2], "x_m": [10.0], "y_m": [2.0],
                       "z_m": [-0.5], "range_m": [10.2], "radial_velocity_mps": [-19.6],
                       "rcs_m2": [0.01]})
    # Same range-Doppler cell as the ground scatterer (angle smeared to the other side),
    # wrong velocity, wrong range.
    d = dets([(0, 10.5, 2.0, -19.5, 12), (0, 7.0, -7.5, -19.0, 12), (0, 10.5, 2.0, -10.0, 12),
              (0, 13.0, 2.0, -19.6, 12)])
    out = associate(d, pd.DataFrame([actor()]), velocity_span_mps=DDMA_SPAN, scatterers=sc)
    assert list(out["label"]) == [CLUTTER, CLUTTER, GHOST, GHOST]
    assert out["actor_class"].iloc[0] == "ground"


def test_empty_detections_and_no_truth():
    empty = dets([])
    out = associate(empty, pd.DataFrame([actor()]), velocity_span_mps=DDMA_SPAN)
    assert len(out) == 0 and "label" in out
    d = dets([(0, 48.0, 0.0, -20.0, 20)])
    truth = pd.DataFrame([actor()]).iloc[:0]
    assert labels(d, truth) == [GHOST]


def test_detection_errors_nearest_scatterer_and_box_fallback():
    truth = pd.DataFrame([actor(), actor(frame=1)])
    sc = pd.DataFrame({"frame": [0, 0], "actor_id": [1, 1], "x_m": [48.0, 48.0],
                       "y_m": [0.5, -0.5], "z_m": [0.0, 0.0],
                       "range_m": [math.hypot(48, 0.5)] * 2,
                       "radial_velocity_mps": [-19.9, -19.8], "rcs_m2": [1.0, 1.0]})
    d = dets([(0, 48.2, 0.4, -19.85, 20), (1, 47.8, 0.0, -20.1, 20)])
    lab = associate(d, truth, velocity_span_mps=DDMA_SPAN)
    out = detection_errors(lab, truth, sc)
    assert out["range_error_m"].iloc[0] == pytest.approx(math.hypot(48.2, 0.4) -
                                                         math.hypot(48, 0.5))
    assert out["radial_velocity_error_mps"].iloc[0] == pytest.approx(-19.85 + 19.9)
    assert out["error_reference"].iloc[0] == "scatterer"
    # Frame 1 has no scatterers: reference = nearest box point (48, 0), truth v = -20.
    assert out["range_error_m"].iloc[1] == pytest.approx(-0.2)
    assert out["radial_velocity_error_mps"].iloc[1] == pytest.approx(-0.1)
    assert out["error_reference"].iloc[1] == "box"


def test_one_detection_detects_one_actor():
    # Two motorcycles side by side at 40 m; one detection between them passes both gates.
    truth = pd.DataFrame([actor(actor_id=1, cls="motorcycle", x=40, y=0.6, length=2.2,
                                width=0.8, vx=-10),
                          actor(actor_id=2, cls="motorcycle", x=40, y=-0.6, length=2.2,
                                width=0.8, vx=-10)])
    one = associate(dets([(0, 38.9, 0.0, -10.0, 20)]), truth, velocity_span_mps=DDMA_SPAN)
    af = actor_frames(one, truth)
    assert af["detected"].sum() == 1
    two = associate(dets([(0, 38.9, 0.5, -10.0, 20), (0, 38.9, -0.5, -10.0, 18)]), truth,
                    velocity_span_mps=DDMA_SPAN)
    af2 = actor_frames(two, truth)
    assert af2["detected"].all()
    assert list(af2["max_snr_db"]) == [20, 18]


def test_visibility_fov_and_occlusion():
    truth = pd.DataFrame([actor(actor_id=1, x=50, y=0), actor(actor_id=2, x=5, y=40),
                          actor(actor_id=3, x=60, y=5)])
    lab = associate(dets([]), truth, velocity_span_mps=DDMA_SPAN)
    sc = pd.DataFrame({"frame": [0, 0], "actor_id": [1, 2], "rcs_m2": [1.0, 1.0]})
    af = actor_frames(lab, truth, scatterers=sc).set_index("actor_id")
    # 2 is at azimuth 83 deg (outside +/-80), 3 has no scatterer (occluded).
    assert list(af["visible"]) == [True, False, False]
    assert not af["detected"].any()


@pytest.mark.parametrize("field,value,match", [
    ("range_gate_m", 0.0, "range_gate_m"),
    ("velocity_gate_mps", -1.0, "velocity_gate_mps"),
    ("azimuth_gate_deg", 90.0, "azimuth_gate_deg"),
    ("pd_min_count", 0, "pd_min_count"),
    ("pd_range_bin_m", float("nan"), "pd_range_bin_m"),
])
def test_config_validation(field, value, match):
    with pytest.raises(ValueError, match=match):
        AssociationConfig(**{field: value})


def test_bad_inputs():
    d = dets([(0, 48.0, 0.0, -20.0, 20)])
    with pytest.raises(ValueError, match="velocity_span_mps"):
        associate(d, pd.DataFrame([actor()]), velocity_span_mps=0.0)
    with pytest.raises(ValueError, match="detections lacks column"):
        associate(d.drop(columns="x_m"), pd.DataFrame([actor()]), velocity_span_mps=1.0)
    with pytest.raises(ValueError, match="truth lacks column"):
        associate(d, pd.DataFrame([actor()]).drop(columns="yaw_radar_deg"),
                  velocity_span_mps=1.0)


def test_gated_pairs_keep_every_pair_in_the_position_gate():
    """`associate` builds only the pairs whose detection can reach the gate (`_gate_reach`):
    on random yawed boxes with detections scattered around them, at every range, every pair
    with pos_cost <= 1 is kept, in the same order and with the same values."""
    g = np.random.default_rng(7)
    truth = pd.DataFrame([actor(frame=f, actor_id=i, x=g.uniform(-150, 150),
                                y=g.uniform(-150, 150), yaw=g.uniform(-180, 180),
                                length=g.uniform(0.5, 40.0), width=g.uniform(0.3, 3.0))
                          for f in range(3) for i in range(12)])
    near = truth.sample(600, replace=True, random_state=1)
    d = dets([(int(r.frame), r.x_radar_m + g.normal(0, r.length_m / 2 + 2),
               r.y_radar_m + g.normal(0, r.length_m / 2 + 2), g.uniform(-30, 30), 10)
              for r in near.itertuples()])
    cfg = AssociationConfig()
    every = _pairs(d, truth, cfg, DDMA_SPAN)
    gated = _pairs(d, truth, cfg, DDMA_SPAN, gated=True)
    in_gate = every[every["pos_cost"].to_numpy() <= 1.0]
    assert 0 < len(in_gate) < len(gated) < len(every) / 2
    pd.testing.assert_frame_equal(gated[gated["pos_cost"].to_numpy() <= 1.0].reset_index(
        drop=True), in_gate.reset_index(drop=True), check_exact=True)
