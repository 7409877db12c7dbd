"""The catalogue: required cases, mounts, criteria as data, validation of every dataclass."""
from __future__ import annotations

import pytest

from scenarios import ACTOR_CLASSES, CASE_CLASSES, MOUNTS, SCENARIOS, get_case
from scenarios.catalog import KMH, ActorSpec, Case, Criterion, Mount

REQUIRED = ["r79_motorcycle_rear", "r79_critical_distance_60", "r79_critical_distance_100",
            "blind_spot_overtaking", "truck_high_closing", "zero_relative_follower",
            "dooring_cyclist", "reversing_pedestrian", "cccscp_crossing", "ccftap_turn_across",
            "head_on_aliasing", "dense_highway"]


def test_catalogue_has_the_required_cases():
    assert len(SCENARIOS) >= 12
    assert set(REQUIRED) <= set(SCENARIOS)
    assert {c.traffic for c in SCENARIOS.values()} >= {"highway", "merge", "roundabout",
                                                       "intersection"}


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_case_is_complete(name):
    case = SCENARIOS[name]
    m = case.mount
    assert m.name in MOUNTS and abs(abs(m.yaw_deg) - 90) == pytest.approx(45)
    assert m.z_m == pytest.approx(0.5, abs=0.2)
    assert 0 < case.duration_s <= 8, "keep sweeps cheap"
    assert case.criteria or CASE_CLASSES[case.case_class].needs_approaching_target, \
        "every case carries a physical pass criterion or its class's verdict"
    for c in case.criteria:
        d = c.to_dict()
        assert set(d) == {"metric", "op", "value", "actor_id", "note"}
    if case.traffic is None:
        assert case.must_detect


def test_r79_cases_are_judged_on_the_regulation():
    """The R79 cases carry no fixed numbers: metrics.r79 computes S_crit from their speeds."""
    r79 = [c for c in SCENARIOS.values() if c.case_class == "r79"]
    assert {c.name for c in r79} == {"r79_motorcycle_rear", "r79_critical_distance_60",
                                     "r79_critical_distance_100"}
    for c in r79:
        assert not c.criteria
        assert c.actors[c.must_detect[0]].speed_mps == pytest.approx(130 * KMH)
    moto = SCENARIOS["r79_motorcycle_rear"]
    assert moto.actors[0].actor_class == "motorcycle"


def test_head_on_closes_faster_than_ddma_span():
    case = SCENARIOS["head_on_aliasing"]
    assert case.ego.speed_mps + case.actors[0].speed_mps > 40.8


def test_criterion_passed():
    c = Criterion(metric="first_detection_range_m", op=">=", value=55.0, actor_id=0)
    assert c.passed(60.0) and not c.passed(50.0) and not c.passed(float("nan"))


def test_classes_sizes():
    assert (ACTOR_CLASSES["car"].length_m, ACTOR_CLASSES["car"].width_m) == (5.0, 2.0)
    assert (ACTOR_CLASSES["motorcycle"].length_m, ACTOR_CLASSES["motorcycle"].width_m) == (2.2,
                                                                                        0.8)
    assert ACTOR_CLASSES["truck"].length_m == pytest.approx(16, abs=1)
    assert ACTOR_CLASSES["motorcycle"].max_speed_mps >= 130 * KMH


def test_get_case_unknown_names_known():
    with pytest.raises(ValueError, match="unknown scenario 'nope'.*r79_motorcycle_rear"):
        get_case("nope")


BASE = dict(name="x", description="d", mount=MOUNTS["rear_left"], duration_s=2.0)


