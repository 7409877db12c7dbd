"""OpenSCENARIO import: the hand-written protocol files, case TOMLs naming a file, refusals."""
from __future__ import annotations

import os
import re
import textwrap

import numpy as np
import pytest
from lxml import etree

from scenarios import get_case, run_scenario
from scenarios.files import load_case_file
from scenarios.openscenario.import_ import read_xosc
from scenarios.openscenario.subset import Unsupported
from tests.scenarios.openscenario.conftest import ALKS, ELK, ROAD

LANE_WIDTH_M = 3.5   # motorway_3lane.xodr


@pytest.mark.parametrize("path", [ELK, ALKS])
def test_hand_written_files_are_schema_valid(path, osc_schema):
    assert osc_schema.validate(etree.parse(str(path))), osc_schema.error_log.last_error


def test_bare_xosc_takes_the_defaults():
    case = load_case_file(ELK)
    assert case.name == "elk_overtaking_motorbike"
    assert case.mount.name == "rear_left" and case.duration_s == 8.0
    assert [a.actor_class for a in case.actors] == ["motorcycle"]
    assert case.ego.speed_mps == 20.0 and case.actors[0].speed_mps == pytest.approx(22.2222)
    assert case.criteria == () and case.must_detect == ()


def test_elk_motorbike_pulls_out_10_m_behind_and_speeds_up():
    run = run_scenario(ELK)
    t, ego = run.truth, run.ego
    bike = t[t["actor_id"] == 0].set_index("frame")
    # Ego reference point is its rear axle, 1.4 m behind its box centre; both start in lane -2.
    assert bike.loc[0, "x_m"] == pytest.approx(78.0 - 100.0 - 1.4)
    assert bike.loc[0, "y_m"] == pytest.approx(0.0, abs=1e-9)
    moved = bike[bike["y_m"] > 0.01].index.min()
    gap = -bike.loc[moved - 1, "x_m"] - 0.5 * (5.0 + 2.2)  # freespace at the trigger
    assert 9.9 < gap < 10.2
    end = bike.index.max()
    assert bike.loc[end, "y_m"] == pytest.approx(LANE_WIDTH_M, abs=1e-6)  # one lane left
    # linear speed-up at 1.5 m/s^2 from 80 km/h to 25 m/s, starting after 5 s
    speed = bike["vx_mps"] + ego.set_index("frame")["ego_speed_mps"]
    assert speed.loc[130] == pytest.approx(22.2222 + 1.5 * (6.5 - 5.0), abs=0.02)
    assert speed.loc[end] == pytest.approx(25.0)


def test_alks_motorbike_reacts_to_the_ego_position_and_recentres():
    run = run_scenario(ALKS)
    bike = run.truth[run.truth["actor_id"] == 0].set_index("frame")
    assert bike.loc[0, "y_m"] == pytest.approx(LANE_WIDTH_M - 0.5)  # 0.5 m towards the ego
    speed = bike["vx_mps"] + run.ego.set_index("frame")["ego_speed_mps"]
    # the ego's reference point comes within 2 m of x = 0 at 48 m / 16.6667 m/s = 2.88 s
    assert speed.loc[57] == pytest.approx(16.6667) and speed.loc[58] > 16.6668
    assert speed.loc[140] == pytest.approx(19.4444, abs=1e-6)
    assert bike.loc[199, "y_m"] == pytest.approx(LANE_WIDTH_M, abs=1e-6)


def _case_toml(tmp_path, body: str):
    (tmp_path / "sub").mkdir(exist_ok=True)
    p = tmp_path / "sub" / "case.toml"
    p.write_text(textwrap.dedent(body))
    return p


def test_case_toml_names_the_file_relative_to_itself(tmp_path):
    p = _case_toml(tmp_path, f"""
        xosc = "{os.path.relpath(ALKS, tmp_path / 'sub')}"
        name = "alks_bike"
        ego = "Ego"
        mount = "front_left"
        duration_s = 4.0
        must_detect = [0]
        [[criteria]]
        metric = "detection_probability"
        op = ">="
        value = 0.5
        actor_id = 0
    """)
    case = get_case(str(p))
    assert case.name == "alks_bike" and case.mount.name == "front_left"
    assert case.duration_s == 4.0 and case.must_detect == (0,)
    assert case.criteria[0].metric == "detection_probability"


