"""The part of OpenSCENARIO 1.x and OpenDRIVE 1.x that the import plays, and its refusals.

`SUPPORTED` is the table of the README's "OpenSCENARIO import" section (one row per element
family: what is played, and how); every other element a file holds is refused by
`Unsupported`, naming the element, its file and line, and what is supported, so nothing a
scenario means is silently dropped. Purely descriptive elements (FileHeader, Properties,
Performance, Axles, road marks, links, objects) are read past.
"""
from __future__ import annotations

from core.errors import BadInput

__all__ = ["SUPPORTED", "Unsupported", "refuse", "subset_table_markdown", "line_of"]

#: (element family, what is played) rows of the supported subset.
SUPPORTED: tuple[tuple[str, str], ...] = (
    ("ParameterDeclarations", "`ParameterDeclaration`s anywhere (one name, one value); "
     "`$name` references in any attribute; `${...}` expressions are refused"),
    ("Entities", "`ScenarioObject` with a `Vehicle` of category car, truck, motorbike or "
     "bicycle, or a `Pedestrian` of category pedestrian; its `BoundingBox` is the truth box "
     "(the reference point may be off the box centre)"),
    ("RoadNetwork", "`LogicFile` (.xodr, relative to the .xosc): roads of `line` and `arc` "
     "geometries, one `laneSection`, constant lane widths and `laneOffset`"),
    ("Init", "`TeleportAction` to a `WorldPosition` (z, pitch, roll 0) or a `LanePosition`; "
     "`SpeedAction` with an `AbsoluteTargetSpeed`"),
    ("Storyboard", "`Story` > `Act` > `ManeuverGroup` > `Maneuver` > `Event` "
     "(maximumExecutionCount 1) > `Action` > `PrivateAction`; a `StopTrigger` of a "
     "`SimulationTimeCondition` sets the duration"),
    ("Conditions", "`SimulationTimeCondition`; `ReachPositionCondition`; "
     "`RelativeDistanceCondition` (longitudinal, lateral, cartesian / euclidian distance, "
     "freespace only for longitudinal and lateral); any rule, `delay` and `conditionEdge`"),
    ("SpeedAction", "`AbsoluteTargetSpeed` with step, linear or sinusoidal dynamics over a "
     "time, a distance or (linear) a rate"),
    ("LaneChangeAction", "`AbsoluteTargetLane` or `RelativeTargetLane`, `targetLaneOffset`; "
     "step, linear, sinusoidal or cubic dynamics over a time or a distance"),
    ("FollowTrajectoryAction", "a `Trajectory` whose `Shape` is a timed `Polyline` of "
     "`WorldPosition` vertices; `Timing` absolute or relative with scale and offset"),
)


class Unsupported(BadInput):
    """An element of an OpenSCENARIO / OpenDRIVE file outside `SUPPORTED` (or invalid).

    The message names the file, the line, the element and what is supported instead.
    """


def line_of(elem) -> int | None:
    """Source line of an lxml element (None when unknown)."""
    return getattr(elem, "sourceline", None)


def refuse(source: str, elem, what: str, supported: str = "") -> Unsupported:
    """The `Unsupported` error for `elem` of file `source` (raise it).

    Parameters
    ----------
    source : str
        The file the element is in.
    elem : lxml.etree._Element or None
    what : str
        What is wrong, e.g. ``"unsupported action TeleportAction"``.
    supported : str
        What is supported instead (appended as ``; supported: ...``).
    """
    line = line_of(elem) if elem is not None else None
    where = f"{source}:{line}" if line is not None else source
    tag = f" <{elem.tag}>" if elem is not None else ""
    tail = f"; supported: {supported}" if supported else ""
    return Unsupported(f"{where}:{tag} {what}{tail}")


def subset_table_markdown() -> str:
    """The supported subset as a Markdown table (the README's)."""
    rows = ["| element | played |", "|---|---|"]
    rows += [f"| {name} | {text} |" for name, text in SUPPORTED]
    return "\n".join(rows)
