"""Scenarios: highway-env traffic for the NCAP / UN R79 corner-radar cases, and ground truth.

    run = scenarios.run_scenario("r79_motorcycle_rear", seed=0)
    run.truth   # per frame and actor: pose, velocity, size in the vehicle and radar frames
    run.ego     # per frame: ego speed and world pose
    for f in run.frames(): ...   # truth rows + radar velocity per frame (for radarsim.rcs)

The catalogue `SCENARIOS` holds the named cases; `load_scenario_file` reads a user case from
TOML. This package knows nothing of the radar beyond the mount pose (DESIGN 2).
"""
from .catalog import (ACTOR_CLASSES, CRITERION_METRICS, MOUNTS, SCENARIOS, ActorSpec, Case,
                      Criterion, Mount, get_case, s_crit_m)
from .files import load_scenario_file, parse_scenario
from .traffic import FrameTruth, ScenarioRun, run_scenario
from .truth import EGO_COLUMNS, TRUTH_COLUMNS

__all__ = ["SCENARIOS", "ACTOR_CLASSES", "MOUNTS", "CRITERION_METRICS", "Case", "ActorSpec",
           "Criterion", "Mount", "get_case", "s_crit_m", "run_scenario", "ScenarioRun",
           "FrameTruth", "load_scenario_file", "parse_scenario", "TRUTH_COLUMNS",
           "EGO_COLUMNS"]
