"""Chip and board registries: each chip limit, each board's virtual array against its drawing,
complex vs real ADC on the same scene."""
from __future__ import annotations

import math

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline.kernels import array_layout
from radarsim.boards import BOARDS, cos_exponent_for_half_power
from radarsim.chips import ADC_MODES, CHIPS


def _cfg(chip: str, **kw) -> radarsim.RadarConfig:
    spec = CHIPS[chip]
    base = dict(chip=chip, mimo="tdma", n_tx=spec.n_tx, n_chirps=12 * spec.n_tx, n_samples=64,
                adc_rate_sps=10e6, start_freq_hz=spec.band_min_hz + 1e9)
    if "real" not in spec.adc:
        base["adc_mode"] = "complex1x"
    base.update(kw)
    return radarsim.RadarConfig.from_fields(**base)


def test_registries_are_consistent():
    assert set(CHIPS) >= {"AWR2944", "AWR2944P", "AWR2544", "AWR1843", "AWR1642", "IWR6843"}
    assert set(BOARDS) >= {"AWR2944EVM", "AWR2944PEVM", "AWR2544LOPEVM", "AWR1843BOOST",
                           "AWR1642BOOST", "IWR6843ISK"}
    for chip in CHIPS.values():
        board = BOARDS[chip.default_board]
        assert board.chip == chip.name
        assert len(board.tx_positions_wl) == chip.n_tx and len(board.rx_positions_wl) == chip.n_rx
        assert set(chip.adc) <= set(ADC_MODES)
        assert chip.adcbuf_interleaved_default in chip.adcbuf_interleave
    # Datasheet values (chips.py docstring): bands, IF bandwidths, channels, shifter bits.
    assert (CHIPS["IWR6843"].band_min_hz, CHIPS["IWR6843"].band_max_hz) == (60e9, 64e9)
    assert CHIPS["AWR1642"].if_bandwidth_hz == 5e6 and CHIPS["AWR1642"].phase_shifter_bits is None
    assert CHIPS["AWR2944"].adc == {"real": (37.5e6,)} and CHIPS["AWR2944"].n_tx == 4
    assert CHIPS["AWR1843"].n_tx == 3 and CHIPS["AWR1642"].n_tx == 2


def test_cos_exponent_gives_half_power_at_the_angle():
    n = cos_exponent_for_half_power(60.0)
    assert math.cos(math.radians(60.0)) ** n == pytest.approx(0.5)


