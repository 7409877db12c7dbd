"""harness.mitigation_report: the recovery-versus-INR curve of every repair method."""
from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from core.errors import BadInput
from harness.report.mitigation import recovery_vs_inr


def _results(tmp_path, frames: pd.DataFrame, methods=("zero", "lowrank")):
    man = {"sweep": {"variants": [{"name": f"m_{m}", "processing": {"intf_mitigation": m}}
                                  for m in methods]}}
    (tmp_path / "manifest.json").write_text(json.dumps(man))
    frames.to_parquet(tmp_path / "frames.parquet")
    return tmp_path


def _frames():
    rows = []
    for m, left in (("zero", 0.5), ("lowrank", 0.1)):  # fraction of the rise left
        for f, inr in enumerate(np.linspace(12.6, 15.4, 8)):
            rows.append({"scenario": "head_on", "variant": f"m_{m}", "seed": 0,
                         "scheme": "ddma", "frame": f, "interference_to_noise_db": inr,
                         "noise_floor_rise_unmitigated_db": 3.0,
                         "noise_floor_rise_db": 3.0 * left})
    rows.append({**rows[0], "frame": 99, "noise_floor_rise_unmitigated_db": 0.2,
                 "noise_floor_rise_db": 0.2})  # nothing to recover: left out
    rows.append({**rows[0], "variant": "other", "frame": 98})  # not a method variant
    return pd.DataFrame(rows)


def test_curve_per_method_binned_by_inr(tmp_path):
    c = recovery_vs_inr(_results(tmp_path, _frames()))
    assert list(dict.fromkeys(c["method"])) == ["zero", "lowrank"]
    assert sorted(set(c["inr_db"])) == [13.0, 14.0, 15.0]
    assert c["n_frames"].sum() == 16
    z = c[c["method"] == "zero"]
    assert z["recovery_fraction"].to_numpy() == pytest.approx(0.5)
    assert c[c["method"] == "lowrank"]["recovery_fraction"].to_numpy() == pytest.approx(0.9)


def test_results_without_method_variants_are_refused(tmp_path):
    with pytest.raises(BadInput, match="no variant sets processing.interference.repair"):
        recovery_vs_inr(_results(tmp_path, _frames(), methods=()))
