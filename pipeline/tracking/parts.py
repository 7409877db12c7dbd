"""Registries of the tracker's parts, so a sweep picks them by name.

Each registry maps the name users type (``TrackerConfig.associator = "nearest"``, a sweep's
``"tracker.associator" = ["max_likelihood", "nearest"]``) to a `TrackerPart`: a builder from the
`TrackerConfig` and the sensor model to the part object. A new part is its module plus one
``register`` call here or in that module; `GroupTracker` looks the parts up, and a part object
passed to `GroupTracker` directly still wins.

Examples
--------
>>> from pipeline.tracking import TrackerConfig, GroupTracker
>>> from pipeline.tracking.parts import ASSOCIATORS
>>> sorted(ASSOCIATORS)
['max_likelihood', 'nearest']
>>> type(GroupTracker(TrackerConfig(associator="nearest")).associator).__name__
'GatedNearestNeighbour'
"""
from __future__ import annotations

from typing import Any, Callable, NamedTuple

from core.registry import Registry

from .association import GatedMaximumLikelihood, GatedNearestNeighbour
from .clustering import LeaderClusterAllocator
from .hypothesis import GroupGateHypothesiser
from .models import MOTION_MODELS
from .update import GroupEkfUpdater, KalmanPredictor

__all__ = ["TrackerPart", "HYPOTHESISERS", "ASSOCIATORS", "UPDATERS", "PREDICTORS",
           "ALLOCATORS", "PART_REGISTRIES"]


class TrackerPart(NamedTuple):
    """A registered part: ``build(cfg, sensor)`` -> the part object."""

    name: str
    build: Callable[[Any, Any], Any]
    description: str


HYPOTHESISERS: Registry[TrackerPart] = Registry("hypothesiser", kind=TrackerPart)
HYPOTHESISERS.register(TrackerPart(
    "group_gate", lambda cfg, sensor: GroupGateHypothesiser(cfg, sensor),
    "TI gtrack group gate: Mahalanobis under H P H' + Rm + D, depth, width, velocity"))

ASSOCIATORS: Registry[TrackerPart] = Registry("associator", kind=TrackerPart)
ASSOCIATORS.register_all((
    TrackerPart("max_likelihood", lambda cfg, sensor: GatedMaximumLikelihood(cfg),
                "TI gtrack: the gated track of smallest d^2 + ln det S"),
    TrackerPart("nearest", lambda cfg, sensor: GatedNearestNeighbour(cfg),
                "the gated track of smallest d^2"),
))

UPDATERS: Registry[TrackerPart] = Registry("updater", kind=TrackerPart)
UPDATERS.register(TrackerPart(
    "group_ekf", lambda cfg, sensor: GroupEkfUpdater(cfg, sensor.noise_cov),
    "EKF update with the group centroid, TI centroid noise plus body jitter"))

PREDICTORS: Registry[TrackerPart] = Registry("predictor", kind=TrackerPart)
PREDICTORS.register(TrackerPart(
    "kalman", lambda cfg, sensor: KalmanPredictor(MOTION_MODELS[cfg.motion_model],
                                                  cfg.process_noise_sigma),
    "x = F x, P = F P F' + Q of the configured motion model"))

ALLOCATORS: Registry[TrackerPart] = Registry("allocator", kind=TrackerPart)
ALLOCATORS.register(TrackerPart(
    "leader_cluster", lambda cfg, sensor: LeaderClusterAllocator(cfg, sensor),
    "TI gtrack allocation from leader clusters of unassociated points"))

#: TrackerConfig field -> the registry its value names.
PART_REGISTRIES: dict[str, Registry[TrackerPart]] = {
    "hypothesiser": HYPOTHESISERS, "associator": ASSOCIATORS, "updater": UPDATERS,
    "predictor": PREDICTORS, "allocator": ALLOCATORS}
