"""TrackerConfig's sub-configs and its keys: dotted paths, a sub-config's table or object, and
the flat keys of the previous release (which warn, naming the new key)."""
from __future__ import annotations

import dataclasses
import warnings

import pytest

from pipeline.tracking import (
    AllocationConfig,
    EgoMotionConfig,
    GateConfig,
    GroupTracker,
    MaintenanceConfig,
    MeasurementNoise,
    MergeConfig,
    MotionConfig,
    MountConfig,
    PartNames,
    TrackerConfig,
    tracker_paths,
)
from pipeline.tracking.config import FIELD_GROUP, FLAT_KEYS, GROUPS

#: Every default of the flat config of the previous release (the contract: unchanged).
PREVIOUS_DEFAULTS = dict(
    motion_model="cv", frame_period_s=0.05, mount_x_m=0.0, mount_y_m=0.0, mount_yaw_deg=0.0,
    range_std_m=0.25, azimuth_std_deg=1.5, radial_velocity_std_mps=0.15,
    process_noise_accel_mps2=3.0, process_noise_jerk_mps3=10.0, gate_mahalanobis=16.27,
    gate_depth_m=5.0, gate_width_m=3.0, gate_velocity_mps=3.0, group_depth_m=4.0,
    group_width_m=1.8, group_velocity_spread_mps=1.0, dispersion_update_weight=0.2,
    centroid_jitter_weight=1.0, alloc_min_points=1, alloc_min_snr_db=15.0,
    alloc_min_speed_mps=0.5, alloc_range_m=5.0, alloc_azimuth_deg=4.0,
    alloc_radial_velocity_mps=1.0, init_velocity_std_mps=10.0, init_accel_std_mps2=3.0,
    hits_to_confirm=3, misses_to_free_detect=3, misses_to_free_active=10, max_tracks=256,
    merge_tracks=True, merge_depth_m=5.0, merge_width_m=2.0, merge_velocity_mps=1.0,
    allow_static_tracks=False, static_threshold_mps=0.3, hypothesiser="group_gate",
    associator="max_likelihood", updater="group_ekf", predictor="kalman",
    allocator="leader_cluster")


def test_defaults_are_the_previous_flat_defaults():
    cfg = TrackerConfig()
    assert set(FIELD_GROUP) == set(PREVIOUS_DEFAULTS)
    assert {name: getattr(cfg, name) for name in FIELD_GROUP} == PREVIOUS_DEFAULTS
    assert cfg.ego_motion == EgoMotionConfig()
    assert len(dataclasses.fields(TrackerConfig)) <= 12


def test_every_field_lives_in_one_sub_config_and_is_read_by_its_own_name():
    cfg = TrackerConfig.from_fields(gate_width_m=2.5, max_tracks=7, mount_yaw_deg=-90.0)
    assert cfg.gating.gate_width_m == cfg.gate_width_m == 2.5
    assert cfg.maintenance.max_tracks == 7 and cfg.mount.mount_yaw_deg == -90.0
    for name, group in FIELD_GROUP.items():
        assert name in {f.name for f in dataclasses.fields(GROUPS[group])}
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.gate_width_m = 1.0


def test_dotted_key_table_and_object_are_the_same_change():
    dotted = TrackerConfig().replace(**{"gating.gate_mahalanobis": 20.0})
    table = TrackerConfig().replace(gating={"gate_mahalanobis": 20.0})
    whole = TrackerConfig().replace(gating=GateConfig(gate_mahalanobis=20.0))
    built = TrackerConfig(gating=GateConfig(gate_mahalanobis=20.0))
    assert dotted == table == whole == built
    assert dotted.gating.gate_mahalanobis == 20.0 and dotted.mount == TrackerConfig().mount
    nested = TrackerConfig().replace(**{"ego_motion.n_hypotheses": 8})
    assert nested.ego_motion == EgoMotionConfig(n_hypotheses=8)


