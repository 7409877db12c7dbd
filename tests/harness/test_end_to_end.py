"""The real parts wired together: `radar-harness run`, `sweep`, `gate` and `report` on tiny
cases (a few frames), checking the contract between scenarios, radarsim, pipeline and metrics.
The sweep is the one the determinism tests compare (`real_pool_sweep`, tests/harness/conftest.py),
run once per test process (an xdist worker that runs neither user runs none)."""
from __future__ import annotations

import json
import shutil

import pandas as pd

from harness.cli import main


def test_run_prints_summary_and_writes_tables(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["run", "r79_motorcycle_rear", "--duration-s", "0.3", "--frame-stride", "3",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "r79_motorcycle_rear" in text and "tdma_raw" in text
    s = pd.read_parquet(out / "summary.parquet").set_index("scheme")
    assert list(s.index) == ["ddma", "tdma", "tdma_raw"]
    assert (s["n_frames"] == 2).all()
    d = pd.read_parquet(out / "detections.parquet")
    assert {"label", "actor_id", "range_error_m", "snr_db", "x_m"} <= set(d.columns)
    # The motorcycle starts 120 m behind: DDMA sees it (TRUE) in the first frames already.
    assert (d[(d["scheme"] == "ddma")]["actor_class"] == "motorcycle").any()


def test_unknown_case_is_bad_input(capsys):
    assert main(["run", "no_such_case"]) == 2
    assert "unknown case" in capsys.readouterr().err


def test_sweep_gate_report_real_parts(tmp_path, real_pool_sweep):
    """`sweep` (the shared real-parts pool sweep: the real CLI, `--workers 2`, frame stride 2),
    then `gate` and `report` on a copy of its folder (the shared one stays read-only)."""
    out = tmp_path / "sweep"
    shutil.copytree(real_pool_sweep, out)
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["n_ok"] == 2
    s = pd.read_parquet(out / "summary.parquet")
    assert len(s) == 6 and (s["error"] == "").all()
    assert (s["n_frames"] == 2).all()  # 0.2 s at stride 2: frames 0 and 2
    (tmp_path / "g.toml").write_text(
        "[[gate]]\nname='ok'\nmetric='n_frames'\nmin=1\n")
    assert main(["gate", str(out), "--thresholds", str(tmp_path / "g.toml")]) == 0
    assert main(["report", str(out)]) == 0
    page = (out / "report.html").read_text()
    assert page.count("Range-Doppler and Doppler-azimuth maps") == 2
    assert "maps not available" not in page
