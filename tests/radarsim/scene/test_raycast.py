"""Ray casting: slab intersection against hand-computed cases, windows, occlusion."""
from __future__ import annotations

import numpy as np
import pytest

from radarsim.scene.raycast import (
    FACE_NORMALS_LOCAL,
    RayGridConfig,
    box_windows,
    cast_rays,
    ray_box_intersect,
)

UNIT = np.array([[1.0, 1.0, 1.0]])


@pytest.mark.parametrize(
    "direction, centre, half, yaw_deg, t_expected, face",
    [
        # Straight ahead into the rear face of a 2 m cube 10 m away: 10 - 1.
        ([1, 0, 0], [10, 0, 0], [1, 1, 1], 0.0, 9.0, 1),
        # Along +y into a 4 x 1 x 2 m box 5 m to the left: enters its -y face at 5 - 0.5.
        ([0, 1, 0], [0, 5, 0], [2, 0.5, 1], 0.0, 4.5, 3),
        # Box yawed 45 deg: the ray meets its corner edge at 10 - sqrt(2).
        ([1, 0, 0], [10, 0, 0], [1, 1, 1], 45.0, 10 - np.sqrt(2), None),
        # Slanted ray: direction (1, 0, 0.1) enters the rear face x = 9 at t = 9 * |d|;
        # there z = 0.9 < 1, inside the face.
        ([1, 0, 0.1], [10, 0, 0], [1, 1, 1], 0.0, 9 * np.sqrt(1.01), 1),
        # Same slant, box top at 0.5 m: z = 0.9 at the rear face is above it -> miss.
        ([1, 0, 0.1], [10, 0, 0], [1, 1, 0.5], 0.0, np.inf, -1),
        # Box behind the radar: no hit at negative t.
        ([1, 0, 0], [-10, 0, 0], [1, 1, 1], 0.0, np.inf, -1),
        # Ray parallel to the y slabs but outside them (box 3 m to the side) -> miss.
        ([1, 0, 0], [10, 3, 0], [1, 1, 1], 0.0, np.inf, -1),
        # A truck's side seen along y from 2 m: 16.5 m long box yawed 90 deg, enters the
        # -x local face (its rear) ... no: yawed 90 deg, local x is world +y: hit at 4 - 8.25.
        ([0, 1, 0], [0, 12.25, 0], [8.25, 1.25, 2], 90.0, 4.0, 1),
    ],
)
def test_ray_box_hand_cases(direction, centre, half, yaw_deg, t_expected, face):
    d = np.asarray(direction, float)
    t, f = ray_box_intersect([d], [centre], [half], [np.radians(yaw_deg)])
    if np.isinf(t_expected):
        assert np.isinf(t[0, 0]) and f[0, 0] == -1
    else:
        # t is in units of |d| (directions need not be unit).
        assert t[0, 0] * np.linalg.norm(d) == pytest.approx(t_expected, abs=1e-9)
        if face is not None:
            assert f[0, 0] == face


def test_origin_inside_box_is_no_hit():
    t, f = ray_box_intersect([[1.0, 0.0, 0.0]], [[0.0, 0.0, 0.0]], UNIT, [0.0])
    assert np.isinf(t[0, 0]) and f[0, 0] == -1


def test_face_normal_opposes_ray():
    rng = np.random.default_rng(1)
    d = rng.normal(size=(200, 3))
    d[:, 0] = np.abs(d[:, 0]) + 2.0
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    t, f = ray_box_intersect(d, [[8.0, 0.5, 0.2]], [[2.0, 1.5, 1.0]], [np.radians(20)])
    hit = f[:, 0] >= 0
    assert hit.sum() > 10
    yaw = np.radians(20)
    n_local = FACE_NORMALS_LOCAL[f[hit, 0]]
    n = np.column_stack([np.cos(yaw) * n_local[:, 0] - np.sin(yaw) * n_local[:, 1],
                         np.sin(yaw) * n_local[:, 0] + np.cos(yaw) * n_local[:, 1],
                         n_local[:, 2]])
    assert np.all(np.einsum("kd,kd->k", n, d[hit]) < 0)


