"""The chirp-level chain (DC removal, interference zeroing, EGE compression) against analytic
references (issue 14; seed 004 section 2)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline import chirp_level as cl
from pipeline.kernels import range_fft, window
from radarsim import interference as itf_mod
from radarsim.frontend import IF_LOWPASS_HZ, IF_LOWPASS_ORDER

OFF = dict(dc_removal=False, interference_mitigation=False, compression=False)


@pytest.fixture(scope="module")
def cfg():
    return radarsim.presets.r79_ddma(antenna_pattern="isotropic")


def _empty():
    return radarsim.Scatterers(position_m=np.zeros((0, 3)), velocity_mps=np.zeros((0, 3)),
                               rcs_m2=[])


def test_switches_off_is_the_plain_range_fft(cfg):
    adc = radarsim.simulate_frame(cfg, _empty(), np.random.default_rng(0))
    rf = cl.range_stage(cfg, adc, pipeline.ProcessingConfig(**OFF))
    assert np.array_equal(rf, range_fft(adc, window("hann", cfg.n_samples)))


@pytest.mark.parametrize("win", ["rect", "hann", "blackman"])
def test_dc_removal_leaves_no_dc_bin(cfg, win):
    """A 500 LSB offset: after removal the rect-window DC bin is zero, and with any window the
    spectrum equals that of the offset-free frame with its own mean removed."""
    adc0 = radarsim.simulate_frame(cfg, _empty(), np.random.default_rng(3))
    adc1 = radarsim.simulate_frame(cfg.replace(adc_dc_offset_lsb=500.0), _empty(),
                                   np.random.default_rng(3))
    proc = pipeline.ProcessingConfig(range_window=win, dc_removal=True,
                                     interference_mitigation=False, compression=False)
    rf0, rf1 = cl.range_stage(cfg, adc0, proc), cl.range_stage(cfg, adc1, proc)
    raw = cl.range_stage(cfg, adc1, pipeline.ProcessingConfig(range_window=win, **OFF))
    noise_bin = np.sqrt(np.mean(np.abs(raw[..., 10:]) ** 2))
    assert np.abs(raw[..., 0]).mean() > 100 * noise_bin       # the offset is there
    assert np.abs(rf1 - rf0).max() < 1e-3 * noise_bin * 100   # rounding ties only
    if win == "rect":
        assert np.abs(rf1[..., 0]).max() < 1e-3 * noise_bin


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


def _burst_energy(cfg, itf, win):
    """sum over bursts of (A^2 / 2) sum_n H(dS (t_n - t*)) w_n^2 from the closed-form crossing
    times and the one-way power: the expected interference energy after the window."""
    amp2 = 2 * itf_mod.received_power_w(cfg, itf)[0] * cfg.adc_code_per_sqrt_w ** 2
    bw = itf_mod.burst_windows(cfg, itf)
    ds = cfg.slope_hz_per_s - itf.slope_hz_per_s[0]
    t_n = cfg.adc_start_time_s + np.arange(cfg.n_samples) / cfg.adc_rate_sps
    total = 0.0
    for row in bw.itertuples():
        sl = slice(row.first_sample, row.first_sample + row.n_samples)
        f_d = ds * (t_n[sl] - row.crossing_time_s)
        h = 1 / (1 + (np.abs(f_d) / IF_LOWPASS_HZ) ** (2 * IF_LOWPASS_ORDER))
        total += amp2 / 2 * np.sum(h * win[sl].astype(float) ** 2)
    return total * cfg.n_rx


def _itf(slope=20e12, r=60.0, power_dbm=12.0):
    return itf_mod.Interferers(position_m=[[r, 5.0, 0.0]], radial_velocity_mps=[-5.0],
                               tx_gain_dbi=[10.0], start_freq_hz=[77.02e9],
                               slope_hz_per_s=[slope], chirp_period_s=[31e-6],
                               ramp_time_s=[25e-6], chirp_offset_s=[2e-6],
                               tx_power_dbm=[power_dbm])


def test_noise_floor_rise_without_mitigation_matches_burst_energy(cfg):
    """After the Doppler FFT the bursts spread over all cells: rise = 10 log10(1 + E_I / E_N)
    with E_I from the closed-form burst timing and one-way power, within 0.5 dB."""
    itf = _itf()
    adc = radarsim.simulate_frame(cfg, _empty(), np.random.default_rng(5), itf)
    proc = pipeline.ProcessingConfig(dc_removal=True, interference_mitigation=False,
                                     compression=False)
    rise = cl.noise_floor_rise(cfg, adc, proc, range_stride=1)
    win = window("hann", cfg.n_samples)
    e_n = cfg.n_chirps * cfg.n_rx * cfg.noise_rms_lsb ** 2 * np.sum(win.astype(float) ** 2)
    want = 10 * np.log10(1 + _burst_energy(cfg, itf, win) / e_n)
    assert want > 3  # a real rise to check
    assert rise.doppler_db == pytest.approx(want, abs=0.5)
    clean = radarsim.simulate_frame(cfg, _empty(), np.random.default_rng(5))
    assert abs(cl.noise_floor_rise(cfg, clean, proc).doppler_db) < 0.2


@pytest.mark.parametrize("slope, recovers", [(50e12, True), (15e12, False)],
                         ids=["short-bursts", "long-bursts"])
def test_mitigation_recovers_short_bursts_not_long_ones(cfg, slope, recovers):
    """The demo's statistics come from the chirp itself (AbsDiffThreshold = 18 dB over the mean
    |dx|): a short burst (|dS| = 41 MHz/us, 0.8 us) stands out and is zeroed; a long one
    (|dS| = 6 MHz/us, 5.5 us, 40 % of the chirp) raises its own threshold and stays."""
    itf = _itf(slope=slope, r=15.0, power_dbm=15.0)
    adc = radarsim.simulate_frame(cfg, _empty(), np.random.default_rng(6), itf)
    off = cl.noise_floor_rise(cfg, adc, pipeline.ProcessingConfig(
        interference_mitigation=False, compression=False)).doppler_db
    on = cl.noise_floor_rise(cfg, adc, pipeline.ProcessingConfig(compression=False)).doppler_db
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
    adc = radarsim.simulate_frame(cfg, _empty(), np.random.default_rng(6), itf)
    off = cl.noise_floor_rise(cfg, adc, pipeline.ProcessingConfig(
        interference_mitigation=False, compression=False)).doppler_db
    on = cl.noise_floor_rise(cfg, adc, pipeline.ProcessingConfig(compression=False)).doppler_db
    assert off > 15
    assert abs(on) < 1.0


def test_ege_block_reproduces_the_hardware_ratio_and_error_bound():
    """One block of 4 Rx x 8 bins (32 complex 16-bit samples = 128 bytes) fits 64 bytes: the
    exact EG code length of the chosen (s, k) plus the 7-bit header is <= 512 bits, and every
    decompressed I/Q value is within 1.5 x 2^s LSB of the input (half a step of rounding, up
    to a step of triangular dither)."""
    rng = np.random.default_rng(11)
    budget = 64 * 8 - cl.EGE_HEADER_BITS
    for level in (10.0, 300.0, 3e4):  # noise-like, moderate, a strong echo in the block
        v = (rng.standard_normal((1, 4, 8)) + 1j * rng.standard_normal((1, 4, 8))) * 8.0
        v[0, 1, 3] += level * 8 * (1 + 1j)
        rf = (v / cl.HWA_OUTPUT_SCALE * cl.HWA_OUTPUT_SCALE / cl.HWA_OUTPUT_SCALE) \
            .astype(np.complex64)
        vin = rf.copy().view(np.float32).reshape(-1) * cl.HWA_OUTPUT_SCALE
        out, shift = cl.ege_compress(rf)
        s = int(shift[0, 0])
        vout = out.view(np.float32).reshape(-1) * cl.HWA_OUTPUT_SCALE
        err = np.abs(vout - vin).max()
        if s == 0:
            assert err <= 0.5  # s = 0: not requantised (cold) or rounded
        else:
            assert err <= 1.5 * 2.0 ** s + 1e-3
        q = np.rint(np.ldexp(vin, -s))
        bits = min(int(cl.ege_block_bits(q[None], k)[0]) for k in cl.EGE_K_ARRAY)
        assert bits <= budget
        assert (bits + cl.EGE_HEADER_BITS) / 8 <= 0.5 * 128
        if s > 0:  # a finer scale would not have fitted
            q1 = np.rint(np.ldexp(vin, -(s - 1)))
            assert min(int(cl.ege_block_bits(q1[None], k)[0]) for k in cl.EGE_K_ARRAY) \
                > budget


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


def _brute_force_shift(vin: np.ndarray, budget: int) -> np.ndarray:
    """Smallest s of each block (n_blocks, n_val) in HWA LSB whose best-k exact EG code length
    fits `budget`: every (s, k) tried."""
    s_all = np.arange(16)
    q = np.rint(np.ldexp(vin[:, None, :].astype(np.float64), -s_all[None, :, None]))
    bits = np.stack([cl.ege_block_bits(q, np.full(q.shape[:2], k)) for k in cl.EGE_K_ARRAY])
    fits = bits.min(axis=0) <= budget                                  # (blocks, s)
    return np.where(fits.any(axis=1), fits.argmax(axis=1), 15)


def test_ege_scale_factor_is_the_smallest_that_fits():
    """Pass 1 of the encoder model against an exhaustive search over every (s, k), on blocks of
    every kind: thermal noise at 2..200 LSB, noise with a strong echo, blocks at the edge of
    the unshifted budget (a mean |v| of 8..16 LSB) and rail-to-rail interference."""
    rng = np.random.default_rng(5)
    n_c, n_r, nb = 48, 4, 24
    sigma = np.exp(rng.uniform(np.log(2.0), np.log(200.0), (n_c, 1, nb, 1)))
    sigma[: n_c // 3] = rng.uniform(8.0, 16.0, (n_c // 3, 1, nb, 1)) * np.sqrt(np.pi / 2)
    v = rng.standard_normal((n_c, n_r, nb, 16)) * sigma
    echo = rng.random((n_c, 1, nb, 1)) < 0.3
    v += echo * rng.uniform(1e2, 3e4, (n_c, 1, nb, 1)) * (rng.random((n_c, n_r, nb, 16)) < 0.1)
    v[-4:] = rng.uniform(-32767, 32767, (4, n_r, nb, 16))
    rf = (v / cl.HWA_OUTPUT_SCALE).astype(np.float32).reshape(n_c, n_r, -1).view(np.complex64)
    vin = rf.view(np.float32).reshape(n_c, n_r, nb, 16).transpose(0, 2, 1, 3) \
        .reshape(n_c * nb, 64) * np.float32(cl.HWA_OUTPUT_SCALE)
    _, shift = cl.ege_compress(rf.copy())
    want = _brute_force_shift(vin, 64 * 8 - cl.EGE_HEADER_BITS)
    assert np.bincount(want).size > 8  # the blocks span the scale factors
    np.testing.assert_array_equal(shift.reshape(-1), want)


@pytest.mark.parametrize("diff_db", [40.0, 60.0, 70.0])  # 70 dB: the 16-bit output's span
def test_compression_loss_of_a_weak_target_next_to_a_strong_one(diff_db):
    """The block's scale factor s follows its strongest values; the weak target's SNR then
    loses 10 log10(1 + (2^(2s) / 4) / sigma^2) (triangular-dithered quantisation of I and Q
    with step 2^s HWA LSB: error variance step^2 / 4 whatever the signal, against the noise
    variance sigma^2 per component); the target's coherent power is kept. Five weak targets
    (bins 35-39 of the block) x 4 Rx give 20 looks; the tolerance is three standard deviations
    of the SNR estimate before and after (a bin of coherent SNR rho averaged over L looks has
    a relative power error of sqrt(2 / (L rho))) plus 0.1 dB."""
    n_c, n_b, sigma = 512, 192, 8.0  # sigma: noise per I/Q in HWA LSB
    weak_bins = [35, 36, 37, 38, 39]
    rng = np.random.default_rng(2)
    lsb = 1 / cl.HWA_OUTPUT_SCALE
    noise = (rng.standard_normal((n_c, 4, n_b)) + 1j * rng.standard_normal((n_c, 4, n_b))) \
        * sigma * lsb
    c = np.arange(n_c)
    k_weak, k_strong = 51, 154  # bin-centred Doppler tones
    weak = 10 * sigma * lsb * np.exp(2j * np.pi * k_weak / n_c * c)[:, None]
    strong = 10 * sigma * lsb * 10 ** (diff_db / 20) * \
        np.exp(2j * np.pi * k_strong / n_c * c)[:, None]
    rf = noise.copy()
    rf[:, :, weak_bins] += weak[:, :, None]
    for b, g in ((32, 0.5), (33, 1.0), (34, 0.5)):  # a Hann main lobe over three bins
        rf[:, :, b] += g * strong
    rf = rf.astype(np.complex64)

    def snr_db(x):
        p = np.abs(np.fft.fft(x[:, :, weak_bins], axis=0)) ** 2
        floor = np.delete(p, [k_weak], axis=0).mean()
        return 10 * np.log10((p[k_weak].mean() - floor) / floor)

    before = snr_db(rf)
    out, shift = cl.ege_compress(rf.copy())
    s4 = shift[:, 4].astype(float)  # block 4 holds bins 32..39
    s = int(np.median(s4))
    loss = before - snr_db(out)
    want = 10 * np.log10(1 + np.mean(4.0 ** s4 / 4) / sigma ** 2)
    looks, rho = 4 * len(weak_bins), n_c * 10 ** 2 / 2  # coherent bin SNR before compression
    sd_db = [10 / np.log(10) * np.sqrt(2 / (looks * r)) for r in (rho, rho / 10 ** (want / 10))]
    assert loss == pytest.approx(want, abs=0.1 + 3 * np.hypot(*sd_db))
    if diff_db >= 70:
        assert s >= 4 and loss > 1.0


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
])
def test_processing_config_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        pipeline.ProcessingConfig(**kw)


def test_demo_defaults_and_sweep_key():
    p = pipeline.ProcessingConfig()
    assert (p.dc_removal, p.interference_mitigation, p.compression) == (True, True, True)
    assert (p.intf_mag_snr_db, p.intf_magdiff_snr_db, p.intf_hysteresis_samples) == \
        (15.0, 18.0, 3)
    assert p.replace(interference_mitigation=False).interference_mitigation is False


@pytest.mark.parametrize("mode", sorted(pipeline.config.INTF_THRESHOLD_MODES))
def test_threshold_modes_flag_a_glitch_and_not_noise(mode):
    rng = np.random.default_rng(4)
    x = (rng.standard_normal((50, 4, 384)) * 7).astype(np.float32)
    assert not cl.interference_flags(x, None, 15, 18, mode).any()
    x[3, 1, 200:210] += 400 * np.cos(np.pi * 0.9 * np.arange(10))
    assert cl.interference_flags(x, None, 15, 18, mode)[3, 1, 200:210].any()


def test_cfg_intf_and_compression_commands_reach_the_processing_config():
    from harness.cmd_ti import processing_from_profile
    from radarsim.ti_cfg import parse_ti_cfg, r79_cfg_text
    text = r79_cfg_text().replace("intfMitigCfg -1 15 18", "intfMitigCfg -1 12 20") \
        .replace("compressionCfg -1 1 0 0.5 8", "compressionCfg -1 0 0 0.5 8")
    proc = processing_from_profile(parse_ti_cfg(text))
    assert (proc.intf_mag_snr_db, proc.intf_magdiff_snr_db, proc.compression) == \
        (12.0, 20.0, False)
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


@pytest.mark.parametrize("n_rx, bins, lowest", [(4, 8, (320 + 7) / 1024),
                                                (2, 4, (80 + 7) / 256), (3, 16, (480 + 7) / 1536)])
def test_compression_ratio_must_hold_the_shortest_code(make_config, n_rx, bins, lowest):
    """A block of n_rx x bins I/Q values needs 5 bits per value (k = 3, the demo's smallest
    order) plus the 7-bit header: a smaller ratio cannot be met by any scale factor. The
    radar-level check refuses it before any frame (as a sweep does for every cell), and
    `ege_compress` refuses it too; the ratio at the limit is accepted."""
    assert cl.ege_min_ratio(n_rx, bins) == pytest.approx(lowest)
    cfg = make_config(n_rx=n_rx, rx_channels=tuple(range(1, n_rx + 1)))
    proc = pipeline.ProcessingConfig(compression_ratio=0.25,
                                     compression_range_bins_per_block=bins)
    with pytest.raises(ValueError, match="compression_ratio=0.25 is below"):
        proc.check_radar(cfg)
    rf = np.zeros((2, n_rx, 4 * bins), np.complex64)
    with pytest.raises(ValueError, match="compression_ratio=0.25 is below"):
        cl.ege_compress(rf, 0.25, bins)
    ok = proc.replace(compression_ratio=math.ceil(lowest * 1e4) / 1e4)
    ok.check_radar(cfg)
    assert not cl.ege_compress(rf, ok.compression_ratio, bins)[1].any()


def test_compression_blocks_must_tile_the_range_bins(make_config):
    """Blocks of 32 bins tile the R79 radar's 192 range bins; a radar of 100 bins is
    refused, naming the block size and the bin count."""
    proc = pipeline.ProcessingConfig(compression_range_bins_per_block=32)
    proc.check_radar(make_config())
    with pytest.raises(ValueError, match="=32 does not divide the radar's 100 range bins"):
        proc.check_compression(4, 100)
