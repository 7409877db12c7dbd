"""Actor classes of the RCS model: facet parameters, published patterns, boxes, strong centres.

`CLASS_RCS` is the class registry (`ClassRcs` per class); `actor_boxes` turns one frame's truth
rows into yawed boxes; `strong_centres` lists each box's candidate scattering centres (wheels,
corner dihedrals, plates, guard-rail posts); `geometric_total_rcs` is the closed-form facet
total of an unoccluded box, which `radarsim.rcs` divides out to put each actor on its
published pattern (`radarsim.scene.rcs_patterns`). Angles and the model itself are described in
`radarsim.rcs`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pandas as pd

from core.checks import require
from core.errors import BadInput

from .raycast import FACE_NORMALS_LOCAL
from .rcs_patterns import CYCLIST_PATTERN, HUMAN_TR38901, PATTERN_TYPES, VEHICLE_TR38901

__all__ = ["ClassRcs", "CLASS_RCS", "REQUIRED_COLUMNS", "POST_SPACING_M", "ActorBoxes",
           "actor_boxes", "strong_centres", "radar_angles", "geometric_total_rcs",
           "class_param", "rotate_yaw", "CentreIncidence", "centre_incidence"]

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
        Calibration gain applied to the class's patches and centres when it has no `pattern`
        (fit once, see `tests/radarsim/test_rcs.py::test_class_mean_rcs_within_3db`).
    wheel_rcs_m2, corner_rcs_m2, plate_rcs_m2 : float
        Strong centres: each wheel (on the side faces), each vertical corner edge (dihedral
        between bumper and side), the plate / rear structure (front and rear faces), m^2.
    pattern : Tr38901Pattern, SectorPattern, IncoherentSum or None
        Published pattern that sets the actor's level by aspect and zenith (None: `gain`).
    fluctuation_db : float
        dB spread of the per-actor, per-frame log-normal factor (mean-preserving), >= 0.
    """

    target_mean_rcs_m2: float
    diffuse_m2_per_m2: float
    specular_m2_per_m2: float
    specular_width_deg: float
    gain: float = 1.0
    wheel_rcs_m2: float = 0.0
    corner_rcs_m2: float = 0.0
    plate_rcs_m2: float = 0.0
    pattern: object = None
    fluctuation_db: float = 0.0

    def __post_init__(self) -> None:
        require(self, ("target_mean_rcs_m2", "specular_width_deg", "gain"), gt=0)
        require(self, ("diffuse_m2_per_m2", "specular_m2_per_m2", "wheel_rcs_m2",
                       "corner_rcs_m2", "plate_rcs_m2", "fluctuation_db"), ge=0)
        if self.pattern is not None and not isinstance(self.pattern, PATTERN_TYPES):
            raise BadInput(f"pattern must be one of {[t.__name__ for t in PATTERN_TYPES]} or "
                           f"None, got {self.pattern!r}")


#: Class registry of the facet model. Classes with a `pattern` take their level from it (the
#: target mean is then the pattern's aspect mean at horizontal incidence); the others' gains are
#: fitted so the 30 m aspect-averaged means meet `target_mean_rcs_m2` (the test checks +/-3 dB).
CLASS_RCS: dict[str, ClassRcs] = {
    "car": ClassRcs(target_mean_rcs_m2=10 ** (VEHICLE_TR38901.aspect_mean_dbsm() / 10),
                    diffuse_m2_per_m2=0.3, specular_m2_per_m2=12.0,
                    specular_width_deg=6.0, wheel_rcs_m2=0.5, corner_rcs_m2=1.0,
                    plate_rcs_m2=2.0, pattern=VEHICLE_TR38901,
                    fluctuation_db=VEHICLE_TR38901.sigma_s_db),
    "truck": ClassRcs(target_mean_rcs_m2=50.0, diffuse_m2_per_m2=0.3, specular_m2_per_m2=15.0,
                      specular_width_deg=5.0, wheel_rcs_m2=2.0, corner_rcs_m2=5.0,
                      plate_rcs_m2=10.0, gain=1.0, fluctuation_db=VEHICLE_TR38901.sigma_s_db),
    "motorcycle": ClassRcs(target_mean_rcs_m2=2.0, diffuse_m2_per_m2=0.2,
                           specular_m2_per_m2=2.0, specular_width_deg=10.0, wheel_rcs_m2=0.3,
                           plate_rcs_m2=0.5, gain=1.27,
                           fluctuation_db=VEHICLE_TR38901.sigma_s_db),
    "bicycle": ClassRcs(target_mean_rcs_m2=10 ** (CYCLIST_PATTERN.aspect_mean_dbsm() / 10),
                        diffuse_m2_per_m2=0.15, specular_m2_per_m2=1.0,
                        specular_width_deg=12.0, wheel_rcs_m2=0.2, plate_rcs_m2=0.1,
                        pattern=CYCLIST_PATTERN, fluctuation_db=CYCLIST_PATTERN.sigma_s_db),
    "pedestrian": ClassRcs(target_mean_rcs_m2=10 ** (HUMAN_TR38901.aspect_mean_dbsm() / 10),
                           diffuse_m2_per_m2=0.25, specular_m2_per_m2=0.5,
                           specular_width_deg=20.0, pattern=HUMAN_TR38901,
                           fluctuation_db=HUMAN_TR38901.sigma_s_db),
    "guard_rail": ClassRcs(target_mean_rcs_m2=1.0, diffuse_m2_per_m2=0.05,
                           specular_m2_per_m2=3.0, specular_width_deg=2.0, wheel_rcs_m2=0.3,
                           gain=1.0),
}


