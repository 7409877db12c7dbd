"""Ray-based radar cross-section model: ground-truth actors of one frame to radar scatterers.

Every actor is a 3D box (class length, width and height from the truth table). The ray grid of
`radarsim.raycast` is cast from the radar; the nearest hit per ray (occlusion between actors
included) becomes a surface patch whose RCS follows a facet model, plus a few strong scattering
centres per class (wheels, vertical corners, licence plate, guard-rail posts) that are kept
when their face looks at the radar and nothing is in the way. Patches and centres are merged per
(actor, range, azimuth, elevation) cell, so a car yields tens of scatterers, not thousands.

Facet model of one hit patch (ray solid angle Omega, distance t, incidence theta from the
face normal, patch area A = t^2 Omega / cos(theta)):

    sigma = A [ mu cos^2(theta)  +  S exp(-(theta / theta_s)^2) ]

the first term the Lambertian diffuse backscatter of a rough painted surface (Ulaby & Long
2014, sec. 10), the second a specular glint whose lobe width theta_s stands for the curvature of
real body panels (a flat 4.5 m^2 door would give 10^7 m^2 in a 0.05 deg lobe; measured car
broadside peaks are 20-25 dBsm over a few degrees). Each class is then scaled by a calibration
gain so that its aspect-averaged mean RCS (azimuth of the actor's heading uniform over 360 deg,
seen at 30 m) meets the class target of `CLASS_RCS`:

======== ========== ============================================================================
class    target m^2 source
======== ========== ============================================================================
car      10         DESIGN 8 "reference car about 10 m^2"; H. Winner, "Automotive RADAR", in
                    Handbook of Driver Assistance Systems, Springer 2016 (car 10 dBsm)
truck    50         "tens of m^2": Winner (op. cit.), trucks 15-25 dBsm
motorcycle 2        1-3 m^2: Winner (op. cit.); motorcycle with rider 0-5 dBsm
bicycle  1          cyclist ~1 m^2: Belgiovane & Chen, "Bicycles and human riders backscattering
                    at 77 GHz for automotive radar", EuCAP 2016 (0 dBsm order of magnitude)
pedestrian 0.5      ~ -3 dBsm: N. Yamada et al., "Radar cross section for pedestrian in 76 GHz
                    band", EuMC 2005 (-10..0 dBsm, 0.5 m^2 taken as the design value)
======== ========== ============================================================================

Guard rails (class "guard_rail") are metal W-beams with posts every 4 m: an extended low target
whose scatterers carry the rail's actor_id (metrics count their detections as clutter). The
ground is an optional constant-gamma clutter surface (sigma0 = gamma sin(grazing), Ulaby & Long
2014, sec. 11; gamma = -15 dB for asphalt, consistent with the -25..-40 dB that Sarabandi et al.
1997 measured at millimetre waves at grazing angles) with actor_id `GROUND_ACTOR_ID`. With
`multipath=True` every actor scatterer is mirrored in the road-side face of the guard rail
(radar -> rail -> target -> rail -> radar, the classic ghost behind the rail), actor_id -1.

References
----------
.. [1] F. T. Ulaby, D. G. Long, Microwave Radar and Radiometric Remote Sensing, U. Michigan Press,
       2014, ch. 10-11 (Lambertian and constant-gamma surface scattering).
.. [2] K. Sarabandi, E. S. Li, A. Nashashibi, "Modeling and measurements of scattering from road
       surfaces at millimeter-wave frequencies", IEEE Trans. AP 45(11), 1997.
.. [3] H. Winner, "Automotive RADAR", Handbook of Driver Assistance Systems, Springer, 2016.
.. [4] E. F. Knott, J. F. Shaeffer, M. T. Tuley, Radar Cross Section, 2nd ed., 1993 (plates,
       dihedral and trihedral corners).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from scenarios.checks import require

from .multipath import MULTIPATH_ACTOR_ID, rail_ghosts
from .raycast import RayGridConfig, cast_rays
from .road_clutter import GROUND_ACTOR_ID, ground_clutter
from .scatterers import Scatterers

__all__ = ["RcsConfig", "ClassRcs", "CLASS_RCS", "GROUND_ACTOR_ID", "MULTIPATH_ACTOR_ID",
           "scene_scatterers", "actor_boxes", "strong_centres", "REQUIRED_COLUMNS"]


#: Guard-rail post spacing, m (2 m for high containment levels, 4 m common on motorways).
POST_SPACING_M = 4.0
#: Columns of the truth rows `scene_scatterers` reads (radar-frame columns of the truth table).
REQUIRED_COLUMNS = ("actor_id", "actor_class", "length_m", "width_m", "height_m", "x_radar_m",
                    "y_radar_m", "z_radar_m", "yaw_radar_deg", "vx_radar_mps", "vy_radar_mps")


@dataclass(frozen=True, kw_only=True, slots=True)
class ClassRcs:
    """Facet-model parameters of one actor class.

    Parameters
    ----------
    target_mean_rcs_m2 : float
        Calibration target: aspect-averaged mean RCS, m^2 (sources in the module docstring).
    diffuse_m2_per_m2 : float
        Lambertian coefficient mu (sigma0 = mu cos^2 theta), m^2/m^2.
    specular_m2_per_m2 : float
        Peak specular density S at normal incidence, m^2/m^2.
    specular_width_deg : float
        Gaussian lobe width theta_s of the specular term, deg.
    gain : float
        Calibration gain applied to the class's patches and centres (fit once, see
        `tests/radarsim/test_rcs.py::test_class_mean_rcs_within_3db`).
    wheel_rcs_m2, corner_rcs_m2, plate_rcs_m2 : float
        Strong centres: each wheel (on the side faces), each vertical corner edge (dihedral
        between bumper and side), the plate / rear structure (front and rear faces), m^2.
    """

    target_mean_rcs_m2: float
    diffuse_m2_per_m2: float
    specular_m2_per_m2: float
    specular_width_deg: float
    gain: float = 1.0
    wheel_rcs_m2: float = 0.0
    corner_rcs_m2: float = 0.0
    plate_rcs_m2: float = 0.0

    def __post_init__(self) -> None:
        require(self, ("target_mean_rcs_m2", "specular_width_deg", "gain"), gt=0)
        require(self, ("diffuse_m2_per_m2", "specular_m2_per_m2", "wheel_rcs_m2",
                       "corner_rcs_m2", "plate_rcs_m2"), ge=0)


#: Class registry of the facet model. Gains fitted so the 30 m aspect-averaged means meet
#: `target_mean_rcs_m2` (the test checks +/-3 dB).
CLASS_RCS: dict[str, ClassRcs] = {
    "car": ClassRcs(target_mean_rcs_m2=10.0, diffuse_m2_per_m2=0.3, specular_m2_per_m2=12.0,
                    specular_width_deg=6.0, wheel_rcs_m2=0.5, corner_rcs_m2=1.0,
                    plate_rcs_m2=2.0, gain=1.03),
    "truck": ClassRcs(target_mean_rcs_m2=50.0, diffuse_m2_per_m2=0.3, specular_m2_per_m2=15.0,
                      specular_width_deg=5.0, wheel_rcs_m2=2.0, corner_rcs_m2=5.0,
                      plate_rcs_m2=10.0, gain=1.0),
    "motorcycle": ClassRcs(target_mean_rcs_m2=2.0, diffuse_m2_per_m2=0.2,
                           specular_m2_per_m2=2.0, specular_width_deg=10.0, wheel_rcs_m2=0.3,
                           plate_rcs_m2=0.5, gain=1.27),
    "bicycle": ClassRcs(target_mean_rcs_m2=1.0, diffuse_m2_per_m2=0.15,
                        specular_m2_per_m2=1.0, specular_width_deg=12.0, wheel_rcs_m2=0.2,
                        plate_rcs_m2=0.1, gain=0.98),
    "pedestrian": ClassRcs(target_mean_rcs_m2=0.5, diffuse_m2_per_m2=0.25,
                           specular_m2_per_m2=0.5, specular_width_deg=20.0, gain=1.22),
    "guard_rail": ClassRcs(target_mean_rcs_m2=1.0, diffuse_m2_per_m2=0.05,
                           specular_m2_per_m2=3.0, specular_width_deg=2.0, wheel_rcs_m2=0.3,
                           gain=1.0),
}


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
        RCS-weighted), m and deg (> 0). Half the 1.32 m range cell and half the 9.6 deg
        azimuth resolution; in elevation the single 0.8 lambda Tx2 row resolves nothing finer
        than tens of degrees. Merging is thus invisible to the radar while K stays at tens
        per actor (the front end's cost grows linearly with K).
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
        (>= 1; default 2: one full resolution cell), since only their presence matters to
        the metrics, not their exact shape; it keeps a rail's K near one per range cell.
    """

    grid: RayGridConfig = field(default_factory=RayGridConfig)
    max_range_m: float = 260.0
    merge_range_m: float = 0.66
    merge_azimuth_deg: float = 4.8
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
    clutter_merge_factor: float = 2.0

    def __post_init__(self) -> None:
        if not isinstance(self.grid, RayGridConfig):
            raise ValueError(f"grid must be a RayGridConfig, got {type(self.grid).__name__}")
        if isinstance(self.ground_points, bool) or not isinstance(self.ground_points, int) \
                or self.ground_points < 1:
            raise ValueError(f"ground_points={self.ground_points!r} must be an integer >= 1")
        require(self, ("max_range_m", "merge_range_m", "merge_azimuth_deg",
                       "merge_elevation_deg", "ground_max_range_m"), gt=0)
        if self.centre_fluctuation_db < 0:
            raise ValueError(f"centre_fluctuation_db={self.centre_fluctuation_db!r} must be "
                             ">= 0")
        if not 0 < self.guard_rail_reflectivity <= 1:
            raise ValueError(f"guard_rail_reflectivity={self.guard_rail_reflectivity!r} must "
                             "be in (0, 1]")
        if not self.clutter_merge_factor >= 1:
            raise ValueError(f"clutter_merge_factor={self.clutter_merge_factor!r} must be >= 1")
        if not self.cull_rcs_at_100m_m2 >= 0:
            raise ValueError(f"cull_rcs_at_100m_m2={self.cull_rcs_at_100m_m2!r} must be >= 0")
        if not -40 <= self.ground_gamma_db <= 0:
            raise ValueError(f"ground_gamma_db={self.ground_gamma_db!r} must be within "
                             "[-40, 0] dB")


