"""UN R79 category C critical distance and verdict (metrics.r79)."""
from __future__ import annotations

import math

import pytest

from metrics.r79 import KMH, R79, R79Constants, critical_distance_m, r79_verdict


@pytest.mark.parametrize("ego_kmh, s_crit_m", [(60, 87.5), (80, 59.9), (100, 42.7)])
def test_design_values(ego_kmh, s_crit_m):
    """design.md 6: 87.5 m at 60 km/h, 59.9 m at 80, 42.7 m at 100 (v_app 130 km/h)."""
    assert critical_distance_m(ego_kmh * KMH) == pytest.approx(s_crit_m, abs=0.05)


def test_formula_terms():
    c = R79Constants(approach_speed_mps=30.0, decel_mps2=2.0, reaction_time_s=0.5,
                     gap_time_s=2.0)
    # dv = 10: 10 x 0.5 + 100 / 4 + 20 x 2
    assert critical_distance_m(20.0, constants=c) == pytest.approx(5 + 25 + 40)
    # the case's own approaching speed replaces the regulation's 130 km/h
    assert critical_distance_m(20.0, 30.0) == critical_distance_m(
        20.0, constants=R79Constants(approach_speed_mps=30.0))
    assert R79.approach_speed_mps == pytest.approx(130 / 3.6)


def test_verdict_takes_the_larger_of_s_crit_and_s_rear():
    v = r79_verdict(56.0, 100 * KMH, 130 * KMH)
    assert v["s_critical_m"] == pytest.approx(42.7, abs=0.05)
    assert v["r79_required_range_m"] == 55.0 and v["r79_pass"] == 1.0
    assert r79_verdict(54.9, 100 * KMH, 130 * KMH)["r79_pass"] == 0.0
    assert r79_verdict(87.0, 60 * KMH, 130 * KMH)["r79_pass"] == 0.0
    assert r79_verdict(math.nan, 60 * KMH, 130 * KMH)["r79_pass"] == 0.0


def test_no_approaching_vehicle():
    with pytest.raises(ValueError, match="approach_speed_mps=20 is below ego_speed_mps=25"):
        critical_distance_m(25.0, 20.0)


def test_speed_not_finite():
    with pytest.raises(ValueError, match="ego_speed_mps=nan must be a finite speed"):
        critical_distance_m(math.nan)


def test_constants_validated():
    with pytest.raises(ValueError, match="decel_mps2=0"):
        R79Constants(decel_mps2=0.0)