@dataclass(frozen=True, slots=True)
class ActorBoxes:
    """Actor boxes of one frame in the radar frame (B boxes)."""

    actor_id: np.ndarray     # (B,) int
    cls: np.ndarray          # (B,) object: class names
    centre: np.ndarray       # (B, 3) m
    half: np.ndarray         # (B, 3) m
    yaw: np.ndarray          # (B,) rad
    velocity: np.ndarray     # (B, 3) m/s, relative to the radar
    code: np.ndarray         # (B,) int: index of the class in `CLASS_RCS` (`class_param`)


def actor_boxes(truth_frame: pd.DataFrame) -> ActorBoxes:
    """Boxes of the truth rows of one frame (radar-frame columns).

    Raises
    ------
    ValueError
        If a column of `REQUIRED_COLUMNS` is missing or a class is unknown.
    """
    missing = [c for c in REQUIRED_COLUMNS if c not in truth_frame.columns]
    if missing:
        raise BadInput(f"truth_frame lacks columns {missing}")
    cls = truth_frame["actor_class"].to_numpy(dtype=object)
    unknown = sorted(set(cls) - set(CLASS_RCS))
    if unknown:
        raise BadInput(f"actor_class {unknown} unknown; known: {sorted(CLASS_RCS)}")
    index = {name: i for i, name in enumerate(CLASS_RCS)}
    code = np.array([index[c] for c in cls], dtype=np.int64)
    col = {c: truth_frame[c].to_numpy(dtype=np.float64) for c in _NUMERIC_COLUMNS}
    centre = np.column_stack([col["x_radar_m"], col["y_radar_m"], col["z_radar_m"]])
    half = 0.5 * np.column_stack([col["length_m"], col["width_m"], col["height_m"]])
    vel = np.column_stack([col["vx_radar_mps"], col["vy_radar_mps"], np.zeros(len(cls))])
    return ActorBoxes(truth_frame["actor_id"].to_numpy(dtype=np.int64), cls,
                      centre.reshape(-1, 3), half.reshape(-1, 3),
                      np.radians(col["yaw_radar_deg"]), vel.reshape(-1, 3), code)


#: Numeric truth columns `actor_boxes` reads.
_NUMERIC_COLUMNS = ("x_radar_m", "y_radar_m", "z_radar_m", "length_m", "width_m", "height_m",
                    "vx_radar_mps", "vy_radar_mps", "yaw_radar_deg")


_TABLES: dict = {"classes": (), "tables": {}}


def _class_table(name: str) -> np.ndarray:
    """(n_classes,) parameter `name` of every registered class, rebuilt whenever the registry's
    entries change (a registry edit in a test or a plugin is seen at the next call)."""
    classes = tuple(CLASS_RCS.values())
    if len(classes) != len(_TABLES["classes"]) \
            or any(a is not b for a, b in zip(classes, _TABLES["classes"])):
        _TABLES["classes"], _TABLES["tables"] = classes, {}
    table = _TABLES["tables"].get(name)
    if table is None:
        if name == "has_pattern":
            values = [float(c.pattern is not None) for c in classes]
        else:
            values = [getattr(c, name) for c in classes]
        table = _TABLES["tables"][name] = np.asarray(values, dtype=np.float64)
        table.setflags(write=False)
    return table


