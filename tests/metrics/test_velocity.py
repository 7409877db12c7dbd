"""The velocity check: right, off by whole resolution steps, or unmatched (metrics.velocity)."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import radarsim
from metrics.association import AssociationConfig
from metrics.velocity import FAILURE, RIGHT, UNMATCHED, velocity_check

TRUTH = pd.DataFrame({"actor_id": [0, 1, 2], "actor_class": ["motorcycle", "car",
                                                             "guard_rail"]})


def scatterers(v_mps=-14.0, range_m=60.0):
    return pd.DataFrame({"frame": [0, 0, 0], "actor_id": [0, 0, 2],
                         "range_m": [range_m, range_m + 0.4, 30.0],
                         "radial_velocity_mps": [v_mps, v_mps + 0.05, -20.0]})


def dets(ranges, velocities):
    return pd.DataFrame({"frame": 0, "range_m": ranges, "radial_velocity_mps": velocities})


@pytest.mark.parametrize("mimo", ["tdma", "ddma"])
def test_aliased_velocity_is_a_failure_of_one_span(mimo):
    """An echo beyond +/-Vmax is reported at v - 2 Vmax sgn(v): off by 2 Vmax, which is one
    TDMA slot span and six DDMA sub-bands ([TI-DDMA] 3.3, [TI-VEXT] 4)."""
    cfg = radarsim.presets.r79(mimo)
    vmax = cfg.max_unambiguous_velocity_mps
    step = cfg.scheme.velocity_failure_step_mps(cfg)
    v = -(vmax + 3.0)
    reported = v + 2 * vmax
    chk = velocity_check(dets([60.2], [reported]), scatterers(v), TRUTH, step)
    assert chk.verdict[0] == FAILURE
    assert chk.alias_k[0] * step == pytest.approx(2 * vmax, abs=1e-9)  # reported - truth
    assert chk.actor_id[0] == 0 and chk.truth_radial_velocity_mps[0] == pytest.approx(v)


def test_right_wins_over_an_alias_and_gates_hold():
    sc = scatterers(-14.0)
    cfg = AssociationConfig()
    d = dets([60.0, 60.0, 60.0 + cfg.range_gate_m + 0.5, 30.0, 60.1],
             [-14.0 + 0.9, -14.0 + 20.44 + 1.2, -14.0, -20.0, -14.0 + 20.44])
    chk = velocity_check(d, sc, TRUTH, 20.44, cfg)
    # right within the 1 m/s gate; alias residual 1.2 > 1 m/s gate: unmatched; beyond the
    # range gate: unmatched; on the guard rail (not a road user): unmatched; an alias: failure
    assert list(chk.verdict) == [RIGHT, UNMATCHED, UNMATCHED, UNMATCHED, FAILURE]
    assert list(chk.actor_id) == [0, -1, -1, -1, 0]


def test_angle_is_not_used():
    """TDMA's aliased echoes come out tens of degrees off (wrong Doppler-phase compensation):
    the check reads range and velocity only."""
    d = dets([60.0], [-14.0 + 20.44]).assign(azimuth_deg=80.0, x_m=10.0, y_m=59.0)
    assert velocity_check(d, scatterers(-14.0), TRUTH, 20.44).verdict[0] == FAILURE


def test_frames_do_not_mix():
    d = dets([60.0], [-14.0]).assign(frame=1)
    assert velocity_check(d, scatterers(-14.0), TRUTH, 20.44).verdict[0] == UNMATCHED


def test_empty_inputs():
    chk = velocity_check(dets([], []), scatterers(), TRUTH, 20.44)
    assert chk.verdict.shape == (0,)
    chk = velocity_check(dets([60.0], [-14.0]), scatterers().iloc[:0], TRUTH, 20.44)
    assert chk.verdict[0] == UNMATCHED and np.isnan(chk.truth_radial_velocity_mps[0])


@pytest.mark.parametrize("step", [float("nan"), 0.0, 1.5])
def test_step_must_exceed_twice_the_gate(step):
    with pytest.raises(ValueError, match="step_mps=.* must be finite and > 2 velocity_gate"):
        velocity_check(dets([60.0], [-14.0]), scatterers(), TRUTH, step)
