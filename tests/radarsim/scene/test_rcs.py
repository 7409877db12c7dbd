"""Ray-based RCS model: calibration, occlusion, velocities, clutter, multipath, validation."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from radarsim import Scatterers
from radarsim.scene.rcs import (
    CLASS_RCS,
    GROUND_ACTOR_ID,
    MULTIPATH_ACTOR_ID,
    REQUIRED_COLUMNS,
    RcsConfig,
    scene_scatterers,
)

MOUNT_Z = 0.5
SIZES = {"car": (5.0, 2.0, 1.5), "truck": (16.5, 2.55, 4.0), "motorcycle": (2.2, 0.8, 1.4),
         "bicycle": (1.8, 0.6, 1.8), "pedestrian": (0.5, 0.6, 1.75),
         "guard_rail": (16.0, 0.3, 0.75)}
NO_CLUTTER = RcsConfig(ground=False)


def frame(*actors) -> pd.DataFrame:
    """Truth rows (radar-frame columns) from (id, class, x, y, yaw_deg, vx, vy) tuples."""
    rows = []
    for aid, cls, x, y, yaw, vx, vy in actors:
        L, W, H = SIZES[cls]
        rows.append(dict(actor_id=aid, actor_class=cls, length_m=L, width_m=W, height_m=H,
                         x_radar_m=x, y_radar_m=y, z_radar_m=-MOUNT_Z + H / 2,
                         yaw_radar_deg=yaw, vx_radar_mps=vx, vy_radar_mps=vy))
    return pd.DataFrame(rows, columns=list(REQUIRED_COLUMNS))


@pytest.mark.parametrize("cls", ["car", "truck", "motorcycle", "bicycle", "pedestrian"])
def test_class_mean_rcs_within_3db(cls):
    """Aspect-averaged mean RCS at 30 m (24 headings) within +/-3 dB of the class target
    (car, pedestrian, bicycle: their published patterns' azimuth means; truck 50, motorcycle
    2 m^2 design values; sources in radarsim.rcs)."""
    rng = np.random.default_rng(0)
    totals = [scene_scatterers(frame((0, cls, 30.0, 0.0, yaw, 0.0, 0.0)), rng,
                               NO_CLUTTER).rcs_m2.sum() for yaw in np.arange(0, 360, 15)]
    mean_db = 10 * np.log10(np.mean(totals))
    assert mean_db == pytest.approx(10 * np.log10(CLASS_RCS[cls].target_mean_rcs_m2), abs=3.0)


def test_aspect_dependence_car():
    """Yaw 0 shows the car's rear (13.6 dBsm), 90 its right side (20.1), 45 a diagonal (7.1):
    TR 38.901 Table 7.9.2.1-4 at horizontal incidence, fluctuation off."""
    cfg = RcsConfig(ground=False, target_fluctuation=False)
    rng = np.random.default_rng(0)
    total = {yaw: scene_scatterers(frame((0, "car", 30.0, 0.0, yaw, 0, 0)), rng,
                                   cfg).rcs_m2.sum() for yaw in (0.0, 45.0, 90.0)}
    assert total[90.0] > 3 * total[0.0] > 6 * total[45.0]


def test_car_gives_one_scatterer_per_radar_cell_it_covers():
    """A quartering car at 20 m covers ~4 m of range and ~13 deg of azimuth: 3-4 range cells
    of 1.32 m by 2 azimuth cells of 9.6 deg at most; head-on at 30 m its front is one cell."""
    sc = scene_scatterers(frame((0, "car", 20.0, 3.0, 60.0, 0, 0)), np.random.default_rng(0),
                          NO_CLUTTER)
    assert 2 <= len(sc) <= 8
    assert np.all(sc.actor_id == 0)
    head_on = scene_scatterers(frame((0, "car", 30.0, 0.0, 180.0, 0, 0)),
                               np.random.default_rng(0), NO_CLUTTER)
    assert len(head_on) == 1


def test_car_hidden_behind_truck_gets_no_scatterers():
    truth = frame((7, "truck", 15.0, 0.0, 0.0, -5.0, 0.0), (8, "car", 35.0, 0.0, 0.0, -5, 0))
    sc = scene_scatterers(truth, np.random.default_rng(3), NO_CLUTTER)
    assert np.sum(sc.actor_id == 7) > 0
    assert np.sum(sc.actor_id == 8) == 0
    # Moved out of the truck's shadow, the car is seen.
    truth = frame((7, "truck", 15.0, 0.0, 0.0, -5, 0), (8, "car", 35.0, 10.0, 0.0, -5, 0))
    sc = scene_scatterers(truth, np.random.default_rng(3), NO_CLUTTER)
    assert np.sum(sc.actor_id == 8) > 0


def test_scatterer_velocity_is_actor_relative_velocity():
    sc = scene_scatterers(frame((3, "car", 40.0, -6.0, 10.0, -12.0, 1.5)),
                          np.random.default_rng(0), NO_CLUTTER)
    np.testing.assert_allclose(sc.velocity_mps, np.tile([-12.0, 1.5, 0.0], (len(sc), 1)))
    # Radial velocity of the points near that of the centre (small angular extent).
    u = np.array([40.0, -6.0]) / np.hypot(40.0, -6.0)
    assert np.allclose(sc.radial_velocity_mps, -12.0 * u[0] + 1.5 * u[1], atol=0.3)


def test_positions_lie_on_the_box():
    truth = frame((0, "car", 25.0, 4.0, 30.0, 0, 0))
    sc = scene_scatterers(truth, np.random.default_rng(0), NO_CLUTTER)
    yaw = np.radians(30.0)
    p = sc.position_m - [25.0, 4.0, -MOUNT_Z + 0.75]
    local = np.column_stack([np.cos(yaw) * p[:, 0] + np.sin(yaw) * p[:, 1],
                             -np.sin(yaw) * p[:, 0] + np.cos(yaw) * p[:, 1], p[:, 2]])
    assert np.all(np.abs(local) <= np.array([2.5, 1.0, 0.75]) + 0.05)


def test_deterministic_per_seed():
    truth = frame((0, "car", 25.0, 4.0, 30.0, -3, 0), (10000, "guard_rail", 10.0, 3.5, 0, -20, 0))
    cfg = RcsConfig(multipath=True)
    a = scene_scatterers(truth, np.random.default_rng(5), cfg)
    b = scene_scatterers(truth, np.random.default_rng(5), cfg)
    c = scene_scatterers(truth, np.random.default_rng(6), cfg)
    for f in ("position_m", "velocity_mps", "rcs_m2", "actor_id"):
        assert np.array_equal(getattr(a, f), getattr(b, f))
    assert not np.array_equal(a.rcs_m2, c.rcs_m2) or len(a) != len(c)


def test_guard_rail_is_extended_clutter_with_its_actor_id():
    truth = frame((10003, "guard_rail", 20.0, 3.0, 0.0, -20.0, 0.0))
    sc = scene_scatterers(truth, np.random.default_rng(0), NO_CLUTTER)
    assert len(sc) >= 5
    assert np.all(sc.actor_id == 10003)
    # Extended along the rail and low (below its 0.75 m top).
    assert np.ptp(sc.position_m[:, 0]) > 8.0
    assert np.all(sc.position_m[:, 2] <= 0.75 - MOUNT_Z + 1e-6)


def test_ground_clutter_is_static_and_near():
    v_radar = np.array([15.0, -3.0, 0.0])
    sc = scene_scatterers(frame(), np.random.default_rng(0), RcsConfig(),
                          radar_velocity_mps=v_radar, mount_height_m=MOUNT_Z)
    assert len(sc) > 0 and np.all(sc.actor_id == GROUND_ACTOR_ID)
    np.testing.assert_allclose(sc.velocity_mps, np.tile(-v_radar, (len(sc), 1)))
    np.testing.assert_allclose(sc.position_m[:, 2], -MOUNT_Z)
    assert sc.range_m.max() <= RcsConfig().ground_max_range_m + 1.0
    # Constant gamma: sigma0 = gamma sin(grazing); per-point area is the same, so the RCS
    # falls as sin(grazing) ~ h / r.
    r = np.hypot(sc.position_m[:, 0], sc.position_m[:, 1])
    ratio = sc.rcs_m2 / np.sin(np.arctan2(MOUNT_Z, r))
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)


def test_ground_hidden_behind_a_wall_of_trucks():
    trucks = [(i, "truck", 6.0, y, 90.0, 0, 0) for i, y in enumerate(np.arange(-24, 25, 16.5))]
    sc = scene_scatterers(frame(*trucks), np.random.default_rng(0),
                          RcsConfig(grid=RcsConfig().grid.__class__(azimuth_limit_deg=60.0)),
                          radar_velocity_mps=[10.0, 0, 0], mount_height_m=MOUNT_Z)
    g = sc.actor_id == GROUND_ACTOR_ID
    assert g.sum() > 0
    assert np.all(sc.position_m[g, 0] < 6.0)


def test_no_ground_without_radar_velocity():
    sc = scene_scatterers(frame((0, "car", 20.0, 0.0, 0.0, 0, 0)), np.random.default_rng(0))
    assert not np.any(sc.actor_id == GROUND_ACTOR_ID)


def test_guard_rail_mirror_ghosts():
    """Double bounce: ghosts are the car mirrored in the rail's road-side face (y = 4.85)."""
    rail = (10000, "guard_rail", 20.0, 5.0, 0.0, 0.0, 0.0)
    car = (1, "car", 30.0, 2.0, 0.0, 5.0, 1.0)
    off = scene_scatterers(frame(rail, car), np.random.default_rng(0), NO_CLUTTER)
    assert not np.any(off.actor_id == MULTIPATH_ACTOR_ID)
    cfg = RcsConfig(ground=False, multipath=True, centre_fluctuation_db=0.0, dither=False)
    on = scene_scatterers(frame(rail, car), np.random.default_rng(0), cfg)
    ghost = on.actor_id == MULTIPATH_ACTOR_ID
    real = on.actor_id == 1
    assert ghost.sum() > 0
    face_y = 5.0 - 0.15
    assert np.all(on.position_m[ghost, 1] > face_y)
    # Each ghost is the mirror image of a real scatterer, RCS scaled by reflectivity^2.
    mirrored = on.position_m[real].copy()
    mirrored[:, 1] = 2 * face_y - mirrored[:, 1]
    for p, s, v in zip(on.position_m[ghost], on.rcs_m2[ghost], on.velocity_mps[ghost]):
        k = np.argmin(np.linalg.norm(mirrored - p, axis=1))
        assert np.linalg.norm(mirrored[k] - p) < 1e-9
        assert s == pytest.approx(on.rcs_m2[real][k] * cfg.guard_rail_reflectivity ** 2)
        np.testing.assert_allclose(v, [5.0, -1.0, 0.0])


