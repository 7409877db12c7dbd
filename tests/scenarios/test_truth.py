"""Ground truth: the single highway-env -> ISO conversion, frames, radial velocity."""
from __future__ import annotations

import numpy as np
import pytest

from scenarios import EGO_COLUMNS, MOUNTS, TRUTH_COLUMNS, run_scenario
from scenarios.catalog import ActorSpec, Case, Mount
from scenarios.truth import highway_to_iso, iso_lateral_to_highway


def test_highway_to_iso_flips_y_once():
    x, y, yaw, vx, vy = highway_to_iso(1.0, 2.0, 0.3, 1.0, 0.5)
    assert (x, y, yaw, vx, vy) == (1.0, -2.0, -0.3, 1.0, -0.5)
    # The inverse map for placing actors is the same flip.
    assert iso_lateral_to_highway(1.5) == -1.5


def _follower_case(mount: Mount) -> Case:
    return Case(name="follower", description="car 20 m behind in the left lane", mount=mount,
                duration_s=1.0, ego=ActorSpec(path="lane_1", speed_mps=20.0),
                actors=(ActorSpec(path="lane_0", s_m=-20.0, speed_mps=20.0),))


def test_actor_behind_left_is_on_boresight_of_rear_left_radar_looking_there():
    """A car 20 m behind in the LEFT lane (highway-env lane_0, y_hw = -4 m relative) is at
    y = +4 m in the vehicle frame, and at azimuth ~0 for a rear-left radar yawed at it."""
    base = MOUNTS["rear_left"]
    yaw = np.degrees(np.arctan2(4.0 - base.y_m, -20.0 - base.x_m))  # 169.75 deg
    mount = Mount(name="rear_left", x_m=base.x_m, y_m=base.y_m, z_m=0.5, yaw_deg=float(yaw))
    t = run_scenario(_follower_case(mount)).truth
    assert list(t.columns) == TRUTH_COLUMNS
    row = t[t.frame == 0].iloc[0]
    assert row.x_m == pytest.approx(-20.0) and row.y_m == pytest.approx(4.0)
    assert row.azimuth_deg == pytest.approx(0.0, abs=1e-6)
    assert row.x_radar_m == pytest.approx(np.hypot(17.7, 3.2))
    assert row.y_radar_m == pytest.approx(0.0, abs=1e-9)
    assert row.z_radar_m == pytest.approx(0.75 - 0.5)
    assert row.radial_velocity_mps == pytest.approx(0.0, abs=1e-9)
    # Same car, the standard rear-left radar (yaw 135): the car sits to the radar's left.
    t = run_scenario(_follower_case(base)).truth
    assert t.iloc[0].azimuth_deg == pytest.approx(yaw - 135.0, abs=1e-6)


@pytest.mark.parametrize("name", ["r79_motorcycle_rear", "blind_spot_overtaking",
                                  "cccscp_crossing", "ccftap_turn_across",
                                  "reversing_pedestrian", "head_on_aliasing"])
def test_radial_velocity_is_range_rate(name, catalogue_run):
    """radial_velocity_mps = d(range)/dt, also for a turning ego (omega x lever arm)."""
    run = catalogue_run(name)
    t = run.truth[run.truth.actor_class != "guard_rail"]
    for _, g in t.groupby("actor_id"):
        rate = np.gradient(g.range_m.to_numpy(), g.time_s.to_numpy())
        vr = g.radial_velocity_mps.to_numpy()
        err = np.abs(vr[1:-1] - rate[1:-1])
        assert np.all(err <= 0.05 + 0.01 * np.abs(vr[1:-1])), err.max()


def test_radar_frame_consistent_with_vehicle_frame(catalogue_run):
    run = catalogue_run("ccftap_turn_across")
    t, m = run.truth, run.mount
    yaw = np.radians(m.yaw_deg)
    xv = np.cos(yaw) * t.x_radar_m - np.sin(yaw) * t.y_radar_m + m.x_m
    yv = np.sin(yaw) * t.x_radar_m + np.cos(yaw) * t.y_radar_m + m.y_m
    np.testing.assert_allclose(xv, t.x_m, atol=1e-9)
    np.testing.assert_allclose(yv, t.y_m, atol=1e-9)
    np.testing.assert_allclose((t.yaw_radar_deg - t.yaw_deg + m.yaw_deg + 180) % 360 - 180, 0,
                               atol=1e-9)


def test_relative_velocity_in_vehicle_frame(catalogue_run):
    """Motorcycle at 130 km/h, ego 80 km/h, both along x: vx = +13.9 m/s, vy = 0."""
    run = catalogue_run("r79_motorcycle_rear")
    t = run.truth[run.truth.actor_id == 0]
    np.testing.assert_allclose(t.vx_mps, (130 - 80) / 3.6, atol=1e-9)
    np.testing.assert_allclose(t.vy_mps, 0.0, atol=1e-9)
    assert np.all(t.radial_velocity_mps < 0), "approaching: negative range rate"


def test_ego_table(catalogue_run):
    run = catalogue_run("r79_critical_distance_60")
    e = run.ego
    assert list(e.columns) == EGO_COLUMNS
    np.testing.assert_allclose(np.diff(e.ego_x_m), 60 / 3.6 / run.frame_rate_hz, atol=1e-9)
    np.testing.assert_allclose(e.ego_speed_mps, 60 / 3.6)
    np.testing.assert_allclose(e.ego_yaw_deg, 0.0, atol=1e-12)


def test_guard_rails_are_static_clutter_rows(catalogue_run):
    run = catalogue_run("r79_motorcycle_rear")
    rails = run.truth[run.truth.actor_class == "guard_rail"]
    assert len(rails) > 0 and np.all(rails.actor_id >= 0)
    f0 = rails[rails.frame == 0]
    # Rails on both sides, 1.5 m beyond the outer lane edges (ego in the middle lane).
    assert set(np.round(f0.y_m, 6)) == {7.5, -7.5}
    # Static in the world: relative velocity is minus the ego's.
    np.testing.assert_allclose(rails.vx_mps, -80 / 3.6, atol=1e-9)