@pytest.mark.parametrize("kwargs, match", [
    ({"name": "Bad Name"}, "name"),
    ({"duration_s": 0.0}, "duration_s"),
    ({"duration_s": 500.0}, "duration_s"),
    ({"road": "moon"}, "road"),
    ({"lanes": 0}, "lanes"),
    ({"traffic": "city"}, "traffic"),
    ({"ego": ActorSpec(actor_class="truck", path="lane_1")}, "ego.actor_class"),
    ({"actors": (ActorSpec(path="lane_9"),)}, r"actors\[0\].path"),
    ({"vehicles_count": 100}, "vehicles_count"),
    ({"vehicles_density": 0.0}, "vehicles_density"),
    ({"truck_fraction": 1.5}, "truck_fraction"),
    ({"truck_fraction": 0.6, "motorcycle_fraction": 0.6}, "fraction"),
    ({"must_detect": (3,)}, "must_detect"),
    ({"criteria": (Criterion(metric="ghost_rate", op="<=", value=0.1, actor_id=2),)},
     "actor_id"),
    ({"mount": "rear_left"}, "mount"),
    ({"case_class": "euro_ncap"}, r"case_class=.euro_ncap. is not one of \[.interference"),
    ({"case_class": "r79"}, "case_class='r79' needs scripted actors and a first must_detect"),
])
def test_case_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Case(**{**BASE, **kwargs})


@pytest.mark.parametrize("kwargs, match", [
    ({"actor_class": "tank"}, "actor_class"),
    ({"actor_class": "pedestrian", "speed_mps": 10.0}, "speed_mps"),
    ({"speed_mps": -8.0}, "reversing"),
    ({"speed_mps": float("nan")}, "speed_mps"),
    ({"lateral_offset_m": 20.0}, "lateral_offset_m"),
    ({"lane_change_left_m": 30.0}, "lane_change_left_m"),
    ({"lane_change_time_s": -1.0}, "lane_change_time_s"),
    ({"lane_change_duration_s": 0.0}, "lane_change_duration_s"),
    ({"brake_decel_mps2": 20.0}, "brake_decel_mps2"),
])
def test_actor_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        ActorSpec(**kwargs)


@pytest.mark.parametrize("kwargs, match", [
    ({"name": "roof"}, "name"),
    ({"x_m": 20.0}, "x_m"),
    ({"y_m": 5.0}, "y_m"),
    ({"z_m": 0.0}, "z_m"),
    ({"yaw_deg": 200.0}, "yaw_deg"),
])
def test_mount_validation(kwargs, match):
    base = dict(name="rear_left", x_m=-2.3, y_m=0.8, z_m=0.5, yaw_deg=135.0)
    with pytest.raises(ValueError, match=match):
        Mount(**{**base, **kwargs})


@pytest.mark.parametrize("kwargs, match", [
    ({"metric": ""}, "metric='' must name a metric"),
    ({"metric": 3}, "metric=3 must be a string"),
    ({"op": "=="}, "op"),
    ({"value": float("inf")}, "value"),
    ({"actor_id": -1}, "actor_id"),
])
def test_criterion_validation(kwargs, match):
    base = dict(metric="ghost_rate", op="<=", value=0.1)
    with pytest.raises(ValueError, match=match):
        Criterion(**{**base, **kwargs})


@pytest.mark.parametrize("kwargs, match", [
    ({"length_m": 0.0}, "length_m=0.0 must be a finite positive number"),
    ({"max_speed_mps": float("nan")}, "max_speed_mps=nan"),
    ({"random_traffic": 1}, "random_traffic=1 must be true or false"),
    ({"cruise_speed_cap_mps": -1.0}, "cruise_speed_cap_mps=-1.0"),
])
def test_actor_class_validation(kwargs, match):
    from scenarios.catalog import ActorClass
    base = dict(name="x", length_m=1.0, width_m=1.0, height_m=1.0, max_speed_mps=1.0)
    with pytest.raises(ValueError, match=match):
        ActorClass(**{**base, **kwargs})


def test_random_traffic_classes_are_data():
    from scenarios.traffic import IDM_CLASSES, VEHICLE_CLASSES
    assert set(IDM_CLASSES) == {n for n, c in ACTOR_CLASSES.items() if c.random_traffic}
    assert VEHICLE_CLASSES["pedestrian"].DEFAULT_INITIAL_SPEEDS == [2.0, 2.8]  # 0.5, 0.7 x 4
