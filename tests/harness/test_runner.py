"""One sweep cell on stand-in parts: tables, seeds, determinism."""
from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest

from core.errors import BadInput
from harness.cell.components import default_components
from harness.cell.run import run_cell
from harness.cell.spec import DEFAULT_SCHEMES, CellSpec, result_schemes
from harness.sweep.streams import SEED_STREAMS, frame_rng, stream_id
from tests.harness.fakes import FAKE, fake_process_frame


def test_cell_tables_and_scheme_rows():
    res = run_cell(CellSpec(scenario="fast", seed=0, duration_s=1.0), FAKE)
    s = res.tables["summary"].set_index("scheme")
    assert list(s.index) == list(DEFAULT_SCHEMES)
    assert (s["n_frames"] == 20).all()
    # 30 m/s exceeds TDMA's 10.2 m/s: raw TDMA is aliased, disambiguated TDMA and DDMA are not.
    assert s.loc["ddma", "velocity_unambiguity_rate"] == 1.0
    assert s.loc["tdma", "velocity_unambiguity_rate"] == 1.0
    # raw TDMA: every car echo aliased; every guard-rail echo (0 m/s) right, counted apart
    assert s.loc["tdma_raw", "velocity_unambiguity_rate"] == 0.0
    assert s.loc["tdma_raw", "infrastructure_velocity_unambiguity_rate"] == 1.0
    # The stand-in chain adds 6 dB to DDMA: the SNR gain sits on the DDMA row only.
    assert s.loc["ddma", "snr_gain_median_db"] == pytest.approx(6.0)
    assert np.isnan(s.loc["tdma", "snr_gain_median_db"])
    # Raw TDMA sees the car only with aliased velocity: no TRUE first detection, and the
    # case's first-detection criterion means the same (TRUE and velocity-correct).
    assert s.loc["ddma", "target_first_detection_range_m"] == pytest.approx(80.0, abs=0.5)
    assert np.isnan(s.loc["tdma_raw", "target_first_detection_range_m"])
    assert list(s["case_pass"]) == [1.0, 1.0, 0.0]
    assert np.isnan(s.loc["tdma_raw", "case_first_detection_range_m"])
    # every numeric summary column is a registered metric
    from metrics import METRICS
    keys = {"scenario", "variant", "seed", "scheme"}
    numeric = [c for c in res.tables["summary"].columns
               if pd.api.types.is_numeric_dtype(res.tables["summary"][c]) and c not in keys]
    assert set(numeric) <= set(METRICS), sorted(set(numeric) - set(METRICS))
    for name in ("detections", "frames", "actors", "truth"):
        t = res.tables[name]
        assert list(t.columns[:3]) == ["scenario", "variant", "seed"], name
    fr = res.tables["frames"]
    assert (fr["n_detections"] == fr[["n_true", "n_velocity_ambiguous", "n_ghost",
                                       "n_clutter"]].sum(axis=1)).all()


def test_velocity_resolution_failures_counted_per_scheme():
    """30 m/s against TDMA's 10.2 m/s: raw TDMA reports every car detection off by 2 Vmax
    (its failure step), the disambiguated schemes none; detections carry the flag."""
    res = run_cell(CellSpec(scenario="fast", seed=0, duration_s=1.0), FAKE)
    s = res.tables["summary"].set_index("scheme")
    assert s.loc["tdma_raw", "n_velocity_resolution_failures"] == 20
    assert s.loc["tdma_raw", "velocity_unambiguity_rate"] == 0.0  # road users only
    assert s.loc["tdma_raw", "n_infrastructure_velocity_right"] == 20  # the rail: right
    assert s.loc["ddma", "n_velocity_resolution_failures"] == 0
    assert s.loc["tdma", "velocity_unambiguity_rate"] == 1.0
    det = res.tables["detections"]
    assert det["velocity_resolution_failure"].dtype == bool
    assert det.groupby("scheme")["velocity_resolution_failure"].sum()["tdma_raw"] == 20


def test_frame_stride():
    res = run_cell(CellSpec(scenario="slow", seed=0, duration_s=1.0, frame_stride=4), FAKE)
    assert sorted(res.tables["frames"]["frame"].unique()) == [0, 4, 8, 12, 16]
    assert sorted(res.tables["truth"]["frame"].unique()) == [0, 4, 8, 12, 16]


def test_same_seed_identical_tables_other_seed_differs():
    spec = CellSpec(scenario="fast", seed=3, duration_s=0.5)
    a, b = run_cell(spec, FAKE), run_cell(spec, FAKE)
    for name in a.tables:
        pd.testing.assert_frame_equal(a.tables[name], b.tables[name])
    c = run_cell(CellSpec(scenario="fast", seed=4, duration_s=0.5), FAKE)
    assert not np.array_equal(a.tables["detections"]["range_m"],
                              c.tables["detections"]["range_m"])


def test_frame_threads_give_the_same_tables():
    spec = CellSpec(scenario="fast", seed=3, duration_s=0.5)
    a = run_cell(spec, FAKE, frame_threads=1)
    for n in (2, 3):
        b = run_cell(spec, FAKE, frame_threads=n)
        for name in a.tables:
            pd.testing.assert_frame_equal(a.tables[name], b.tables[name], check_exact=True)


