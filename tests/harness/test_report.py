"""`radar-harness report`: self-contained HTML, every image embedded and decodable."""
from __future__ import annotations

import base64
import contextlib
import io
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from harness.cli import main

CHROMIUM = Path("/usr/bin/chromium")


@pytest.fixture
def report(fake_report):
    """The stand-in results' report page (drawn once per run, `fake_report`)."""
    return fake_report


def test_report_is_self_contained(report):
    page = report.read_text()
    srcs = re.findall(r'<img[^>]*src="([^"]+)"', page)
    # Pd vs range, SNR-gain histogram, ghost map, and one bird's-eye view per case (2 cases).
    assert len(srcs) == 5
    for src in srcs:
        assert src.startswith("data:image/png;base64,")
        img = Image.open(io.BytesIO(base64.b64decode(src.split(",", 1)[1]))).convert("L")
        assert np.asarray(img).std() > 5  # a plot, not a blank canvas
    assert "Case fast" in page and "Case slow" in page
    assert "<h2>Gates (shipped thresholds)" in page
    assert not re.search(r'src="(?!data:)', page)  # nothing fetched from disk or network


def test_report_leads_with_the_answer(report):
    """Headline table, then the two figures, then the cases; the gate table last, collapsed."""
    page = report.read_text()
    order = [page.index(h) for h in ("<h2>Headline", "<h2>Detection probability versus range",
                                     "<h2>SNR gain over", "<h2>Case fast", "<h2>Ghost map",
                                     "<details><summary><h2>Gates (shipped thresholds)")]
    assert order == sorted(order)
    head = page[order[0]:order[1]]
    for col in ("Pd car", "first detection car, m", "range RMSE, m", "velocity RMSE, m/s",
                "velocity unambiguous (road users)", "ghost rate", "gates"):
        assert f"<th>{col}</th>" in head
    # the headline says which runs' road users alias (or that none do)
    assert "Velocity aliasing" in head
    assert page.rstrip().endswith("</details></body></html>")


def test_report_missing_results_exit_2(tmp_path):
    assert main(["report", str(tmp_path)]) == 2


@pytest.mark.skipif(not CHROMIUM.exists(), reason="headless Chromium not installed "
                    "(.ci/run installs it with apt-get install -y chromium)")
