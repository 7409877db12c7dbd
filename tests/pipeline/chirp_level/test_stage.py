"""The chirp-level range stage as a whole: switches, the demo defaults, profile commands, a
frame through the whole chain ([TI-DAZ] section 2)."""
from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

import pipeline
import radarsim
from pipeline import chirp_level as cl
from pipeline.kernels import range_fft, window

from .helpers import OFF, empty, one_interferer


def test_switches_off_is_the_plain_range_fft(cfg):
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(0))
    rf = cl.range_stage(cfg, adc, pipeline.ProcessingConfig().replace(**OFF))
    assert np.array_equal(rf, range_fft(adc, window("hann", cfg.n_samples)))


@pytest.mark.parametrize("kw, match", [
    (dict(dc_removal=1), "dc_removal"),
    (dict(interference_mitigation="yes"), "interference_mitigation"),
    (dict(compression=None), "compression"),
    (dict(intf_mag_snr_db=0), "intf_mag_snr_db"),
    (dict(intf_magdiff_snr_db=100.0), "intf_magdiff_snr_db"),
    (dict(intf_threshold_mode="both"), "intf_threshold_mode"),
    (dict(intf_hysteresis_samples=-1), "intf_hysteresis_samples"),
    (dict(compression_ratio=1.0), "compression_ratio"),
    (dict(compression_range_bins_per_block=6), "compression_range_bins_per_block"),
    ({"interference.weak_burst_snr_db": 0.0}, r"weak_burst_snr_db=0\.0 must be in \(0, 60\]"),
    ({"interference.weak_burst_snr_db": float("nan")}, "weak_burst_snr_db=nan"),
    ({"interference.weak_burst_snr_db": "11"}, "weak_burst_snr_db='11'"),
    ({"interference.weak_burst_window_samples": 2}, "weak_burst_window_samples=2"),
    ({"interference.weak_burst_window_samples": 256}, "weak_burst_window_samples=256"),
    ({"interference.weak_burst_window_samples": 30.0}, "weak_burst_window_samples=30.0"),
    ({"interference.weak_burst_window_samples": 30}, "weak_burst_window_samples=30 must be a "
                                                     "multiple of 4"),
])
def test_processing_config_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        pipeline.ProcessingConfig().replace(**kw)


def test_weak_burst_detection_on_by_default_and_switchable():
    intf = pipeline.ProcessingConfig().interference
    assert (intf.weak_burst_snr_db, intf.weak_burst_window_samples) == (11.0, 32)
    off = pipeline.ProcessingConfig().replace(**{"interference.weak_burst_snr_db": None})
    assert off.interference.weak_burst_snr_db is None


def test_demo_defaults_and_sweep_key():
    p = pipeline.ProcessingConfig()
    assert (p.range.dc_removal, p.interference.enabled, p.compression.enabled) == \
        (True, True, True)
    intf = p.interference
    assert (intf.mag_snr_db, intf.magdiff_snr_db, intf.hysteresis_samples) == (15.0, 18.0, 3)
    assert p.replace(interference_mitigation=False).interference.enabled is False


def test_cfg_intf_and_compression_commands_reach_the_processing_config():
    from harness.cli.cmd_ti import processing_from_profile
    from radarsim.ti import parse_ti_cfg, r79_cfg_text
    text = r79_cfg_text().replace("intfMitigCfg -1 15 18", "intfMitigCfg -1 12 20") \
        .replace("compressionCfg -1 1 0 0.5 8", "compressionCfg -1 0 0 0.5 8")
    proc = processing_from_profile(parse_ti_cfg(text))
    assert (proc.interference.mag_snr_db, proc.interference.magdiff_snr_db,
            proc.compression.enabled) == (12.0, 20.0, False)
    with pytest.raises(ValueError, match="BFP"):
        parse_ti_cfg(r79_cfg_text().replace("compressionCfg -1 1 0 0.5 8",
                                            "compressionCfg -1 1 1 0.5 8"))


def test_process_frame_still_finds_a_target_with_the_demo_chain(cfg):
    sc = radarsim.Scatterers(position_m=[[60.0, 10.0, 0.0]], velocity_mps=[[-12.0, 0, 0]],
                             rcs_m2=[10.0])
    adc = radarsim.simulate_frame(cfg.replace(adc_dc_offset_lsb=300.0), sc,
                                  np.random.default_rng(9))
    pc = pipeline.process_frame(cfg, adc, pipeline.ProcessingConfig())
    near = pc[np.abs(pc["range_m"] - math.hypot(60, 10)) < 2]
    assert len(near) >= 1


def test_shared_range_stage_computes_each_frame_and_setting_once(cfg, monkeypatch):
    """Inside the scope the chains and the noise-floor metric read one read-only cube per frame
    and chirp-level setting (a setting that only the detector reads shares it; one the range
    stage reads does not); the numbers equal the unshared ones; outside, nothing is kept."""
    from pipeline.chirp_level import stage
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(1))
    base = pipeline.ProcessingConfig()
    want = cl.range_stage(cfg, adc, base)
    want_floor = cl.noise_floor_rise(cfg, adc, base)
    want_pc = pipeline.process_frame(cfg, adc, base)
    calls = []
    real = stage._range_stage
    monkeypatch.setattr(stage, "_range_stage", lambda *a: calls.append(1) or real(*a))
    with cl.shared_range_stage():
        floor = cl.noise_floor_rise(cfg, adc, base)
        pc = pipeline.process_frame(cfg, adc, base.replace(tdma_disambiguation=False))
        rf = cl.range_stage(cfg, adc, base)
        assert len(calls) == 1
        assert not rf.flags.writeable
        other = cl.range_stage(cfg, adc, base.replace(intf_magdiff_snr_db=20.0))
        assert len(calls) == 2 and other is not rf
        copy = cl.range_stage(cfg, adc.copy(), base)  # another frame object
        assert len(calls) == 3
    assert rf.tobytes() == want.tobytes() and copy.tobytes() == want.tobytes()
    assert floor == want_floor
    pd.testing.assert_frame_equal(pc, want_pc)
    cl.range_stage(cfg, adc, base)
    assert len(calls) == 4


