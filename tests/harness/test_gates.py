"""`radar-harness gate`: exit codes, JUnit XML, Markdown, the shipped gates file."""
from __future__ import annotations

import shutil
import xml.etree.ElementTree as ET

import pandas as pd
import pytest

from harness.cli import main
from harness.gates import check as g


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
[[gate]]
name = "tdma_ghosts"
metric = "ghost_rate"
scheme = "tdma"
aggregate = "max"
max = 0.3
"""


def test_all_pass_exit_0_and_junit(fake_results, tmp_path):
    junit = tmp_path / "j.xml"
    assert main(["gate", str(fake_results), "--thresholds", write(tmp_path, PASSING),
                 "--junit", str(junit)]) == 0
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite.get("failures") == "0"
    names = [c.get("name") for c in suite.findall("testcase")]
    # sweep_cells_ok + schemes_gated + one per DDMA row (2 scenarios) + one for tdma_raw in
    # "fast" + one TDMA aggregate.
    assert len(names) == 6
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


def test_shipped_gates_file_is_valid():
    gates = g.load_gates()
    assert len(gates) >= 5
    by = {x.name: x for x in gates}
    assert by["ddma_velocity_unambiguity"].min == 0.99
    # every scheme of the default run is gated, each on every case class
    for scheme in ("ddma", "tdma", "tdma_raw"):
        mine = [x for x in gates if x.scheme in (scheme, "*")]
        assert {x.case_class for x in mine} >= {"r79", "interference"} or \
            any(x.case_class == "*" for x in mine), scheme
    # ordinary cases keep a ghost-rate bound of 0.1 or tighter for every scheme (DDMA per
    # case, as before; TDMA and raw TDMA on the median over the cases)
    ordinary = [x for x in gates if x.metric == "ghost_rate" and x.case_class == "ordinary"
                and x.max <= 0.1]
    assert {x.scheme for x in ordinary} == {"ddma", "tdma", "tdma_raw"}
    assert by["ddma_ghost_rate"].aggregate == "each" and by["ddma_ghost_rate"].max == 0.1
    # the head-on case: at least half the floor rise recovered; the ghosts mitigation adds
    # bounded for every scheme (at the default's measured level, not the 0.02)
    assert by["interference_floor_recovered"].min == 0.5
    added = [x for x in gates if x.metric == "mitigation_ghost_rate_added"]
    assert {x.scheme for x in added} == {"ddma", "tdma*"}
    assert all(x.case_class == "interference" and x.max <= 0.08 for x in added)


@pytest.mark.parametrize("text, match", [
    ("[[gate]]\nname = 'x'\nmetric = 'ghost_rate'\nmax = 1\nmax_pct = 2",
     r"gate\[0\]\.max_pct: unknown key; known: \["),
    ("[[gate]]\nname = 'x'\nmetric = 'ghost_rate'\nmax = '0.1'",
     r"gate\[0\]\.max: must be a number"),
    ("[[gate]]\nname = 'x'\nmax = 1", r"gate\[0\]\.metric: required key missing"),
])
def test_gates_file_messages_follow_the_shared_file_policy(tmp_path, text, match):
    """Same message shape as case files and sweeps: file, key with its position, what."""
    from harness.gates.check import load_gates
    p = tmp_path / "g.toml"
    p.write_text(text)
    with pytest.raises(ValueError, match=rf"g\.toml: {match}"):
        load_gates(p)


@pytest.mark.parametrize("text,match", [
    ("[[gate]]\nname = 'x'\nmetric = 'first_detection_range_m'\nmin = 1",
     "metric='first_detection_range_m' cannot be gated .*target_first_detection_range_m"),
    ("[[gate]]\nname = 'x'\nmetric = 'ghost_rate'\nmax = 1\ncase_class = 'ncap'",
     "case_class='ncap' is not one of"),
    ("[[gate]]\nname = 'x'\nmetric = 'ghosts'\nmax = 1", "unknown metric 'ghosts'; known: "),
])
def test_registry_and_case_class_bad_input_exit_2(fake_results, tmp_path, capsys, text, match):
    assert main(["gate", str(fake_results), "--thresholds", write(tmp_path, text)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    import re
    assert re.search(match, err)


def test_case_class_filter_and_ungated_schemes(fake_results, tmp_path):
    summary, manifest = g.load_summary(fake_results)
    text = """
[[gate]]
name = "ordinary_ghosts"
metric = "ghost_rate"
case_class = "ordinary"
scheme = "ddma"
max = 1.0
[[gate]]
name = "r79_only"
metric = "ghost_rate"
case_class = "r79"
scheme = "ddma"
max = 1.0
allow_missing = true
"""
    res = g.evaluate_gates(summary, g.load_gates(write(tmp_path, text)), manifest)
    by = {}
    for r in res:
        by.setdefault(r.gate, []).append(r)
    # the stand-in cases are ordinary: two DDMA rows; no R79 rows (skipped)
    assert len(by["ordinary_ghosts"]) == 2
    assert [r.status for r in by["r79_only"]] == ["skip"]
    # tdma and tdma_raw ran but no gate addresses them
    assert by["schemes_gated"][0].status == "fail"
    assert "tdma" in by["schemes_gated"][0].message
    v = g.verdict_table(res)
    assert list(v.columns) == ["ddma"] and v.loc["fast", "ddma"].startswith("pass ghost_rate=")


def test_verdict_table_names_the_failing_numbers():
    res = [g.GateResult("a", "ghost_rate", "c/baseline/0/ddma", 0.2, "<= 0.1", "fail"),
           g.GateResult("b", "r79_pass", "c/baseline/0/ddma", 1.0, ">= 1", "pass"),
           g.GateResult("b", "r79_pass", "c/baseline/0/tdma", 1.0, ">= 1", "pass"),
           g.GateResult("m", "x", "mean over 2 rows", 1.0, ">= 1", "pass")]
    v = g.verdict_table(res)
    assert v.loc["c", "ddma"] == "FAIL ghost_rate=0.2 (<= 0.1)"
    assert v.loc["c", "tdma"] == "pass r79_pass=1"
    res.append(g.GateResult("z", "range_error_rmse_m", "c/baseline/0/tdma", 0.2, "<= 1", "pass"))
    assert g.verdict_table(res).loc["c", "tdma"] == "pass r79_pass=1, range_error_rmse_m=0.2"


@pytest.mark.parametrize("metric, match", [
    ("joy", r"criteria\[0\]\.metric: unknown metric 'joy'; known: "),
    ("n_frames", r"criteria\[0\]\.metric: criterion metric 'n_frames' cannot be a case "
                 r"criterion; criterion metrics: detection_probability"),
])
def test_case_file_criterion_on_no_criterion_metric_exit_2(tmp_path, capsys, metric, match):
    """A user's case file names its criteria's metrics by metrics.METRICS: `show` refuses an
    unknown one and one that cannot be a criterion, in one line."""
    import re

    from scenarios.registry import CASES_DIR
    text = (CASES_DIR / "blind_spot_overtaking.toml").read_text().replace(
        'metric = "detection_probability"', f'metric = "{metric}"')
    f = tmp_path / "mine.toml"
    f.write_text(text)
    assert main(["show", str(f), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and re.search(match, err)