def class_param(code: np.ndarray, name: str) -> np.ndarray:
    """(B,) parameter `name` of each box's class, from the boxes' class codes
    (`ActorBoxes.code`); `name` "has_pattern" gives whether the class has a published
    pattern (1.0) or not (0.0)."""
    return _class_table(name)[code]


def strong_centres(boxes: ActorBoxes):
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
    hx, hy, hz = boxes.half[:, 0], boxes.half[:, 1], boxes.half[:, 2]
    cls = boxes.cls
    wheel = class_param(boxes.code, "wheel_rcs_m2")
    corner = class_param(boxes.code, "corner_rcs_m2")
    plate = class_param(boxes.code, "plate_rcs_m2")
    is_rail = cls == "guard_rail"
    is_truck = cls == "truck"

    def add(rows, x, y, z, normal, rcs, lobe_deg):
        parts.append((rows, np.column_stack([x, y, z]), np.broadcast_to(normal, (rows.size, 3)),
                      rcs, np.full(rows.size, lobe_deg)))

    # Wheels on both sides near each axle, 0.35 m up (trucks: three axles).
    for fx in (-0.64, 0.64, 0.0):
        rows = np.flatnonzero((wheel > 0) & ~is_rail & ((fx != 0.0) | is_truck))
        z = -hz[rows] + np.minimum(0.35, hz[rows])
        for sy in (-1.0, 1.0):
            add(rows, fx * hx[rows], sy * hy[rows], z, (0.0, sy, 0.0), wheel[rows], 50.0)
    # Vertical corner edges: dihedral between bumper and side, radiating along the diagonal.
    rows = np.flatnonzero(corner > 0)
    z = -hz[rows] + np.minimum(0.5, hz[rows])
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            add(rows, sx * hx[rows], sy * hy[rows], z, np.array([sx, sy, 0.0]) / np.sqrt(2),
                corner[rows], 35.0)
    # Plate / rear structure on the front and rear faces.
    rows = np.flatnonzero(plate > 0)
    z = -hz[rows] + np.minimum(0.5, hz[rows])
    for sx in (-1.0, 1.0):
        add(rows, sx * hx[rows], np.zeros(rows.size), z, (sx, 0.0, 0.0), plate[rows], 12.0)
    # Guard-rail posts every POST_SPACING_M on both long faces (the beam is the box itself).
    if np.any(is_rail):
        rb = np.flatnonzero(is_rail)
        n_posts = np.maximum(np.floor(2 * hx[rb] / POST_SPACING_M).astype(int), 1)
        pb = np.repeat(rb, n_posts)
        k = np.arange(n_posts.sum()) - np.repeat(np.cumsum(n_posts) - n_posts, n_posts)
        px = -hx[pb] + 0.5 * POST_SPACING_M + POST_SPACING_M * k
        for sy in (-1.0, 1.0):
            add(pb, px, sy * hy[pb], np.zeros(pb.size), (0.0, sy, 0.0), wheel[pb], 35.0)
    box = np.concatenate([p[0] for p in parts]).astype(np.int64)
    return (box, np.concatenate([p[1] for p in parts]).reshape(-1, 3),
            np.concatenate([p[2] for p in parts]).reshape(-1, 3),
            np.concatenate([p[3] for p in parts]), np.concatenate([p[4] for p in parts]))


