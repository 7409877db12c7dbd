"""Scatterers: validation, empty/concatenate, and the geometric properties (design.md 3)."""
from __future__ import annotations

import numpy as np
import pytest

from radarsim import Scatterers


def _one(**kw):
    base = dict(position_m=[[10.0, 0.0, 0.0]], velocity_mps=[[0.0, 0.0, 0.0]], rcs_m2=[1.0])
    base.update(kw)
    return Scatterers(**base)


@pytest.mark.parametrize("kw, match", [
    (dict(position_m=[[1.0, 2.0]]), r"position_m must have shape \(K, 3\)"),
    (dict(velocity_mps=[1.0, 2.0, 3.0]), r"velocity_mps must have shape \(K, 3\)"),
    (dict(rcs_m2=[[1.0]]), r"rcs_m2 must have shape \(K,\)"),
    (dict(position_m=[[np.nan, 0.0, 0.0]]), "position_m contains non-finite"),
    (dict(velocity_mps=[[np.inf, 0.0, 0.0]]), "velocity_mps contains non-finite"),
    (dict(rcs_m2=[np.nan]), "rcs_m2 contains non-finite"),
    (dict(rcs_m2=[-1.0]), "rcs_m2 must be >= 0"),
    (dict(rcs_m2=[1.0, 2.0]), "same K"),
    (dict(position_m=[[1e-4, 0.0, 0.0]]), "position_m: a scatterer sits at the radar"),
    (dict(actor_id=np.array([0.5])), "actor_id must be an integer array"),
    (dict(actor_id=np.array([1, 2])), r"actor_id must be an integer array of shape \(1,\)"),
], ids=["pos_shape", "vel_shape", "rcs_shape", "pos_nan", "vel_inf", "rcs_nan", "rcs_negative",
        "k_mismatch", "at_radar", "actor_float", "actor_shape"])
def test_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        _one(**kw)


def test_geometry_properties_follow_design_conventions():
    """design.md 3: azimuth = atan2(y, x) positive left, elevation = asin(z / r),
    radial velocity = d(range)/dt (negative approaching)."""
    pos = np.array([[10.0, 10.0, 0.0], [3.0, 0.0, 4.0], [0.0, -2.0, 0.0]])
    vel = np.array([[-1.0, -1.0, 0.0], [0.0, 5.0, 0.0], [0.0, -3.0, 0.0]])
    sc = Scatterers(pos, vel, [1.0, 2.0, 3.0], actor_id=np.array([7, 8, -1]))
    np.testing.assert_allclose(sc.range_m, [np.sqrt(200), 5.0, 2.0])
    np.testing.assert_allclose(sc.azimuth_deg, [45.0, 0.0, -90.0])
    np.testing.assert_allclose(sc.elevation_deg, [0.0, np.degrees(np.arcsin(0.8)), 0.0])
    # Approaching along the line of sight at sqrt(2) m/s; tangential -> 0; receding 3 m/s.
    np.testing.assert_allclose(sc.radial_velocity_mps, [-np.sqrt(2), 0.0, 3.0], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(sc.unit_vector, axis=1), 1.0)
    assert len(sc) == 3
    assert sc.actor_id.dtype == np.int64


def test_default_actor_id_and_read_only():
    sc = _one()
    np.testing.assert_array_equal(sc.actor_id, [-1])
    with pytest.raises(ValueError):
        sc.position_m[0, 0] = 5.0
    with pytest.raises(AttributeError):
        sc.rcs_m2 = np.ones(1)  # type: ignore[misc]


def test_empty_and_concatenate():
    e = Scatterers.empty()
    assert len(e) == 0 and e.position_m.shape == (0, 3) and e.range_m.shape == (0,)
    a = _one(actor_id=np.array([3]))
    b = Scatterers([[0.0, 5.0, 0.0], [0.0, 0.0, 2.0]], np.zeros((2, 3)), [2.0, 4.0])
    c = Scatterers.concatenate([a, e, b])
    assert len(c) == 3
    np.testing.assert_array_equal(c.actor_id, [3, -1, -1])
    np.testing.assert_array_equal(c.rcs_m2, [1.0, 2.0, 4.0])
    assert len(Scatterers.concatenate([])) == 0
    # Empty inputs given as plain empty lists are accepted too.
    assert len(Scatterers([], [], [])) == 0


def test_from_spherical_round_trips_range_angles_and_radial_velocity():
    sc = Scatterers.from_spherical([50.0, 120.0], [30.0, -60.0], [5.0, -10.0],
                                   [-12.0, 7.5], [1.0, 10.0])
    np.testing.assert_allclose(sc.range_m, [50.0, 120.0])
    np.testing.assert_allclose(sc.azimuth_deg, [30.0, -60.0])
    np.testing.assert_allclose(sc.elevation_deg, [5.0, -10.0])
    np.testing.assert_allclose(sc.radial_velocity_mps, [-12.0, 7.5])
    np.testing.assert_array_equal(sc.actor_id, [-1, -1])


def test_concatenate_and_select_keep_values_order_and_read_only_arrays():
    """Joined and selected sets (built without re-checking checked arrays) hold the parts'
    values in order, as new read-only arrays the parts do not share."""
    a = Scatterers.from_spherical([10.0, 20.0], [5.0, -5.0], [0.0, 1.0], [-3.0, 2.0],
                                  [1.0, 2.0], actor_id=[4, 5])
    b = Scatterers.from_spherical([30.0], [0.0], [0.0], [1.0], [3.0])
    ab = Scatterers.concatenate([a, b])
    np.testing.assert_array_equal(ab.position_m, np.vstack([a.position_m, b.position_m]))
    np.testing.assert_array_equal(ab.velocity_mps, np.vstack([a.velocity_mps, b.velocity_mps]))
    np.testing.assert_array_equal(ab.rcs_m2, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(ab.actor_id, [4, 5, -1])
    sel = ab.select(np.array([True, False, True]))
    np.testing.assert_array_equal(sel.rcs_m2, [1.0, 3.0])
    np.testing.assert_array_equal(sel.actor_id, [4, -1])
    for s in (ab, sel):
        assert len(s) == s.position_m.shape[0]
        for arr in (s.position_m, s.velocity_mps, s.rcs_m2, s.actor_id):
            assert not arr.flags.writeable
            assert not np.shares_memory(arr, a.position_m)
    assert len(Scatterers.concatenate([Scatterers.empty(), Scatterers.empty()])) == 0