@pytest.mark.parametrize("first", ["range_stage", "process_frame"])
@pytest.mark.parametrize("burst", [False, True])
def test_a_cube_its_mitigation_left_alone_is_also_the_unmitigated_cube(cfg, monkeypatch, first,
                                                                        burst):
    """Inside the scope, the cube of a frame in which the mitigation flags nothing is also kept
    as the cube of the same settings with mitigation off (`idle_mitigation`), whichever path
    made it: the mitigation reference reads it without a range stage of its own and gets the
    bits its own would have. A frame with a burst gets its own."""
    from pipeline.chirp_level import stage
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(2),
                                  one_interferer() if burst else None)
    on = pipeline.ProcessingConfig()
    off = on.unmitigated
    assert cl.idle_mitigation(adc, on) is not burst
    assert not cl.idle_mitigation(adc, off)  # no mitigation: nothing to leave alone
    want = cl.range_stage(cfg, adc, off)
    calls = []
    real = stage._range_stage
    monkeypatch.setattr(stage, "_range_stage", lambda *a: calls.append(a[2]) or real(*a))
    with cl.shared_range_stage():
        if first == "range_stage":
            cl.range_stage(cfg, adc, on)
        else:  # the windowed, blockwise path
            pipeline.process_frame(cfg, adc, on)
        got = cl.range_stage(cfg, adc, off)
    made_by_first = [on] if first == "range_stage" else []
    assert calls == (made_by_first + [off] if burst else made_by_first)
    assert got.tobytes() == want.tobytes()


@pytest.mark.parametrize("kw", [{}, dict(compression=False), dict(dc_removal=False),
                                dict(compression_range_bins_per_block=4, compression_ratio=0.4),
                                OFF])
def test_windowed_range_stage_is_the_range_stage_times_the_window_bit_for_bit(cfg, kw):
    """The blockwise stage (window, rFFT, DC correction, EGE and the slow-time window per block
    of chirps) gives the range stage's cube times the window, bit for bit: on a frame with a
    strong target (EGE requantises), with an interferer (flagged chirps: the whole-frame path),
    in one part and in two, and inside `shared_range_stage` (which then keeps the cube)."""
    from pipeline import threads
    sc = radarsim.Scatterers(position_m=[[8.0, 1.0, 0.0]], velocity_mps=[[-3.0, 0, 0]],
                             rcs_m2=[100.0])
    proc = pipeline.ProcessingConfig().replace(**kw)
    w = np.hanning(cfg.n_chirps).astype(np.float32)
    for itf in (None, one_interferer()):
        adc = radarsim.simulate_frame(cfg.replace(adc_dc_offset_lsb=200.0), sc,
                                      np.random.default_rng(2), itf)
        want = (cl.range_stage(cfg, adc, proc) * w[:, None, None]).tobytes()
        assert cl.windowed_range_stage(cfg, adc, proc, w).tobytes() == want
        n_parts = threads.N_PARTS
        threads.N_PARTS = 1
        try:
            assert cl.windowed_range_stage(cfg, adc, proc, w).tobytes() == want
        finally:
            threads.N_PARTS = n_parts
        with cl.shared_range_stage():
            assert cl.windowed_range_stage(cfg, adc, proc, w).tobytes() == want
            kept = cl.range_stage(cfg, adc, proc)
            assert not kept.flags.writeable
            assert (kept * w[:, None, None]).tobytes() == want


def test_inline_dirty_range_stage_hands_nothing_to_the_helper(cfg, monkeypatch):
    """Inside `threads.inline` (a sweep cell's frames) the range stage of a frame with a
    repaired burst runs every step on the calling thread, the basis and its neighbours
    included: no part goes to the helper thread."""
    from pipeline import threads

    def no_helper():
        raise AssertionError("a part went to the helper thread")
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(8), one_interferer())
    proc = pipeline.ProcessingConfig()
    w = np.hanning(cfg.n_chirps).astype(np.float32)
    want = cl.windowed_range_stage(cfg, adc, proc, w)
    monkeypatch.setattr(threads, "_pool", no_helper)
    with threads.inline():
        assert cl.windowed_range_stage(cfg, adc, proc, w).tobytes() == want.tobytes()


def test_dirty_range_stage_finishes_alone_while_the_helper_is_busy(cfg, monkeypatch):
    """In parts, the repair's steps and the blocks are one queue whose items wait only for
    items taken before them: with the helper thread busy elsewhere the caller takes every
    item itself, in order, and finishes (no wait for an item nobody took), same cube."""
    import threading

    from pipeline import threads
    monkeypatch.setattr(threads, "N_PARTS", 2)
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(8), one_interferer())
    proc = pipeline.ProcessingConfig()
    w = np.hanning(cfg.n_chirps).astype(np.float32)
    with threads.inline():
        want = cl.windowed_range_stage(cfg, adc, proc, w)
    release = threading.Event()
    blocker = threads._pool().submit(release.wait, 30)  # the helper is busy elsewhere
    try:
        got = []
        worker = threading.Thread(target=lambda: got.append(
            cl.windowed_range_stage(cfg, adc, proc, w)), daemon=True)
        worker.start()
        worker.join(20)
        assert not worker.is_alive(), "the stage waits for an item nobody took"
    finally:
        release.set()
        blocker.result()
    assert got[0].tobytes() == want.tobytes()