def rotate_yaw(vec: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.column_stack([c * vec[:, 0] - s * vec[:, 1], s * vec[:, 0] + c * vec[:, 1],
                            vec[:, 2]])


def radar_angles(boxes: ActorBoxes) -> tuple[np.ndarray, np.ndarray]:
    """Direction of the radar seen from each box centre, in the box's frame.

    Returns
    -------
    phi_deg : (B,) float
        Azimuth: 0 the radar is ahead (the actor's front faces it), 90 on its left, 180 behind.
    theta_deg : (B,) float
        Zenith: 90 horizontal, < 90 the radar is above the actor's centre.
    """
    c, s = np.cos(boxes.yaw), np.sin(boxes.yaw)
    o = -boxes.centre
    ux, uy = c * o[:, 0] + s * o[:, 1], -s * o[:, 0] + c * o[:, 1]
    return (np.degrees(np.arctan2(uy, ux)),
            np.degrees(np.arctan2(np.hypot(ux, uy), o[:, 2])))


class CentreIncidence(NamedTuple):
    """Strong centres placed in the radar frame (C centres of `strong_centres`)."""

    position_m: np.ndarray   # (C, 3) radar frame, m
    normal: np.ndarray       # (C, 3) unit direction the centre radiates around, radar frame
    range_m: np.ndarray      # (C,) distance from the radar, m
    cos_inc: np.ndarray      # (C,) cosine between the normal and the direction to the radar


def centre_incidence(boxes: ActorBoxes, centres) -> CentreIncidence:
    """Radar-frame position, normal, range and incidence cosine of every strong centre
    (`centres`: `strong_centres(boxes)`), shared by the facet total and the visibility test."""
    box, local, n_local = centres[0], centres[1], centres[2]
    pos = rotate_yaw(local, boxes.yaw[box]) + boxes.centre[box]
    normal = rotate_yaw(n_local, boxes.yaw[box])
    x, y, z = pos[:, 0], pos[:, 1], pos[:, 2]
    r = np.sqrt(x * x + y * y + z * z)     # the sum np.linalg.norm(pos, axis=1) forms
    cos_inc = -np.einsum("cd,cd->c", pos / np.maximum(r, 1e-9)[:, None], normal)
    return CentreIncidence(pos, normal, r, cos_inc)


def geometric_total_rcs(boxes: ActorBoxes, centres=None, *, incidence=None,
                        only=None) -> np.ndarray:
    """(B,) facet-model RCS of each box alone (no occluder, no gain, no fluctuation), m^2.

    Closed form of what the ray cast sums for an unoccluded box: a face of area A seen at
    incidence theta collects rays over its projected area A cos(theta), each patch carrying
    t^2 Omega (mu cos(theta) + S lobe(theta) / max(cos(theta), 0.05)), so the face totals
    A cos(theta) (mu cos(theta) + S lobe / max(cos, 0.05)); plus every strong centre facing the
    radar with its lobe. `centres`: `strong_centres(boxes)` and `incidence`:
    `centre_incidence(boxes, centres)` if already computed; `only` (B,) bool: the boxes wanted
    (the others get 0; each wanted box's value is the same as without `only`).
    """
    n_box = boxes.centre.shape[0]
    sel = np.arange(n_box) if only is None else np.flatnonzero(only)
    o = -boxes.centre[sel]
    yaw = boxes.yaw[sel]
    c, s = np.cos(yaw), np.sin(yaw)
    u = np.column_stack([c * o[:, 0] + s * o[:, 1], -s * o[:, 0] + c * o[:, 1], o[:, 2]])
    u /= np.maximum(np.linalg.norm(u, axis=1), 1e-9)[:, None]
    h = boxes.half[sel]
    area = 4 * np.column_stack([h[:, 1] * h[:, 2], h[:, 1] * h[:, 2], h[:, 0] * h[:, 2],
                                h[:, 0] * h[:, 2], h[:, 0] * h[:, 1], h[:, 0] * h[:, 1]])
    cos_f = u @ FACE_NORMALS_LOCAL.T                                  # (B, 6)
    code = boxes.code[sel]
    mu = class_param(code, "diffuse_m2_per_m2")[:, None]
    spec = class_param(code, "specular_m2_per_m2")[:, None]
    w = np.radians(class_param(code, "specular_width_deg"))[:, None]
    cos_c = np.clip(cos_f, 0.0, 1.0)
    lobe = np.exp(-(np.arccos(cos_c) / w) ** 2)
    faces = np.zeros(n_box)
    faces[sel] = np.where(cos_f > 0, area * cos_c * (mu * cos_c + spec * lobe
                                                     / np.maximum(cos_c, 0.05)), 0.0).sum(axis=1)
    centres = strong_centres(boxes) if centres is None else centres
    incidence = centre_incidence(boxes, centres) if incidence is None else incidence
    box, rcs0, lobe_deg, cos_inc = centres[0], centres[3], centres[4], incidence.cos_inc
    if only is not None:   # a box's centres keep their order: the same per-box sums
        keep = np.asarray(only, dtype=bool)[box]
        box, rcs0, lobe_deg, cos_inc = box[keep], rcs0[keep], lobe_deg[keep], cos_inc[keep]
    theta = np.degrees(np.arccos(np.clip(cos_inc, -1, 1)))
    centre_rcs = np.where(cos_inc > 0, rcs0 * np.exp(-(theta / lobe_deg) ** 2), 0.0)
    return faces + np.bincount(box, weights=centre_rcs, minlength=n_box)
