"""Scenarios: highway-env traffic for the NCAP / UN R79 corner-radar cases, and ground truth.

    run = scenarios.run_scenario("r79_motorcycle_rear", seed=0)
    run.truth   # per frame and actor: pose, velocity, size in the vehicle and radar frames
    run.ego     # per frame: ego speed and world pose
    for f in run.frames(): ...   # truth rows + radar velocity per frame (for radarsim.rcs)

The catalogue `SCENARIOS` holds the shipped cases, one TOML file each in ``scenarios/cases/``;
`load_scenario_file` reads a user's case file the same way. This package knows nothing of the
radar beyond the mount pose (DESIGN 2).

Where to add what: a case is a TOML file in ``scenarios/cases/``; a road layout or a random
traffic environment is an entry of `scenarios.roads.ROAD_LAYOUTS` / `TRAFFIC_ENVS`; a road-user
class an entry of `scenarios.catalog.ACTOR_CLASSES`.

The public names are loaded on first use (PEP 562): `scenarios.checks`, the shared validation
helper every package imports, must not pull in highway-env.
"""
from __future__ import annotations

import importlib

#: Public name -> submodule that defines it.
_EXPORTS = {
    "SCENARIOS": "registry", "get_case": "registry",
    "ACTOR_CLASSES": "catalog", "CASE_CLASSES": "catalog", "MOUNTS": "catalog",
    "ActorSpec": "catalog", "Case": "catalog", "Criterion": "catalog", "Mount": "catalog",
    "ROAD_LAYOUTS": "roads", "TRAFFIC_ENVS": "roads",
    "load_scenario_file": "files", "parse_scenario": "files",
    "FrameTruth": "traffic", "ScenarioRun": "traffic", "run_scenario": "traffic",
    "EGO_COLUMNS": "truth", "TRUTH_COLUMNS": "truth",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'scenarios' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
