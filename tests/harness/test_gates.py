"""`radar-harness gate`: exit codes, JUnit XML, Markdown, the shipped gates file."""
from __future__ import annotations

import shutil
import xml.etree.ElementTree as ET

import pandas as pd
import pytest

from harness import gates as g
from harness.cli import main
from metrics.tracks import TRACK_METRIC_COLUMNS


def write(tmp_path, text, name="g.toml"):
    f = tmp_path / name
    f.write_text(text)
    return str(f)


PASSING = """
[[gate]]
name = "gain"
metric = "snr_gain_median_db"
scheme = "ddma"
min = 5.0
[[gate]]
name = "raw_tdma_aliases"
metric = "velocity_unambiguity_rate"
scheme = "tdma_raw"
scenario = "fast"
max = 0.5
"""


def test_all_pass_exit_0_and_junit(fake_results, tmp_path):
    junit = tmp_path / "j.xml"
    assert main(["gate", str(fake_results), "--thresholds", write(tmp_path, PASSING),
                 "--junit", str(junit)]) == 0
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite.get("failures") == "0"
    names = [c.get("name") for c in suite.findall("testcase")]
    # sweep_cells_ok + one per DDMA row (2 scenarios) + one for tdma_raw in "fast".
    assert len(names) == 4
    assert "gain[fast/baseline/0/ddma]" in names
    assert (fake_results / "gates.md").read_text().startswith("## Radar gates: PASS")


def test_failure_exit_1_with_junit_failure(fake_results, tmp_path):
    text = PASSING.replace("min = 5.0", "min = 7.0")
    junit = tmp_path / "j.xml"
    md = tmp_path / "g.md"
    assert main(["gate", str(fake_results), "--thresholds", write(tmp_path, text),
                 "--junit", str(junit), "--markdown", str(md)]) == 1
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite.get("failures") == "2"
    fails = [c for c in suite.findall("testcase") if c.find("failure") is not None]
    assert all("violates >= 7" in f.find("failure").get("message") for f in fails)
    assert "| FAIL | gain |" in md.read_text()


def test_mean_aggregate_and_skips(fake_results, tmp_path):
    text = """
[[gate]]
name = "mean_pd"
metric = "detection_probability_mean"
scheme = "ddma"
aggregate = "mean"
min = 0.9
[[gate]]
name = "nobody"
metric = "ghost_rate"
scenario = "no_such_case"
max = 0.1
allow_missing = true
"""
    summary, manifest = g.load_summary(fake_results)
    res = g.evaluate_gates(summary, g.load_gates(write(tmp_path, text)), manifest)
    by = {r.gate: r for r in res}
    assert by["mean_pd"].status == "pass" and "mean over 2 rows" in by["mean_pd"].where
    assert by["nobody"].status == "skip"


@pytest.mark.parametrize("text,match", [
    ("[[gate]]\nname = 'x'\nmetric = 'no_such_metric'\nmin = 1", "unknown metric"),
    ("[[gate]]\nname = 'x'\nmetric = 'ghost_rate'", "needs min and/or max"),
    ("[[gate]]\nname = 'x'\nmetric = 'ghost_rate'\nmax = 1\nfoo = 2", "unknown key"),
    ("[[gate]]\nname = 'x'\nmetric = 'ghost_rate'\nmax = 1\naggregate = 'mode'",
     "aggregate"),
    ("[[gate]\n", "malformed TOML"),
    ("title = 'x'", "title: unknown key"),
])
def test_bad_thresholds_exit_2(fake_results, tmp_path, capsys, text, match):
    assert main(["gate", str(fake_results), "--thresholds", write(tmp_path, text)]) == 2
    assert match in capsys.readouterr().err


def test_missing_results_exit_2(tmp_path, capsys):
    assert main(["gate", str(tmp_path / "nowhere")]) == 2
    assert "no results summary" in capsys.readouterr().err


def test_errored_cell_fails_the_sweep_gate(fake_results, tmp_path):
    d = tmp_path / "res"
    shutil.copytree(fake_results, d)
    s = pd.read_parquet(d / "summary.parquet")
    s = pd.concat([s, pd.DataFrame([{"scenario": "boom", "variant": "baseline", "seed": 0,
                                     "scheme": "", "error": "RuntimeError: x"}])],
                  ignore_index=True)
    s.to_parquet(d / "summary.parquet", index=False)
    assert main(["gate", str(d), "--thresholds", write(tmp_path, PASSING)]) == 1
    res = g.evaluate_gates(s, g.load_gates(write(tmp_path, PASSING)))
    assert res[0].gate == "sweep_cells_ok" and res[0].status == "fail"


def test_shipped_gates_file_is_valid(fake_results):
    gates = g.load_gates()
    assert len(gates) >= 5
    # Every shipped metric is a summary column of a sweep (the stand-in parts have no tracker,
    # so the track metrics come from metrics.tracks).
    known = set(pd.read_parquet(fake_results / "summary.parquet").columns) | \
        set(TRACK_METRIC_COLUMNS)
    assert {x.metric for x in gates} <= known
    by = {x.name: x for x in gates}
    assert by["ddma_velocity_unambiguity"].min == 0.99
    assert by["r79_motorcycle_first_detection"].min == 55.0


@pytest.mark.parametrize("text, match", [
    ("[[gate]]\nname = 'x'\nmetric = 'ghost_rate'\nmax = 1\nmax_pct = 2",
     r"gate\[0\]\.max_pct: unknown key; known: \["),
    ("[[gate]]\nname = 'x'\nmetric = 'ghost_rate'\nmax = '0.1'",
     r"gate\[0\]\.max: must be a number"),
    ("[[gate]]\nname = 'x'\nmax = 1", r"gate\[0\]\.metric: required key missing"),
])
def test_gates_file_messages_follow_the_shared_file_policy(tmp_path, text, match):
    """Same message shape as case files and sweeps: file, key with its position, what."""
    from harness.gates import load_gates
    p = tmp_path / "g.toml"
    p.write_text(text)
    with pytest.raises(ValueError, match=rf"g\.toml: {match}"):
        load_gates(p)