_DEFAULT_CONFIG = RcsConfig()


@dataclass(frozen=True, slots=True)
class _Boxes:
    """Actor boxes of one frame in the radar frame (B boxes)."""

    actor_id: np.ndarray     # (B,) int
    cls: np.ndarray          # (B,) object: class names
    centre: np.ndarray       # (B, 3) m
    half: np.ndarray         # (B, 3) m
    yaw: np.ndarray          # (B,) rad
    velocity: np.ndarray     # (B, 3) m/s, relative to the radar


def actor_boxes(truth_frame: pd.DataFrame) -> _Boxes:
    """Boxes of the truth rows of one frame (radar-frame columns).

    Raises
    ------
    ValueError
        If a column of `REQUIRED_COLUMNS` is missing or a class is unknown.
    """
    missing = [c for c in REQUIRED_COLUMNS if c not in truth_frame.columns]
    if missing:
        raise ValueError(f"truth_frame lacks columns {missing}")
    cls = truth_frame["actor_class"].to_numpy(dtype=object)
    unknown = sorted(set(cls) - set(CLASS_RCS))
    if unknown:
        raise ValueError(f"actor_class {unknown} unknown; known: {sorted(CLASS_RCS)}")
    v = truth_frame
    centre = np.column_stack([v["x_radar_m"], v["y_radar_m"], v["z_radar_m"]]).astype(float)
    half = 0.5 * np.column_stack([v["length_m"], v["width_m"], v["height_m"]]).astype(float)
    vel = np.column_stack([v["vx_radar_mps"], v["vy_radar_mps"],
                           np.zeros(len(v))]).astype(float)
    return _Boxes(v["actor_id"].to_numpy(dtype=np.int64), cls, centre.reshape(-1, 3),
                  half.reshape(-1, 3), np.radians(v["yaw_radar_deg"].to_numpy(dtype=float)),
                  vel.reshape(-1, 3))