@pytest.mark.parametrize("n", [0, -1, 2.0, True, None])
def test_frame_threads_must_be_an_integer_of_at_least_one(n):
    with pytest.raises(BadInput, match=r"frame_threads=.* must be an integer >= 1"):
        run_cell(CellSpec(scenario="fast", seed=3, duration_s=0.5), FAKE, frame_threads=n)


def test_independent_streams_per_frame_and_scheme():
    x = [frame_rng(0, f, s).standard_normal() for f in (0, 1) for s in ("rcs", "ddma", "tdma")]
    assert len(set(x)) == 6
    assert frame_rng(0, 1, "ddma").standard_normal() == x[4]


def test_stream_ids_fixed_for_legacy_streams_and_by_name_for_others():
    assert {s: stream_id(s) for s in SEED_STREAMS} == {"rcs": 0, "ddma": 1, "tdma": 2,
                                                        "track": 3}
    ids = {stream_id(n) for n in ("bpm", "ddma_classic", "toy")}
    assert len(ids) == 3 and min(ids) >= 2 ** 16
    assert stream_id("bpm") == stream_id("bpm")


def test_adding_or_removing_a_scheme_keeps_the_other_schemes_numbers():
    """Seed streams are per scheme name: a cell with fewer schemes, in another order, gives the
    same rows for the schemes it shares."""
    full = run_cell(CellSpec(scenario="fast", seed=1, duration_s=0.5), FAKE)
    part = run_cell(CellSpec(scenario="fast", seed=1, duration_s=0.5,
                             schemes=("tdma_raw", "ddma")), FAKE)
    for name in ("detections", "frames", "actors"):
        a, b = full.tables[name], part.tables[name]
        for s in ("ddma", "tdma_raw"):
            pd.testing.assert_frame_equal(a[a.scheme == s].reset_index(drop=True),
                                          b[b.scheme == s].reset_index(drop=True))
    # Without the baseline scheme in the cell there is no SNR gain.
    assert part.tables["summary"]["snr_gain_median_db"].isna().all()


def test_result_schemes_resolve_variants_to_their_mimo():
    rs = {r.name: r for r in result_schemes(["ddma", "tdma", "tdma_raw"])}
    assert rs["tdma_raw"].mimo == "tdma" and rs["tdma_raw"].is_variant
    assert rs["tdma_raw"].processing == {"velocity.tdma_disambiguation": False}
    assert not rs["ddma"].is_variant


@pytest.mark.parametrize("kw,match", [
    ({"scenario": "a", "schemes": ("ddma", "nope")}, r"unknown scheme\(s\) \['nope'\]"),
    ({"scenario": "a", "schemes": ()}, "schemes: the list is empty"),
    ({"scenario": "a", "schemes": ("ddma", "ddma")}, "duplicates"),
    ({"scenario": "a", "baseline_scheme": "nope"}, "baseline_scheme='nope'"),
    ({"scenario": ""}, "scenario"),
    ({"scenario": "a", "seed": -1}, "seed"),
    ({"scenario": "a", "frame_stride": 0}, "frame_stride"),
    ({"scenario": "a", "duration_s": 0.0}, "duration_s"),
])
def test_cell_spec_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        CellSpec(**kw)


def test_cell_id_depends_on_overrides():
    a = CellSpec(scenario="x", radar={"phase_noise_deg_rms": 2.0})
    b = CellSpec(scenario="x", radar={"phase_noise_deg_rms": 5.0})
    assert a.cell_id != b.cell_id
    assert a.cell_id == CellSpec(scenario="x", radar={"phase_noise_deg_rms": 2.0}).cell_id
    assert a.cell_id != CellSpec(scenario="x", radar={"phase_noise_deg_rms": 2.0},
                                 schemes=("ddma", "tdma")).cell_id


def test_random_traffic_runs_at_a_slow_profile_frame_rate():
    # The R79 profile's 250 ms frames (4 Hz) are below the drivers' 10 Hz decisions: the
    # traffic is integrated in substeps instead of being refused.
    from harness.cell import components
    run = components.default_components().run_scenario("dense_highway", 0, 0.5, frame_rate_hz=4.0)
    assert run.ego["frame"].nunique() == 2


def test_the_settings_of_one_adc_frame_reach_process_frames_together():
    """With `Components.process_frames` the cell asks for the clouds of all settings of one ADC
    frame in one call (the chain shares their common stages): TDMA and tdma_raw together, the
    same tables as one `process_frame` call per setting."""
    calls = []

    def batch(cfg, adc, procs):
        calls.append((cfg.mimo, len(procs)))
        return [fake_process_frame(cfg, adc, p) for p in procs]
    spec = CellSpec(scenario="fast", seed=0, duration_s=0.5)
    got = run_cell(spec, dataclasses.replace(FAKE, process_frames=batch)).tables
    ref = run_cell(spec, FAKE).tables
    for name in ref:
        pd.testing.assert_frame_equal(got[name], ref[name], check_exact=True, obj=name)
    assert set(calls) == {("ddma", 1), ("tdma", 2)}


def test_a_replaced_chain_with_the_built_in_batch_chain_is_refused():
    with pytest.raises(ValueError, match="process_frame is replaced but process_frames"):
        dataclasses.replace(default_components(), process_frame=fake_process_frame)
    dataclasses.replace(default_components(), process_frame=fake_process_frame,
                        process_frames=None)
