"""metrics.METRICS: one definition per reported number, read by criteria and gates."""
from __future__ import annotations

from types import SimpleNamespace as C

import numpy as np
import pandas as pd
import pytest

from metrics import METRICS
from metrics.association import GHOST, TRUE, VELOCITY_AMBIGUOUS
from metrics.detection import actor_detection
from metrics.registry import (
    BETTER,
    case_criteria,
    check_criterion,
    criterion_metrics,
    describe,
    get_metric,
)
from metrics.scoring import CASE_VERDICTS

UNIT_OF_TOKEN = {"m": "m", "mps": "m/s", "db": "dB", "deg": "deg", "s": "s"}


@pytest.mark.parametrize("name", sorted(METRICS))
def test_metric_is_complete(name):
    m = METRICS[name]
    assert m.name == name and isinstance(m.unit, str) and m.description
    assert m.better in BETTER and callable(m.source)
    # the unit is the last unit token of the name (track_confirm_latency_s_max: s)
    tokens = [t for t in name.split("_")[1:] if t in UNIT_OF_TOKEN]
    expected = UNIT_OF_TOKEN[tokens[-1]] if tokens else ""
    assert m.unit == expected, f"{name}: unit {m.unit!r}, its name says {expected!r}"
    if m.criterion is not None:
        assert f"case_{name}" in METRICS


def test_contract_names():
    assert METRICS["ghost_rate"].unit == "" and "ghosts" in METRICS["ghost_rate"].description
    assert METRICS["s_critical_m"].unit == "m" and METRICS["r79_pass"].unit == ""
    assert criterion_metrics() == ["detection_probability", "first_detection_range_m",
                                   "ghost_rate", "range_error_rmse_m",
                                   "velocity_unambiguity_rate"]


def test_unknown_metric_lists_the_known_ones():
    with pytest.raises(ValueError, match="unknown metric 'speed'; known: .*ghost_rate"):
        get_metric("speed")


def test_metric_that_cannot_be_a_criterion():
    with pytest.raises(ValueError, match="'n_frames' cannot be a case criterion; criterion "
                                         "metrics: detection_probability"):
        check_criterion("n_frames")


def test_run_wide_criterion_takes_no_actor():
    with pytest.raises(ValueError, match="'ghost_rate' is run-wide: actor_id=2"):
        check_criterion("ghost_rate", 2)


def test_shipped_case_criteria_are_registry_metrics():
    import scenarios
    for case in scenarios.SCENARIOS.values():
        for c in case.criteria:
            check_criterion(c.metric, c.actor_id)


def test_case_classes_have_verdicts():
    import scenarios
    assert set(CASE_VERDICTS) == set(scenarios.CASE_CLASSES)


def actor_frames_table():
    return pd.DataFrame({
        "frame": [0, 1, 2, 3, 0, 1], "time_s": [0, .05, .1, .15, 0, .05],
        "actor_id": [1, 1, 1, 1, 2, 2], "actor_class": ["motorcycle"] * 4 + ["car"] * 2,
        "range_m": [100.0, 98.0, 96.0, 94.0, 30.0, 30.0],
        "visible": [True, True, True, True, True, False],
        "detected": [False, True, True, True, False, False]})


def test_case_criteria_measure_as_the_columns_do():
    actors = actor_detection(actor_frames_table())
    lab = pd.DataFrame({"label": [TRUE, TRUE, VELOCITY_AMBIGUOUS, GHOST],
                        "actor_id": [1, 1, 1, -1],
                        "velocity_check": ["right", "right", "failure", "failure"],
                        "velocity_actor_id": [1, 1, 1, 1]})
    row = {"ghost_rate": 0.25, "range_error_rmse_m": 0.3}
    ok = case_criteria([C(metric="first_detection_range_m", op=">=", value=55.0, actor_id=1),
                        C(metric="ghost_rate", op="<=", value=0.3, actor_id=None)],
                       lab, actors, row)
    assert ok["case_pass"] == 1.0 and ok["case_criteria_n"] == 2
    # first detection: the first TRUE assigned detection (98 m), not the first sighting
    assert ok["case_first_detection_range_m"] == 98.0
    bad = case_criteria([C(metric="velocity_unambiguity_rate", op=">=", value=0.9, actor_id=1),
                         C(metric="detection_probability", op=">=", value=0.5, actor_id=2)],
                        lab, actors, row)
    assert bad["case_pass"] == 0.0
    # the ghost-labelled aliased echo counts: 2 right of 4 checked
    assert bad["case_velocity_unambiguity_rate"] == pytest.approx(2 / 4)
    assert "detection_probability actor 2 = 0 not >= 0.5" in bad["case_criteria_failed"]
    assert np.isnan(case_criteria((), lab, actors, row)["case_pass"])
    for k in ok:
        if k not in ("case_criteria_failed",):
            assert k in METRICS


def test_case_criteria_refuse_unknown_metrics():
    with pytest.raises(ValueError, match="unknown metric 'speed'"):
        case_criteria([C(metric="speed", op=">=", value=1, actor_id=None)], pd.DataFrame(),
                      pd.DataFrame(), {})


def test_case_criteria_refuse_unknown_operators():
    with pytest.raises(ValueError, match="criterion op '==' is not one of"):
        case_criteria([C(metric="ghost_rate", op="==", value=1, actor_id=None)],
                      pd.DataFrame(), pd.DataFrame(), {})


def test_describe_is_the_report_legend():
    t = describe(["ghost_rate", "not_a_metric", "range_error_rmse_m"])
    assert list(t["column"]) == ["ghost_rate", "range_error_rmse_m"]
    assert list(t["unit"]) == ["", "m"]