LIMITS = {
    # kind: (chip, overrides, message)
    "n_tx_over_chip": ("AWR1642", dict(n_tx=3, n_chirps=36), r"n_tx=3 must be an integer in "
                                                              r"1..2 \(AWR1642\)"),
    "n_rx_over_chip": ("AWR1843", dict(n_rx=5), r"n_rx=5 must be an integer in 1..4 \(AWR1843\)"),
    "tx_channel_outside_chip": ("AWR1843", dict(n_tx=2, n_chirps=24, tx_channels=(1, 4)),
                                r"tx_channels=\(1, 4\) must list 2 distinct channel numbers "
                                r"in 1..3"),
    "band_low_6843": ("IWR6843", dict(start_freq_hz=59e9), r"start_freq_hz=5.9e\+10 is below "
                                                           r"the IWR6843 band limit 6e\+10"),
    "band_low_1843": ("AWR1843", dict(start_freq_hz=75e9), r"below the AWR1843 band limit"),
    "band_high_2944": ("AWR2944", dict(start_freq_hz=80.99e9), r"exceeds the AWR2944 band"),
    "rate_real_1843": ("AWR1843", dict(adc_rate_sps=26e6, n_samples=64),
                       r"adc_rate_sps=2.6e\+07 exceeds the AWR1843 limit 2.5e\+07 sps "
                       r"\(real ADC\)"),
    "rate_complex1x_6843": ("IWR6843", dict(adc_mode="complex1x", adc_rate_sps=13e6),
                            r"exceeds the IWR6843 limit 1.25e\+07 sps \(complex1x ADC\)"),
    "if_band_real_1642": ("AWR1642", dict(adc_mode="real", adc_rate_sps=12e6),
                          r"IF bandwidth limit 5e\+06 Hz"),
    "if_band_real_2544": ("AWR2544", dict(adc_rate_sps=31e6), r"AWR2544 IF bandwidth limit"),
    "complex_on_real_only_chip": ("AWR2944P", dict(adc_mode="complex1x"),
                                  r"adc_mode='complex1x': the AWR2944P supports \['real'\]"),
    "samples_over_buffer": ("AWR1843", dict(n_samples=1026, adc_rate_sps=2e6,
                                            ramp_end_time_s=600e-6, chirp_period_s=605e-6,
                                            slope_hz_per_s=1e12),
                            r"n_samples=1026 exceeds the AWR1843 limit of 1024"),
    "chirps_over_frame": ("AWR2944", dict(n_tx=1, n_chirps=512 * 255 + 1),
                          r"exceeds the AWR2944 limit of 130560 chirps"),
    "shifter_bits": ("AWR1843", dict(phase_shifter_bits=5),
                     r"phase_shifter_bits=5: the AWR1843 phase shifter has 6 bits"),
    "shifter_absent": ("AWR1642", dict(phase_shifter_bits=6),
                       r"phase_shifter_bits=6: the AWR1642 has no phase shifter"),
    "ddma_without_shifter": ("AWR1642", dict(mimo="ddma", n_chirps=30),
                             r"mimo='ddma' needs per-Tx phase shifters; the AWR1642 has none"),
    "board_of_other_chip": ("AWR1843", dict(board="IWR6843ISK"),
                            r"board='IWR6843ISK' carries a IWR6843, not chip='AWR1843'"),
    "unknown_board": ("AWR1843", dict(board="FOO"), r"board='FOO' is not one of"),
    "interleaved_on_xwr18": ("AWR1843", dict(adcbuf_interleaved=True),
                             r"AWR1843 demo firmware accepts only a non-interleaved"),
    "odd_real_samples": ("AWR1843", dict(adc_mode="real", n_samples=63),
                         r"n_samples=63 must be even"),
    "positions_wrong_size": ("AWR1843", dict(tx_positions_wl=((0, 0), (1, 0))),
                             r"tx_positions_wl must hold 3 finite"),
    "rx_positions_not_finite": ("AWR1843", dict(rx_positions_wl=((0, 0), (0.5, 0), (1, 0),
                                                                 (float("nan"), 0))),
                                r"rx_positions_wl must hold 4 finite"),
    "positions_not_pairs": ("AWR1843", dict(rx_positions_wl=(0, 0.5, 1, 1.5)),
                            r"rx_positions_wl=\(0, 0.5, 1, 1.5\) must be a sequence of \(y, z\) "
                            r"pairs in wavelengths"),
}


@pytest.mark.parametrize("kind", sorted(LIMITS))
def test_each_chip_limit(kind):
    chip, kw, pattern = LIMITS[kind]
    with pytest.raises(ValueError, match=pattern):
        _cfg(chip, **kw)


def test_unknown_chip_is_named():
    with pytest.raises(ValueError, match=r"chip='AWR9999' is not one of \['AWR1243'"):
        radarsim.RadarConfig.from_fields(chip="AWR9999")


def test_limits_are_the_chips_not_the_awr2944s():
    """Values the AWR2944 refuses are fine on a chip that allows them, and vice versa."""
    _cfg("IWR6843", start_freq_hz=60e9)            # below 76 GHz: the 60-64 GHz band
    _cfg("AWR1843", adc_mode="complex1x", n_samples=63)   # complex: odd N allowed
    _cfg("AWR2944", adc_rate_sps=30e6, n_samples=64)      # 15 MHz IF: the R79 rate
    with pytest.raises(ValueError, match=r"AWR1843 limit .* \(real ADC\)"):
        _cfg("AWR1843", adc_mode="real", adc_rate_sps=30e6)


# Each board's virtual array against its drawing (boards.py sources): horizontal lambda/2
# positions of the z = 0 row, the raised row's positions and its height in wavelengths.
DRAWINGS = {
    "AWR2944EVM": (4, (1, 3, 4, 2), list(range(12)), [2, 3, 4, 5], 0.8),
    "AWR2944PEVM": (4, (1, 3, 4, 2), list(range(12)), [2, 3, 4, 5], 0.8),
    "AWR2544LOPEVM": (4, (1, 2, 3, 4), list(range(16)), [], 0.0),
    "AWR1843BOOST": (3, (1, 3, 2), list(range(8)), [2, 3, 4, 5], 0.5),
    "IWR6843ISK": (3, (1, 3, 2), list(range(8)), [2, 3, 4, 5], 0.5),
    "AWR1642BOOST": (2, (1, 2), list(range(8)), [], 0.0),
}


