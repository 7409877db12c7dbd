"""Registries of the tracker's parts, so a sweep picks them by name.

Each registry maps the name users type (``TrackerConfig.parts.associator = "nearest"``, a
sweep's ``"tracker.parts.associator" = ["max_likelihood", "nearest"]``) to a `TrackerPart`: a
builder from the `TrackerConfig` and the sensor model to the part object, which hands the part
its own sub-config. A new part is its module plus one ``register`` call here or in that
module; `GroupTracker` looks the parts up, and a part object passed to `GroupTracker` directly
still wins.

Examples
--------
>>> from pipeline.tracking import TrackerConfig, GroupTracker
>>> from pipeline.tracking.parts import ASSOCIATORS, PartNames
>>> sorted(ASSOCIATORS)
['max_likelihood', 'nearest']
>>> cfg = TrackerConfig(parts=PartNames(associator="nearest"))
>>> type(GroupTracker(cfg).associator).__name__
'GatedNearestNeighbour'
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, NamedTuple

from core.registry import Registry

from .associators import AssociationRules, GatedMaximumLikelihood, GatedNearestNeighbour
from .clustering import LeaderClusterAllocator
from .hypothesis import GroupGateHypothesiser
from .update import GroupEkfUpdater, KalmanPredictor

__all__ = ["TrackerPart", "HYPOTHESISERS", "ASSOCIATORS", "UPDATERS", "PREDICTORS",
           "ALLOCATORS", "PART_REGISTRIES", "PartNames"]


class TrackerPart(NamedTuple):
    """A registered part: ``build(cfg, sensor)`` -> the part object."""

    name: str
    build: Callable[[Any, Any], Any]
    description: str


HYPOTHESISERS: Registry[TrackerPart] = Registry("hypothesiser", kind=TrackerPart)
HYPOTHESISERS.register(TrackerPart(
    "group_gate", lambda cfg, sensor: GroupGateHypothesiser(cfg.gating, sensor),
    "TI gtrack group gate: Mahalanobis under H P H' + Rm + D, depth, width, velocity"))

ASSOCIATORS: Registry[TrackerPart] = Registry("associator", kind=TrackerPart)
ASSOCIATORS.register_all((
    TrackerPart("max_likelihood", lambda cfg, sensor: GatedMaximumLikelihood(_rules(cfg)),
                "TI gtrack: the gated track of smallest d^2 + ln det S"),
    TrackerPart("nearest", lambda cfg, sensor: GatedNearestNeighbour(_rules(cfg)),
                "the gated track of smallest d^2"),
))

UPDATERS: Registry[TrackerPart] = Registry("updater", kind=TrackerPart)
UPDATERS.register(TrackerPart(
    "group_ekf", lambda cfg, sensor: GroupEkfUpdater(cfg.update, sensor.noise_cov),
    "EKF update with the group centroid, TI centroid noise plus body jitter"))

PREDICTORS: Registry[TrackerPart] = Registry("predictor", kind=TrackerPart)
PREDICTORS.register(TrackerPart(
    "kalman", lambda cfg, sensor: KalmanPredictor.from_config(cfg.motion),
    "x = F x, P = F P F' + Q of the configured motion model"))

ALLOCATORS: Registry[TrackerPart] = Registry("allocator", kind=TrackerPart)
ALLOCATORS.register(TrackerPart(
    "leader_cluster", lambda cfg, sensor: LeaderClusterAllocator(
        cfg.allocation, sensor, merging=cfg.merging, n_state=cfg.motion.n_state),
    "TI gtrack allocation from leader clusters of unassociated points"))

#: `PartNames` field -> the registry its value names.
PART_REGISTRIES: dict[str, Registry[TrackerPart]] = {
    "hypothesiser": HYPOTHESISERS, "associator": ASSOCIATORS, "updater": UPDATERS,
    "predictor": PREDICTORS, "allocator": ALLOCATORS}


def _rules(cfg) -> AssociationRules:
    """The associator's rules: static points may confirm tracks when they may start them."""
    return AssociationRules(allow_static_tracks=cfg.allocation.allow_static_tracks)


@dataclass(frozen=True, kw_only=True, slots=True)
class PartNames:
    """The parts `GroupTracker` builds, by their registered names (``TrackerConfig.parts``;
    default TI's gtrack).

    Parameters
    ----------
    hypothesiser, associator, updater, predictor, allocator : str
        A name of `HYPOTHESISERS`, `ASSOCIATORS`, `UPDATERS`, `PREDICTORS`, `ALLOCATORS`.

    Raises
    ------
    core.errors.BadInput
        A name its registry does not hold, naming the known ones.
    """

    hypothesiser: str = "group_gate"
    associator: str = "max_likelihood"
    updater: str = "group_ekf"
    predictor: str = "kalman"
    allocator: str = "leader_cluster"

    def __post_init__(self) -> None:
        for name, registry in PART_REGISTRIES.items():
            registry.lookup(getattr(self, name))

    def build(self, role: str, cfg, sensor) -> Any:
        """The part of `role` (a `PART_REGISTRIES` key) named here, built from the tracker's
        config `cfg` and the `sensor`."""
        return PART_REGISTRIES[role].lookup(getattr(self, role)).build(cfg, sensor)
