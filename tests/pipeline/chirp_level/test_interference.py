"""Interference statistics, flags and zeroing against analytic references (TI SWRA725)."""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline import chirp_level as cl
from radarsim import interference as itf_mod

from .helpers import empty, one_interferer


@pytest.mark.parametrize("f", [0.1, 0.25, 0.5])
def test_zeroing_a_fraction_costs_coherent_power_and_snr(f):
    """Zeroing f of the samples: coherent tone power 20 log10(1 - f), noise power
    10 log10(1 - f), so SNR 10 log10(1 - f) (rectangular window, bin-centred tone)."""
    n, k0 = 384, 40
    rng = np.random.default_rng(7)
    t = np.arange(n)
    tone = np.cos(2 * np.pi * k0 * t / n).astype(np.float32)
    noise = rng.standard_normal((4000, n)).astype(np.float32)
    flags = np.zeros((1, n), dtype=bool)
    flags[0, 100:100 + int(round(f * n))] = True
    kept = 1 - flags.mean()
    s0 = np.abs(np.fft.rfft(tone)[k0]) ** 2
    s1 = np.abs(np.fft.rfft(cl.zero_flagged(tone[None].copy(), flags, hysteresis=0))[0, k0]) ** 2
    n0 = np.mean(np.abs(np.fft.rfft(noise, axis=-1)[:, 1:-1]) ** 2)
    n1 = np.mean(np.abs(np.fft.rfft(cl.zero_flagged(noise.copy(), np.broadcast_to(
        flags, noise.shape), hysteresis=0), axis=-1)[:, 1:-1]) ** 2)
    assert 10 * np.log10(s1 / s0) == pytest.approx(20 * np.log10(kept), abs=0.05)
    assert 10 * np.log10(n1 / n0) == pytest.approx(10 * np.log10(kept), abs=0.1)
    snr_loss = 10 * np.log10((s1 / n1) / (s0 / n0))
    assert snr_loss == pytest.approx(10 * np.log10(kept), abs=0.1)


def test_hysteresis_widens_each_flagged_run():
    flags = np.zeros((1, 20), dtype=bool)
    flags[0, [5, 12]] = True
    x = cl.zero_flagged(np.ones((1, 20), np.float32), flags, hysteresis=2)
    assert np.flatnonzero(x[0] == 0).tolist() == [3, 4, 5, 6, 7, 10, 11, 12, 13, 14]


@pytest.mark.parametrize("hysteresis", [0, 1, 3, 50])
def test_hysteresis_widens_every_flagged_run(hysteresis):
    """Sample i is zeroed iff a flag of its own chirp lies in [i - h, i + h], checked sample by
    sample (runs at both ends of a chirp, and a hysteresis longer than the chirp)."""
    mask = np.random.default_rng(4).random((6, 40)) < 0.06
    mask[0, 0] = mask[1, -1] = True
    want = np.array([[mask[r, max(i - hysteresis, 0): i + hysteresis + 1].any()
                      for i in range(40)] for r in range(6)])
    x = cl.zero_flagged(np.ones((6, 40), np.float32), mask, hysteresis)
    np.testing.assert_array_equal(x == 0, want)


@pytest.mark.parametrize("mode", sorted(pipeline.config.INTF_THRESHOLD_MODES))
def test_threshold_modes_flag_a_glitch_and_not_noise(mode):
    rng = np.random.default_rng(4)
    x = (rng.standard_normal((50, 4, 384)) * 7).astype(np.float32)
    assert not cl.interference_flags(x, None, 15, 18, mode).any()
    x[3, 1, 200:210] += 400 * np.cos(np.pi * 0.9 * np.arange(10))
    assert cl.interference_flags(x, None, 15, 18, mode)[3, 1, 200:210].any()


@pytest.mark.parametrize("slope, recovers", [(50e12, True), (15e12, False)],
                         ids=["short-bursts", "long-bursts"])
def test_mitigation_recovers_short_bursts_not_long_ones(cfg, slope, recovers):
    """The demo's statistics come from the chirp itself (AbsDiffThreshold = 18 dB over the mean
    |dx|): a short burst (|dS| = 41 MHz/us, 0.8 us) stands out and is zeroed; a long one
    (|dS| = 6 MHz/us, 5.5 us, 40 % of the chirp) raises its own threshold and stays."""
    itf = one_interferer(slope=slope, r=15.0, power_dbm=15.0)
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(6), itf)
    off = cl.noise_floor_rise(cfg, adc, pipeline.ProcessingConfig().replace(
        interference_mitigation=False, compression=False)).doppler_db
    on = cl.noise_floor_rise(cfg, adc, pipeline.ProcessingConfig().replace(
        compression=False)).doppler_db
    assert off > 10
    if recovers:
        assert on < 1.0
    else:
        assert on > off - 1.0


