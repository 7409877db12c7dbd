"""OpenSCENARIO export: schema-valid files for every road layout, what they hold, the CLI."""
from __future__ import annotations

import dataclasses
import json

import pytest
from lxml import etree

from harness.cli import main
from scenarios import get_case
from scenarios.openscenario.export import EGO_NAME, export_case
from scenarios.openscenario.road import read_xodr

#: One case per road layout and traffic environment (scripted highway, two-way, urban; random
#: highway, merge, roundabout, intersection).
LAYOUT_CASES = ["blind_spot_overtaking", "head_on_aliasing", "ccftap_turn_across",
                "dense_highway", "merge_random", "roundabout_random", "intersection_random"]


def test_layout_cases_cover_every_road_and_traffic_env():
    from scenarios import ROAD_LAYOUTS, TRAFFIC_ENVS
    cases = [get_case(n) for n in LAYOUT_CASES]
    assert {c.road for c in cases if c.traffic is None} == set(ROAD_LAYOUTS)
    assert {c.traffic for c in cases if c.traffic is not None} == set(TRAFFIC_ENVS)


@pytest.mark.parametrize("name", LAYOUT_CASES)
def test_export_is_schema_valid_with_its_road(name, tmp_path, osc_schema):
    xosc, xodr = export_case(name, tmp_path)
    doc = etree.parse(str(xosc))
    assert osc_schema.validate(doc), osc_schema.error_log.last_error
    assert doc.find("RoadNetwork/LogicFile").get("filepath") == xodr.name
    roads = read_xodr(xodr)   # our own reader takes what we write: lines and arcs only
    assert roads and all(len(r.lanes) == 1 for r in roads.values())


def test_export_holds_entities_trajectories_and_harness_fields(tmp_path):
    case = get_case("r79_motorcycle_rear")
    assert not case.criteria
    case = dataclasses.replace(case, criteria=get_case("blind_spot_overtaking").criteria)
    xosc, _ = export_case(case, tmp_path)
    doc = etree.parse(str(xosc))
    names = [o.get("name") for o in doc.iter("ScenarioObject")]
    assert names[0] == EGO_NAME and len(names) == 1 + len(case.actors)
    bike = doc.find("Entities/ScenarioObject[2]/Vehicle")
    assert bike.get("vehicleCategory") == "motorbike"
    dims = bike.find("BoundingBox/Dimensions")
    assert (float(dims.get("length")), float(dims.get("width"))) == (2.2, 0.8)
    verts = doc.findall(".//FollowTrajectoryAction//Polyline")[1].findall("Vertex")
    n_frames = round(case.duration_s * 20)
    assert len(verts) == 2 * n_frames   # every frame, and its velocity probe 1 ms later
    params = {p.get("name"): p.get("value") for p in doc.iter("ParameterDeclaration")}
    assert json.loads(params["harness_mount"])["name"] == case.mount.name
    assert json.loads(params["harness_criteria"])[0]["metric"] == case.criteria[0].metric
    assert json.loads(params["harness_must_detect"]) == list(case.must_detect)


def test_export_is_deterministic(tmp_path):
    a, _ = export_case("merge_random", tmp_path / "a", seed=3)
    b, _ = export_case("merge_random", tmp_path / "b", seed=3)
    assert a.read_bytes() == b.read_bytes()


def test_cli_export_writes_both_files(tmp_path, capsys):
    assert main(["export", "zero_relative_follower", "--format", "xosc", "--out",
                 str(tmp_path)]) == 0
    assert (tmp_path / "zero_relative_follower.xosc").is_file()
    assert (tmp_path / "zero_relative_follower.xodr").is_file()
    assert "wrote" in capsys.readouterr().out


@pytest.mark.parametrize("args,match", [
    (["nope", "--format", "xosc"], "unknown scenario 'nope'"),
    (["zero_relative_follower", "--format", "csv"], "invalid choice: 'csv'"),
    (["zero_relative_follower"], "the following arguments are required: --format"),
    (["missing_case.xosc", "--format", "xosc"], "missing_case.xosc"),
])
def test_cli_export_bad_input_exits_2(args, match, tmp_path, capsys):
    assert main(["export", *args, "--out", str(tmp_path)]) == 2
    assert match in capsys.readouterr().err


def test_cli_export_out_is_a_file_exits_2(tmp_path, capsys):
    f = tmp_path / "f"
    f.write_text("")
    assert main(["export", "zero_relative_follower", "--format", "xosc", "--out",
                 str(f)]) == 2
    assert "exists and is not a folder" in capsys.readouterr().err


def test_readme_lists_the_supported_subset():
    from pathlib import Path

    from scenarios.openscenario.subset import subset_table_markdown
    readme = (Path(__file__).resolve().parents[3] / "README.md").read_text()
    assert subset_table_markdown() in readme
