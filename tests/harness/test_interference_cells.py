"""Interference in sweep cells: the scene section, the summary and frame columns."""
from __future__ import annotations

import math

import pytest

from harness.cell.run import run_cell
from harness.cell.spec import CellSpec, check_scene
from harness.sweep.file import load_sweep


@pytest.mark.parametrize("scene, match", [
    ({"equiped_share": 0.5}, "unknown scene field"),
    ({"equipped_share": 1.5}, r"equipped_share=1.5 must be in \[0, 1\]"),
    ({"equipped_share": True}, "equipped_share=True"),
    ([0.5], "must be a table"),
])
def test_scene_validation(scene, match):
    with pytest.raises(ValueError, match=match):
        check_scene(scene)
    if isinstance(scene, dict):
        with pytest.raises(ValueError, match=match):
            CellSpec(scenario="a", scene=scene)


def test_scene_enters_the_cell_id_only_when_used():
    assert CellSpec(scenario="x").cell_id == CellSpec(scenario="x", scene={}).cell_id
    assert CellSpec(scenario="x").cell_id != \
        CellSpec(scenario="x", scene={"equipped_share": 0.5}).cell_id


def test_shipped_interference_sweep():
    spec = load_sweep("harness/sweeps/interference.toml")
    shares = {c.scene["equipped_share"] for c in spec.cells()}
    mitig = {c.processing["interference_mitigation"] for c in spec.cells()}
    assert shares == {0.0, 0.25, 0.5, 1.0} and mitig == {True, False}
    assert all("interfer" in c.scenario for c in spec.cells())


def test_interference_case_summary_columns():
    """A real (short) run of the same-slope case: the contract columns exist, the INR is the
    in-burst ratio of a radar 20 m ahead (tens of dB), the floor rise is per scheme."""
    res = run_cell(CellSpec(scenario="interference_same_slope_ghosts", duration_s=0.1,
                            frame_stride=10, schemes=("ddma", "tdma")))
    s = res.tables["summary"].set_index("scheme")
    for col in ("noise_floor_rise_db", "noise_floor_rise_range_db",
                "interference_to_noise_db"):
        assert col in s.columns and s[col].notna().all()
    assert 10 < s.loc["ddma", "interference_to_noise_db"] < 40
    f = res.tables["frames"]
    assert {"interference_to_noise_db", "noise_floor_rise_db"} <= set(f.columns)
    off = run_cell(CellSpec(scenario="interference_same_slope_ghosts", duration_s=0.1,
                            frame_stride=10, schemes=("ddma",),
                            processing={"interference_mitigation": False}))
    assert math.isfinite(off.tables["summary"]["noise_floor_rise_db"].iloc[0])


def test_report_interference_section():
    import pandas as pd

    from harness.report.interference import html_section as interference_section
    summary = pd.DataFrame({
        "scenario": ["interference_x"] * 4, "variant": ["a", "a", "b", "b"],
        "seed": 0, "scheme": ["ddma", "tdma"] * 2, "noise_floor_rise_db": [0.1, 0.1, 5.0, 4.8],
        "noise_floor_rise_range_db": [0.3, 0.3, 1.0, 1.0],
        "interference_to_noise_db": [float("nan")] * 2 + [17.0, 17.0], "ghost_rate": 0.01,
        "n_detections": 10})
    actors = pd.DataFrame({"scenario": "interference_x", "variant": ["a", "b"] * 10,
                           "seed": 0, "scheme": "ddma", "actor_id": 0, "actor_class": "car",
                           "frame": range(20), "range_m": [50.0 + i for i in range(20)],
                           "visible": True, "detected": [True, False] * 10})
    html = interference_section(summary, actors)
    assert "Interference: noise-floor rise" in html and html.count("<img") == 2
    assert interference_section(summary.drop(columns="interference_to_noise_db"), actors) == ""


def test_noise_floor_is_shared_only_by_equal_chirp_level_settings():
    """Schemes of one ADC frame share a measured floor when every setting the floor reads
    (`chirp_level.noise_floor_key`) is equal: TDMA and its raw variant do, a second TDMA
    chain with another compression ratio does not."""
    import dataclasses

    import pipeline
    from harness.cell import components
    from harness.cell import run as cell
    from harness.cell import spec as cellspec
    calls = []
    comps = dataclasses.replace(components.default_components(),
                                noise_floor=lambda cfg, adc, p: calls.append(p) or (0.0, 0.0))
    base = pipeline.ProcessingConfig()
    schemes = [cellspec.ResultScheme("tdma", "tdma", {}),
               cellspec.ResultScheme("tdma_raw", "tdma",
                                     {"velocity.tdma_disambiguation": False}),
               cellspec.ResultScheme("tdma_c", "tdma", {"compression.ratio": 0.4})]
    procs = {"tdma": base, "tdma_raw": base.replace(**{"velocity.tdma_disambiguation": False}),
             "tdma_c": base.replace(**{"compression.ratio": 0.4})}
    rows = cell._noise_floors(comps, {"tdma": None}, {"tdma": None}, procs, schemes, 0, 0.0)
    assert [r["scheme"] for r in rows] == ["tdma", "tdma_raw", "tdma_c"]
    assert [p.compression.ratio for p in calls] == [0.5, 0.4]
