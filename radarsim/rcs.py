"""`radarsim.rcs`: the public name of the scene's RCS model, `radarsim.scene.rcs`.

The model lives with the rest of the scene (`radarsim.scene`); this module keeps the documented
entry points importable under their published name, e.g.
``radarsim.rcs.single_actor("car", 180.0, range_m=30.0, rng=rng)``.
"""
from .scene.rcs import (
    CLASS_RCS,
    GROUND_ACTOR_ID,
    MULTIPATH_ACTOR_ID,
    REQUIRED_COLUMNS,
    SPEED_OF_LIGHT_MPS,
    ClassRcs,
    RcsConfig,
    actor_boxes,
    geometric_total_rcs,
    radar_angles,
    scene_scatterers,
    single_actor,
    strong_centres,
)

__all__ = ["RcsConfig", "ClassRcs", "CLASS_RCS", "GROUND_ACTOR_ID", "MULTIPATH_ACTOR_ID",
           "scene_scatterers", "single_actor", "actor_boxes", "strong_centres",
           "geometric_total_rcs", "radar_angles", "REQUIRED_COLUMNS", "SPEED_OF_LIGHT_MPS"]
