"""highway-env traffic: scripted kinematics, random traffic, determinism, every case runs."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from scenarios import MOUNTS, SCENARIOS, run_scenario
from scenarios.catalog import ActorSpec, Case
from scenarios.traffic import IDM_CLASSES, RAIL_ID_BASE, RANDOM_ID_BASE, VEHICLE_CLASSES


def _case(*actors, ego=None, duration_s=4.0, road="highway", mount="rear_left"):
    return Case(name="t", description="test", mount=MOUNTS[mount], duration_s=duration_s,
                road=road, ego=ego or ActorSpec(path="lane_1", speed_mps=20.0),
                actors=tuple(actors))


def test_constant_speed_distance_is_analytic():
    """Like highway-env's own test: 20 m/s for 2 s is 40 m (here: relative 10 m/s -> 20 m)."""
    run = run_scenario(_case(ActorSpec(path="lane_0", s_m=-50.0, speed_mps=30.0),
                             duration_s=2.05))
    t = run.truth[run.truth.actor_id == 0].set_index("frame")
    assert run.n_frames == 41
    assert t.loc[40, "x_m"] - t.loc[0, "x_m"] == pytest.approx(20.0, abs=1e-9)


def test_scripted_braking_stops_at_v2_over_2a():
    run = run_scenario(_case(ActorSpec(path="lane_1", s_m=30.0, speed_mps=20.0,
                                       brake_time_s=0.5, brake_decel_mps2=5.0),
                             ego=ActorSpec(path="lane_1", s_m=0.0, speed_mps=0.0),
                             duration_s=6.0))
    t = run.truth[run.truth.actor_id == 0]
    travelled = t.x_m.iloc[-1] - t.x_m.iloc[0]
    assert travelled == pytest.approx(20.0 * 0.5 + 20.0 ** 2 / (2 * 5.0), abs=1e-6)
    assert t.vx_mps.iloc[-1] == pytest.approx(0.0, abs=1e-12)


def test_scripted_lane_change_moves_left():
    run = run_scenario(_case(ActorSpec(path="lane_2", s_m=20.0, speed_mps=20.0,
                                       lane_change_time_s=0.5, lane_change_left_m=4.0,
                                       lane_change_duration_s=2.0), duration_s=3.0))
    t = run.truth[run.truth.actor_id == 0]
    assert t.y_m.iloc[0] == pytest.approx(-4.0)          # right lane: y = -4 m (ISO)
    assert t.y_m.iloc[-1] == pytest.approx(0.0, abs=1e-9)  # now in the ego's lane
    assert t.vy_mps.max() > 0.5                            # moving left (+y) meanwhile
    assert t.yaw_deg.max() > 0.5                           # heading turned left (CCW)


def test_meet_ego_puts_actor_on_collision_course():
    run = run_scenario("cccscp_crossing", duration_s=6.0)
    t = run.truth[run.truth.actor_id == 0]
    # The crossing car's straight path passes within 1 m of the ego position: the miss
    # distance of the relative track (position x velocity / speed, ego-relative) at the
    # nearest frame. Sampled distances alone could be off by half a frame's travel (~0.5 m).
    k = np.hypot(t.x_m, t.y_m).to_numpy().argmin()
    x, y, vx, vy = (t[c].to_numpy()[k] for c in ("x_m", "y_m", "vx_mps", "vy_mps"))
    assert abs(x * vy - y * vx) / np.hypot(vx, vy) < 1.0


def test_reversing_ego(catalogue_run):
    run = catalogue_run("reversing_pedestrian")
    assert np.all(run.ego.ego_speed_mps < 0)
    assert run.ego.ego_x_m.iloc[-1] < run.ego.ego_x_m.iloc[0]


def test_new_classes_have_their_sizes():
    for name, cls in VEHICLE_CLASSES.items():
        assert cls.ACTOR_CLASS == name
    assert VEHICLE_CLASSES["motorcycle"].LENGTH == 2.2
    assert VEHICLE_CLASSES["motorcycle"].WIDTH == 0.8
    assert VEHICLE_CLASSES["truck"].LENGTH == pytest.approx(16.5)
    assert VEHICLE_CLASSES["pedestrian"].MAX_SPEED <= 4.0
    assert IDM_CLASSES["truck"].LENGTH == pytest.approx(16.5)


def test_random_traffic_mixes_classes_and_ids():
    run = run_scenario("dense_highway", seed=1)
    t = run.truth
    mv = t[t.actor_class != "guard_rail"]
    assert mv.actor_id.min() >= RANDOM_ID_BASE
    assert t[t.actor_class == "guard_rail"].actor_id.min() >= RAIL_ID_BASE
    assert {"car", "truck"} <= set(mv.actor_class)
    trucks = mv[mv.actor_class == "truck"]
    np.testing.assert_allclose(trucks.length_m, 16.5)
    # Stable ids: each id keeps its class over the run.
    assert (mv.groupby("actor_id").actor_class.nunique() == 1).all()