def _class_param(cls: np.ndarray, name: str) -> np.ndarray:
    """(B,) parameter `name` of each box's class (one lookup per distinct class)."""
    names, inv = np.unique(np.asarray(cls, dtype=str), return_inverse=True)
    return np.array([getattr(CLASS_RCS[n], name) for n in names], dtype=np.float64)[inv]


def strong_centres(boxes: _Boxes):
    """Candidate strong scattering centres of every box, box-local, before visibility.

    Returns
    -------
    box : (C,) int
        Box of each centre.
    local_m : (C, 3) float
        Position in box-local coordinates (origin at the box centre), m.
    normal_local : (C, 3) float
        Unit direction the centre radiates around (face normal or corner diagonal).
    rcs_m2 : (C,) float
        Peak RCS before the class gain, m^2.
    lobe_deg : (C,) float
        Gaussian lobe width around `normal_local`, deg.
    """
    parts = []
    n_box = boxes.centre.shape[0]
    idx = np.arange(n_box)
    hx, hy, hz = boxes.half[:, 0], boxes.half[:, 1], boxes.half[:, 2]
    cls = boxes.cls
    wheel = _class_param(cls, "wheel_rcs_m2")
    corner = _class_param(cls, "corner_rcs_m2")
    plate = _class_param(cls, "plate_rcs_m2")
    is_rail = cls == "guard_rail"
    is_truck = cls == "truck"
    # Wheels on both sides near each axle, 0.35 m up (trucks: three axles).
    for fx in (-0.64, 0.64, 0.0):
        for sy in (-1.0, 1.0):
            keep = (wheel > 0) & ~is_rail & ((fx != 0.0) | is_truck)
            z = -hz + np.minimum(0.35, hz)
            parts.append((idx[keep], np.column_stack([fx * hx, sy * hy, z])[keep],
                          np.tile([0.0, sy, 0.0], (n_box, 1))[keep], wheel[keep],
                          np.full(n_box, 50.0)[keep]))
    # Vertical corner edges: dihedral between bumper and side, radiating along the diagonal.
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            keep = corner > 0
            diag = np.array([sx, sy, 0.0]) / np.sqrt(2)
            z = -hz + np.minimum(0.5, hz)
            parts.append((idx[keep], np.column_stack([sx * hx, sy * hy, z])[keep],
                          np.tile(diag, (n_box, 1))[keep], corner[keep],
                          np.full(n_box, 35.0)[keep]))
    # Plate / rear structure on the front and rear faces.
    for sx in (-1.0, 1.0):
        keep = plate > 0
        z = -hz + np.minimum(0.5, hz)
        parts.append((idx[keep], np.column_stack([sx * hx, np.zeros(n_box), z])[keep],
                      np.tile([sx, 0.0, 0.0], (n_box, 1))[keep], plate[keep],
                      np.full(n_box, 12.0)[keep]))
    # Guard-rail posts every POST_SPACING_M on both long faces (the beam is the box itself).
    if np.any(is_rail):
        rb = np.flatnonzero(is_rail)
        n_posts = np.maximum(np.floor(2 * hx[rb] / POST_SPACING_M).astype(int), 1)
        pb = np.repeat(rb, n_posts)
        k = np.arange(n_posts.sum()) - np.repeat(np.cumsum(n_posts) - n_posts, n_posts)
        px = -hx[pb] + 0.5 * POST_SPACING_M + POST_SPACING_M * k
        for sy in (-1.0, 1.0):
            parts.append((pb, np.column_stack([px, sy * hy[pb], np.zeros(pb.size)]),
                          np.tile([0.0, sy, 0.0], (pb.size, 1)), wheel[pb],
                          np.full(pb.size, 35.0)))
    box = np.concatenate([p[0] for p in parts]).astype(np.int64)
    return (box, np.concatenate([p[1] for p in parts]).reshape(-1, 3),
            np.concatenate([p[2] for p in parts]).reshape(-1, 3),
            np.concatenate([p[3] for p in parts]), np.concatenate([p[4] for p in parts]))


