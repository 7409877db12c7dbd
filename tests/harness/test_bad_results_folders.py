"""Bad results folders given to gate, report and sweep: exit code 2 (one line) or a recompute.

The folder is named in every message; nothing is silently read as an empty or partial result.
A damaged cell inside a results folder is recomputed by the next sweep
(`test_sweep_reliability.test_corrupt_table_under_an_ok_cell_is_recomputed`).
"""
from __future__ import annotations

import json
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



def _copy(fake_results, tmp):
    d = tmp / "res"
    shutil.copytree(fake_results, d, ignore=shutil.ignore_patterns("cells", "*.html", "*.md"))
    return d


def _manifest(d, **fields):
    man = json.loads((d / "manifest.json").read_text())
    man.update(fields)
    (d / "manifest.json").write_text(json.dumps(man))


#: Damaged manifests: (fields set, or the file's text) -> the one-line answer.
DAMAGED_MANIFESTS = {
    "cells_string": ({"cells": "abc"}, r"cells='abc' must be a list of records"),
    "cells_numbers": ({"cells": [1, 2]}, r"cells\[0\]=1 must be an object"),
    "cell_without_id": ({"cells": [{"status": "missing"}]},
                        r"cells\[0\]\.cell_id=None must be a string"),
    "git_string": ({"git": "abc"}, r"git='abc' must be an object"),
    "git_commit_number": ({"git": {"commit": 5}}, r"git\.commit=5 must be a string"),
    "baseline_number": ({"baseline_scheme": 5}, r"baseline_scheme=5 must be a string"),
    "n_ok_string": ({"n_ok": "x"}, r"n_ok='x' must be a non-negative integer"),
    "n_cells_negative": ({"n_cells": -1}, r"n_cells=-1 must be a non-negative integer"),
    "schemes_string": ({"schemes": "ddma"}, r"schemes='ddma' must be a list"),
    "tables_list": ({"tables": ["x"]}, r"tables=\['x'\] must be an object"),
    "sweep_string": ({"sweep": "x"}, r"sweep='x' must be an object"),
    "variant_number": ({"sweep": {"variants": [5]}}, r"sweep\.variants\[0\]=5 must be"),
    "nested_200000": ("[" * 200_000 + "]" * 200_000, r"nested deeper than a manifest can be"),
}


@pytest.mark.parametrize("cmd", ["gate", "report"])
@pytest.mark.parametrize("kind", list(DAMAGED_MANIFESTS))
def test_damaged_manifest_exits_2_naming_the_field(tmp_path, fake_results, capsys, cmd, kind):
    d = _copy(fake_results, tmp_path)
    change, match = DAMAGED_MANIFESTS[kind]
    if isinstance(change, str):
        (d / "manifest.json").write_text(change)
    else:
        _manifest(d, **change)
    argv = [cmd, str(d)] + (["--no-maps"] if cmd == "report" else
                            ["--markdown", str(tmp_path / "g.md")])
    assert main(argv) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if "error" in ln]
    assert len(err) == 1 and re.search(r"manifest\.json: damaged manifest \(" + match,
                                       err[0]), err


def _drop(table, column):
    def change(d):
        f = d / f"{table}.parquet"
        pd.read_parquet(f).drop(columns=column).to_parquet(f)
    return change


#: Damaged tables the report reads -> the one-line answer (the file and the column).
DAMAGED_TABLES = {
    "actors_without_detected": (_drop("actors", "detected"),
                                r"actors\.parquet: the actors table lacks column\(s\) "
                                r"\['detected'\]"),
    "detections_without_label": (_drop("detections", "label"),
                                 r"detections\.parquet: .* lacks column\(s\) \['label'\]"),
    "summary_without_variant": (_drop("summary", "variant"),
                                r"summary\.parquet: .* lacks column\(s\) \['variant'\]"),
    "actor_summary_without_class": (_drop("actor_summary", "actor_class"),
                                    r"actor_summary\.parquet: .*\['actor_class'\]"),
    "truth_without_yaw": (_drop("truth", "yaw_radar_deg"), r"truth\.parquet: .*yaw_radar_deg"),
    "detections_missing": (lambda d: (d / "detections.parquet").unlink(),
                           r"detections\.parquet: missing \(manifest\.json lists"),
    "actors_torn": (lambda d: (d / "actors.parquet").write_bytes(b"PAR1 torn"),
                    r"actors\.parquet: not a readable Parquet actors table"),
}


@pytest.mark.parametrize("kind", list(DAMAGED_TABLES))
def test_report_on_a_damaged_table_exits_2_naming_file_and_column(tmp_path, fake_results,
                                                                    capsys, kind):
    d = _copy(fake_results, tmp_path)
    change, match = DAMAGED_TABLES[kind]
    change(d)
    assert main(["report", str(d), "--no-maps"]) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if "error" in ln]
    assert len(err) == 1 and re.search(match, err[0]), err


def test_report_without_a_manifest_reads_absent_tables_as_empty(tmp_path, fake_results):
    """No manifest lists the tables (an older or hand-made folder): absent ones are empty."""
    d = _copy(fake_results, tmp_path)
    for name in ("manifest.json", "detections.parquet", "actors.parquet", "truth.parquet"):
        (d / name).unlink()
    assert main(["report", str(d), "--no-maps"]) == 0


N_KINDS = len(KINDS) + 2 + 5 + 2 * len(DAMAGED_MANIFESTS) + len(DAMAGED_TABLES) + 1
