"""`pipeline.process_frames`: several processing settings of one frame in one call give exactly
the point clouds of `process_frame`, and a chain computes the stages they share once."""
import numpy as np
import pandas as pd
import pytest

import pipeline
import radarsim
from core.errors import BadInput
from pipeline.mimo import MIMO_CHAINS
from pipeline.mimo import tdma as slot_chain
from tests.pipeline.test_chain import REGISTRY, scene_at_snr

TARGETS = [(40.0, 10.0, 0.0, -12.0, 25.0), (95.0, -25.0, 2.0, 30.0, 20.0),
           (150.0, 40.0, 0.0, 3.0, 18.0)]


def _settings(name: str) -> list:
    """The default settings, the scheme's variants, a CFAR at Pfa 1e-8, the "drop" saturation
    policy and None (the default again)."""
    base = pipeline.ProcessingConfig()
    variants = [base.replace(**o) for o in MIMO_CHAINS[name].variants.values()]
    return [base, *variants, base.replace(**{"cfar.pfa": 1e-8}),
            base.replace(saturation_policy="drop"), None]


@pytest.fixture
def frame(make_config, make_scene):
    def _frame(name: str):
        cfg = make_config(name)
        sc = scene_at_snr(cfg, make_scene, TARGETS)
        return cfg, radarsim.simulate_frame(cfg, sc, np.random.default_rng(7))
    return _frame


@pytest.mark.parametrize("name", REGISTRY)
def test_every_setting_gives_the_cloud_of_process_frame(name, frame):
    cfg, adc = frame(name)
    procs = _settings(name)
    got = pipeline.process_frames(cfg, adc, procs)
    assert len(got) == len(procs)
    for proc, pc in zip(procs, got):
        ref = pipeline.process_frame(cfg, adc, proc)
        pd.testing.assert_frame_equal(pc, ref, check_exact=True)
        assert pc.attrs == ref.attrs
    assert len(got[0]) >= len(TARGETS)  # a real cloud, not two empty ones


def test_tdma_and_its_raw_variant_share_one_detection_stage(frame, monkeypatch):
    """TDMA and tdma_raw differ only after the velocity hypotheses: one slot map for both;
    settings that change the CFAR get their own."""
    calls = []
    real = slot_chain.slot_maps

    def counting(cfg, adc, proc):
        calls.append(proc)
        return real(cfg, adc, proc)
    monkeypatch.setattr(slot_chain, "slot_maps", counting)
    cfg, adc = frame("tdma")
    base = pipeline.ProcessingConfig()
    raw = base.replace(**MIMO_CHAINS["tdma"].variants["tdma_raw"])
    pipeline.process_frames(cfg, adc, [base, raw])
    assert len(calls) == 1
    strict = base.replace(**{"cfar.pfa": 1e-8})
    pipeline.process_frames(cfg, adc, [base, raw, strict])
    assert len(calls) == 3


def test_detection_key_leaves_out_only_the_velocity_settings():
    base = pipeline.ProcessingConfig()
    raw = base.replace(**{"velocity.tdma_disambiguation": False})
    assert slot_chain.detection_key(raw) == slot_chain.detection_key(base)
    for other in ({"cfar.pfa": 1e-8},
                  {"fov.velocity_mps": (-5.0, 5.0)}, {"saturation_policy": "drop"}):
        assert slot_chain.detection_key(base.replace(**other)) != \
            slot_chain.detection_key(base), other


def test_no_settings_no_clouds(frame):
    cfg, adc = frame("ddma")
    assert pipeline.process_frames(cfg, adc, []) == []


def test_a_bad_setting_is_refused_as_by_process_frame(frame):
    cfg, adc = frame("tdma")
    with pytest.raises(BadInput, match="proc must be a pipeline.ProcessingConfig, got dict"):
        pipeline.process_frames(cfg, adc, [pipeline.ProcessingConfig(), {}])


def test_a_bad_frame_is_refused_before_any_chain_runs(make_config):
    cfg = make_config("tdma")
    with pytest.raises(BadInput, match="adc"):
        pipeline.process_frames(cfg, np.zeros((2, 2, 2), np.int16), [None])