@pytest.mark.parametrize("body,match", [
    ('xosc = "x.xosc"\nroad = "highway"', "road: unknown key"),
    ('xosc = 3', "xosc=3 must be a string"),
    ('xosc = "x.toml"', "must name an .xosc file"),
    ('xosc = "missing.xosc"', "missing.xosc"),
    (f'xosc = "{ALKS}"\nduration_s = "4 s"', "duration_s='4 s' must be a number"),
    (f'xosc = "{ALKS}"\nmust_detect = [true]', "must_detect"),
    (f'xosc = "{ALKS}"\nmount = "roof"', "unknown mount 'roof'"),
    (f'xosc = "{ALKS}"\nego = "Nobody"', "no entity named 'Nobody'"),
    (f'xosc = "{ALKS}"\nduration_s = 500.0', r"duration_s=500 must be in \(0, 120\]"),
    (f'xosc = "{ALKS}"\nmust_detect = [3]', "must_detect id 3 is not a scripted actor"),
])
def test_bad_xosc_case_toml_is_named(tmp_path, body, match):
    with pytest.raises((ValueError, OSError), match=match):
        get_case(str(_case_toml(tmp_path, body)))


def _line_of(text: str, needle: str) -> int:
    return text[:text.index(needle)].count("\n") + 1


#: (what is replaced in the ALKS file, its replacement, the element refused, message part);
#: the refused element is the replacement's first, unless `NEEDLES` says where it is.
REFUSALS = [
    ("<LateralAction>\n", "<LateralAction><LaneOffsetAction continuous=\"false\"/>\n",
     "LaneOffsetAction", "unsupported action LaneOffsetAction"),
    ("<ReachPositionCondition tolerance=\"2.0\">",
     "<StandStillCondition duration=\"1.0\"/><ReachPositionCondition tolerance=\"2.0\">",
     "StandStillCondition", "unsupported condition StandStillCondition"),
    ('<Vehicle name="l3_motorbike" vehicleCategory="motorbike">',
     '<Vehicle name="l3_motorbike" vehicleCategory="bus">',
     "Vehicle", "unsupported vehicleCategory bus"),
    ('<WorldPosition x="-55.0" y="-2.25" z="0.0" h="0.0"/>',
     '<RelativeLanePosition entityRef="Ego" dLane="1" ds="-5.0"/>',
     "RelativeLanePosition", "unsupported position RelativeLanePosition"),
    ('<AbsoluteTargetSpeed value="19.4444"/>',
     '<AbsoluteTargetSpeed value="${$EgoSpeed + 2.78}"/>',
     "AbsoluteTargetSpeed", "expressions are not supported"),
    ('<AbsoluteTargetSpeed value="19.4444"/>', '<AbsoluteTargetSpeed value="$Nope"/>',
     "AbsoluteTargetSpeed", "parameter Nope is not declared"),
    ('dynamicsShape="sinusoidal" value="3.0" dynamicsDimension="time"',
     'dynamicsShape="cubic" value="3.0" dynamicsDimension="time"',
     "SpeedActionDynamics", "unsupported dynamicsShape cubic"),
    ('<SimulationTimeCondition value="10.0" rule="greaterThan"/>',
     '<SpeedCondition value="10.0" rule="greaterThan"/>',
     "StopTrigger", "a storyboard StopTrigger other than one SimulationTimeCondition"),
    ('<LogicFile filepath="motorway_3lane.xodr"/>', '', "RoadNetwork",
     "no RoadNetwork/LogicFile"),
    ('<LanePosition roadId="1" laneId="-2" offset="0.0" s="50.0"/>',
     '<LanePosition roadId="7" laneId="-2" offset="0.0" s="50.0"/>',
     "LanePosition", "roadId=7 is not a road of the OpenDRIVE file"),
    ('<Event name="bike_recentres" priority="parallel" maximumExecutionCount="1">',
     '<Event name="bike_recentres" priority="parallel" maximumExecutionCount="2">',
     "Event", "maximumExecutionCount above 1"),
]


#: Where the refused element is when the replacement removes it or sits inside it.
NEEDLES = {"StopTrigger": "        <StopTrigger>", "RoadNetwork": "<RoadNetwork>",
           "LaneOffsetAction": "<LaneOffsetAction"}


@pytest.mark.parametrize("old,new,tag,what", REFUSALS, ids=[r[2] + ":" + r[3][:24]
                                                            for r in REFUSALS])
def test_unsupported_elements_are_refused_with_their_line(scene_dir, old, new, tag, what):
    assert old in scene_dir.text
    text = scene_dir.text.replace(old, new, 1)
    line = _line_of(text, NEEDLES.get(tag, new))
    path = scene_dir(text)
    with pytest.raises(Unsupported, match=rf"{re.escape(str(path))}:{line}: <{tag}> "
                       rf"(.*: )?{re.escape(what)}"):
        read_xosc(path)


def test_entity_from_a_catalog_is_refused(scene_dir):
    text = scene_dir.text
    start = text.index('<Vehicle name="l3_motorbike"')
    end = text.index("</Vehicle>", start) + len("</Vehicle>")
    text = text[:start] + '<CatalogReference catalogName="VehicleCatalog" ' \
        'entryName="motorbike"/>' + text[end:]
    with pytest.raises(Unsupported, match=r":\d+: <CatalogReference> unsupported entity kind "
                       r"CatalogReference in ScenarioObject; supported: Pedestrian, Vehicle"):
        read_xosc(scene_dir(text))


