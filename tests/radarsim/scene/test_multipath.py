"""Multipath: guard-rail ghost legs occluded on hand-built geometries; two-ray ground bounce
against its closed form (design.md 8)."""
from __future__ import annotations

import numpy as np
import pytest

from radarsim import Scatterers
from radarsim.scene.multipath import MULTIPATH_ACTOR_ID, rail_ghosts, two_ray_power_factor
from radarsim.scene.raycast import segments_blocked

# Boxes: 0 a rail along x at y = 5 (road-side face y = 4.85), 1 the target car.
RAIL = ([20.0, 5.0, 0.0], [8.0, 0.15, 0.375], 0.0)
CAR = ([20.0, 2.0, 0.0], [2.5, 1.0, 0.75], 0.0)


def boxes(*extra):
    items = [RAIL, CAR, *extra]
    return (np.array([b[0] for b in items], float), np.array([b[1] for b in items], float),
            np.array([b[2] for b in items], float), np.array([i == 0 for i in range(len(items))]))


def ghosts(points, *extra, source_box=1):
    c, h, yaw, rail = boxes(*extra)
    sc = Scatterers(np.atleast_2d(points), np.zeros((len(np.atleast_2d(points)), 3)),
                    np.ones(len(np.atleast_2d(points))), np.zeros(len(np.atleast_2d(points)),
                                                                  dtype=np.int64))
    return rail_ghosts(sc, np.full(len(sc), source_box), c, h, yaw, rail, reflectivity=0.3,
                       max_range_m=250.0)


def test_ghost_is_mirror_image_with_two_bounce_loss():
    """Point on the car's rail-facing side (y = 3): ghost at 2 x 4.85 - 3 = 6.7, RCS x 0.3^2."""
    g = ghosts([20.0, 3.0, 0.0])
    assert len(g) == 1 and g.actor_id[0] == MULTIPATH_ACTOR_ID
    np.testing.assert_allclose(g.position_m[0], [20.0, 6.7, 0.0])
    assert g.rcs_m2[0] == pytest.approx(0.09)


def test_far_side_of_the_target_gives_no_ghost():
    """A point on the car's radar-facing side (y = 1) is hidden from the rail by the car."""
    assert len(ghosts([20.0, 1.0, 0.0])) == 0


def test_leg_from_radar_to_rail_occluded_by_a_truck():
    """A truck between the radar and the bounce point blocks leg 1; moved away, it does not."""
    # Bounce point of (20, 3): the line radar -> image (20, 6.7) meets y = 4.85 at x = 14.5.
    truck = ([10.0, 3.4, 0.0], [2.0, 0.5, 1.5], 0.0)
    assert len(ghosts([20.0, 3.0, 0.0], truck)) == 0
    assert len(ghosts([20.0, 3.0, 0.0], ([10.0, -3.0, 0.0], [2.0, 0.5, 1.5], 0.0))) == 1


def test_leg_from_rail_to_target_occluded():
    """A box between the bounce point (14.5, 4.85) and the target point blocks leg 2."""
    blocker = ([17.0, 4.0, 0.0], [0.4, 0.3, 1.0], 0.0)
    assert len(ghosts([20.0, 3.0, 0.0], blocker)) == 0


def test_bounce_point_beyond_the_rail_end_gives_no_ghost():
    assert len(ghosts([60.0, 3.0, 0.0], ([60.0, 2.0, 0.0], [2.5, 1.0, 0.75], 0.0),
                      source_box=2)) == 0


def test_segments_blocked_end_tolerance():
    """A segment ending on a box face is not blocked by that box; one ending inside is."""
    c, h, yaw = np.array([[10.0, 0, 0]]), np.array([[1.0, 1.0, 1.0]]), np.zeros(1)
    start = np.zeros((2, 3))
    end = np.array([[9.0, 0, 0], [10.0, 0, 0]])
    blocked = segments_blocked(start, end, c, h, yaw, end_tolerance_m=0.3)
    assert blocked.tolist() == [False, True]


@pytest.mark.parametrize("h_t", [0.3, 0.75, 1.2])
def test_two_ray_factor_matches_the_closed_form(h_t):
    """|1 - exp(-jk Delta)|^4 = (2 sin(2 pi h_r h_t / (lambda R)))^4 for R >> h (design.md 8);
    the exact and the small-angle Delta differ by O(h^2 / R^2)."""
    lam, h_r = 3.894e-3, 0.5
    r = np.linspace(60.0, 250.0, 400)
    pos = np.column_stack([r, np.zeros_like(r), np.full_like(r, h_t - h_r)])
    slant = np.linalg.norm(pos, axis=1)
    f4 = two_ray_power_factor(pos, h_r, lam, -1.0)
    closed = (2 * np.sin(2 * np.pi * h_r * h_t / (lam * slant))) ** 4
    # Next term of Delta = 2 h_r h_t / R - h_r h_t (h_r^2 + h_t^2) / R^3 + ...: its phase
    # (doubled for margin) times the largest slope of 16 sin^4(x/2), 16 * 3 sqrt(3) / 8 per rad.
    phase_err = 2 * 2 * np.pi / lam * h_r * h_t * (h_r ** 2 + h_t ** 2) / r[0] ** 3
    np.testing.assert_allclose(f4, closed, rtol=0, atol=16 * 3 * np.sqrt(3) / 8 * phase_err)
    # Lobing: the factor swings between ~0 (nulls) and 16 (+12 dB) over this range.
    assert f4.max() > 14.0 and f4.min() < 0.5


def test_two_ray_without_reflection_is_free_space():
    pos = np.array([[30.0, 1.0, 0.2], [80.0, -3.0, 0.5]])
    np.testing.assert_allclose(two_ray_power_factor(pos, 0.5, 3.9e-3, 0.0), 1.0)
