"""Multipath of the road scene: guard-rail ghosts and the two-ray ground bounce.

Guard rail: a metal W-beam is a mirror for the radar. The double bounce radar -> rail -> target
-> rail -> radar puts a ghost at the target's mirror image behind the rail (its velocity mirrored
too), attenuated by the rail's power reflection coefficient once per bounce. A ghost exists only
where the bounce point lies on the rail and both legs, radar -> bounce point and bounce point ->
scatterer, are free of other boxes (the scatterer's own box included: a point on the far side
of a car is not seen from the rail).

Ground: a corner radar 0.5 m above a flat road sees each scatterer also through its ground
image. With reflection coefficient Gamma and path difference Delta between the reflected and
the direct path, the one-way field factor is F = |1 + Gamma exp(-j 2 pi Delta / lambda)|; the
monostatic echo carries F^4 (out and back). For Gamma = -1 and R >> heights,
Delta ~ 2 h_r h_t / R and F^2 = (2 sin(2 pi h_r h_t / (lambda R)))^2 (design.md 8): the echo of a
target lobes with range, with nulls where h_r h_t / (lambda R) is an integer / 2.

References
----------
.. [1] M. I. Skolnik, Introduction to Radar Systems, 3rd ed., McGraw-Hill 2001, sec. 8.2
       (two-ray propagation factor, lobing over a flat earth).
.. [2] E. F. Knott, J. F. Shaeffer, M. T. Tuley, Radar Cross Section, 2nd ed., 1993, ch. 5
       (multiple bounces between a target and a reflecting plane).
"""
from __future__ import annotations

import numpy as np

from .raycast import segments_blocked
from .scatterers import Scatterers

__all__ = ["rail_ghosts", "two_ray_power_factor", "MULTIPATH_ACTOR_ID"]

#: actor_id of multipath (guard-rail mirror) ghost scatterers.
MULTIPATH_ACTOR_ID = -1


def rail_ghosts(sc: Scatterers, source_box: np.ndarray, centres_m: np.ndarray,
                half_sizes_m: np.ndarray, yaws_rad: np.ndarray, rail: np.ndarray, *,
                reflectivity: float, max_range_m: float) -> Scatterers:
    """Guard-rail double-bounce ghosts of actor scatterers, both legs checked for occlusion.

    Parameters
    ----------
    sc : Scatterers
        The actors' scatterers (K), radar frame.
    source_box : (K,) int
        Box index of each scatterer (-1: none; such scatterers get no ghost).
    centres_m, half_sizes_m : (B, 3) float
        Every box of the frame (occluders), radar frame, m.
    yaws_rad : (B,) float
    rail : (B,) bool
        Which boxes are guard rails (mirrors).
    reflectivity : float
        Power reflection coefficient of the rail per bounce, in (0, 1].
    max_range_m : float
        Ghosts beyond this range are dropped, m.

    Returns
    -------
    Scatterers
        One ghost per (scatterer, rail) whose bounce point lies on the rail and whose legs are
        unoccluded; rcs = reflectivity^2 x the scatterer's, actor_id `MULTIPATH_ACTOR_ID`.
    """
    rail_idx = np.flatnonzero(rail)
    src = np.flatnonzero((source_box >= 0) & ~np.isin(source_box, rail_idx))
    if rail_idx.size == 0 or src.size == 0:
        return Scatterers.empty()
    c, h, yaw = centres_m[rail_idx], half_sizes_m[rail_idx], yaws_rad[rail_idx]
    n = np.column_stack([-np.sin(yaw), np.cos(yaw), np.zeros(rail_idx.size)])  # local +y
    e = np.column_stack([np.cos(yaw), np.sin(yaw), np.zeros(rail_idx.size)])
    # Face toward the radar (origin): flip n so that the radar is on its positive side.
    side = -np.einsum("bd,bd->b", c, n)
    n = n * np.sign(np.where(side == 0, 1.0, side))[:, None]
    q0 = c + n * h[:, 1:2]
    p = sc.position_m[src]
    v = sc.velocity_mps[src]
    dp = np.einsum("kd,bd->kb", p, n) - np.einsum("bd,bd->b", q0, n)[None, :]   # (K, R)
    radar_side = np.einsum("bd,bd->b", -q0, n) > 0
    p_img = p[:, None, :] - 2 * dp[..., None] * n[None, :, :]
    denom = np.einsum("kbd,bd->kb", p_img, n)
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.einsum("bd,bd->b", q0, n)[None, :] / denom
    cross = lam[..., None] * p_img                       # bounce point on the rail face
    along = np.einsum("kbd,bd->kb", cross - c[None, :, :], e)
    ok = ((dp > 0) & radar_side[None, :] & (lam > 0) & (lam < 1)
          & (np.abs(along) <= h[None, :, 0]))
    k_idx, r_idx = np.nonzero(ok)
    if k_idx.size == 0:
        return Scatterers.empty()
    bounce = cross[k_idx, r_idx]
    ignore = np.zeros((k_idx.size, centres_m.shape[0]), dtype=bool)
    ignore[np.arange(k_idx.size), rail_idx[r_idx]] = True
    leg1 = segments_blocked(np.zeros_like(bounce), bounce, centres_m, half_sizes_m, yaws_rad,
                            ignore=ignore)
    # Leg 2 ends on the scatterer's own surface: an entry within 0.3 m of it (the merge
    # cell's half size) is that surface, not an occluder.
    leg2 = segments_blocked(bounce, p[k_idx], centres_m, half_sizes_m, yaws_rad, ignore=ignore,
                            end_tolerance_m=0.3)
    free = ~(leg1 | leg2)
    k_idx, r_idx = k_idx[free], r_idx[free]
    nb = n[r_idx]
    vv = v[k_idx]
    v_img = vv - 2 * np.einsum("kd,kd->k", vv, nb)[:, None] * nb
    rcs = sc.rcs_m2[src][k_idx] * reflectivity ** 2
    pos = p_img[k_idx, r_idx]
    keep = np.linalg.norm(pos, axis=1) < max_range_m
    return Scatterers(pos[keep], v_img[keep], rcs[keep],
                      np.full(int(keep.sum()), MULTIPATH_ACTOR_ID))


def two_ray_power_factor(position_m: np.ndarray, mount_height_m: float, wavelength_m: float,
                         reflection_coefficient: float = -1.0) -> np.ndarray:
    """Two-way power factor F^4 of the flat-ground two-ray channel for each point.

    Parameters
    ----------
    position_m : (K, 3) float
        Scatterer positions, radar frame (ground plane z = -mount_height_m), m.
    mount_height_m : float
        Radar height above the ground, m (> 0).
    wavelength_m : float
        Carrier wavelength, m.
    reflection_coefficient : float
        Ground field reflection coefficient Gamma (real, in [-1, 1]; -1: smooth ground at
        grazing incidence).

    Returns
    -------
    (K,) float
        |1 + Gamma exp(-j k Delta)|^4 with Delta = |p - radar image| - |p| the exact path
        difference (radar image at z = -2 mount_height_m); 1 when Gamma = 0. Points at or
        below the ground get 0 when Gamma = -1 (the two paths cancel).
    """
    p = np.asarray(position_m, dtype=np.float64).reshape(-1, 3)
    image = np.array([0.0, 0.0, -2.0 * mount_height_m])
    delta = np.linalg.norm(p - image, axis=1) - np.linalg.norm(p, axis=1)
    f = np.abs(1.0 + reflection_coefficient * np.exp(-2j * np.pi * delta / wavelength_m))
    return f ** 4