def test_flat_key_warns_naming_the_new_key_and_still_works():
    with pytest.warns(DeprecationWarning, match=r"'gate_mahalanobis' is deprecated: use "
                                                r"'gating\.gate_mahalanobis'"):
        cfg = TrackerConfig().replace(gate_mahalanobis=20.0)
    assert cfg == TrackerConfig().replace(**{"gating.gate_mahalanobis": 20.0})
    with pytest.warns(DeprecationWarning, match=r"use 'ego_motion\.static_threshold_mps'"):
        TrackerConfig().replace(static_threshold_mps=0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert TrackerConfig.from_fields(gate_mahalanobis=20.0) == cfg


def test_flat_keys_map_to_their_sub_config():
    assert FLAT_KEYS["gate_mahalanobis"] == "gating.gate_mahalanobis"
    assert FLAT_KEYS["associator"] == "parts.associator"
    assert tracker_paths({"mount_x_m": 1.0, "maintenance": {"max_tracks": 9}}, warn=False) == \
        {"mount.mount_x_m": 1.0, "maintenance.max_tracks": 9}


@pytest.mark.parametrize("changes,match", [
    ({"bogus": 1}, r"unknown TrackerConfig field\(s\) \['bogus'\]"),
    ({"gating.bogus": 1}, r"unknown TrackerConfig field\(s\) \['gating\.bogus'\]; gating holds"),
    ({"gating.gate_mahalanobis.x": 1}, r"\['gating\.gate_mahalanobis\.x'\]"),
    ({"gating": 5}, r"gating=5 must be a GateConfig"),
    ({"gating.gate_mahalanobis": 0.0}, r"gate_mahalanobis=0\.0 must be"),
    ({"parts.associator": "gnn"}, r"associator='gnn' is not one of"),
])
def test_bad_keys_are_refused(changes, match):
    with pytest.raises(ValueError, match=match):
        TrackerConfig().replace(**changes)


def test_from_fields_refuses_unknown_and_dotted_names():
    with pytest.raises(ValueError, match=r"unknown TrackerConfig field\(s\) \['bogus'\]"):
        TrackerConfig.from_fields(bogus=1)
    with pytest.raises(ValueError, match=r"unknown TrackerConfig field\(s\) \['gating\.x'\]"):
        TrackerConfig.from_fields(**{"gating.x": 1})


@pytest.mark.parametrize("cls,kw,match", [
    (MotionConfig, dict(motion_model="zz"), r"motion_model='zz' is not one of"),
    (MotionConfig, dict(frame_period_s=0.0), r"frame_period_s=0\.0 must be"),
    (MountConfig, dict(mount_x_m=float("nan")), r"mount_x_m=nan must be"),
    (MeasurementNoise, dict(azimuth_std_deg=0.0), r"azimuth_std_deg=0\.0 must be"),
    (MergeConfig, dict(merge_tracks="yes"), r"merge_tracks='yes' must be"),
    (MaintenanceConfig, dict(max_tracks=0), r"max_tracks=0 must be"),
    (AllocationConfig, dict(allow_static_tracks=1), r"allow_static_tracks=1 must be"),
    (PartNames, dict(allocator="kmeans"), r"allocator='kmeans' is not one of"),
    (EgoMotionConfig, dict(static_threshold_mps=0.0), r"static_threshold_mps=0\.0 must be"),
], ids=lambda v: v.__name__ if isinstance(v, type) else None)
def test_each_sub_config_checks_its_own_values(cls, kw, match):
    with pytest.raises(ValueError, match=match):
        cls(**kw)


def test_each_built_part_holds_its_own_sub_config():
    cfg = TrackerConfig.from_fields(gate_width_m=2.5, alloc_min_points=2, merge_tracks=False,
                                    centroid_jitter_weight=0.5)
    tracker = GroupTracker(cfg)
    assert tracker.hypothesiser.cfg is cfg.gating
    assert tracker.updater.cfg is cfg.update
    assert tracker.allocator.cfg is cfg.allocation and tracker.allocator.merging is cfg.merging
    assert tracker.sensor.mount is cfg.mount and tracker.sensor.noise is cfg.noise
    assert tracker.ego_motion.config is cfg.ego_motion
