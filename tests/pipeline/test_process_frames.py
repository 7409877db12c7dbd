"""`pipeline.process_frames`: several processing settings of one frame in one call give exactly
the point clouds of `process_frame`, and a chain computes the stages they share once."""
import numpy as np
import pandas as pd
import pytest

import pipeline
import radarsim
from core.errors import BadInput
from pipeline import chain as chain_mod
from pipeline.mimo import MIMO_CHAINS
from pipeline.mimo import tdma as slot_chain
from tests.pipeline.chirp_level.helpers import empty, one_interferer
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


def _spy_runs(monkeypatch, name: str) -> list:
    """The settings each `process_variants` call of the chain of `name` receives."""
    chain = MIMO_CHAINS[name]
    runs = []
    real = chain.process_variants

    def spy(cfg, adc, procs):
        runs.append(list(procs))
        return real(cfg, adc, procs)
    monkeypatch.setattr(chain, "process_variants", spy)
    return runs


@pytest.mark.parametrize("name", REGISTRY)
def test_mitigation_with_nothing_to_repair_shares_the_cloud_without_it(name, frame,
                                                                       monkeypatch):
    """A frame in which the mitigation flags nothing (`chirp_level.idle_mitigation`) is processed
    once for the settings with and without it (an interference case's reference): the same
    clouds as `process_frame` gives each, bit for bit, as separate frames."""
    cfg, adc = frame(name)
    on = pipeline.ProcessingConfig()
    strict = on.replace(**{"cfar.pfa": 1e-8})
    procs = [on, on.unmitigated, strict, on.unmitigated]
    runs = _spy_runs(monkeypatch, name)
    got = pipeline.process_frames(cfg, adc, procs)
    assert runs == [[on, strict]]
    for proc, pc in zip(procs, got):
        ref = pipeline.process_frame(cfg, adc, proc)
        pd.testing.assert_frame_equal(pc, ref, check_exact=True)
        assert pc.attrs == ref.attrs
    assert len({id(pc) for pc in got}) == len(got)  # each caller owns its cloud


@pytest.mark.parametrize("name", ["ddma", "tdma"])
def test_a_frame_with_a_burst_is_processed_with_and_without_mitigation(name, make_config,
                                                                       monkeypatch):
    cfg = make_config(name)
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(3), one_interferer())
    on = pipeline.ProcessingConfig()
    runs = _spy_runs(monkeypatch, name)
    got = pipeline.process_frames(cfg, adc, [on, on.unmitigated])
    assert runs == [[on, on.unmitigated]]
    for proc, pc in zip([on, on.unmitigated], got):
        pd.testing.assert_frame_equal(pc, pipeline.process_frame(cfg, adc, proc),
                                      check_exact=True)


def test_a_chain_that_handles_interference_itself_gets_every_setting(frame, monkeypatch):
    """Only a chain that reads the interference settings through the range stage alone
    (`MimoChain.mitigation_in_range_stage`, the built-in ones) shares clouds across them."""
    cfg, adc = frame("ddma")
    chain = MIMO_CHAINS["ddma"]
    monkeypatch.setattr(chain, "mitigation_in_range_stage", False)
    runs = _spy_runs(monkeypatch, "ddma")
    on = pipeline.ProcessingConfig()
    pipeline.process_frames(cfg, adc, [on, on.unmitigated, on])
    assert runs == [[on, on.unmitigated]]


@pytest.mark.parametrize("name", REGISTRY)
def test_every_built_in_chain_reads_interference_through_the_range_stage(name):
    assert MIMO_CHAINS[name].mitigation_in_range_stage


def test_the_statistics_are_read_only_where_settings_could_share(frame, monkeypatch):
    checked = []
    real = chain_mod.idle_mitigation
    monkeypatch.setattr(chain_mod, "idle_mitigation",
                        lambda adc, proc: checked.append(proc) or real(adc, proc))
    cfg, adc = frame("ddma")
    on = pipeline.ProcessingConfig()
    pipeline.process_frames(cfg, adc, [on, on.replace(**{"cfar.pfa": 1e-8}), on])
    assert checked == []
    pipeline.process_frames(cfg, adc, [on, on.unmitigated, on])
    assert checked == [on]
