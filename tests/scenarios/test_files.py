"""TOML scenario files: a valid file loads and runs; each bad-file rule gives a named error."""
from __future__ import annotations

import pytest

from scenarios import load_scenario_file, parse_scenario, run_scenario

GOOD = '''
name = "my_r79"
description = "motorcycle at 130 km/h"
mount = "rear_left"
duration_s = 1.0
road = "highway"
lanes = 3
guard_rails = true
must_detect = [0]

[ego]
path = "lane_1"
speed_mps = 22.2

[[actors]]
actor_class = "motorcycle"
path = "lane_0"
s_m = -120.0
speed_mps = 36.1

[[criteria]]
metric = "first_detection_range_m"
op = ">="
value = 55.0
actor_id = 0
'''


def _write(tmp_path, text):
    p = tmp_path / "case.toml"
    p.write_text(text)
    return p


def test_good_file_loads_and_runs(tmp_path):
    case = load_scenario_file(_write(tmp_path, GOOD))
    assert case.name == "my_r79" and case.mount.name == "rear_left"
    assert case.actors[0].actor_class == "motorcycle"
    assert case.criteria[0].value == 55.0
    run = run_scenario(case)
    assert run.n_frames == 20
    assert set(run.truth.actor_class) == {"motorcycle", "guard_rail"}


def test_mount_table(tmp_path):
    text = GOOD.replace('mount = "rear_left"\n', "") + \
        '\n[mount]\nname = "rear_left"\nx_m = -2.0\ny_m = 0.9\nz_m = 0.6\nyaw_deg = 150.0\n'
    case = load_scenario_file(_write(tmp_path, text))
    assert case.mount.yaw_deg == 150.0


@pytest.mark.parametrize("old, new, match", [
    # unknown keys, at the top and nested (position named)
    ('lanes = 3', 'lanes = 3\ncolour = "red"', "colour: unknown key"),
    ('s_m = -120.0', 's_m = -120.0\nhelmet = true', r"actors\[0\]\.helmet: unknown key"),
    ('op = ">="', 'op = ">="\nweight = 2', r"criteria\[0\]\.weight: unknown key"),
    # wrong units: a non-SI key, and a value written with its unit
    ('speed_mps = 36.1', 'speed_kmh = 130.0', r"actors\[0\]\.speed_kmh: wrong unit.*speed_mps"),
    ('duration_s = 1.0', 'duration_ms = 1000', r"duration_ms: wrong unit.*duration_s"),
    ('speed_mps = 22.2', 'speed_mps = "80 km/h"', r"ego\.speed_mps: must be a number in mps"),
    # impossible values
    ('duration_s = 1.0', 'duration_s = -1.0', "duration_s=-1.0 must be in"),
    ('speed_mps = 36.1', 'speed_mps = 90.0', r"actors\[0\]\.speed_mps=90.0 exceeds"),
    ('actor_class = "motorcycle"', 'actor_class = "tank"', r"actors\[0\]\.actor_class='tank'"),
    ('path = "lane_0"', 'path = "lane_7"', r"actors\[0\]\.path='lane_7' unknown"),
    ('mount = "rear_left"', 'mount = "roof"', "mount: unknown mount 'roof'"),
    ('lanes = 3', 'lanes = 0', "lanes=0 must be"),
    ('metric = "first_detection_range_m"', 'metric = ""', r"criteria\[0\]\.metric='' must name"),
    ('guard_rails = true', 'guard_rails = "yes"', "guard_rails: must be true or false"),
    ('name = "my_r79"', '', "name: required key missing"),
])
def test_bad_file_rejected_naming_the_key(tmp_path, old, new, match):
    assert old in GOOD
    with pytest.raises(ValueError, match=match):
        load_scenario_file(_write(tmp_path, GOOD.replace(old, new, 1)))


def test_bad_mount_table_value(tmp_path):
    text = GOOD.replace('mount = "rear_left"\n', "") + \
        '\n[mount]\nname = "rear_left"\nx_m = -2.0\ny_m = 0.9\nz_m = -1.0\nyaw_deg = 150.0\n'
    with pytest.raises(ValueError, match=r"mount\.mount z_m=-1.0"):
        load_scenario_file(_write(tmp_path, text))


def test_malformed_toml(tmp_path):
    with pytest.raises(ValueError, match="malformed TOML"):
        load_scenario_file(_write(tmp_path, "name = = 3"))


def test_error_names_the_file(tmp_path):
    p = _write(tmp_path, GOOD.replace("lanes = 3", "lanes = 9"))
    with pytest.raises(ValueError, match=str(p.name)):
        load_scenario_file(p)


def test_actors_must_be_array_of_tables():
    with pytest.raises(ValueError, match=r"actors: must be an array of tables"):
        parse_scenario({"name": "a", "description": "b", "mount": "front_left",
                        "duration_s": 2.0, "actors": 3})


def test_parse_dict():
    case = parse_scenario({"name": "a", "description": "b", "mount": "front_left",
                           "duration_s": 2.0})
    assert case.mount.yaw_deg == 45.0


def test_shipped_catalogue_is_the_case_files():
    """The catalogue is the TOML files of scenarios/cases, read by the user-file loader."""
    from scenarios import SCENARIOS
    from scenarios.files import load_case_directory
    from scenarios.registry import CASES_DIR

    files = sorted(CASES_DIR.glob("*.toml"))
    assert [p.stem for p in files] == list(SCENARIOS)
    for p in files:
        assert load_scenario_file(p) == SCENARIOS[p.stem]
    assert load_case_directory(CASES_DIR) == SCENARIOS


def test_case_file_named_after_its_case(tmp_path):
    from scenarios.files import load_case_directory

    (tmp_path / "my_r79.toml").write_text(GOOD)
    with pytest.raises(ValueError, match=r"b\.toml: holds case 'my_r79'; name the file my_r79"):
        (tmp_path / "b.toml").write_text(GOOD)
        load_case_directory(tmp_path)
