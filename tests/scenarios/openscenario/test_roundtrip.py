"""Round trip: every catalogue case exported as OpenSCENARIO and imported again drives the same
ground truth (positions within 0.1 m, speeds within 0.05 m/s, every frame and actor), and its
export is valid against the ASAM schema."""
from __future__ import annotations

import numpy as np
import pytest
from lxml import etree

from scenarios import SCENARIOS, run_scenario
from scenarios.openscenario.export import export_run
from scenarios.openscenario.import_ import read_xosc
from scenarios.traffic import RAIL_ID_BASE

POSITION_TOL_M = 0.1
SPEED_TOL_MPS = 0.05


def _renumbered(truth):
    """Truth with road users renumbered 0, 1, ... in id order (the file's entity order);
    guard-rail segments keep their ids."""
    ids = sorted(i for i in truth["actor_id"].unique() if i < RAIL_ID_BASE)
    new = {old: k for k, old in enumerate(ids)}
    out = truth.assign(actor_id=truth["actor_id"].map(lambda i: new.get(i, i)))
    return out.sort_values(["frame", "actor_id"], kind="stable").reset_index(drop=True)


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_export_then_import_gives_the_same_truth(name, tmp_path, osc_schema, catalogue_run):
    first = catalogue_run(name)
    xosc, _ = export_run(first, tmp_path)
    assert osc_schema.validate(etree.parse(str(xosc))), osc_schema.error_log.last_error
    again = run_scenario(read_xosc(xosc), seed=0)
    a, b = _renumbered(first.truth), again.truth
    assert len(a) == len(b) and (a["frame"].to_numpy() == b["frame"].to_numpy()).all()
    assert (a["actor_id"].to_numpy() == b["actor_id"].to_numpy()).all()
    assert (a["actor_class"].to_numpy() == b["actor_class"].to_numpy()).all()
    pos = np.hypot(a["x_m"] - b["x_m"], a["y_m"] - b["y_m"]).to_numpy()
    vel = np.hypot(a["vx_mps"] - b["vx_mps"], a["vy_mps"] - b["vy_mps"]).to_numpy()
    assert pos.max(initial=0.0) < POSITION_TOL_M
    assert vel.max(initial=0.0) < SPEED_TOL_MPS
    ego = np.abs(first.ego["ego_speed_mps"] - again.ego["ego_speed_mps"]).to_numpy()
    assert ego.max() < SPEED_TOL_MPS
    ego_pos = np.hypot(first.ego["ego_x_m"] - again.ego["ego_x_m"],
                       first.ego["ego_y_m"] - again.ego["ego_y_m"]).to_numpy()
    assert ego_pos.max() < POSITION_TOL_M


def test_imported_case_keeps_the_harness_fields(tmp_path, catalogue_run):
    first = catalogue_run("blind_spot_overtaking")
    case = read_xosc(export_run(first, tmp_path)[0])
    orig = first.case
    assert case.mount == orig.mount and case.must_detect == orig.must_detect
    assert case.criteria == orig.criteria and case.duration_s == orig.duration_s
    assert case.guard_rails and case.case_class == orig.case_class
    assert case.ego.speed_mps == orig.ego.speed_mps
    assert [a.speed_mps for a in case.actors] == [a.speed_mps for a in orig.actors]
