"""Road-layout and traffic-environment registries: every entry builds and names its paths."""
from __future__ import annotations

import pytest

from scenarios.catalog import path_names
from scenarios.roads import LANE_WIDTH_M, RAIL_SHOULDER_M, ROAD_LAYOUTS, TRAFFIC_ENVS


@pytest.mark.parametrize("name", list(ROAD_LAYOUTS))
@pytest.mark.parametrize("lanes", [1, 3])
def test_layout_builds_its_paths(name, lanes):
    layout = ROAD_LAYOUTS[name].build(lanes)
    assert tuple(layout.paths) == path_names(name, lanes)
    for path in layout.paths.values():
        # s = 0 is the path's point nearest the layout origin
        assert abs(path.position(0.0)).max() <= 2 * LANE_WIDTH_M


def test_highway_paths_and_rails():
    layout = ROAD_LAYOUTS["highway"].build(3)
    assert tuple(layout.paths) == ("lane_0", "lane_1", "lane_2")
    # highway-env y: lane i at 4 i m; rails 1.5 m beyond both outer lane edges
    assert layout.rails_y_hw == [-0.5 * LANE_WIDTH_M - RAIL_SHOULDER_M,
                                 2.5 * LANE_WIDTH_M + RAIL_SHOULDER_M]
    assert ROAD_LAYOUTS["two_way"].path_names(1) == ("lane_0", "oncoming")
    assert ROAD_LAYOUTS["urban"].build(1).rails_y_hw == []


def test_unknown_road_names_the_known_ones():
    with pytest.raises(ValueError, match=r"road='moon' is not one of \["):
        path_names("moon", 2)


@pytest.mark.parametrize("name", list(TRAFFIC_ENVS))
def test_traffic_env_class_and_config(name):
    env = TRAFFIC_ENVS[name]
    assert isinstance(env.env_class(), type)
    cfg = env.env_config(4, 30, 2.0)
    if env.road is None:
        assert cfg == {} and env.rails_y_hw(4) == []
    else:
        assert cfg == {"lanes_count": 4, "vehicles_count": 30, "vehicles_density": 2.0}
        assert env.rails_y_hw(4) == ROAD_LAYOUTS[env.road].build(4).rails_y_hw