def _brute_force(grid, centres, halves, yaws):
    az = grid.azimuths_rad()
    el = grid.elevations_rad()
    E, A = np.meshgrid(el, az, indexing="ij")
    d = np.column_stack([(np.cos(E) * np.cos(A)).ravel(), (np.cos(E) * np.sin(A)).ravel(),
                         np.sin(E).ravel()])
    t, _ = ray_box_intersect(d, centres, halves, yaws)
    return t.min(axis=1), np.where(np.isfinite(t.min(axis=1)), t.argmin(axis=1), -1)


def test_cast_equals_brute_force_nearest_hit():
    """Windowed casting finds exactly the nearest hit of every ray (windows conservative)."""
    rng = np.random.default_rng(7)
    n = 12
    centres = np.column_stack([rng.uniform(2, 40, n), rng.uniform(-25, 25, n),
                               rng.uniform(-0.4, 1.0, n)])
    halves = np.column_stack([rng.uniform(0.3, 8, n), rng.uniform(0.2, 1.3, n),
                              rng.uniform(0.3, 2, n)])
    yaws = rng.uniform(-np.pi, np.pi, n)
    # A long low guard rail close to the radar: nearest in its middle, not at a corner.
    centres = np.vstack([centres, [0.0, 2.5, -0.1]])
    halves = np.vstack([halves, [30.0, 0.15, 0.375]])
    yaws = np.append(yaws, 0.0)
    grid = RayGridConfig(azimuth_step_deg=1.0, elevation_step_deg=1.0)
    t_ref, b_ref = _brute_force(grid, centres, halves, yaws)
    hits = cast_rays(grid, centres, halves, yaws)
    ray = hits.elevation_index * grid.n_azimuth + hits.azimuth_index
    t = np.full(t_ref.size, np.inf)
    b = np.full(t_ref.size, -1)
    t[ray] = hits.t_m
    b[ray] = hits.box
    assert np.array_equal(np.isfinite(t), np.isfinite(t_ref))
    np.testing.assert_allclose(t[np.isfinite(t)], t_ref[np.isfinite(t_ref)], rtol=1e-12)
    assert np.array_equal(b, b_ref)


def test_occluded_box_gets_no_rays():
    """A car (1.5 m) directly behind a truck (4 m) from a 0.5 m high radar: no hit."""
    centres = np.array([[15.0, 0.0, 1.5], [30.0, 0.0, 0.25]])  # radar frame: ground at -0.5
    halves = np.array([[8.25, 1.275, 2.0], [2.5, 1.0, 0.75]])
    hits = cast_rays(RayGridConfig(), centres, halves, np.zeros(2))
    assert np.sum(hits.box == 0) > 100
    assert np.sum(hits.box == 1) == 0


def test_windows_contain_box():
    az_lo, az_hi, el_lo, el_hi = box_windows([[10.0, 0.0, 0.0]], [[1.0, 1.0, 1.0]], [0.0])
    assert az_lo[0] == pytest.approx(-np.arctan2(1, 9))
    assert az_hi[0] == pytest.approx(np.arctan2(1, 9))
    assert el_hi[0] == pytest.approx(np.arctan2(1, 9))
    assert el_lo[0] == pytest.approx(-np.arctan2(1, 9))


def test_one_degree_at_100m_resolved():
    """Default grid: a target 1 deg wide at 100 m (1.75 m) gets >= 3 ray columns, a 1.5 m
    high one >= 2 rows; a 0.8 m motorcycle at 100 m is still hit."""
    hits = cast_rays(RayGridConfig(), [[100.0, 0.0, 0.25]], [[1.0, 0.5 * 1.745, 0.75]], [0.0])
    assert len(np.unique(hits.azimuth_index)) >= 3
    assert len(np.unique(hits.elevation_index)) >= 2
    moto = cast_rays(RayGridConfig(), [[100.0, 3.0, 0.2]], [[1.1, 0.4, 0.7]], [0.0])
    assert len(moto) >= 1


@pytest.mark.parametrize("kwargs, match", [
    ({"azimuth_step_deg": 0.0}, "azimuth_step_deg"),
    ({"elevation_step_deg": 6.0}, "elevation_step_deg"),
    ({"azimuth_limit_deg": 120.0}, "azimuth_limit_deg"),
    ({"elevation_min_deg": -70.0}, "elevation_min_deg"),
    ({"elevation_min_deg": 10.0, "elevation_max_deg": 5.0}, "below"),
])
def test_grid_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        RayGridConfig(**kwargs)
