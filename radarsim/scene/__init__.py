"""The scene as the radar sees it: ground-truth actors of a frame turned into point scatterers.

`scatterers` holds the `Scatterers` record the front end consumes; `rcs` the ray-based RCS
model (`scene_scatterers`, `single_actor`), its class records (`rcs_classes`) and published
patterns (`rcs_patterns`); `raycast` the ray grid and box intersections; `multipath` the
guard-rail mirror ghosts and the road's two-ray factor; `road_clutter` the ground surface;
`canonical` closed-form RCS of plates and corners that check the facet model. Nothing here
knows the radar's waveform: the front end (`radarsim.frontend`) turns scatterers into ADC
samples.
"""
from .rcs import (
           CLASS_RCS,
           GROUND_ACTOR_ID,
           MULTIPATH_ACTOR_ID,
           RcsConfig,
           scene_scatterers,
           single_actor,
)
from .scatterers import Scatterers

__all__ = ["Scatterers", "RcsConfig", "CLASS_RCS", "GROUND_ACTOR_ID", "MULTIPATH_ACTOR_ID",
           "scene_scatterers", "single_actor"]
