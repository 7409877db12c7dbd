"""metrics.scoring: aliased echoes relabelled, the R79 verdict from the case's speeds."""
from __future__ import annotations

from types import SimpleNamespace as NS

import numpy as np
import pandas as pd
import pytest

from metrics.association import TRUE, VELOCITY_AMBIGUOUS, AssociationConfig
from metrics.r79 import KMH
from metrics.scoring import CaseInfo, case_info, label_detections, score_scheme


def truth_row(frame, range_m=60.0, v_mps=-14.0):
    # a motorcycle straight ahead, approaching at 14 m/s relative
    return {"frame": frame, "time_s": frame * 0.05, "actor_id": 0, "actor_class": "motorcycle",
            "length_m": 2.2, "width_m": 0.8, "x_radar_m": range_m, "y_radar_m": 0.0,
            "yaw_radar_deg": 180.0, "vx_radar_mps": v_mps, "vy_radar_mps": 0.0,
            "range_m": range_m, "azimuth_deg": 0.0, "radial_velocity_mps": v_mps}


def tables(aliased: bool):
    truth = pd.DataFrame([truth_row(f, 60.0 - f) for f in range(4)])
    sc = pd.DataFrame({"frame": range(4), "actor_id": 0, "x_m": truth["x_radar_m"] - 1.1,
                       "y_m": 0.0, "z_m": 0.5, "range_m": truth["range_m"] - 1.1,
                       "radial_velocity_mps": -14.0, "rcs_m2": 1.0})
    # TDMA without disambiguation reports -14 + 20.44 and, with the wrong Doppler-phase
    # compensation, an azimuth 30 deg off: outside the 2D footprint gate
    v = -14.0 + (20.44 if aliased else 0.0)
    az = np.radians(30.0 if aliased else 0.0)
    r = sc["range_m"].to_numpy()
    det = pd.DataFrame({"frame": range(4), "range_m": r, "azimuth_deg": np.degrees(az),
                        "x_m": r * np.cos(az), "y_m": r * np.sin(az), "radial_velocity_mps": v,
                        "snr_db": 20.0})
    return det, truth, sc


def test_aliased_echoes_are_velocity_failures_not_ghosts():
    det, truth, sc = tables(aliased=True)
    cfg = AssociationConfig()
    lab = label_detections(det, truth, sc, velocity_span_mps=20.44, failure_step_mps=20.44,
                           config=cfg)
    assert (lab["label"] == VELOCITY_AMBIGUOUS).all() and (lab["actor_id"] == 0).all()
    assert lab["velocity_resolution_failure"].all()
    s = score_scheme(lab, truth, sc, 4, cfg, CaseInfo(target_ids=[0]))
    assert s.row["n_ghost"] == 0 and s.row["ghost_rate"] == 0.0
    assert s.row["velocity_unambiguity_rate"] == 0.0
    assert np.isnan(s.row["target_first_detection_range_m"])


def test_r79_verdict_from_the_case_speeds():
    det, truth, sc = tables(aliased=False)
    cfg = AssociationConfig()
    lab = label_detections(det, truth, sc, velocity_span_mps=81.8, failure_step_mps=13.63,
                           config=cfg)
    assert (lab["label"] == TRUE).all()
    case = NS(must_detect=(0,), criteria=(), case_class="r79", ego=NS(speed_mps=80 * KMH),
              actors=(NS(speed_mps=130 * KMH),))
    s = score_scheme(lab, truth, sc, 4, cfg, case_info(case))
    assert s.row["s_critical_m"] == pytest.approx(59.9, abs=0.05)
    assert s.row["target_first_detection_range_m"] == 60.0
    assert s.row["r79_pass"] == 1.0 and s.row["case_class"] == "r79"
    far = case_info(NS(must_detect=(0,), criteria=(), case_class="r79",
                       ego=NS(speed_mps=60 * KMH), actors=(NS(speed_mps=130 * KMH),)))
    assert score_scheme(lab, truth, sc, 4, cfg, far).row["r79_pass"] == 0.0  # needs 87.5 m
    ordinary = score_scheme(lab, truth, sc, 4, cfg, case_info(None)).row
    assert "r79_pass" not in ordinary and ordinary["case_class"] == "ordinary"


