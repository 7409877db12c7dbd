"""The equivalence checks a bit-moving speed change is judged by: each must be able to fail."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import radarsim
from benchmarks import equivalence as eq


def test_clopper_pearson_matches_the_closed_forms():
    # k = 0: the upper limit solves (1 - p)^n = alpha / 2; k = n mirrors it.
    lo, hi = eq.clopper_pearson(0, 10)
    assert lo == 0.0 and hi == pytest.approx(1 - 0.025 ** (1 / 10))
    lo, hi = eq.clopper_pearson(10, 10)
    assert hi == 1.0 and lo == pytest.approx(0.025 ** (1 / 10))


def test_clopper_pearson_covers_the_rate():
    lo, hi = eq.clopper_pearson(50, 200)
    assert lo < 0.25 < hi and hi - lo < 0.13


@pytest.fixture
def stats():
    def make(pfa_k=10, pd_k=100, rmse=(0.05, 0.01, 0.4)):
        level = {"snr_db": 20.0, "n_targets": 200, "n_detected": pd_k,
                 "n_velocity_failures": 0, "rmse": list(rmse),
                 "rmse_over_crb": [1.2, 1.2, 1.1]}
        return {"ddma": {"n_noise_cells": 1_000_000, "n_false_alarms": pfa_k,
                         "levels": [level]}}
    return make


def _failed(verdicts):
    return [line for ok, line in verdicts if not ok]


def test_identical_stats_agree(stats):
    assert not _failed(eq.compare(stats(), stats()))


def test_a_false_alarm_rate_outside_the_interval_fails(stats):
    assert any("Pfa" in f for f in _failed(eq.compare(stats(pfa_k=10), stats(pfa_k=40))))


def test_a_detection_probability_outside_the_interval_fails(stats):
    assert any("Pd at 20 dB" in f for f in _failed(eq.compare(stats(), stats(pd_k=150))))


def test_an_rmse_six_percent_off_fails_and_four_percent_passes(stats):
    base = stats()
    worse = _failed(eq.compare(base, stats(rmse=(0.053, 0.01, 0.4))))
    assert worse and "range RMSE" in worse[0]
    assert not _failed(eq.compare(base, stats(rmse=(0.052, 0.01, 0.4))))


def _sweep(tmp_path, name, values):
    rows = [{"scenario": "case", "variant": "baseline", "scheme": "ddma", "seed": s,
             "n_frames": 50, "ghost_rate": v, "r79_pass": True}
            for s, v in enumerate(values)]
    d = tmp_path / name
    d.mkdir()
    pd.DataFrame(rows).to_parquet(d / "summary.parquet")
    return d


def test_sweep_mean_within_the_seed_spread_passes(tmp_path):
    base = _sweep(tmp_path, "a", [0.10, 0.20, 0.15])
    new = _sweep(tmp_path, "b", [0.11, 0.22, 0.14])
    assert not _failed(eq.compare_sweeps(base, new))


def test_sweep_mean_outside_the_seed_spread_fails(tmp_path):
    base = _sweep(tmp_path, "a", [0.10, 0.12, 0.11])
    new = _sweep(tmp_path, "b", [0.20, 0.22, 0.21])
    bad = _failed(eq.compare_sweeps(base, new))
    assert any("ghost_rate" in f for f in bad)


def test_sweep_metric_constant_over_seeds_must_stay(tmp_path):
    base = _sweep(tmp_path, "a", [0.1, 0.1, 0.1])
    assert _failed(eq.compare_sweeps(base, _sweep(tmp_path, "b", [0.1, 0.1, 0.1001])))


def test_sweep_metric_on_one_seed_only_is_reported_not_judged(tmp_path):
    """A metric defined on one seed (NaN on the others) has no seed-to-seed spread: its
    difference is printed, the check passes; where the new version defines it on another
    number of seeds, it fails."""
    nan = float("nan")
    base = _sweep(tmp_path, "a", [nan, 2.747228, nan])
    out = eq.compare_sweeps(base, _sweep(tmp_path, "b", [nan, 2.747229, nan]))
    assert not _failed(out) and any("one seed only" in line for _, line in out)
    assert _failed(eq.compare_sweeps(base, _sweep(tmp_path, "c", [1.0, 2.747228, nan])))


def test_sweep_needs_three_seeds(tmp_path):
    with pytest.raises(SystemExit, match=">= 3 seeds"):
        eq.compare_sweeps(_sweep(tmp_path, "a", [0.1, 0.2]), _sweep(tmp_path, "b", [0.1, 0.2]))


def test_match_counts_detections_failures_and_errors():
    cfg = radarsim.presets.r79("tdma")
    t = np.array([[20.0, 5.0, 0.0, 3.0, 20.0], [60.0, -5.0, 0.0, -3.0, 20.0],
                  [100.0, 0.0, 0.0, 1.0, 20.0]])
    cloud = pd.DataFrame({"range_m": [20.01, 60.0, 60.02], "radial_velocity_mps": [3.001, 9.0,
                                                                                    8.0],
                          "azimuth_deg": [5.1, -5.0, -5.0], "snr_db": [20.0, 25.0, 10.0]})
    detected, failures, e = eq.match(cfg, t, cloud)
    assert (detected, failures) == (2, 1)  # 100 m missed; 60 m's strongest point is 6 m/s off
    np.testing.assert_allclose(e, [[0.01, 0.001, 0.1, 5.0]], atol=1e-12)