def test_missing_column_and_unknown_class_rejected():
    with pytest.raises(ValueError, match="lacks columns"):
        scene_scatterers(frame((0, "car", 20, 0, 0, 0, 0)).drop(columns="yaw_radar_deg"),
                         np.random.default_rng(0))
    bad = frame((0, "car", 20, 0, 0, 0, 0))
    bad["actor_class"] = "tank"
    with pytest.raises(ValueError, match="actor_class"):
        scene_scatterers(bad, np.random.default_rng(0))


def test_returns_scatterers_in_range():
    sc = scene_scatterers(frame((0, "car", 300.0, 0.0, 0, 0, 0)), np.random.default_rng(0),
                          NO_CLUTTER)
    assert isinstance(sc, Scatterers) and len(sc) == 0


@pytest.mark.parametrize("kwargs, match", [
    ({"max_range_m": 0.0}, "max_range_m"),
    ({"merge_range_m": -1.0}, "merge_range_m"),
    ({"merge_azimuth_deg": 0.0}, "merge_azimuth_deg"),
    ({"merge_elevation_deg": 0.0}, "merge_elevation_deg"),
    ({"ground_max_range_m": 0.0}, "ground_max_range_m"),
    ({"ground_points": 0}, "ground_points"),
    ({"centre_fluctuation_db": -1.0}, "centre_fluctuation_db"),
    ({"guard_rail_reflectivity": 1.5}, "guard_rail_reflectivity"),
    ({"ground_gamma_db": 5.0}, "ground_gamma_db"),
    ({"cull_rcs_at_100m_m2": -1.0}, "cull_rcs_at_100m_m2"),
    ({"clutter_merge_factor": 0.5}, "clutter_merge_factor"),
    ({"grid": "fine"}, "grid"),
    ({"ground_reflection_coefficient": -1.5}, "ground_reflection_coefficient"),
    ({"wavelength_m": 0.0}, "wavelength_m"),
])
def test_config_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        RcsConfig(**kwargs)


def test_radarsim_rcs_is_the_scene_model_under_its_published_name():
    import radarsim.rcs
    import radarsim.scene.rcs
    for name in radarsim.rcs.__all__:
        assert getattr(radarsim.rcs, name) is getattr(radarsim.scene.rcs, name), name
    assert set(radarsim.rcs.__all__) == set(radarsim.scene.rcs.__all__)
