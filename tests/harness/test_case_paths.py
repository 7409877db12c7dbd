"""Case files by path: `run`, `show` and a sweep's `scenarios` take .toml and .xosc files,
checked before any work starts; the hand-written OpenSCENARIO files run through a sweep with
criteria."""
from __future__ import annotations

import os
import shutil
import textwrap

import pandas as pd
import pytest

from core.errors import BadInput
from harness.cli import main
from harness.sweep.file import load_sweep, validate_cells
from tests.scenarios.openscenario.conftest import ALKS, ELK, ROAD

CRITERION = """
[[criteria]]
metric = "detection_probability"
op = ">="
value = {value}
actor_id = 0
"""


@pytest.fixture
def case_files(tmp_path):
    """The hand-written files beside a sweep folder with a case TOML for each (criteria on
    the motorbike) and a sweep naming them relative to itself."""
    for f in (ELK, ALKS, ROAD):
        shutil.copy(f, tmp_path / f.name)
    (tmp_path / "cases").mkdir()
    for name, src, mount, value in (("elk_bike", ELK, "rear_left", 0.5),
                                    ("alks_bike", ALKS, "rear_left", 0.5)):
        (tmp_path / "cases" / f"{name}.toml").write_text(
            f'xosc = "../{src.name}"\nname = "{name}"\nmount = "{mount}"\n'
            f"must_detect = [0]\n" + CRITERION.format(value=value))
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(textwrap.dedent("""
        name = "osc"
        scenarios = ["cases/elk_bike.toml", "cases/alks_bike.toml", "alks_side_motorbike.xosc"]
        seeds = [0]
        duration_s = 1.0
        schemes = ["ddma"]
    """))
    return tmp_path


def test_sweep_scenarios_are_paths_relative_to_the_sweep_file(case_files, monkeypatch):
    monkeypatch.chdir("/")
    spec = load_sweep(case_files / "sweep.toml")
    assert spec.scenarios == (str(case_files / "cases" / "elk_bike.toml"),
                              str(case_files / "cases" / "alks_bike.toml"),
                              str(case_files / "alks_side_motorbike.xosc"))
    ids = [c.cell_id for c in spec.cells()]
    assert ids[0].startswith("elk_bike.toml__baseline__s0__") and len(set(ids)) == 3


@pytest.mark.parametrize("entry,match", [
    ("cases/missing.toml", "scenarios: case file .*missing.toml"),
    ("notes.txt/", "scenarios: case file .*notes.txt"),
    ("no_such_case", r"unknown case\(s\) \['no_such_case'\]"),
])
def test_sweep_bad_case_entry_is_refused_before_work(case_files, entry, match):
    (case_files / "notes.txt").mkdir()
    sweep = case_files / "bad.toml"
    sweep.write_text(f'scenarios = ["{entry}"]\n')
    with pytest.raises((BadInput, OSError), match=match):
        load_sweep(sweep)


def test_sweep_case_file_with_a_bad_criterion_is_refused(case_files):
    toml = case_files / "cases" / "elk_bike.toml"
    toml.write_text(toml.read_text().replace("detection_probability", "not_a_metric"))
    with pytest.raises(BadInput,
                       match=r"case .*elk_bike.toml: criteria\[0\]\.metric: .*not_a_metric"):
        validate_cells(load_sweep(case_files / "sweep.toml"))


def test_run_takes_a_bare_xosc(capsys):
    assert main(["run", str(ALKS), "--duration-s", "0.1", "--schemes", "ddma"]) == 0
    out = capsys.readouterr().out
    assert str(ALKS) in out and "ddma" in out


def test_run_takes_a_case_toml_by_relative_path(case_files, monkeypatch, capsys):
    monkeypatch.chdir(case_files)
    assert main(["run", os.path.join("cases", "elk_bike.toml"), "--duration-s", "0.1",
                 "--schemes", "ddma"]) == 0
    assert str(case_files / "cases" / "elk_bike.toml") in capsys.readouterr().out


