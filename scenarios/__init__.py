"""Scenarios: highway-env traffic for the NCAP / UN R79 corner-radar cases, and ground truth.

    run = scenarios.run_scenario("r79_motorcycle_rear", seed=0)
    run.truth   # per frame and actor: pose, velocity, size in the vehicle and radar frames
    run.ego     # per frame: ego speed and world pose
    for f in run.frames(): ...   # truth rows + radar velocity per frame (for radarsim.rcs)

The catalogue `SCENARIOS` holds the shipped cases, one TOML file each in ``scenarios/cases/``;
`load_scenario_file` reads a user's case file the same way, and `load_case_file` also reads an
OpenSCENARIO file (``scenarios.openscenario``: export and import of OpenSCENARIO 1.x). This
package knows nothing of the radar beyond the mount pose (design.md 2).

Where to add what: a case is a TOML file in ``scenarios/cases/``; a road layout or a random
traffic environment is an entry of `scenarios.roads.ROAD_LAYOUTS` / `TRAFFIC_ENVS`; a road-user
class an entry of `scenarios.catalog.ACTOR_CLASSES`.
"""
from __future__ import annotations

from .catalog import ACTOR_CLASSES, CASE_CLASSES, MOUNTS, ActorSpec, Case, Criterion, Mount
from .files import load_case_file, load_scenario_file, parse_scenario
from .registry import SCENARIOS, get_case
from .roads import ROAD_LAYOUTS, TRAFFIC_ENVS
from .traffic import FrameTruth, ScenarioRun, run_scenario
from .truth import EGO_COLUMNS, TRUTH_COLUMNS

__all__ = ["ACTOR_CLASSES", "CASE_CLASSES", "EGO_COLUMNS", "MOUNTS", "ROAD_LAYOUTS", "SCENARIOS",
           "TRAFFIC_ENVS", "TRUTH_COLUMNS", "ActorSpec", "Case", "Criterion", "FrameTruth",
           "Mount", "ScenarioRun", "get_case", "load_case_file", "load_scenario_file",
           "parse_scenario", "run_scenario"]
