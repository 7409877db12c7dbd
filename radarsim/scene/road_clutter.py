"""Road-surface clutter: random ground patches whose RCS follows sigma0(grazing angle).

The road in front of a corner radar is seen at grazing angles of a few degrees down to a
fraction of a degree (0.5 m mount: 2.9 deg at 10 m, 0.7 deg at 40 m). Each frame draws
`n_points` patch positions uniformly in area over the annular sector the ray grid can see
(from where the lowest ray meets the ground to `max_range_m`), drops those in the shadow of the
nearest box hit of their azimuth column, and gives each the RCS sigma0(grazing) x area / n, so
that the total clutter power is right while K stays small and the clutter decorrelates frame to
frame like speckle.

sigma0 model: constant gamma, sigma0 = gamma sin(grazing) (Ulaby & Long 2014, sec. 11;
gamma = -15 dB for asphalt by default). No published 77 GHz road measurement with numbers could
be reached from this session (docs/rcs.md): the grazing-angle law is the constant-gamma law,
not a fit to measured data.

References
----------
.. [1] F. T. Ulaby, D. G. Long, Microwave Radar and Radiometric Remote Sensing, U. Michigan Press,
       2014, ch. 11 (constant-gamma surface scattering).
.. [2] E. S. Li, K. Sarabandi, "Low grazing incidence millimeter-wave scattering models and
       measurements for various road surfaces", IEEE Trans. AP 47(5), 1999 (94 GHz, 70-88 deg
       incidence; abstract only reachable here).
"""
from __future__ import annotations

import numpy as np

from .scatterers import Scatterers

__all__ = ["GROUND_ACTOR_ID", "constant_gamma_sigma0", "ground_clutter"]

#: actor_id of ground-clutter scatterers (not a truth actor; not a ghost either).
GROUND_ACTOR_ID = -2


def constant_gamma_sigma0(grazing_rad, gamma_db: float) -> np.ndarray:
    """sigma0 = gamma sin(grazing), m^2/m^2 (`grazing_rad` any shape, rad)."""
    return 10 ** (gamma_db / 10) * np.sin(np.asarray(grazing_rad, dtype=np.float64))


def ground_clutter(hits, grid, az_grid: np.ndarray, *, mount_height_m: float,
                   radar_velocity_mps, max_range_m: float, n_points: int, gamma_db: float,
                   rng: np.random.Generator) -> Scatterers:
    """Ground patches at random positions, hidden behind the first box hit of their column.

    Parameters
    ----------
    hits : radarsim.scene.raycast.RayHits
        The frame's ray hits (shadows).
    grid : radarsim.scene.raycast.RayGridConfig
    az_grid : (n_azimuth,) float
        The frame's (dithered) ray azimuths, rad.
    mount_height_m : float
        Radar height above the road, m.
    radar_velocity_mps : (3,) float
        Radar velocity over the ground, radar frame (clutter moves at minus it), m/s.
    max_range_m : float
        Clutter extends to this horizontal range, m.
    n_points : int
        Patches drawn per frame.
    gamma_db : float
        Constant-gamma coefficient, dB.
    rng : numpy.random.Generator

    Returns
    -------
    Scatterers
        actor_id `GROUND_ACTOR_ID`, z = -mount_height_m.
    """
    if grid.elevation_min_deg >= 0:
        return Scatterers.empty()
    # Nearest ground the lowest ray reaches; patches start there.
    r_min = mount_height_m / np.tan(np.radians(-grid.elevation_min_deg))
    if r_min >= max_range_m:
        return Scatterers.empty()
    a_lim = np.radians(grid.azimuth_limit_deg)
    # Uniform in area over the annular sector: r = sqrt(U(r_min^2, r_max^2)).
    r = np.sqrt(rng.uniform(r_min ** 2, max_range_m ** 2, n_points))
    az = rng.uniform(-a_lim, a_lim, n_points)
    area_total = a_lim * (max_range_m ** 2 - r_min ** 2)   # (2 a_lim / 2) (r_max^2 - r_min^2)
    # Shadow: the nearest horizontal hit distance in each ray column.
    col_min = np.full(az_grid.size, np.inf)
    if len(hits):
        np.minimum.at(col_min, hits.azimuth_index,
                      hits.t_m * np.sqrt(1 - hits.direction[:, 2] ** 2))
    col = np.clip(np.rint((az - az_grid[0]) / np.radians(grid.azimuth_step_deg)).astype(int), 0,
                  az_grid.size - 1)
    vis = r < col_min[col]
    r, az = r[vis], az[vis]
    sigma0 = constant_gamma_sigma0(np.arctan2(mount_height_m, r), gamma_db)
    pos = np.column_stack([r * np.cos(az), r * np.sin(az), np.full(r.size, -mount_height_m)])
    vel = np.broadcast_to(-np.asarray(radar_velocity_mps, dtype=float), pos.shape)
    return Scatterers(pos, vel, sigma0 * area_total / n_points,
                      np.full(r.size, GROUND_ACTOR_ID))