def test_aliased_static_clutter_is_clutter_and_a_velocity_failure():
    """Raw TDMA on a moving ego: a guard rail at -20 m/s comes out at +0.44 m/s and, through
    the wrong Doppler-phase compensation, at a wrong angle. It is modelled infrastructure
    aliased by one span 2 Vmax: clutter, and a velocity-resolution failure."""
    det, truth, sc = tables(aliased=False)
    rail = {**truth_row(0, 30.0, -20.0), "actor_id": 5, "actor_class": "guard_rail",
            "length_m": 16.0, "width_m": 0.3, "y_radar_m": 5.0}
    truth = pd.concat([truth, pd.DataFrame([rail])], ignore_index=True)
    sc = pd.concat([sc, pd.DataFrame({"frame": [0], "actor_id": [5], "x_m": [29.6],
                                      "y_m": [5.0], "z_m": [0.5], "range_m": [30.0],
                                      "radial_velocity_mps": [-20.0], "rcs_m2": [1.0]})],
                   ignore_index=True)
    ghost = pd.DataFrame({"frame": [0], "range_m": [30.3], "azimuth_deg": [-40.0],
                          "x_m": [23.2], "y_m": [-19.5], "radial_velocity_mps": [0.44],
                          "snr_db": [15.0]})
    cfg = AssociationConfig()
    lab = label_detections(pd.concat([det, ghost], ignore_index=True), truth, sc,
                           velocity_span_mps=20.44, failure_step_mps=20.44, config=cfg)
    last = lab.iloc[-1]
    assert last["label"] == "CLUTTER" and last["actor_id"] == 5
    assert last["velocity_check"] == "failure" and last["velocity_step_k"] == 1
    assert (lab["label"].iloc[:-1] == TRUE).all()
    assert last["velocity_on_infrastructure"] and not lab["velocity_on_infrastructure"].iloc[
        :-1].any()
    s = score_scheme(lab, truth, sc, 4, cfg, CaseInfo(target_ids=[0]))
    # the rail's failure is infrastructure's, not a road user's
    assert s.row["n_ghost"] == 0 and s.row["n_velocity_resolution_failures"] == 0
    assert s.row["velocity_unambiguity_rate"] == 1.0
    assert s.row["n_infrastructure_velocity_failures"] == 1
    assert s.row["infrastructure_velocity_unambiguity_rate"] == 0.0


def test_right_guard_rail_points_do_not_hide_an_aliased_road_user():
    """Head-on beyond the span: the car's echoes all alias while many guard-rail points,
    static inside the span, are right. The road users' rate shows the aliasing; the rail's
    right velocities are counted in the infrastructure columns only."""
    det, truth, sc = tables(aliased=True)
    rail = {**truth_row(0, 30.0, -20.0), "actor_id": 5, "actor_class": "guard_rail",
            "length_m": 16.0, "width_m": 0.3, "y_radar_m": 5.0}
    truth = pd.concat([truth, pd.DataFrame([rail])], ignore_index=True)
    sc = pd.concat([sc, pd.DataFrame({"frame": [0], "actor_id": [5], "x_m": [29.6],
                                      "y_m": [5.0], "z_m": [0.5], "range_m": [30.0],
                                      "radial_velocity_mps": [-20.0], "rcs_m2": [1.0]})],
                   ignore_index=True)
    n_rail = 40
    rails = pd.DataFrame({"frame": 0, "range_m": np.linspace(29.8, 30.2, n_rail),
                          "azimuth_deg": 9.5, "x_m": 29.6, "y_m": 5.0,
                          "radial_velocity_mps": -20.0, "snr_db": 15.0})
    cfg = AssociationConfig()
    lab = label_detections(pd.concat([det, rails], ignore_index=True), truth, sc,
                           velocity_span_mps=81.8, failure_step_mps=20.44, config=cfg)
    s = score_scheme(lab, truth, sc, 4, cfg, CaseInfo(target_ids=[0])).row
    assert s["velocity_unambiguity_rate"] == 0.0 and s["n_velocity_resolution_failures"] == 4
    assert s["n_velocity_right"] == 0
    assert s["n_infrastructure_velocity_right"] == n_rail
    assert s["infrastructure_velocity_unambiguity_rate"] == 1.0


def _joined_gain_pairs(af, a, b):
    """The pandas formulation of the pairs: both schemes' detected actor-frames indexed by
    (frame, actor_id), inner join."""
    key = ["frame", "actor_id"]
    da = af[(af["scheme"] == a) & af["detected"]].set_index(key)
    db = af[(af["scheme"] == b) & af["detected"]].set_index(key)
    j = da[["actor_class", "range_m", "max_snr_db"]].join(
        db[["max_snr_db"]].rename(columns={"max_snr_db": "reference_snr_db"}), how="inner")
    j["snr_gain_db"] = j["max_snr_db"] - j["reference_snr_db"]
    return j.reset_index()[["frame", "actor_id", "actor_class", "range_m", "reference_snr_db",
                            "snr_gain_db"]]


def test_gain_pairs_are_the_inner_join_in_its_order():
    """detection.snr_gain_pairs, and add_snr_gains' two pair columns, equal an inner join of
    the two schemes' detected actor-frames (same rows, same order: scheme a's detected
    actor-frames in table order that b detected too), shuffled tables, pairs only one scheme
    detected, a scheme without rows."""
    from metrics.detection import snr_gain_pairs
    from metrics.scoring import _gain_pairs
    g = np.random.default_rng(4)
    rows = [{"scheme": s, "frame": f, "actor_id": a, "actor_class": "car", "range_m": 10.0 + f,
             "detected": bool(g.random() < 0.7), "max_snr_db": float(g.uniform(5, 40))}
            for s in ("ddma", "tdma") for f in range(6) for a in (3, 1, 7)]
    af = pd.DataFrame(rows).sample(frac=1.0, random_state=1).reset_index(drop=True)
    for a, b in (("ddma", "tdma"), ("tdma", "ddma"), ("ddma", "none")):
        want = _joined_gain_pairs(af, a, b)
        got = snr_gain_pairs(af, a, b)
        assert len(want) > 0 or b == "none"
        pd.testing.assert_frame_equal(got, want, check_index_type=False)
        two = _gain_pairs(af, a, b)
        for col in ("snr_gain_db", "reference_snr_db"):
            np.testing.assert_array_equal(two[col].to_numpy(), want[col].to_numpy())