@pytest.mark.parametrize("name", ["dense_highway", "roundabout_random", "r79_motorcycle_rear"])
def test_deterministic_per_seed(name):
    a = run_scenario(name, seed=3, duration_s=1.0)
    b = run_scenario(name, seed=3, duration_s=1.0)
    pd.testing.assert_frame_equal(a.truth, b.truth)
    pd.testing.assert_frame_equal(a.ego, b.ego)


def test_different_seed_different_traffic():
    a = run_scenario("dense_highway", seed=3, duration_s=0.5)
    b = run_scenario("dense_highway", seed=4, duration_s=0.5)
    assert not a.truth.equals(b.truth)


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_every_case_runs_its_full_duration(name, catalogue_run):
    case = SCENARIOS[name]
    run = catalogue_run(name)
    assert run.n_frames == round(case.duration_s * 20)
    assert run.ego.time_s.iloc[-1] == pytest.approx(case.duration_s - 0.05)
    frames = list(run.frames())
    assert len(frames) == run.n_frames
    assert np.all(np.isfinite(run.truth.select_dtypes("number").to_numpy()))
    # Every scripted actor that must be detected is present in every frame.
    for aid in case.must_detect:
        assert (run.truth.actor_id == aid).sum() == run.n_frames
    assert len(run.truth.drop_duplicates(["frame", "actor_id"])) == len(run.truth)


def test_frame_rate_and_frames_iterator():
    run = run_scenario("r79_motorcycle_rear", frame_rate_hz=10, duration_s=1.0)
    assert run.n_frames == 10
    f = next(iter(run))
    assert f.frame == 0 and f.mount_height_m == 0.5
    assert set(f.truth.frame) == {0}
    # Ego at 80 km/h straight, radar yawed 135 deg: v_radar = Rz(-135 deg) (v, 0).
    v = 80 / 3.6
    np.testing.assert_allclose(f.radar_velocity_mps,
                               [v * np.cos(np.radians(135)), -v * np.sin(np.radians(135)), 0],
                               atol=1e-9)


@pytest.mark.parametrize("kwargs, match", [
    ({"frame_rate_hz": 0.0}, "frame_rate_hz"),
    ({"substeps": 0}, "substeps"),
    ({"duration_s": -1.0}, "duration_s"),
    ({"decision_rate_hz": 100.0}, "decision_rate_hz"),
])
def test_run_arguments_validated(kwargs, match):
    with pytest.raises(ValueError, match=match):
        run_scenario("r79_motorcycle_rear", **kwargs)


def test_unknown_case():
    with pytest.raises(ValueError, match="unknown scenario 'nope'; known: .*r79_motorcycle_rear"):
        run_scenario("nope")


_DRIVER_CONSTANTS = ("DISTANCE_WANTED", "COMFORT_ACC_MAX", "COMFORT_ACC_MIN")


def test_an_environment_s_driver_constants_stay_in_its_own_simulation():
    """highway-env's intersection environment sets IDMVehicle's jam distance and comfort
    accelerations on the class at reset; they must not reach the next case a process runs."""
    from highway_env.vehicle.behavior import IDMVehicle
    before = {k: getattr(IDMVehicle, k) for k in _DRIVER_CONSTANTS}
    run_scenario("intersection_random", seed=0, duration_s=0.1)
    assert {k: getattr(IDMVehicle, k) for k in _DRIVER_CONSTANTS} == before
    assert {k: getattr(IDM_CLASSES["car"], k) for k in _DRIVER_CONSTANTS} == before


def test_class_state_restored_undoes_set_and_added_constants():
    from scenarios.traffic import vehicle_class_state_restored
    cls = IDM_CLASSES["truck"]
    own, inherited = cls.LENGTH, cls.COMFORT_ACC_MAX
    with vehicle_class_state_restored():
        cls.LENGTH = own + 1.0           # the class's own constant changed
        cls.COMFORT_ACC_MAX = 99.0       # an inherited constant shadowed
        cls.NEW_CONSTANT = 1             # a constant added
    assert cls.LENGTH == own and "LENGTH" in vars(cls)
    assert cls.COMFORT_ACC_MAX == inherited and "COMFORT_ACC_MAX" not in vars(cls)
    assert not hasattr(cls, "NEW_CONSTANT")


def test_class_state_restored_keeps_a_class_defined_inside_the_block():
    """A vehicle class first defined inside the block (a module imported there) had no state
    on entry: its own constants stay."""
    from scenarios.traffic import vehicle_class_state_restored
    with vehicle_class_state_restored():
        new = type("LateVehicle", (IDM_CLASSES["car"],), {"LENGTH": 3.2, "MAX_SPEED": 9.0})
    assert vars(new)["LENGTH"] == 3.2 and vars(new)["MAX_SPEED"] == 9.0


def test_roundabout_traffic_is_the_same_after_an_intersection_case():
    """The sweep-order dependence found on the default run: roundabout_random simulated after
    intersection_random in the same worker drove its ego differently from frame 39 on."""
    ref = run_scenario("roundabout_random", seed=0, duration_s=None).truth
    run_scenario("intersection_random", seed=0, duration_s=0.5)
    pd.testing.assert_frame_equal(run_scenario("roundabout_random", seed=0,
                                               duration_s=None).truth, ref, check_exact=True)
