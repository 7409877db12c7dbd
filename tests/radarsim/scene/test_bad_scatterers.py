"""Bad scatterers: ValueError naming the field (and value or limit), never a garbage frame.

Before these checks an RCS of 1e300 m^2 overflowed the received power and the front end returned an
all-zero ADC frame without a word; a string gave numpy's message without the field name.
"""
from __future__ import annotations

import numpy as np
import pytest

import radarsim
from radarsim.scene.scatterers import MAX_RCS_M2, MAX_SPEED_MPS

P, V = [[10.0, 0.0, 0.0]], [[0.0, 0.0, 0.0]]

CASES = {
    "nan_position": (dict(position_m=[[np.nan, 0, 0]], velocity_mps=V, rcs_m2=[1.0]),
                     r"position_m contains non-finite values"),
    "inf_velocity": (dict(position_m=P, velocity_mps=[[np.inf, 0, 0]], rcs_m2=[1.0]),
                     r"velocity_mps contains non-finite values"),
    "negative_rcs": (dict(position_m=P, velocity_mps=V, rcs_m2=[-1.0]), r"rcs_m2 must be >= 0"),
    "huge_rcs": (dict(position_m=P, velocity_mps=V, rcs_m2=[1e300]),
                 r"rcs_m2=1e\+300 exceeds the limit 1e\+09 m\^2"),
    "string_rcs": (dict(position_m=P, velocity_mps=V, rcs_m2=["big"]),
                   r"rcs_m2 must hold real numbers: .*'big'"),
    "boolean_rcs": (dict(position_m=P, velocity_mps=V, rcs_m2=[True]),
                    r"rcs_m2 must hold real numbers, got booleans"),
    "complex_position": (dict(position_m=[[10, 0, 1j]], velocity_mps=V, rcs_m2=[1.0]),
                         r"position_m must hold real numbers"),
    "faster_than_1000_mps": (dict(position_m=P, velocity_mps=[[1e9, 0, 0]], rcs_m2=[1.0]),
                             r"velocity_mps: speed 1e\+09 m/s exceeds the limit 1000 m/s"),
    "2d_positions": (dict(position_m=[[10.0, 0.0]], velocity_mps=V, rcs_m2=[1.0]),
                     r"position_m must have shape \(K, 3\), got \(1, 2\)"),
    "k_mismatch": (dict(position_m=[[10, 0, 0], [20, 0, 0]], velocity_mps=V, rcs_m2=[1.0]),
                   r"must have the same K, got 2, 1, 1"),
    "at_the_radar": (dict(position_m=[[0, 0, 0]], velocity_mps=V, rcs_m2=[1.0]),
                     r"position_m: a scatterer sits at the radar"),
    "float_actor_id": (dict(position_m=P, velocity_mps=V, rcs_m2=[1.0], actor_id=[1.5]),
                       r"actor_id must be an integer array of shape \(1,\), got float64"),
}


@pytest.mark.parametrize("kw, match", list(CASES.values()), ids=list(CASES))
def test_bad_scatterers_raise_naming_the_field(kw, match):
    with pytest.raises(ValueError, match=match):
        radarsim.Scatterers(**kw)


def test_limits_leave_real_scenes_alone():
    sc = radarsim.Scatterers([[50.0, 5.0, 0.0]], [[-40.0, 0.0, 0.0]], [MAX_RCS_M2])
    adc = radarsim.simulate_frame(radarsim.presets.r79("ddma"), sc, np.random.default_rng(0))
    assert np.abs(adc).max() > 0 and MAX_SPEED_MPS >= 300


N_KINDS = len(CASES)
