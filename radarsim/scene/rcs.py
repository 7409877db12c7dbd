"""Ray-based radar cross-section model: ground-truth actors of one frame to radar scatterers.

Every actor is a 3D box (class length, width and height from the truth table). The ray grid of
`radarsim.scene.raycast` is cast from the radar; the nearest hit per ray (occlusion between actors
included) becomes a surface patch whose RCS follows a facet model, plus a few strong scattering
centres per class (wheels, vertical corners, licence plate, guard-rail posts) that are kept
when their face looks at the radar and nothing is in the way. Patches and centres are merged per
actor into cells of the radar's resolution that start at the actor's nearest point, so an
actor yields one scatterer per radar cell it covers (a head-on car at 30 m: one; a quartering
car at 20 m: a handful), not thousands, and no radar cell holds two beating points of one actor.

Facet model of one hit patch (ray solid angle Omega, distance t, incidence theta from the
face normal, patch area A = t^2 Omega / cos(theta)):

    sigma = A [ mu cos^2(theta)  +  S exp(-(theta / theta_s)^2) ]

the first term the Lambertian diffuse backscatter of a rough painted surface (Ulaby & Long
2014, sec. 10), the second a specular glint whose lobe width theta_s stands for the curvature of
real body panels. The facet model decides WHERE on an actor the echo comes from and what an
occluder takes away; the LEVEL follows a published pattern where one could be sourced
(`radarsim.scene.rcs_patterns`, docs/rcs.md):

- car: 3GPP TR 38.901 Table 7.9.2.1-4 (vehicle, model 2): front 10.8, side 20.1, rear 13.6,
  diagonals 7.1 dBsm at horizontal incidence, elevation lobes from the table (so the radar's
  mount height enters through the zenith angle under which it sees the actor);
- pedestrian: TR 38.901 Table 7.9.2.1-3 (human, model 2): 2.1 dBsm front/back, 0.1 dBsm side;
- bicycle (a cyclist: bicycle and rider): the rider as the TR 38.901 human plus Belgiovane &
  Chen's 77 GHz bicycle sector means (-11.57 front/rear, -13.24 oblique, -8.1 dBsm side, as
  MathWorks' backscatterBicyclist encodes them), added in power: 2.3 / 1.8 / 0.7 dBsm at
  0 / 45 / 90 deg.

Each actor's patches and centres are scaled together by pattern(aspect, zenith) / (the facet
model's unoccluded total at that aspect, computed in closed form from the box faces and centres),
so an unoccluded actor has the published RCS and a half-hidden one about half of it. Classes
without a reachable published pattern (truck, motorcycle, guard rail) keep the facet
model scaled by a calibration gain so that their aspect-averaged mean at 30 m meets
`target_mean_rcs_m2` (truck 50, motorcycle 2 m^2: design values of earlier
rounds, H. Winner, "Automotive RADAR", Handbook of Driver Assistance Systems, 2016; not
re-checked against a measurement here).

Fluctuation: the coherent sum of an actor's scattering centres fluctuates from frame to frame
(a fraction of a degree of aspect change reshuffles the phases at 3.9 mm wavelength). Each actor
draws one log-normal factor per frame with the class's spread (TR 38.901 sigma_S: vehicle 3.41
dB, human 3.94 dB, a cyclist the rider's 3.94 dB; the vehicle value is borrowed for trucks and
motorcycles, for which no published spread was reachable), mean-preserving as eq. 7.9.2-1 defines it
(dB mean = -ln(10)/20 sigma^2); the strong centres keep a small independent spread
(`centre_fluctuation_db`) so the cells of one actor are not perfectly correlated.

Guard rails (class "guard_rail") are metal W-beams with posts every 4 m: an extended low target
whose scatterers carry the rail's actor_id (metrics count their detections as clutter). The
ground is an optional clutter surface (`radarsim.scene.road_clutter`) with actor_id
`GROUND_ACTOR_ID`. With `multipath=True` actor scatterers are mirrored in the road-side face of
the guard rail where both legs of the bounce are free (`radarsim.scene.multipath`), actor_id
-1; with `ground_bounce=True` every actor scatterer carries the two-ray lobing factor of the
road.

References
----------
.. [1] F. T. Ulaby, D. G. Long, Microwave Radar and Radiometric Remote Sensing, U. Michigan Press,
       2014, ch. 10-11 (Lambertian and constant-gamma surface scattering).
.. [2] 3GPP TR 38.901 V19, clause 7.9.2.1 (RCS of sensing targets).
.. [3] H. Winner, "Automotive RADAR", Handbook of Driver Assistance Systems, Springer, 2016.
.. [4] E. F. Knott, J. F. Shaeffer, M. T. Tuley, Radar Cross Section, 2nd ed., 1993 (plates,
       dihedral and trihedral corners).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np
import pandas as pd

from core.checks import require
from core.errors import BadInput

from .multipath import MULTIPATH_ACTOR_ID, rail_ghosts, two_ray_power_factor
from .raycast import RayGridConfig, cast_rays
from .rcs_classes import (  # noqa: F401
    CLASS_RCS,
    POST_SPACING_M,
    REQUIRED_COLUMNS,
    ActorBoxes,
    CentreIncidence,
    ClassRcs,
    actor_boxes,
    centre_incidence,
    class_param,
    geometric_total_rcs,
    radar_angles,
    strong_centres,
)
from .rcs_patterns import lognormal_mu_db
from .road_clutter import GROUND_ACTOR_ID, ground_clutter
from .scatterers import Scatterers

__all__ = ["RcsConfig", "ClassRcs", "CLASS_RCS", "GROUND_ACTOR_ID", "MULTIPATH_ACTOR_ID",
           "scene_scatterers", "single_actor", "actor_boxes", "strong_centres",
           "geometric_total_rcs", "radar_angles", "REQUIRED_COLUMNS", "SPEED_OF_LIGHT_MPS"]

#: m/s (the ground-bounce wavelength default).
SPEED_OF_LIGHT_MPS = 299_792_458.0


@dataclass(frozen=True, kw_only=True, slots=True)
class RcsConfig:
    """Options of the ray-based RCS model.

    Parameters
    ----------
    grid : RayGridConfig
        Ray grid (default 0.25 deg azimuth x 0.5 deg elevation over +/-90 x +/-20 deg).
    max_range_m : float
        Actors and hits beyond this range are dropped, m (> 0). Default 260 m, just beyond the
        R79 preset's 253 m.
    merge_range_m, merge_azimuth_deg, merge_elevation_deg : float
        Merge cell: hits of one actor in one cell become one scatterer (RCS summed, position
        RCS-weighted), m and deg (> 0); cells start at the actor's own nearest point (see
        `_merge`). Default: the R79 preset's 1.32 m range cell and 9.6 deg azimuth
        resolution; in elevation the single 0.8 lambda Tx2 row resolves nothing finer than
        tens of degrees. One scatterer per actor and radar cell is what makes the radar's
        coherent sum in that cell follow the published log-normal (TR 38.901 sigma_S): several
        comparable points at random relative phases inside one cell would add a Rayleigh-like
        beat (5.6 dB spread) on top (docs/rcs.md). Radars of finer resolution should use
        their own cell.
    dither : bool
        Shift the ray grid by a random fraction of a step each frame (from `rng`), so a fixed
        grid does not alias with the actors' motion.
    centre_fluctuation_db : float
        Log-normal spread of the strong centres' RCS per frame, dB (>= 0; mean preserved).
    ground : bool
        Add ground clutter (needs the radar velocity, see `scene_scatterers`).
    ground_gamma_db : float
        Constant-gamma coefficient of the road surface, dB.
    ground_max_range_m : float
        Ground clutter extends to this range, m (> 0). Beyond ~40 m a 0.5 m high radar sees
        asphalt at < 0.7 deg grazing: sigma0 < -32 dB, far below any actor.
    ground_points : int
        Ground patches drawn per frame (>= 1): random positions, uniform in area, each carrying
        sigma0 x (visible area / ground_points), so the total clutter power is right while K
        stays small and the clutter decorrelates frame to frame like real speckle.
    multipath : bool
        Add the guard-rail mirror (double-bounce) ghosts.
    guard_rail_reflectivity : float
        Power reflection coefficient of the rail per bounce, in (0, 1]. Default 0.3: a steel
        beam (|Gamma| ~ 1) filling about a third of the first Fresnel zone at the specular point.
    cull_rcs_at_100m_m2 : float
        Scatterers whose echo is weaker than that of this RCS at 100 m (rcs (100 / r)^4 below
        it) are dropped, m^2 (>= 0; 0 keeps all). Default 3e-3 m^2: with the R79 preset 1 m^2 at
        100 m integrates to ~17 dB SNR after window losses, so the cull sits ~8 dB under the
        noise of one cell and ~25 dB under a CFAR threshold: the radar output is unchanged
        while weak distant guard-rail cells stop inflating K.
    clutter_merge_factor : float
        Guard-rail (clutter) merge cells are this many times larger in range and azimuth
        (>= 1; default 1: the merge cell already is one resolution cell); only a rail's
        presence matters to the metrics, not its exact shape.
    target_fluctuation : bool
        Draw each actor's per-frame log-normal factor (`ClassRcs.fluctuation_db`). Off: every
        actor has its class's mean RCS (pattern checks).
    ground_bounce : bool
        Multiply every actor scatterer by the two-ray power factor of a flat road
        (`radarsim.scene.multipath.two_ray_power_factor`): the lobing of a target's echo with range
        under a low-mounted radar. Off by default.
    ground_reflection_coefficient : float
        Field reflection coefficient of the road for `ground_bounce`, in [-1, 1] (-1: smooth
        road at grazing incidence).
    wavelength_m : float
        Carrier wavelength for `ground_bounce`, m (default 77 GHz).
    """

    grid: RayGridConfig = field(default_factory=RayGridConfig)
    max_range_m: float = 260.0
    merge_range_m: float = 1.32
    merge_azimuth_deg: float = 9.6
    merge_elevation_deg: float = 20.0
    dither: bool = True
    centre_fluctuation_db: float = 1.0
    ground: bool = True
    ground_gamma_db: float = -15.0
    ground_max_range_m: float = 40.0
    ground_points: int = 64
    multipath: bool = False
    guard_rail_reflectivity: float = 0.3
    cull_rcs_at_100m_m2: float = 3e-3
    clutter_merge_factor: float = 1.0
    target_fluctuation: bool = True
    ground_bounce: bool = False
    ground_reflection_coefficient: float = -1.0
    wavelength_m: float = SPEED_OF_LIGHT_MPS / 77e9

    def __post_init__(self) -> None:
        if not isinstance(self.grid, RayGridConfig):
            raise BadInput(f"grid must be a RayGridConfig, got {type(self.grid).__name__}")
        if isinstance(self.ground_points, bool) or not isinstance(self.ground_points, int) \
                or self.ground_points < 1:
            raise BadInput(f"ground_points={self.ground_points!r} must be an integer >= 1")
        require(self, ("max_range_m", "merge_range_m", "merge_azimuth_deg",
                       "merge_elevation_deg", "ground_max_range_m"), gt=0)
        if self.centre_fluctuation_db < 0:
            raise BadInput(f"centre_fluctuation_db={self.centre_fluctuation_db!r} must be "
                           ">= 0")
        if not 0 < self.guard_rail_reflectivity <= 1:
            raise BadInput(f"guard_rail_reflectivity={self.guard_rail_reflectivity!r} must "
                           "be in (0, 1]")
        if not self.clutter_merge_factor >= 1:
            raise BadInput(f"clutter_merge_factor={self.clutter_merge_factor!r} must be >= 1")
        if not self.cull_rcs_at_100m_m2 >= 0:
            raise BadInput(f"cull_rcs_at_100m_m2={self.cull_rcs_at_100m_m2!r} must be >= 0")
        if not -40 <= self.ground_gamma_db <= 0:
            raise BadInput(f"ground_gamma_db={self.ground_gamma_db!r} must be within "
                           "[-40, 0] dB")
        require(self, "ground_reflection_coefficient", ge=-1, le=1)
        require(self, "wavelength_m", gt=0, le=0.1, unit="m")


_DEFAULT_CONFIG = RcsConfig()


def _row_norm(a: np.ndarray) -> np.ndarray:
    """(N,) Euclidean norm of the rows of (N, 3) `a`: the same sum (x^2 + y^2) + z^2 as
    `np.linalg.norm(a, axis=1)`, without its strided reduction (several times faster)."""
    x, y, z = a[:, 0], a[:, 1], a[:, 2]
    return np.sqrt(x * x + y * y + z * z)


_BOX_FIELDS = ("actor_id", "cls", "centre", "half", "yaw", "velocity", "code")


def _actor_scale(boxes: ActorBoxes, cfg: RcsConfig, rng: np.random.Generator,
                 centres, incidence: CentreIncidence) -> np.ndarray:
    """(B,) factor on every patch and centre of each box: pattern level over the facet total
    (or the class gain) times the actor's log-normal fluctuation of this frame. `centres`:
    `strong_centres(boxes)`, `incidence`: `centre_incidence(boxes, centres)`."""
    n = boxes.centre.shape[0]
    scale = class_param(boxes.code, "gain")
    patterned = class_param(boxes.code, "has_pattern") > 0
    if patterned.any():
        phi, theta = radar_angles(boxes)
        total = geometric_total_rcs(boxes, centres, incidence=incidence, only=patterned)
        for code in np.unique(boxes.code[patterned]):
            m = boxes.code == code
            pattern = list(CLASS_RCS.values())[code].pattern
            scale[m] = 10 ** (pattern.rcs_dbsm(phi[m], theta[m]) / 10) \
                / np.maximum(total[m], 1e-12)
    z = rng.standard_normal(n)   # drawn even when unused: the same stream either way
    if cfg.target_fluctuation:
        sigma = class_param(boxes.code, "fluctuation_db")
        scale = scale * 10 ** ((lognormal_mu_db(sigma) + sigma * z) / 10)
    return scale


def _visible_centres(boxes: ActorBoxes, cfg: RcsConfig, rng: np.random.Generator, hits,
                     az_grid: np.ndarray, el_grid: np.ndarray, scale: np.ndarray, centres,
                     incidence: CentreIncidence):
    """Strong centres that face the radar, lie in the grid's field of view and are not occluded.

    Returns (box (C,), position (C, 3), rcs (C,)) in the radar frame, `scale` (B,) applied.
    """
    box, rcs0, lobe = centres[0], centres[3], centres[4]
    pos, r, cos_inc = incidence.position_m, incidence.range_m, incidence.cos_inc
    ray_box = np.full(az_grid.size * el_grid.size, -1, dtype=np.int64)
    ray_t = np.full(az_grid.size * el_grid.size, np.inf)
    hit_ray = hits.elevation_index * az_grid.size + hits.azimuth_index
    ray_box[hit_ray] = hits.box
    ray_t[hit_ray] = hits.t_m
    az = np.degrees(np.arctan2(pos[:, 1], pos[:, 0]))
    el = np.degrees(np.arcsin(np.clip(pos[:, 2] / np.maximum(r, 1e-9), -1, 1)))
    g = cfg.grid
    ok = ((cos_inc > 0) & (r > 0.1) & (r < cfg.max_range_m) & (np.abs(az) <= g.azimuth_limit_deg)
          & (el >= g.elevation_min_deg) & (el <= g.elevation_max_deg))
    box, pos, r, cos_inc, rcs0, lobe = (a[ok] for a in (box, pos, r, cos_inc, rcs0, lobe))
    az, el = np.radians(az[ok]), np.radians(el[ok])
    # Occlusion from the cast itself: the grid ray nearest the centre's direction must hit
    # this box, or nothing closer than the centre (it sits on the surface: 0.3 m tolerance).
    ia = np.clip(np.rint((az - az_grid[0]) / np.radians(g.azimuth_step_deg)).astype(int), 0,
                 az_grid.size - 1)
    ie = np.clip(np.rint((el - el_grid[0]) / np.radians(g.elevation_step_deg)).astype(int), 0,
                 el_grid.size - 1)
    ray = ie * az_grid.size + ia
    vis = (ray_box[ray] == box) | (ray_t[ray] >= r - 0.3)
    box, pos, r, cos_inc, rcs0, lobe = (a[vis] for a in (box, pos, r, cos_inc, rcs0, lobe))
    theta = np.degrees(np.arccos(np.clip(cos_inc, -1, 1)))
    rcs = rcs0 * np.exp(-(theta / lobe) ** 2) * scale[box]
    if cfg.centre_fluctuation_db > 0 and rcs.size:
        s = cfg.centre_fluctuation_db * np.log(10) / 10
        rcs = rcs * np.exp(s * rng.standard_normal(rcs.size) - 0.5 * s * s)
    return box, pos, rcs


def _patch_rcs(hits, boxes: ActorBoxes, cfg: RcsConfig, scale: np.ndarray) -> np.ndarray:
    """(H,) RCS of each hit patch from the facet model, m^2, `scale` (B,) applied.

    For a class with a published (far-field) pattern the incidence that sets a patch's density
    is that of its face seen from the actor's centre direction (a panel's far-field glint
    depends on its orientation, not on where on it a ray lands), so the patches of a face sum
    to the closed form of `geometric_total_rcs` at any range and the actor meets its pattern.
    Classes calibrated by a gain keep each ray's own incidence (a long truck side seen at 30 m
    spans +/-15 deg of incidence and glints only near its middle), as their gains were fit.
    """
    b = hits.box
    code = boxes.code[b]
    u_c = boxes.centre / np.maximum(np.linalg.norm(boxes.centre, axis=1), 1e-9)[:, None]
    far = class_param(code, "has_pattern") > 0
    u = np.where(far[:, None], u_c[b], hits.direction)
    cos_inc = np.clip(-np.einsum("hd,hd->h", u, hits.normal), 0.0, 1.0)
    theta = np.arccos(cos_inc)
    omega = cfg.grid.solid_angle_sr * np.sqrt(1 - hits.direction[:, 2] ** 2)
    mu = class_param(code, "diffuse_m2_per_m2")
    s = class_param(code, "specular_m2_per_m2")
    w = np.radians(class_param(code, "specular_width_deg"))
    # A = t^2 Omega / cos(theta); sigma = A (mu cos^2 + S lobe), written without dividing by 0.
    density = (mu * cos_inc + s * np.exp(-(theta / w) ** 2) / np.maximum(cos_inc, 0.05))
    return hits.t_m ** 2 * omega * density * scale[b]


def _merge(actor_key: np.ndarray, pos: np.ndarray, rcs: np.ndarray, cfg: RcsConfig,
           scale: np.ndarray | float = 1.0):
    """Merge points per (key, range, azimuth, elevation) cell: RCS summed, position weighted.

    The cells of each key (actor) start at that actor's own nearest range, smallest azimuth
    and lowest elevation, not on a grid fixed to the radar: a fixed grid cuts an actor at
    whatever boundary happens to cross it (every actor straddles elevation 0 for a radar at
    mid-height), and two halves of one face in adjacent cells then beat against each other in
    the radar's coherent sum, a fluctuation the published RCS statistics do not contain.
    `scale` (per point) multiplies the range and azimuth cell sizes.
    `actor_key` (P,) holds non-negative integers (box indices).
    Returns (first index of each cell (M,), position (M, 3), rcs (M,)).
    """
    r = _row_norm(pos)
    az = np.degrees(np.arctan2(pos[:, 1], pos[:, 0]))
    el = np.degrees(np.arcsin(np.clip(pos[:, 2] / np.maximum(r, 1e-9), -1, 1)))
    group = np.asarray(actor_key, dtype=np.int64)   # box indices: 0 <= key < B
    lows = []
    for v in (r, az, el):
        low = np.full(group.max(initial=-1) + 1, np.inf)
        np.minimum.at(low, group, v)
        lows.append(low[group])
    ir = np.floor((r - lows[0]) / (cfg.merge_range_m * scale)).astype(np.int64)
    ia = np.floor((az - lows[1]) / (cfg.merge_azimuth_deg * scale)).astype(np.int64)
    ie = np.floor((el - lows[2]) / cfg.merge_elevation_deg).astype(np.int64)
    key = ((group * 4096 + ir) * 2048 + ia) * 256 + ie
    # What np.unique(key, return_index=True, return_inverse=True) gives (cells in increasing
    # key order, each cell's first point), by hashing instead of sorting all P keys: unsorted
    # factorize numbers the cells in order of first appearance, so a cell's first point is
    # where the running maximum of the codes steps up; then the few cells are sorted.
    codes, uniq = pd.factorize(key, sort=False)
    seen = np.maximum.accumulate(codes)
    first_seen = np.flatnonzero(np.r_[True, seen[1:] > seen[:-1]])
    order = np.argsort(uniq, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    inv, first, uniq = rank[codes], first_seen[order], uniq[order]
    w = np.bincount(inv, weights=rcs, minlength=uniq.size)
    wsafe = np.where(w > 0, w, 1.0)
    merged = np.column_stack([np.bincount(inv, weights=rcs * pos[:, d], minlength=uniq.size)
                              for d in range(3)]) / wsafe[:, None]
    # A cell of zero total RCS keeps its first point's position.
    merged = np.where((w > 0)[:, None], merged, pos[first])
    return first, merged, w


def scene_scatterers(truth_frame: pd.DataFrame, rng: np.random.Generator,
                     cfg: RcsConfig | None = None, *, radar_velocity_mps=None,
                     mount_height_m: float | None = None) -> Scatterers:
    """Scatterers of one frame: ray-cast actors, strong centres, ground and multipath.

    Parameters
    ----------
    truth_frame : pandas.DataFrame
        Truth rows of ONE frame with the radar-frame columns `REQUIRED_COLUMNS`
        (`scenarios` truth table). Box centre z is in the radar frame.
    rng : numpy.random.Generator
        Grid dither and strong-centre fluctuation.
    cfg : RcsConfig, optional
    radar_velocity_mps : (3,) float, optional
        Velocity of the radar over the ground in the radar frame, m/s (for ground clutter). If
        omitted it is taken from any guard-rail row (static: its relative velocity is minus the
        radar's); with neither, no ground clutter is generated.
    mount_height_m : float, optional
        Radar height above the ground, m; default from the boxes (they stand on the ground:
        bottom z = -mount height), else 0.5 m.

    Returns
    -------
    Scatterers
        Radar frame; velocity relative to the radar; actor_id = truth actor_id, -1 multipath
        ghosts, `GROUND_ACTOR_ID` ground clutter.
    """
    cfg = _DEFAULT_CONFIG if cfg is None else cfg
    boxes = actor_boxes(truth_frame)
    rng_range = np.linalg.norm(boxes.centre[:, :2], axis=1) - np.hypot(boxes.half[:, 0],
                                                                      boxes.half[:, 1])
    near = rng_range < cfg.max_range_m
    if mount_height_m is None:
        bottoms = (boxes.centre[:, 2] - boxes.half[:, 2])
        mount_height_m = float(-np.median(bottoms)) if bottoms.size else 0.5
    if radar_velocity_mps is None:
        rails = np.flatnonzero(boxes.cls == "guard_rail")
        radar_velocity_mps = -boxes.velocity[rails[0]] if rails.size else None
    boxes = ActorBoxes(*(getattr(boxes, f)[near] for f in _BOX_FIELDS))
    a_off, e_off = rng.random(2) if cfg.dither else (0.0, 0.0)
    centres = strong_centres(boxes)
    incidence = centre_incidence(boxes, centres)
    scale = _actor_scale(boxes, cfg, rng, centres, incidence)
    hits = cast_rays(cfg.grid, boxes.centre, boxes.half, boxes.yaw, azimuth_offset=a_off,
                     elevation_offset=e_off, max_range_m=cfg.max_range_m)
    parts = []
    actor_box = np.zeros(0, dtype=np.int64)
    if boxes.centre.shape[0]:
        p_rcs = _patch_rcs(hits, boxes, cfg, scale)
        c_box, c_pos, c_rcs = _visible_centres(boxes, cfg, rng, hits,
                                               cfg.grid.azimuths_rad(a_off),
                                               cfg.grid.elevations_rad(e_off), scale, centres,
                                               incidence)
        box = np.concatenate([hits.box, c_box])
        pos = np.concatenate([hits.point_m, c_pos])
        rcs = np.concatenate([p_rcs, c_rcs])
        if box.size:
            cell_scale = np.where((boxes.cls == "guard_rail")[box], cfg.clutter_merge_factor,
                                  1.0)
            first, mpos, mrcs = _merge(box, pos, rcs, cfg, cell_scale)
            mbox = box[first]
            actor_box = mbox
            if cfg.ground_bounce:
                mrcs = mrcs * two_ray_power_factor(mpos, mount_height_m, cfg.wavelength_m,
                                                   cfg.ground_reflection_coefficient)
            parts.append(Scatterers(mpos, boxes.velocity[mbox], mrcs, boxes.actor_id[mbox]))
    actors = Scatterers.concatenate(parts)
    out = [actors]
    if cfg.multipath:
        out.append(rail_ghosts(actors, actor_box, boxes.centre, boxes.half, boxes.yaw,
                               boxes.cls == "guard_rail",
                               reflectivity=cfg.guard_rail_reflectivity,
                               max_range_m=cfg.max_range_m))
    if cfg.ground and radar_velocity_mps is not None:
        out.append(ground_clutter(hits, cfg.grid, cfg.grid.azimuths_rad(a_off),
                                  mount_height_m=mount_height_m,
                                  radar_velocity_mps=radar_velocity_mps,
                                  max_range_m=cfg.ground_max_range_m,
                                  n_points=cfg.ground_points, gamma_db=cfg.ground_gamma_db,
                                  rng=rng))
    sc = Scatterers.concatenate(out)
    if cfg.cull_rcs_at_100m_m2 > 0 and len(sc):
        keep = sc.rcs_m2 * (100.0 / _row_norm(sc.position_m)) ** 4 >= cfg.cull_rcs_at_100m_m2
        if not keep.all():
            sc = sc.select(keep)
    return sc


def single_actor(actor_class: str, aspect_deg: float, *, range_m: float = 30.0,
                 rng: np.random.Generator, mount_height_m: float = 0.5,
                 cfg: RcsConfig | None = None) -> Scatterers:
    """Scatterers of one actor alone on the radar's boresight, exactly as the scene model makes
    them (`scene_scatterers`, no ground clutter).

    Parameters
    ----------
    actor_class : str
        A road-user class of `scenarios.catalog.ACTOR_CLASSES` (its catalogue size) or
        ``"guard_rail"``.
    aspect_deg : float
        Aspect: 0 its front faces the radar, 90 its left side, 180 its rear, deg.
    range_m : float
        Horizontal distance from the radar to the actor's centre, m (> 0).
    rng : numpy.random.Generator
        Grid dither and fluctuation.
    mount_height_m : float
        Radar height above the road, m (the catalogue's corner mounts: 0.5 m).
    cfg : RcsConfig, optional

    Returns
    -------
    Scatterers
        Radar frame, actor_id 0.

    Raises
    ------
    ValueError
        Unknown class, aspect not finite, range not a positive finite number.

    Examples
    --------
    >>> import numpy as np
    >>> from radarsim.rcs import single_actor
    >>> sc = single_actor("car", 90.0, rng=np.random.default_rng(0))
    >>> bool(sc.rcs_m2.sum() > 10.0)   # broadside car: ~20 dBsm
    True
    """
    from scenarios.catalog import ACTOR_CLASSES, GUARD_RAIL
    sizes = {**ACTOR_CLASSES, GUARD_RAIL.name: GUARD_RAIL}
    if not isinstance(actor_class, str) or actor_class not in sizes:
        raise BadInput(f"actor_class={actor_class!r} unknown; known: {sorted(sizes)}")
    args = SimpleNamespace(aspect_deg=aspect_deg, range_m=range_m, mount_height_m=mount_height_m)
    require(args, "aspect_deg", unit="deg")
    require(args, "range_m", gt=0, unit="m")
    require(args, "mount_height_m", gt=0, le=3, unit="m")
    size = sizes[actor_class]
    row = dict(actor_id=0, actor_class=actor_class, length_m=size.length_m,
               width_m=size.width_m, height_m=size.height_m, x_radar_m=float(range_m),
               y_radar_m=0.0, z_radar_m=size.height_m / 2 - mount_height_m,
               yaw_radar_deg=180.0 - float(aspect_deg), vx_radar_mps=0.0, vy_radar_mps=0.0)
    truth = pd.DataFrame([row], columns=list(REQUIRED_COLUMNS))
    return scene_scatterers(truth, rng, cfg, mount_height_m=mount_height_m)