@pytest.mark.parametrize("arg,match", [
    ("missing.xosc", "missing.xosc"),
    ("cases/elk_bike.yaml", "a case file ends in .toml or .xosc"),
])
def test_run_bad_case_path_exits_2_with_one_line(case_files, monkeypatch, capsys, arg, match):
    monkeypatch.chdir(case_files)
    (case_files / "cases" / "elk_bike.yaml").write_text("")
    assert main(["run", arg, "--duration-s", "0.1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and match in err[0]


def test_run_case_file_with_a_bad_criterion_exits_2_before_work(case_files, capsys):
    toml = case_files / "cases" / "elk_bike.toml"
    toml.write_text(toml.read_text().replace("detection_probability", "not_a_metric"))
    assert main(["run", str(toml), "--out", str(case_files / "out")]) == 2
    assert "not_a_metric" in capsys.readouterr().err
    assert not (case_files / "out").exists()


@pytest.mark.slow
def test_show_draws_an_imported_case(tmp_path, capsys):
    assert main(["show", str(ELK), "--out", str(tmp_path)]) == 0
    assert (tmp_path / "elk_overtaking_motorbike.png").is_file()


@pytest.mark.slow
def test_hand_written_files_run_through_a_sweep_with_criteria(case_files, capsys):
    out = case_files / "out"
    assert main(["sweep", str(case_files / "sweep.toml"), "--out", str(out),
                 "--workers", "1", "--no-progress", "--export-xosc",
                 str(case_files / "xosc")]) == 0
    s = pd.read_parquet(out / "summary.parquet").set_index("scenario")
    elk, alks = str(case_files / "cases" / "elk_bike.toml"), \
        str(case_files / "cases" / "alks_bike.toml")
    assert s.loc[elk, "case_criteria_n"] == 1 and s.loc[alks, "case_criteria_n"] == 1
    # the motorbike is in the rear-left radar's view all second in both protocols
    assert s.loc[elk, "case_pass"] == 1 and s.loc[alks, "case_pass"] == 1
    bare = str(case_files / "alks_side_motorbike.xosc")
    assert s.loc[bare, "case_criteria_n"] == 0   # a bare file: the defaults, no criteria
    # --export-xosc wrote every case it ran, as it ran (1 s), and they play back
    written = sorted(p.name for p in (case_files / "xosc").glob("*.xosc"))
    assert written == ["alks_bike.xosc", "alks_side_motorbike.xosc", "elk_bike.xosc"]
    from scenarios import get_case
    assert get_case(str(case_files / "xosc" / "elk_bike.xosc")).duration_s == 1.0


def test_exported_case_gives_the_catalogue_summary(tmp_path):
    """Round trip at the harness level: same truth, same seed -> the same summary."""
    from harness.cell.run import run_cell
    from harness.cell.spec import CellSpec
    from scenarios.openscenario.export import export_case
    xosc, _ = export_case("r79_motorcycle_rear", tmp_path)
    kw = dict(seed=0, duration_s=0.3, schemes=("ddma",))
    a = run_cell(CellSpec(scenario="r79_motorcycle_rear", **kw)).tables["summary"]
    b = run_cell(CellSpec(scenario=str(xosc), **kw)).tables["summary"]
    cols = ["detections_per_frame", "ghost_rate", "range_error_rmse_m",
            "detection_probability_mean", "target_first_detection_range_m"]
    pd.testing.assert_frame_equal(a[cols], b[cols])


def test_sweep_export_xosc_to_a_file_exits_2_before_work(case_files, capsys):
    f = case_files / "taken"
    f.write_text("")
    assert main(["sweep", str(case_files / "sweep.toml"), "--out", str(case_files / "out"),
                 "--workers", "1", "--export-xosc", str(f)]) == 2
    err = capsys.readouterr().err
    assert "--export-xosc" in err and "exists and is not a folder" in err
    assert not (case_files / "out" / "summary.parquet").exists()