@pytest.mark.parametrize("adc_mode", ["real", "complex1x"])
def test_mitigation_works_on_every_adc_mode(make_x18, adc_mode):
    """xWR18xx at 10 Msps, real and I/Q: a strong interferer crossing mid-window (|dS| = 25
    MHz/us, INR 33 dB) raises the Doppler floor by more than 15 dB; the magnitude-difference
    statistics (|dx| of the I/Q samples for a complex ADC) flag its bursts and zeroing brings
    the floor back within 1 dB of thermal."""
    cfg = make_x18(adc_mode)
    ds, r = 25e12, 15.0
    si = cfg.slope_hz_per_s - ds
    itf = itf_mod.Interferers(
        position_m=[[r, 0.0, 0.0]], radial_velocity_mps=[0.0], tx_gain_dbi=[10.0],
        start_freq_hz=[cfg.start_freq_hz + 11.4e-6 * ds + si * (0.7e-6 + r / 299792458.0)],
        slope_hz_per_s=[si], chirp_period_s=[31e-6], ramp_time_s=[25e-6],
        chirp_offset_s=[0.7e-6], tx_power_dbm=[15.0])
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(6), itf)
    off = cl.noise_floor_rise(cfg, adc, pipeline.ProcessingConfig().replace(
        interference_mitigation=False, compression=False)).doppler_db
    on = cl.noise_floor_rise(cfg, adc, pipeline.ProcessingConfig().replace(
        compression=False, intf_mitigation="zero")).doppler_db
    assert off > 15
    assert abs(on) < 1.0


def test_windowed_block_is_the_windowed_samples_with_the_repaired_rows_in_place():
    """`RepairedRows.windowed_block`: every row of the block float32 x window (numpy), the
    repaired rows' `windowed()` (their means subtracted, then the window) in their place, bit
    for bit: repaired rows at the block's first and last row, rows of other blocks around it,
    a block without any."""
    from pipeline.interference import RepairedRows
    g = np.random.default_rng(4)
    adc = g.integers(-3000, 3000, (10, 3, 32)).astype(np.int16)
    rows = np.array([2, 12, 14, 17, 26])  # chirp x 3 + Rx: chirps 0, 4, 4, 5, 8
    win = np.hanning(32).astype(np.float32)
    y = (g.standard_normal((5, 32)) * 1e3 + 300).astype(np.float32)
    rep = RepairedRows(rows, y, win, None, y.mean(axis=-1))
    full = np.multiply(adc, win, dtype=np.float32).reshape(-1, 32)
    full[rows] = rep.windowed()
    assert rep.windowed().tobytes() == np.multiply(
        y - y.mean(axis=-1, keepdims=True), win).tobytes()
    for c0, c1 in ((4, 6), (0, 10), (1, 4), (6, 8)):
        out = np.full((c1 - c0, 3, 32), np.nan, np.float32)
        got = rep.windowed_block(adc[c0:c1], c0, out)
        assert got is out and got.tobytes() == full[3 * c0:3 * c1].tobytes()
    strided = np.empty((32, 3, 2), np.float32).T  # (2, 3, 32), not C-contiguous
    with pytest.raises(ValueError, match=r"out must be a C-contiguous \(2, 3, 32\) array"):
        rep.windowed_block(adc[4:6], 4, strided)


@pytest.mark.parametrize("method", ["lowrank", "zero"])
def test_repaired_rows_window_the_repair_of_the_dc_removed_rows(cfg, method):
    """`repaired_rows(...).windowed()` is `repair` of the flagged rows (DC removed, numpy's
    float32 difference) times the window, bit for bit: "lowrank" leaves its rows' means to
    the window product, which must subtract exactly what the fill would have."""
    from pipeline.chirp_level.stage import chirp_statistics
    from pipeline.interference import FrameRows, get_mitigation, repair, repaired_rows
    from pipeline.kernels import window
    adc = radarsim.simulate_frame(cfg.replace(adc_dc_offset_lsb=-120.0), empty(),
                                  np.random.default_rng(8), one_interferer())
    proc = pipeline.ProcessingConfig().replace(intf_mitigation=method)
    dc, rows, flags = chirp_statistics(adc, proc)
    n = adc.shape[-1]
    win = window("hann", n)
    y = np.subtract(adc.reshape(-1, n)[rows], dc.reshape(-1, 1)[rows], dtype=np.float32)
    want = repair(y, flags, win, proc.interference.hysteresis_samples, get_mitigation(method),
                  frame=FrameRows(adc.reshape(-1, n), rows, adc.shape[1])) * win
    rep = repaired_rows(adc, dc, rows, flags, win, proc.interference)
    assert rows.size and rep.windowed().tobytes() == want.tobytes()
    assert (rep.means != 0).any() == (method == "lowrank")
