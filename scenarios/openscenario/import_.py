"""An OpenSCENARIO 1.x file as a case: `read_xosc`.

The file is read with lxml (each element knows its source line), its `$name` parameter
references are substituted, and every element is checked against the supported subset
(`scenarios.openscenario.subset`): anything else is refused naming the element, its line and
what is supported. The road comes from the referenced OpenDRIVE file (`road.read_xodr`); the
storyboard is played by `scenarios.openscenario.player` into one timed trajectory per entity,
and the case drives those in highway-env (`scenarios.motion`). The ego is the entity named
`ego` (default ``"Ego"``); the other entities are the actors, truth ids 0, 1, ... in the
file's entity order.

Harness fields the file does not hold (mount, criteria, must_detect, duration) come from the
arguments (a case TOML's keys), else from the ``harness_*`` parameters our export writes
(`export.HARNESS_PARAMETERS`), else the defaults: mount ``rear_left``, the storyboard's
stop time or `DEFAULT_DURATION_S`, no criteria.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
from lxml import etree

from core.errors import BadInput
from core.fileio import read_input_bytes

from ..catalog import MOUNTS, ActorSpec, Case, Criterion, Mount
from ..equipment import RadarSpec
from ..motion import EntityMotion, Motion
from . import player
from .document import Document
from .road import OdrRoad, read_xodr
from .storyboard import acts, apply_init, stop_time
from .subset import refuse

__all__ = ["read_xosc", "DEFAULT_EGO", "DEFAULT_MOUNT", "DEFAULT_DURATION_S", "CATEGORIES",
           "case_name_of"]

DEFAULT_EGO = "Ego"
DEFAULT_MOUNT = "rear_left"
#: Duration of a file whose storyboard has no simulation-time stop, s.
DEFAULT_DURATION_S = 10.0
#: OpenSCENARIO vehicle category -> actor class.
CATEGORIES = {"car": "car", "truck": "truck", "motorbike": "motorcycle",
              "bicycle": "bicycle"}


def case_name_of(path: str | Path) -> str:
    """Case name of a bare .xosc file: its stem in lowercase letters, digits and _."""
    name = re.sub(r"[^a-z0-9_]+", "_", Path(path).stem.lower()).strip("_")
    return name or "xosc_case"


def _entities(doc: Document, root) -> list[tuple[str, str, tuple, tuple]]:
    """(name, actor class, (L, W, H), (centre x, centre y)) per ScenarioObject, in order."""
    out = []
    ents = root.find("Entities")
    if ents is None:
        raise doc.refuse(root, "no Entities")
    for obj in doc.children(ents, {"ScenarioObject"}, "entity"):
        name = doc.get(obj, "name")
        kind = doc.one(obj, {"Vehicle", "Pedestrian"}, "entity kind")
        if kind.tag == "Vehicle":
            cat = doc.get(kind, "vehicleCategory")
            if cat not in CATEGORIES:
                raise doc.refuse(kind, f"entity {name}: unsupported vehicleCategory {cat}",
                                 ", ".join(CATEGORIES))
            cls = CATEGORIES[cat]
        else:
            cat = doc.get(kind, "pedestrianCategory", "pedestrian")
            if cat != "pedestrian":
                raise doc.refuse(kind, f"entity {name}: unsupported pedestrianCategory {cat}",
                                 "pedestrian")
            cls = "pedestrian"
        box = kind.find("BoundingBox")
        if box is None or box.find("Dimensions") is None or box.find("Center") is None:
            raise doc.refuse(kind, f"entity {name} has no BoundingBox with Center and "
                             "Dimensions")
        dims, centre = box.find("Dimensions"), box.find("Center")
        size = tuple(doc.num(dims, k) for k in ("length", "width", "height"))
        if min(size) <= 0:
            raise doc.refuse(dims, f"entity {name}: bounding box {size} must be > 0")
        out.append((name, cls, size, (doc.num(centre, "x"), doc.num(centre, "y"))))
    if not out:
        raise doc.refuse(ents, "the file has no entity")
    return out


def _harness(doc: Document, name: str, default):
    """A ``harness_*`` parameter (our export's), JSON-decoded; `default` when absent."""
    if name not in doc.params:
        return default
    try:
        return json.loads(doc.params[name])
    except ValueError:
        raise doc.refuse(None, f"parameter {name}={doc.params[name]!r} is not valid JSON") \
            from None


def _road(doc: Document, root, path: Path) -> dict[str, OdrRoad]:
    net = root.find("RoadNetwork")
    logic = net.find("LogicFile") if net is not None else None
    if logic is None:
        raise doc.refuse(net if net is not None else root, "no RoadNetwork/LogicFile",
                         "a LogicFile naming an OpenDRIVE (.xodr) file")
    if net is not None:
        doc.children(net, {"LogicFile"}, "road network element")
    return read_xodr(path.parent / doc.get(logic, "filepath"))


def _motion(doc, ents, trajectories, ego: str, roads, rails) -> Motion:
    lanes = tuple(g for r in roads.values() for g in r.lane_geometries())
    motions = {}
    for name, cls, (length, width, height), (cx, cy) in ents:
        tr = trajectories[name]
        if cx or cy:  # the truth is the box centre; the file moves the reference point
            c, s = np.cos(tr.yaw_rad), np.sin(tr.yaw_rad)
            tr = type(tr)(tr.time_s, tr.x_m + c * cx - s * cy, tr.y_m + s * cx + c * cy,
                          tr.yaw_rad)
        motions[name] = EntityMotion(name=name, actor_class=cls, length_m=length,
                                     width_m=width, height_m=height, trajectory=tr)
    return Motion(ego=motions[ego], actors=tuple(m for n, m in motions.items() if n != ego),
                  lanes=lanes, rails_y_m=tuple(float(v) for v in rails))


def read_xosc(path: str | Path, *, name: str | None = None, description: str | None = None,
              ego: str = DEFAULT_EGO, mount: Mount | None = None,
              criteria: tuple[Criterion, ...] | None = None,
              must_detect: tuple[int, ...] | None = None,
              duration_s: float | None = None) -> Case:
    """A `Case` from an OpenSCENARIO 1.x file (see the module docstring).

    Parameters
    ----------
    path : str or Path
    name, description : str, optional
        Default: from the file's name / our export's parameters.
    ego : str
        Entity name of the ego (a car).
    mount, criteria, must_detect, duration_s : optional
        Harness fields; None takes the file's ``harness_*`` parameters, else the defaults.

    Raises
    ------
    scenarios.openscenario.subset.Unsupported
        An element outside the supported subset, or invalid (naming it and its line).
    core.errors.BadInput
        A harness field the case refuses (naming it).
    """
    path = Path(path)
    source = str(path)
    try:
        root = etree.fromstring(read_input_bytes(path, "OpenSCENARIO file"))
    except etree.XMLSyntaxError as exc:
        raise refuse(source, None, f"not well-formed XML: {exc}") from None
    if root.tag != "OpenSCENARIO":
        raise refuse(source, root, "the root element is not OpenSCENARIO")
    doc = Document(source, root)
    doc.children(root, {"Entities", "Storyboard", "RoadNetwork"}, "element")
    header = root.find("FileHeader")
    if header is not None and doc.get(header, "revMajor", "1") != "1":
        raise doc.refuse(header, f"OpenSCENARIO {doc.get(header, 'revMajor')}.x", "1.x")
    roads = _road(doc, root, path)
    ents = _entities(doc, root)
    names = {e[0] for e in ents}
    if ego not in names:
        raise doc.refuse(root.find("Entities"), f"no entity named {ego!r} (the ego); "
                         f"entities: {sorted(names)}")
    movers = {n: player.Mover(n, size[0], size[1], centre[0], centre[1])
              for n, _, size, centre in ents}
    board = root.find("Storyboard")
    if board is None or board.find("Init") is None:
        raise doc.refuse(root, "no Storyboard with an Init")
    speeds = apply_init(doc, board.find("Init"), movers, roads)
    board_acts = acts(doc, board, roads, names)
    duration = duration_s if duration_s is not None else stop_time(doc, board)
    if duration is None:
        duration = float(_harness(doc, "harness_duration_s", DEFAULT_DURATION_S))
    if not 0 < duration <= 120:
        raise BadInput(f"{source}: duration_s={duration:g} must be in (0, 120] s")
    trajectories = player.play(movers, board_acts, duration)
    motion = _motion(doc, ents, trajectories, ego, roads, _harness(doc, "harness_rails_y_m",
                                                                    []))
    if mount is None:
        m = _harness(doc, "harness_mount", None)
        mount = Mount(**m) if m is not None else MOUNTS[DEFAULT_MOUNT]
    if criteria is None:
        criteria = tuple(Criterion(**c) for c in _harness(doc, "harness_criteria", []))
    if must_detect is None:
        must_detect = tuple(_harness(doc, "harness_must_detect", []))
    radars = tuple(RadarSpec(actor_id=r["actor_id"], family=r["family"],
                             overrides=tuple(r["overrides"].items()))
                   for r in _harness(doc, "harness_radars", []))
    try:
        specs = {n: ActorSpec(actor_class=cls, path="lane_0", speed_mps=speeds[n])
                 for n, cls, _, _ in ents}
    except BadInput as exc:
        raise BadInput(f"{source}: {exc}") from None
    return Case(name=name or case_name_of(path),
                description=description or doc.params.get(
                    "harness_description", f"OpenSCENARIO file {path.name}"),
                mount=mount, duration_s=duration, road="highway", lanes=1,
                guard_rails=bool(motion.rails_y_m),
                ego=specs[ego], actors=tuple(s for n, s in specs.items() if n != ego),
                must_detect=must_detect, criteria=criteria,
                references=doc.params.get("harness_references", f"OpenSCENARIO {path.name}"),
                case_class=doc.params.get("harness_case_class", "ordinary"),
                equipped_share=float(doc.params.get("harness_equipped_share", 0.0)),
                radars=radars, motion=motion)