def test_report_renders_in_headless_chromium(report, tmp_path):
    shot = tmp_path / "shot.png"
    # One Chromium run takes the screenshot and dumps the DOM (each start costs ~1.5 s).
    cmd = [str(CHROMIUM), "--headless", "--no-sandbox", "--disable-gpu",
           "--hide-scrollbars", "--window-size=1280,2400", f"--screenshot={shot}",
           "--virtual-time-budget=5000", "--dump-dom", report.as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert shot.exists(), proc.stderr[-2000:]
    img = np.asarray(Image.open(shot).convert("RGB")).astype(float)
    assert img.std() > 10, "blank screenshot"
    # Rendered plots contain saturated colours (labels, heat maps); text alone does not.
    sat = img.max(axis=2) - img.min(axis=2)
    assert (sat > 60).mean() > 5e-4
    # Chromium's DOM dump: every <img> decoded (naturalWidth > 0), none broken.
    dom = proc.stdout
    assert dom.count("<img") == 5


def test_report_panels_follow_the_schemes_in_the_tables(tmp_path):
    """A sweep of other schemes (BPM against a TDMA baseline) gets panels for exactly those:
    no fixed DDMA/TDMA list in the report."""
    from harness.report.figures import scheme_order as _schemes
    from harness.report.page import build_report
    from harness.sweep.schedule import run_sweep
    from harness.sweep.spec import SweepSpec
    from tests.harness.fakes import FAKE

    spec = SweepSpec(name="bpm", scenarios=("fast",), seeds=(0,), duration_s=0.5,
                     schemes=("bpm", "tdma", "tdma_raw"))
    run_sweep(spec, tmp_path, components=FAKE, progress=False)
    import pandas as pd
    det = pd.read_parquet(tmp_path / "detections.parquet")
    assert _schemes(det) == ["bpm", "tdma", "tdma_raw"]
    assert _schemes(det, mimo_only=True) == ["bpm", "tdma"]
    page = build_report(tmp_path, maps=False).read_text()
    assert "SNR gain over tdma" in page and ">bpm<" in page


def _case_section_args(results) -> tuple:
    """`report._case_sections`' arguments for every case of a results folder, no maps."""
    import pandas as pd
    tabs = {t: pd.read_parquet(results / f"{t}.parquet")
            for t in ("summary", "detections", "truth")}
    keys = [tuple(k) for k in tabs["summary"][["scenario", "variant", "seed"]]
            .drop_duplicates().itertuples(index=False)]
    return tabs["summary"], tabs["detections"], tabs["truth"], {}, keys, False


def test_case_sections_drawn_in_worker_processes_equal_inline(fake_results, monkeypatch):
    """Case sections drawn in a process pool (a report with many cases): the same HTML, in
    the same order, as drawn inline."""
    from harness.report import page as rp
    args = _case_section_args(fake_results)
    keys = args[4]
    monkeypatch.setattr(rp, "PARALLEL_MIN_CASES", 10 ** 9)
    inline = rp._case_sections(*args)
    monkeypatch.setattr(rp, "PARALLEL_MIN_CASES", 2)
    monkeypatch.setattr(rp.os, "cpu_count", lambda: 2)
    pooled = rp._case_sections(*args)
    assert len(keys) == 2 and sum("<h2>Case " in p for p in pooled) == 2
    assert pooled == inline


def test_ctrl_c_while_the_case_pool_forks_stops_the_report(fake_results, monkeypatch):
    """A Ctrl-C landing while the report's pool forks its workers used to be dropped by
    Python (raised inside os.fork's at-fork hooks) and the report ran on: it must stop it."""
    import multiprocessing

    from harness.report import page as rp
    from tests.harness.forked import ctrl_c_at_the_next_fork
    if multiprocessing.get_start_method() != "fork":
        pytest.skip("this Python starts pool workers without forking: no at-fork hook runs")
    args = _case_section_args(fake_results)
    monkeypatch.setattr(rp, "PARALLEL_MIN_CASES", 2)
    monkeypatch.setattr(rp.os, "cpu_count", lambda: 2)
    with ctrl_c_at_the_next_fork() as ctrl_c, pytest.raises(KeyboardInterrupt):
        rp._case_sections(*args)
    assert ctrl_c["fired"]


def _damaged_copy(fake_results, tmp_path, manifest=None, summary=None):
    import json
    import shutil

    import pandas as pd
    d = tmp_path / "res"
    shutil.copytree(fake_results, d, ignore=shutil.ignore_patterns("cells", "*.html", "*.md"))
    if manifest:
        man = json.loads((d / "manifest.json").read_text())
        (d / "manifest.json").write_text(json.dumps({**man, **manifest}))
    if summary:
        f = d / "summary.parquet"
        summary(pd.read_parquet(f)).to_parquet(f)
    return d


#: What a results folder may lack -> what the page and stderr must say.
GAPS = {
    "baseline_not_run": ({"baseline_scheme": "bpm"}, None,
                         r"baseline scheme 'bpm' was not run \(schemes \['ddma', 'tdma'"),
    "n_ok_nan": ({"n_ok": float("nan")}, None, r"records no n_ok \(nan\)"),
    "n_cells_null": ({"n_cells": None}, None, r"records no n_cells \(None\)"),
    "metric_column_missing": (None, lambda s: s.drop(columns=["n_ghost", "ghost_rate"]),
                              r"has no column\(s\) \['n_ghost', 'ghost_rate'\]"),
    "metric_column_all_nan": (None, lambda s: s.assign(range_error_rmse_m=np.nan),
                              r"column\(s\) \['range_error_rmse_m'\] hold no finite value"),
}


@pytest.fixture(scope="module")
def gaps_report(fake_results, tmp_path_factory):
    """One copy of the results lacking every item of `GAPS` at once, reported once (a report
    draws its figures for ~1.5 s CPU): (the page, what the report printed on stderr)."""
    manifest = {k: v for m, _, _ in GAPS.values() if m for k, v in m.items()}
    edits = [e for _, e, _ in GAPS.values() if e]

    def summary(s):
        for e in edits:
            s = e(s)
        return s
    d = _damaged_copy(fake_results, tmp_path_factory.mktemp("gaps"), manifest, summary)
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        assert main(["report", str(d), "--no-maps"]) == 0
    return (d / "report.html").read_text(), err.getvalue()


@pytest.mark.parametrize("kind", list(GAPS))
def test_report_says_what_the_results_lack_in_the_page_and_on_stderr(gaps_report, kind):
    _, _, match = GAPS[kind]
    page, err = gaps_report
    warned = [ln for ln in err.splitlines() if re.search(match, ln)]
    assert len(warned) == 1 and warned[0].startswith("radar-harness report: warning: ")
    assert "Missing from these results" in page
    assert re.search(match, page.replace("&#x27;", "'"))
    assert "nan of" not in page


def test_report_of_a_complete_run_lacks_nothing(report):
    assert "Missing from these results" not in report.read_text()


def test_registering_a_wrong_object_as_a_section_names_the_type():
    """register_report_section looked the name up before the type check: AttributeError."""
    from harness.report.sections import register_report_section
    with pytest.raises(ValueError, match=r"report section must be a ReportSection, got object"):
        register_report_section(object())