@pytest.mark.parametrize("board", sorted(DRAWINGS))
def test_board_virtual_array_matches_its_drawing(board):
    n_tx, order, h_pos, v_pos, v_h = DRAWINGS[board]
    cfg = _cfg(BOARDS[board].chip, board=board)
    assert cfg.n_tx == n_tx and cfg.tx_order == order
    lay = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    assert list(lay.h_pos) == h_pos
    assert sorted(lay.v_pos) == v_pos and lay.v_height_wl == pytest.approx(v_h)
    # Demodulated order: Tx in tx_order, Rx1..Rx4 within each; Rx at lambda/2.
    y = cfg.virtual_positions_m[:, 1] / (cfg.wavelength_m / 2)
    np.testing.assert_allclose(np.diff(y[:4]), 1.0)


@pytest.mark.parametrize("chans, order, h_pos", [
    ((1, 3), (1, 2), list(range(8))),           # txChannelEn 5: Tx1 + Tx3, 2 lambda apart
    ((2, 3), (2, 1), [4, 5, 6, 7]),             # Tx2 raised (z = 0.5), Tx3 horizontal
    ((3, 1), (1, 2), list(range(8))),           # logical Tx1 = chip Tx3 (both z = 0)
])
def test_any_tx_subset_and_order_follows_from_geometry(chans, order, h_pos):
    cfg = _cfg("AWR1843", n_tx=2, n_chirps=24, tx_channels=chans)
    assert cfg.tx_order == order
    lay = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    assert list(lay.h_pos) == h_pos


def test_replace_chip_rederives_board_and_geometry():
    cfg = radarsim.presets.r79_tdma()
    other = cfg.replace(chip="AWR2944P")
    assert other.board == "AWR2944PEVM" and other.tx_positions_wl == cfg.tx_positions_wl
    d = other.to_dict()
    assert radarsim.RadarConfig.from_dict(d) == other


def test_r79_preset_is_unchanged_by_the_registries():
    """The AWR2944 EVM values of the single-chip era (design.md 4.2, 4.4)."""
    cfg = radarsim.presets.r79_ddma()
    assert (cfg.chip, cfg.board, cfg.adc_mode, cfg.phase_shifter_bits) == \
        ("AWR2944", "AWR2944EVM", "real", 6)
    assert (cfg.pattern_exponent_az, cfg.pattern_exponent_el) == (1.2, 4.0)
    np.testing.assert_array_equal(cfg.tx_positions_m / cfg.wavelength_m,
                                  [[0, 0, 0], [0, 1, 0.8], [0, 2, 0], [0, 4, 0]])
    assert cfg.n_range_bins == 192 and cfg.max_range_m == pytest.approx(253.1, abs=0.1)


