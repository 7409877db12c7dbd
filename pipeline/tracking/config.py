"""Settings of the group tracker: a frozen dataclass of the parts' own frozen sub-configs.

Each sub-config is declared next to the part that reads it and checks its own values:

| field | class | module | read by |
|---|---|---|---|
| `parts` | `PartNames` | `parts` | `GroupTracker` (which registered parts to build) |
| `motion` | `MotionConfig` | `models` | predictor, allocator (state length) |
| `mount` | `MountConfig` | `models` | the sensor model (`RangeAzimuthDoppler`) |
| `noise` | `MeasurementNoise` | `models` | the sensor model, hence gate, update, merging |
| `gating` | `GateConfig` | `hypothesis` | hypothesiser |
| `update` | `GroupUpdateConfig` | `update` | updater |
| `allocation` | `AllocationConfig` | `clustering` | allocator (and the associator's static rule) |
| `merging` | `MergeConfig` | `clustering` | allocator, duplicate removal |
| `maintenance` | `MaintenanceConfig` | `state` | track maintenance |
| `ego_motion` | `EgoMotionConfig` | `ego_motion` | the ego-motion part (RANSAC, static labels) |

Changes take dotted keys (``cfg.replace(**{"gating.gate_mahalanobis": 20.0})``, a sweep's
``"tracker.gating.gate_mahalanobis"``), a sub-config's table (``gating={...}``) or a whole
sub-config, through the one mechanism of `core.config`. The flat keys of the previous release
(``gate_mahalanobis``) still work for one release and warn (`DeprecationWarning`) with the new
key; every field is also read by its own name (``cfg.gate_mahalanobis`` is
``cfg.gating.gate_mahalanobis``).

    >>> cfg = TrackerConfig().replace(**{"gating.gate_mahalanobis": 20.0})
    >>> cfg.gating.gate_mahalanobis, cfg.gate_mahalanobis
    (20.0, 20.0)
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from core.config import add_flat_properties, dotted_changes, replace_paths
from core.errors import BadInput

from .clustering import AllocationConfig, MergeConfig
from .ego_motion import EgoMotionConfig
from .hypothesis import GateConfig
from .models import MeasurementNoise, MotionConfig, MountConfig
from .parts import PartNames
from .track_state import MaintenanceConfig
from .update import GroupUpdateConfig

__all__ = ["TrackerConfig", "GROUPS", "FIELD_GROUP", "FLAT_KEYS", "tracker_paths"]

#: Sub-config name -> its class (the fields of `TrackerConfig`, in order).
GROUPS: dict[str, type] = {
    "parts": PartNames, "motion": MotionConfig, "mount": MountConfig, "noise": MeasurementNoise,
    "gating": GateConfig, "update": GroupUpdateConfig, "allocation": AllocationConfig,
    "merging": MergeConfig, "maintenance": MaintenanceConfig, "ego_motion": EgoMotionConfig}

#: Field name of the previous release's flat config -> the sub-config now holding it. The
#: ego-motion settings were nested before (``ego_motion``); only its static threshold was flat.
FIELD_GROUP: dict[str, str] = {
    f.name: group for group, cls in GROUPS.items() if group != "ego_motion"
    for f in dataclasses.fields(cls)}
FIELD_GROUP["static_threshold_mps"] = "ego_motion"

#: Flat key of the previous release -> its dotted path (``"gate_mahalanobis"`` ->
#: ``"gating.gate_mahalanobis"``).
FLAT_KEYS: dict[str, str] = {name: f"{group}.{name}" for name, group in FIELD_GROUP.items()}


# Not slotted: the fields' read-only properties are set on the class after it is made (as
# `RadarConfig` does).
@dataclass(frozen=True, kw_only=True)
class TrackerConfig:
    """Settings of the group tracker (all SI, unit in the name), one sub-config per part.

    Parameters
    ----------
    parts : PartNames
        The parts `GroupTracker` builds, by their names in `pipeline.tracking.parts`
        (default TI's gtrack: "group_gate", "max_likelihood", "group_ekf", "kalman",
        "leader_cluster").
    motion : MotionConfig
        Motion model, first frame period, process noise.
    mount : MountConfig
        Radar pose in the vehicle frame.
    noise : MeasurementNoise
        Per-point measurement noise (diagonal Rm).
    gating : GateConfig
        Mahalanobis gate and hard limits of the hypothesiser.
    update : GroupUpdateConfig
        Centroid noise and dispersion update of the group EKF.
    allocation : AllocationConfig
        Leader clustering, start thresholds, initial extent and covariance, static points.
    merging : MergeConfig
        One track per group.
    maintenance : MaintenanceConfig
        DETECT -> ACTIVE -> FREE and the track limit.
    ego_motion : EgoMotionConfig
        RANSAC settings (the whole ego velocity when `step` gets no ego speed, the lateral
        part only, planar model, when it does) and the static threshold.

    Build one from sub-configs (``TrackerConfig(gating=GateConfig(gate_width_m=2.5))``), from
    fields by their own names (`from_fields`), or change one (`replace`, dotted keys).

    Raises
    ------
    core.errors.BadInput
        A field that is not its sub-config's class; each sub-config names its own bad value
        and limit.
    """

    parts: PartNames = PartNames()
    motion: MotionConfig = MotionConfig()
    mount: MountConfig = MountConfig()
    noise: MeasurementNoise = MeasurementNoise()
    gating: GateConfig = GateConfig()
    update: GroupUpdateConfig = GroupUpdateConfig()
    allocation: AllocationConfig = AllocationConfig()
    merging: MergeConfig = MergeConfig()
    maintenance: MaintenanceConfig = MaintenanceConfig()
    ego_motion: EgoMotionConfig = EgoMotionConfig()

    def __post_init__(self) -> None:
        for group, cls in GROUPS.items():
            if not isinstance(getattr(self, group), cls):
                raise BadInput(f"{group}={getattr(self, group)!r} must be a {cls.__name__}")

    @classmethod
    def from_fields(cls, **fields: Any) -> "TrackerConfig":
        """Build from the previous release's flat fields by their own names
        (``gate_width_m=2.5``; ``ego_motion`` an `EgoMotionConfig`), each sent to its
        sub-config, without a warning: the bridge for a vocabulary that names the fields.

        Raises
        ------
        BadInput
            An unknown field name (with the known ones), or a value its sub-config refuses.
        """
        return cls().replace_fields(**fields)

    def replace(self, **changes: Any) -> "TrackerConfig":
        """A copy with some fields changed (every changed sub-config validated again), by
        dotted key (``**{"gating.gate_mahalanobis": 20.0}``), by sub-config
        (``gating={"gate_mahalanobis": 20.0}`` or a `GateConfig`); the flat keys of the
        previous release (``gate_mahalanobis=20.0``) still work and warn
        (`DeprecationWarning`) with the new key. Unknown fields raise BadInput."""
        return replace_paths(self, tracker_paths(changes, stacklevel=4))

    def replace_fields(self, **changes: Any) -> "TrackerConfig":
        """`replace` with the previous release's flat fields by their own names (a
        sub-config's name takes a whole sub-config), without a warning.

        Raises
        ------
        BadInput
            An unknown field name (with the known ones), or a value its sub-config refuses.
        """
        unknown = sorted(set(changes) - set(FIELD_GROUP) - set(GROUPS))
        if unknown:
            raise BadInput(f"unknown TrackerConfig field(s) {unknown}; known: "
                           f"{sorted(FIELD_GROUP)} and the sub-configs {list(GROUPS)}")
        return replace_paths(self, {FLAT_KEYS.get(k, k): v for k, v in changes.items()})

    @property
    def n_state(self) -> int:
        """Length of the state vector (4 for CV, 6 for CA)."""
        return self.motion.n_state

    @property
    def measurement_noise(self) -> np.ndarray:
        """Per-point measurement covariance Rm, (3, 3): range m^2, azimuth rad^2, (m/s)^2."""
        return self.noise.covariance

    @property
    def process_noise_sigma(self) -> float:
        """The process-noise intensity of the selected motion model."""
        return self.motion.process_noise_sigma


def tracker_paths(changes: dict[str, Any], *, warn: bool = True,
                  stacklevel: int = 3) -> dict[str, Any]:
    """`TrackerConfig` changes as dotted paths and whole sub-configs
    (`core.config.dotted_changes`): a sub-config's table becomes its dotted keys, a flat key
    its dotted path (with a `DeprecationWarning` unless `warn` is False).

    Raises
    ------
    BadInput
        A key that names no sub-config, field of a sub-config, or flat field.
    """
    paths = dotted_changes(changes, GROUPS, FLAT_KEYS, "TrackerConfig", warn=warn,
                           stacklevel=stacklevel)
    for path in paths:
        group, _, name = path.partition(".")
        if name and name not in {f.name for f in dataclasses.fields(GROUPS[group])}:
            raise BadInput(f"unknown TrackerConfig field(s) [{path!r}]; {group} holds "
                           f"{sorted(f.name for f in dataclasses.fields(GROUPS[group]))}")
    return paths


# Every field of the previous release is also read by its own name: cfg.gate_mahalanobis is
# cfg.gating.gate_mahalanobis.
add_flat_properties(TrackerConfig, FIELD_GROUP)