def _rotate(vec: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.column_stack([c * vec[:, 0] - s * vec[:, 1], s * vec[:, 0] + c * vec[:, 1],
                            vec[:, 2]])


def _visible_centres(boxes: _Boxes, cfg: RcsConfig, rng: np.random.Generator, hits,
                     az_grid: np.ndarray, el_grid: np.ndarray):
    """Strong centres that face the radar, lie in the grid's field of view and are not occluded.

    Returns (box (C,), position (C, 3), rcs (C,)) in the radar frame, gain applied.
    """
    box, local, n_local, rcs0, lobe = strong_centres(boxes)
    pos = _rotate(local, boxes.yaw[box]) + boxes.centre[box]
    normal = _rotate(n_local, boxes.yaw[box])
    r = np.linalg.norm(pos, axis=1)
    u = pos / np.maximum(r, 1e-9)[:, None]
    cos_inc = -np.einsum("cd,cd->c", u, normal)
    ray_box = np.full(az_grid.size * el_grid.size, -1, dtype=np.int64)
    ray_t = np.full(az_grid.size * el_grid.size, np.inf)
    hit_ray = hits.elevation_index * az_grid.size + hits.azimuth_index
    ray_box[hit_ray] = hits.box
    ray_t[hit_ray] = hits.t_m
    az = np.degrees(np.arctan2(pos[:, 1], pos[:, 0]))
    el = np.degrees(np.arcsin(np.clip(u[:, 2], -1, 1)))
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
    rcs = rcs0 * np.exp(-(theta / lobe) ** 2) * _class_param(boxes.cls, "gain")[box]
    if cfg.centre_fluctuation_db > 0 and rcs.size:
        s = cfg.centre_fluctuation_db * np.log(10) / 10
        rcs = rcs * np.exp(s * rng.standard_normal(rcs.size) - 0.5 * s * s)
    return box, pos, rcs


def _patch_rcs(hits, boxes: _Boxes, cfg: RcsConfig) -> np.ndarray:
    """(H,) RCS of each hit patch from the facet model, m^2, gain applied."""
    cls, b = boxes.cls, hits.box
    cos_inc = np.clip(-np.einsum("hd,hd->h", hits.direction, hits.normal), 0.0, 1.0)
    theta = np.arccos(cos_inc)
    omega = cfg.grid.solid_angle_sr * np.sqrt(1 - hits.direction[:, 2] ** 2)
    mu = _class_param(cls, "diffuse_m2_per_m2")[b]
    s = _class_param(cls, "specular_m2_per_m2")[b]
    w = np.radians(_class_param(cls, "specular_width_deg"))[b]
    # A = t^2 Omega / cos(theta); sigma = A (mu cos^2 + S lobe), written without dividing by 0.
    density = (mu * cos_inc + s * np.exp(-(theta / w) ** 2) / np.maximum(cos_inc, 0.05))
    return hits.t_m ** 2 * omega * density * _class_param(cls, "gain")[b]


def _merge(actor_key: np.ndarray, pos: np.ndarray, rcs: np.ndarray, cfg: RcsConfig,
           scale: np.ndarray | float = 1.0):
    """Merge points per (key, range, azimuth, elevation) cell: RCS summed, position weighted.

    `scale` (per point) multiplies the range and azimuth cell sizes.
    Returns (first index of each cell (M,), position (M, 3), rcs (M,)).
    """
    r = np.linalg.norm(pos, axis=1)
    ir = np.floor(r / (cfg.merge_range_m * scale)).astype(np.int64)
    ia = np.floor(np.degrees(np.arctan2(pos[:, 1], pos[:, 0])) / (cfg.merge_azimuth_deg * scale)
                  ).astype(np.int64) + 1000
    ie = np.floor(np.degrees(np.arcsin(np.clip(pos[:, 2] / np.maximum(r, 1e-9), -1, 1)))
                  / cfg.merge_elevation_deg).astype(np.int64) + 100
    key = ((actor_key * 4096 + ir) * 2048 + ia) * 256 + ie
    uniq, first, inv = np.unique(key, return_index=True, return_inverse=True)
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
    boxes = _Boxes(*(getattr(boxes, f)[near] for f in ("actor_id", "cls", "centre", "half",
                                                       "yaw", "velocity")))
    a_off, e_off = rng.random(2) if cfg.dither else (0.0, 0.0)
    hits = cast_rays(cfg.grid, boxes.centre, boxes.half, boxes.yaw, azimuth_offset=a_off,
                     elevation_offset=e_off, max_range_m=cfg.max_range_m)
    parts = []
    actor_box = np.zeros(0, dtype=np.int64)
    if boxes.centre.shape[0]:
        p_rcs = _patch_rcs(hits, boxes, cfg)
        c_box, c_pos, c_rcs = _visible_centres(boxes, cfg, rng, hits,
                                               cfg.grid.azimuths_rad(a_off),
                                               cfg.grid.elevations_rad(e_off))
        box = np.concatenate([hits.box, c_box])
        pos = np.concatenate([hits.point_m, c_pos])
        rcs = np.concatenate([p_rcs, c_rcs])
        if box.size:
            scale = np.where(boxes.cls[box] == "guard_rail", cfg.clutter_merge_factor, 1.0)
            first, mpos, mrcs = _merge(box, pos, rcs, cfg, scale)
            mbox = box[first]
            actor_box = mbox
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
        keep = sc.rcs_m2 * (100.0 / sc.range_m) ** 4 >= cfg.cull_rcs_at_100m_m2
        if not keep.all():
            sc = Scatterers(sc.position_m[keep], sc.velocity_mps[keep], sc.rcs_m2[keep],
                            sc.actor_id[keep])
    return sc