def _routing_instead_of_lane_change(text: str, routing: str) -> str:
    """The ALKS file with its lane change replaced by a routing action."""
    start = text.index("<LateralAction>")
    end = text.index("</LateralAction>") + len("</LateralAction>")
    return text[:start] + routing + text[end:]


def test_untimed_polyline_is_refused(scene_dir):
    text = _routing_instead_of_lane_change(
        scene_dir.text, "<RoutingAction><FollowTrajectoryAction><TrajectoryRef>"
        "<Trajectory name=\"t\" closed=\"false\"><Shape><Polyline>"
        "<Vertex><Position><WorldPosition x=\"0\" y=\"0\"/></Position></Vertex>"
        "<Vertex><Position><WorldPosition x=\"9\" y=\"0\"/></Position></Vertex>"
        "</Polyline></Shape></Trajectory></TrajectoryRef><TimeReference><None/>"
        "</TimeReference><TrajectoryFollowingMode followingMode=\"position\"/>"
        "</FollowTrajectoryAction></RoutingAction>")
    with pytest.raises(Unsupported, match=r"<Polyline> an untimed Polyline; supported: "
                       "vertices with a time"):
        read_xosc(scene_dir(text))


def test_not_xml_is_refused(scene_dir):
    with pytest.raises(Unsupported, match="not well-formed XML"):
        read_xosc(scene_dir(scene_dir.text[:200]))


@pytest.mark.parametrize("old,new,what", [
    ("<line/>", '<spiral curvStart="0.0" curvEnd="0.001"/>', "unsupported geometry spiral"),
    ('<width sOffset="0.0" a="3.5" b="0.0"', '<width sOffset="0.0" a="3.5" b="0.01"',
     "lane width varies along the road"),
    ('</laneSection>', '</laneSection><laneSection s="500.0"><center><lane id="0"/>'
     '</center></laneSection>', "2 lane sections"),
])
def test_unsupported_roads_are_refused_with_their_line(scene_dir, old, new, what):
    road = scene_dir.dir / ROAD.name
    text = road.read_text().replace(old, new, 1)
    road.write_text(text)
    with pytest.raises(Unsupported, match=rf"{re.escape(str(road))}:\d+: <\w+> "
                       rf"(road 1: )?{re.escape(what)}"):
        read_xosc(scene_dir(scene_dir.text))


def test_cli_run_refusal_exits_2_with_one_line(scene_dir, capsys):
    from harness.cli import main
    path = scene_dir(scene_dir.text.replace('vehicleCategory="motorbike"',
                                            'vehicleCategory="train"'))
    assert main(["run", str(path), "--duration-s", "0.1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unsupported vehicleCategory train" in err[0]


def _relative_trajectory_text() -> str:
    """The ALKS file whose lane change is a trajectory with relative timing, scale 2 and
    offset 0.5 s."""
    text = _routing_instead_of_lane_change(
        ALKS.read_text(), "<RoutingAction><FollowTrajectoryAction><TrajectoryRef>"
        "<Trajectory name=\"t\" closed=\"false\"><Shape><Polyline>"
        "<Vertex time=\"0\"><Position><WorldPosition x=\"0\" y=\"20\" h=\"0\"/></Position>"
        "</Vertex><Vertex time=\"1\"><Position><WorldPosition x=\"10\" y=\"20\" h=\"0\"/>"
        "</Position></Vertex></Polyline></Shape></Trajectory></TrajectoryRef>"
        "<TimeReference><Timing domainAbsoluteRelative=\"relative\" scale=\"2\" "
        "offset=\"0.5\"/></TimeReference><TrajectoryFollowingMode followingMode=\"position\"/>"
        "</FollowTrajectoryAction></RoutingAction>")
    return text


def test_relative_trajectory_timing(scene_dir):
    case = read_xosc(scene_dir(_relative_trajectory_text()))
    tr = case.motion.actors[0].trajectory
    # the event fires 1 s after "time > 5 s" rises (at the 5.01 s step): vertices at
    # 6.01 + 0.5 + 2 x (0, 1) s
    x, y, _, vx, _ = tr.pose(7.51)
    assert (x, y) == pytest.approx((5.0, 20.0)) and vx == pytest.approx(5.0)
    x, y, _, vx, _ = tr.pose(9.51)  # after the end: straight on at the last velocity
    assert (x, y) == pytest.approx((15.0, 20.0)) and vx == pytest.approx(5.0)
    assert np.isfinite(tr.time_s).all()
