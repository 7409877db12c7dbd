"""Canonical scatterers computed the way the harness sums echoes: a coherent sum of patches.

The front end adds the echoes of point scatterers coherently (amplitude sqrt(sigma_i), phase
-2 k r_i). A surface cut into patches of area dA, each a point scatterer of RCS
4 pi dA^2 / lambda^2 (a patch's physical-optics RCS at normal incidence), summed that way is the
physical-optics integral

    sigma = (4 pi / lambda^2) | sum_i dA_i cos(theta_i) exp(-j 2 k r_i) |^2,

so these functions check the harness's summation against the closed forms of Knott:

- flat rectangular plate a x b, rotated by theta about its b edge: sigma = 4 pi (a b)^2 /
  lambda^2 cos^2(theta) sinc^2(2 a sin(theta) / lambda) (normal incidence: 4 pi A^2 / lambda^2,
  design.md 8: 10 cm square at 77 GHz = 19.2 dBsm; first null at sin(theta) = lambda / (2 a));
- square trihedral corner of edge a seen along its symmetry axis: shooting and bouncing rays
  (three specular bounces, each flipping one direction component) gives the retro-reflecting
  aperture; all returning rays travel the same path, so sigma = 4 pi A_eff^2 / lambda^2 with
  A_eff the aperture's projected area: 12 pi a^4 / lambda^2 for the square trihedral.

References
----------
.. [1] E. F. Knott, J. F. Shaeffer, M. T. Tuley, Radar Cross Section, 2nd ed., Artech House 1993,
       ch. 6 (flat plate) and table 6.1 (trihedral corner reflectors).
.. [2] H. Ling, R.-C. Chou, S.-W. Lee, "Shooting and bouncing rays", IEEE Trans. AP 37(2), 1989.
"""
from __future__ import annotations

import numpy as np

__all__ = ["plate_rcs_po", "trihedral_rcs_sbr"]


def plate_rcs_po(a_m: float, b_m: float, theta_rad, wavelength_m: float,
                 n_patches: int = 400) -> np.ndarray:
    """Monostatic RCS of an a x b plate rotated by theta about its b edge, by the coherent sum
    of `n_patches` strips along a (the sum over b is uniform and done in closed form), m^2.

    Parameters
    ----------
    a_m, b_m : float
        Plate sides, m.
    theta_rad : array_like
        Incidence from the normal in the plane containing side a, rad.
    wavelength_m : float
    n_patches : int
        Strips along a (>= 2 per wavelength of 2 a sin(theta) path for the sum to be exact).

    Returns
    -------
    numpy.ndarray
        Shape of `theta_rad`, m^2.
    """
    theta = np.asarray(theta_rad, dtype=np.float64)
    x = (np.arange(n_patches) + 0.5) / n_patches * a_m - a_m / 2      # strip centres
    d_area = a_m * b_m / n_patches
    k = 2 * np.pi / wavelength_m
    # Two-way path of strip x: 2 x sin(theta) relative to the centre; projected area dA cos.
    phase = -2j * k * np.multiply.outer(np.sin(theta), x)
    field = (d_area * np.cos(theta))[..., None] * np.exp(phase)
    return 4 * np.pi / wavelength_m ** 2 * np.abs(field.sum(axis=-1)) ** 2


def trihedral_rcs_sbr(edge_m: float, wavelength_m: float, n_rays: int = 400) -> float:
    """RCS of a square trihedral corner (three mutually perpendicular square plates of edge a,
    corner at the origin, faces on the coordinate planes) seen along its symmetry axis, m^2.

    Rays on an n x n grid over the corner's projection travel along -(1, 1, 1)/sqrt(3); each
    is traced through specular bounces on the three faces (x = 0, y = 0, z = 0 within [0, a]^2);
    a ray that bounces on all three leaves along +(1, 1, 1)/sqrt(3) (retro-reflected) with the
    same total path as every other such ray, so the coherent sum is the returned projected area
    A_eff and sigma = 4 pi A_eff^2 / lambda^2.
    """
    u = np.ones(3) / np.sqrt(3.0)
    # Orthonormal basis of the plane normal to u; the corner's projection lies within
    # radius a sqrt(2/3) of the axis.
    e1 = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)
    e2 = np.cross(u, e1)
    half = edge_m * np.sqrt(2.0 / 3.0)
    s = (np.arange(n_rays) + 0.5) / n_rays * 2 * half - half
    g1, g2 = np.meshgrid(s, s, indexing="ij")
    start = (g1.reshape(-1, 1) * e1 + g2.reshape(-1, 1) * e2) + 3 * edge_m * u
    d = np.tile(-u, (start.shape[0], 1))
    p = start.copy()
    bounced = np.zeros((start.shape[0], 3), dtype=bool)
    alive = np.ones(start.shape[0], dtype=bool)
    for _ in range(3):
        # Next face hit: plane i (coordinate i = 0) at t = -p_i / d_i for d_i < 0.
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(d < 0, -p / d, np.inf)
        t = np.where(bounced, np.inf, t)
        face = np.argmin(t, axis=1)
        t_hit = t[np.arange(t.shape[0]), face]
        hit = p + t_hit[:, None] * d
        others = np.ones((hit.shape[0], 3), dtype=bool)
        others[np.arange(hit.shape[0]), face] = False
        inside = np.all(np.where(others, (hit >= 0) & (hit <= edge_m), True), axis=1)
        alive &= np.isfinite(t_hit) & inside
        p = np.where(alive[:, None], hit, p)
        d = np.where(alive[:, None] & ~others, -d, d)
        bounced[np.arange(hit.shape[0]), face] |= alive
    returned = alive & bounced.all(axis=1) & np.all(np.abs(d - u) < 1e-9, axis=1)
    cell = (2 * half / n_rays) ** 2
    a_eff = cell * np.count_nonzero(returned)
    return 4 * np.pi * a_eff ** 2 / wavelength_m ** 2