# ---------------------------------------------------------------------------- complex ADC
@pytest.mark.parametrize("chip, f0", [("AWR1843", 77e9), ("IWR6843", 60e9)])
def test_complex_and_real_frames_give_the_same_detections(chip, f0):
    """Same scene, same bandwidth and chirps: a complex profile of N samples at f_s and a real
    one of 2N samples at 2 f_s sample the same ramp, so both see the same range bins (the
    complex one keeps all N, the real one N of its 2N) and report the same targets within one
    resolution cell in range, velocity and angle."""
    common = dict(chip=chip, mimo="tdma", n_tx=3, start_freq_hz=f0, slope_hz_per_s=30e12,
                  idle_time_s=10e-6, adc_start_time_s=5e-6, ramp_end_time_s=40e-6,
                  chirp_period_s=50e-6, n_chirps=3 * 64)
    cplx = radarsim.RadarConfig.from_fields(**common, adc_mode="complex1x", n_samples=256,
                                            adc_rate_sps=10e6)
    real = radarsim.RadarConfig.from_fields(
        **common, adc_mode="real", n_samples=512, adc_rate_sps=20e6)
    assert cplx.range_resolution_m == real.range_resolution_m
    assert cplx.max_range_m == real.max_range_m == pytest.approx(10e6 * 299792458 / 60e12)
    assert cplx.n_range_bins == 256 == real.n_range_bins
    sc = radarsim.Scatterers(position_m=[[20.0, 3.0, 0.0], [35.0, -6.0, 0.0]],
                             velocity_mps=[[-3.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
                             rcs_m2=[10.0, 5.0])
    out = {}
    for cfg in (cplx, real):
        adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(1))
        assert adc.dtype == cfg.adc_dtype and adc.shape == (192, 4, cfg.n_samples)
        pc = pipeline.process_frame(cfg, adc)
        out[cfg.adc_mode] = pc.sort_values("range_m").reset_index(drop=True)
    a, b = out["complex1x"], out["real"]
    assert len(a) == len(b) == 2
    np.testing.assert_allclose(a["range_m"], b["range_m"], atol=cplx.range_resolution_m)
    np.testing.assert_allclose(a["radial_velocity_mps"], b["radial_velocity_mps"],
                               atol=cplx.velocity_resolution_mps)
    # Angle: within the 8-element horizontal row's resolution, 2/8 rad in sin(az).
    np.testing.assert_allclose(np.sin(np.radians(a["azimuth_deg"])),
                               np.sin(np.radians(b["azimuth_deg"])), atol=2 / 8)
    truth_r = np.hypot([20.0, 35.0], [3.0, -6.0])
    np.testing.assert_allclose(a["range_m"], truth_r, atol=cplx.range_resolution_m)


def test_complex_range_fft_keeps_all_bins_and_puts_the_tone_at_fb_n_over_fs():
    """Beat f_b = 2 S R / c of a static target at 5 m: bin f_b N / f_s of the complex FFT."""
    cfg = _cfg("AWR1843", adc_mode="complex1x", slope_hz_per_s=30e12, n_samples=128,
               adc_rate_sps=10e6, antenna_pattern="isotropic")
    sc = radarsim.Scatterers(position_m=[[5.0, 0.0, 0.0]], velocity_mps=[[0.0, 0.0, 0.0]],
                             rcs_m2=[100.0])
    adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(0))
    spec = pipeline.kernels.range_fft(adc, pipeline.kernels.window("hann", 128))
    assert spec.shape == (cfg.n_chirps, 4, 128)
    expected_bin = 2 * 30e12 * 5.0 / 299792458 * 128 / 10e6
    peak = np.argmax(np.abs(spec).sum(axis=(0, 1)))
    assert abs(peak - expected_bin) <= 0.5
    # No image at the mirrored bin (the image band is rejected): > 30 dB below the peak.
    p = np.abs(spec).sum(axis=(0, 1)) ** 2
    assert p[128 - peak] < p[peak] * 1e-3


def test_if_corner_follows_the_sampled_band():
    """Anti-alias corner: the chip's IF low-pass, or 1.1 x the sampled band when narrower, so
    an echo at 1.5 x the max range of a complex profile is down by 1 / (1 + (1.5/1.1)^20)."""
    from radarsim.frontend import IF_LOWPASS_ORDER, if_corner_hz, received_power_w
    assert if_corner_hz(radarsim.presets.r79_ddma()) == 16.5e6
    cfg = _cfg("AWR1843", adc_mode="complex1x", slope_hz_per_s=30e12, adc_rate_sps=5e6,
               antenna_pattern="isotropic")
    assert if_corner_hz(cfg) == pytest.approx(5.5e6)
    near, far = 0.5 * cfg.max_range_m, 1.5 * cfg.max_range_m
    sc = radarsim.Scatterers(position_m=[[near, 0, 0], [far, 0, 0]],
                             velocity_mps=np.zeros((2, 3)), rcs_m2=[1.0, 1.0])
    p = received_power_w(cfg, sc) * np.array([near, far]) ** 4
    h = lambda f: 1 / (1 + (f / 5.5e6) ** (2 * IF_LOWPASS_ORDER))  # noqa: E731
    assert p[1] / p[0] == pytest.approx(h(7.5e6) / h(2.5e6), rel=1e-9)
    assert p[1] / p[0] < 2.1e-3  # -26.9 dB
