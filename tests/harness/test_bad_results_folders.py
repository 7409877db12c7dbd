"""Bad results folders given to gate, report and sweep: exit code 2 (one line) or a recompute.

The folder is named in every message; nothing is silently read as an empty or partial result.
A damaged cell inside a results folder is recomputed by the next sweep
(`test_sweep_reliability.test_corrupt_table_under_an_ok_cell_is_recomputed`).
"""
from __future__ import annotations

import re
import shutil

import pandas as pd
import pytest

from harness.cli import main
from harness.sweep import spec as sweepspec


def _folder(tmp, fake_results, kind):
    d = tmp / kind
    if kind == "missing":
        return d, r"no results summary at .*missing"
    if kind == "file":
        d.write_text("not a folder")
        return d, r"file: not a readable Parquet summary table"
    d.mkdir()
    if kind == "empty_folder":
        return d, r"no results summary at .*empty_folder/summary\.parquet"
    if kind == "corrupt_summary":
        (d / "summary.parquet").write_bytes(b"PAR1 torn")
        return d, r"summary\.parquet: not a readable Parquet summary table"
    if kind == "summary_without_ids":
        pd.DataFrame({"ghost_rate": [0.1]}).to_parquet(d / "summary.parquet")
        return d, r"summary lacks column\(s\) \['scenario', 'scheme'\]"
    if kind == "malformed_manifest":
        shutil.copy(fake_results / "summary.parquet", d / "summary.parquet")
        (d / "manifest.json").write_text("{ torn")
        return d, r"manifest\.json: damaged manifest"
    raise AssertionError(kind)


KINDS = ["missing", "file", "empty_folder", "corrupt_summary", "summary_without_ids",
         "malformed_manifest"]


@pytest.mark.parametrize("kind", KINDS)
def test_gate_on_a_bad_results_folder_exits_2(tmp_path, fake_results, capsys, kind):
    d, match = _folder(tmp_path, fake_results, kind)
    assert main(["gate", str(d), "--markdown", str(tmp_path / "g.md")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and re.search(match, err[0]), err


@pytest.mark.parametrize("kind", ["missing", "file"])
def test_report_on_a_bad_results_folder_exits_2(tmp_path, fake_results, capsys, kind):
    d, _ = _folder(tmp_path, fake_results, kind)
    assert main(["report", str(d), "--no-maps"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not a results directory" in err[0]


def test_default_out_stays_under_results(tmp_path, monkeypatch):
    """The run id (sweep name + hash) is a single folder name under results/."""
    spec = sweepspec.SweepSpec(name="ok.name-1", scenarios=("a",))
    assert "/" not in spec.run_id and not spec.run_id.startswith(".")
    for bad in ("../../x", "/abs", ".hidden", "a/b", ""):
        with pytest.raises(ValueError, match=r"name=.* must be 1-100 letters"):
            sweepspec.SweepSpec(name=bad, scenarios=("a",))


N_KINDS = len(KINDS) + 2 + 5
