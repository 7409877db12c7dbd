"""ADC saturation monitor (pipeline.saturation): per-chirp, per-Rx counts, flag or drop.

A frame of full-scale codes became 3 500 detections with SNRs up to 169 dB and passed
as a normal frame. Now the chain reports saturation per chirp and Rx (as the chip's CQ Rx
saturation monitor does) and flags (default) or drops the detections of a saturated frame.
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline.saturation import SATURATION_POLICIES, apply_policy, monitor


@pytest.fixture
def cfg():
    return radarsim.presets.r79("ddma")


def _zeros(cfg):
    return np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), np.int16)


def test_counts_per_chirp_and_rx_are_exact(cfg):
    adc = _zeros(cfg)
    adc[5, 2, :10] = 32767
    adc[5, 2, 20] = -32768
    adc[700, 0, -3:] = -32768
    adc[9, 1, 0] = 32766  # one code below the rail: not saturated
    rep = monitor(adc)
    assert rep.counts.shape == (cfg.n_chirps, cfg.n_rx)
    assert rep.counts[5, 2] == 11 and rep.counts[700, 0] == 3 and rep.counts[9, 1] == 0
    assert (rep.n_saturated_chirp_rx, rep.n_saturated_samples, rep.saturated) == (2, 14, True)


def test_clean_frame_reports_nothing(cfg, make_scene, rng):
    adc = radarsim.simulate_frame(cfg, make_scene([(60.0, 10.0, 0.0, -5.0, 10.0)]), rng)
    pc = pipeline.process_frame(cfg, adc)
    assert len(pc) and not pc["saturated"].any()
    assert pc.attrs["saturation"] == {"saturated": False, "n_saturated_chirp_rx": 0,
                                      "n_saturated_samples": 0,
                                      "n_chirp_rx": cfg.n_chirps * cfg.n_rx}


@pytest.mark.parametrize("mimo", ["ddma", "tdma"])
def test_full_scale_frame_is_flagged_not_passed_as_normal(mimo):
    cfg = radarsim.presets.r79(mimo)
    adc = np.full((cfg.n_chirps, cfg.n_rx, cfg.n_samples), 32767, np.int16)
    pc = pipeline.process_frame(cfg, adc)
    assert pc["saturated"].all()
    assert pc.attrs["saturation"]["n_saturated_chirp_rx"] == cfg.n_chirps * cfg.n_rx
    dropped = pipeline.process_frame(cfg, adc, pipeline.ProcessingConfig(saturation_policy="drop"))
    assert dropped.empty and list(dropped.columns) == pipeline.POINT_CLOUD_COLUMNS
    assert dropped.attrs["saturation"]["saturated"]


def test_a_flat_truck_back_at_two_metres_clips_and_the_chain_flags_it(cfg, make_scene, rng):
    """The front end clips a strong near echo (40 dBsm at 2 m: 19 % of the samples) at the
    int16 rails; the chain sees it."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", radarsim.ADCSaturationWarning)
        adc = radarsim.simulate_frame(cfg, make_scene([(2.0, 0.0, 0.0, -1.0, 1e4)]), rng)
    pc = pipeline.process_frame(cfg, adc)
    assert pc.attrs["saturation"]["saturated"] and pc["saturated"].all()


def test_policy_registry_and_bad_policy():
    assert set(SATURATION_POLICIES) == {"flag", "drop"}
    rep = monitor(np.zeros((2, 1, 4), np.int16))
    with pytest.raises(ValueError, match=r"saturation_policy='keep' is not one of"):
        apply_policy(pipeline.stages.empty_cloud(), rep, "keep")


def test_sweep_frame_table_counts_saturated_frames(tmp_path):
    """The runner carries the per-frame count into frames.parquet and the summary."""
    from harness.cell.run import run_cell
    from harness.cell.spec import CellSpec
    from tests.harness.fakes import FAKE
    res = run_cell(CellSpec(scenario="fast", duration_s=0.2), FAKE)
    assert (res.tables["frames"]["n_saturated_chirp_rx"] == 0).all()
    assert (res.tables["summary"]["n_saturated_frames"] == 0).all()


@pytest.mark.parametrize("policy", sorted(SATURATION_POLICIES))
@pytest.mark.parametrize("saturated", [False, True])
def test_apply_policy_on_an_owned_frame_gives_the_frame_of_a_copy(policy, saturated):
    """``owned=True`` returns the frame the default returns (values, dtypes, columns, attrs);
    `points` itself only where nothing but attrs changes (no saturation, an all-False bool
    column), else a new frame as before."""
    import pandas as pd

    import pipeline.saturation
    rep = monitor(np.full((2, 1, 4), 32767 if saturated else 0, np.int16))
    g = np.random.default_rng(2)

    def clouds():
        yield pd.DataFrame({"range_m": g.random(4), "saturated": np.zeros(4, bool)}), True
        yield pd.DataFrame({"range_m": g.random(4), "saturated": np.eye(4, dtype=bool)[1]}), False
        yield pd.DataFrame({"range_m": g.random(4), "saturated": np.zeros(4)}), False  # float
        yield pd.DataFrame({"range_m": g.random(4)}), False
        yield pipeline.stages.empty_cloud(), False

    for points, in_place in clouds():
        want = apply_policy(points.copy(), rep, policy)
        got = apply_policy(points, rep, policy, owned=True)
        assert (got is points) == (in_place and not saturated)
        assert list(got.columns) == list(want.columns) and got.equals(want)
        assert list(got.dtypes) == list(want.dtypes) and got.attrs == want.attrs


@pytest.mark.parametrize("policy", sorted(SATURATION_POLICIES))
@pytest.mark.parametrize("saturated", [False, True])
def test_apply_policy_is_assign_of_the_flag_column(policy, saturated):
    """`apply_policy` returns what ``points.assign(saturated=...)`` (after the policy's drop)
    returns, for a cloud with the column (where it stays in place), one without it (appended)
    and the empty cloud, and leaves its input as it was."""
    import pandas as pd
    rep = monitor(np.full((2, 1, 4), 32767 if saturated else 0, np.int16))
    g = np.random.default_rng(1)
    cloud = pd.DataFrame({"range_m": g.random(5), "saturated": np.ones(5, bool),
                          "azimuth_bin": np.arange(5)})
    for points in (cloud, cloud.drop(columns="saturated"), pipeline.stages.empty_cloud()):
        before = points.copy()
        got = apply_policy(points, rep, policy)
        base = points.iloc[:0] if saturated and SATURATION_POLICIES[policy].drops_frame else points
        want = base.assign(saturated=np.full(len(base), saturated, dtype=bool))
        assert got is not points and points.equals(before) and "saturation" not in points.attrs
        assert list(got.columns) == list(want.columns) and got.equals(want)
        assert list(got.dtypes) == list(want.dtypes)
        assert got.attrs["saturation"] == rep.to_dict()
