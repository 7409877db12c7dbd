"""compRangeBiasAndRxChanPhase as the demos apply it (`pipeline.compensation`): TI's chip
order and Q15 format, the exact range shift of every scheme, and the channel correction that
undoes a board's imbalance before angle estimation."""
import numpy as np
import pytest

import pipeline
import radarsim
from pipeline.compensation import (
    check_channel_comp,
    comp_line,
    n_chip_pairs,
    q15,
    ti_pair_index,
    virtual_coefficients,
)
from tests.pipeline.test_chain import REGISTRY, best_near, scene_at_snr

#: A board with every kind of imbalance (the first Tx and Rx are the reference).
IMBALANCE = dict(tx_phase_error_deg=(0.0, 70.0, -50.0, 120.0),
                 tx_gain_error_db=(0.0, 1.0, -1.5, 0.5),
                 rx_phase_error_deg=(0.0, 40.0, -65.0, 100.0),
                 rx_gain_error_db=(0.0, -1.0, 0.8, 1.5))


def board_gain(cfg):
    """(n_virtual,) complex gain g_k g_r of each virtual channel in the virtual-array order."""
    o = np.array(cfg.tx_order) - 1
    db = np.add.outer(np.asarray(cfg.tx_gain_error_db)[o], cfg.rx_gain_error_db)
    deg = np.add.outer(np.asarray(cfg.tx_phase_error_deg)[o], cfg.rx_phase_error_deg)
    return (10 ** (db / 20) * np.exp(1j * np.radians(deg))).reshape(-1)


def inverse_comp(cfg):
    """TI-ordered coefficients that undo `cfg`'s board gains (|c| <= 1), as (re, im) pairs."""
    g = board_gain(cfg)
    c = np.conj(g) / np.abs(g) ** 2 * np.abs(g).min()
    chip = np.ones(n_chip_pairs(cfg), complex)
    chip[ti_pair_index(cfg)] = c
    return tuple((float(v.real), float(v.imag)) for v in chip)


def test_q15_truncates_and_saturates_as_the_demo():
    """mmw_cli.c: (int32_t)(v * 32768.) saturated to int16: 1.0 -> 32767, -1.0 -> -32768,
    truncation toward zero."""
    got = q15([1.0, -1.0, 0.5, 1e-5, -1e-5, 0.123456]) * 32768
    np.testing.assert_array_equal(got, [32767, -32768, 16384, 0, 0, 4045])


def test_chip_order_follows_tx_channels_and_order():
    """Index of each virtual channel in the line: (chip Tx - 1) x chip Rx + (chip Rx - 1)
    (DPC_ObjDet_GetRxChPhaseComp), whatever order the frame transmits in."""
    r79 = radarsim.presets.r79_ddma()  # tx_order (1, 3, 4, 2)
    np.testing.assert_array_equal(ti_pair_index(r79), [0, 1, 2, 3, 8, 9, 10, 11, 12, 13, 14, 15,
                                                       4, 5, 6, 7])
    x18 = radarsim.RadarConfig.from_fields(
        chip="AWR1843", adc_mode="complex1x", mimo="tdma", n_tx=2, tx_channels=(1, 3), n_rx=2,
        rx_channels=(2, 4), n_chirps=96, n_samples=128, adc_rate_sps=10e6, slope_hz_per_s=30e12)
    np.testing.assert_array_equal(ti_pair_index(x18), [1, 3, 9, 11])
    assert n_chip_pairs(x18) == 12 and n_chip_pairs(r79) == 16


def test_wrong_coefficient_count_is_refused(make_config):
    cfg = make_config("tdma")
    with pytest.raises(ValueError, match=r"compRangeBiasAndRxChanPhase: 12 \(re, im\) "
                                         r"coefficients \(25 values\), the AWR2944 needs 16"):
        check_channel_comp(cfg, ((1.0, 0.0),) * 12)
    with pytest.raises(ValueError, match="the AWR2944 needs 16"):
        pipeline.process_frame(cfg, np.zeros((cfg.n_chirps, 4, cfg.n_samples), np.int16),
                               pipeline.ProcessingConfig().replace(channel_comp=((1.0, 0.0),) * 12))


@pytest.mark.parametrize("kw, match", [
    (dict(channel_comp=((1.5, 0.0),)), r"channel_comp value 1.5 is outside the Q15 range"),
    (dict(channel_comp=((float("nan"), 0.0),)), "must hold finite"),
    (dict(channel_comp=((1.0,),)), r"sequence of \(re, im\) pairs"),
    (dict(range_bias_m=float("inf")), "range_bias_m=inf must be a finite number"),
    (dict(range_bias_m=1e300), r"range_bias_m=1e\+300 is outside \+/-10 m"),
    (dict(range_bias_m=-1e6), r"range_bias_m=-1000000.0 is outside \+/-10 m"),
    (dict(channel_comp=((0.0, 0.0),) * 16), r"channel_comp is all zero \(16 coefficients"),
])
def test_bad_compensation_values(kw, match):
    with pytest.raises(ValueError, match=match):
        pipeline.ProcessingConfig().replace(**kw)


def test_process_and_sweep_share_one_range_bias_bound():
    """A profile's rangeBias and a simulated board's bias obey the same limit: what a sweep
    cell refuses, `process` refuses."""
    from radarsim.config_rules import MAX_RANGE_BIAS_M
    pipeline.ProcessingConfig().replace(**{"calibration.range_bias_m": MAX_RANGE_BIAS_M})
    radarsim.presets.r79_ddma(**{"impairments.range_bias_m": MAX_RANGE_BIAS_M})
    with pytest.raises(ValueError, match=r"range_bias_m=10\.5 must be finite and within"):
        radarsim.presets.r79_ddma(**{"impairments.range_bias_m": MAX_RANGE_BIAS_M + 0.5})
    with pytest.raises(ValueError, match=r"range_bias_m=10\.5 is outside \+/-10 m"):
        pipeline.ProcessingConfig().replace(**{"calibration.range_bias_m": MAX_RANGE_BIAS_M + 0.5})


def test_a_zero_coefficient_on_a_used_channel_is_refused(make_config):
    """0 + 0j erases the channel (SNR -inf, azimuth from the others' leakage); the chip's
    pairs the radar does not use may hold anything."""
    cfg = make_config("tdma")
    comp = [(1.0, 0.0)] * 16
    comp[5] = (0.0, 0.0)  # chip order: Tx2 Rx2
    with pytest.raises(ValueError, match=r"coefficient of chip Tx2 Rx2 is 0 \+ 0j \(1 of the "
                                         r"radar's 16 virtual channels\)"):
        check_channel_comp(cfg, tuple(comp))
    with pytest.raises(ValueError, match=r"Tx2 Rx2 is 0 \+ 0j"):
        pipeline.process_frame(cfg, np.zeros((cfg.n_chirps, 4, cfg.n_samples), np.int16),
                               pipeline.ProcessingConfig().replace(
                                   **{"calibration.channel_comp": tuple(comp)}))


def test_lists_become_tuples():
    proc = pipeline.ProcessingConfig().replace(channel_comp=[[1, 0], [0.5, -0.5]])
    assert proc.calibration.channel_comp == ((1.0, 0.0), (0.5, -0.5))
    hash(proc)


def test_comp_line_format():
    line = comp_line(-0.0123, np.array([1 + 0j, 0.5 - 0.25j]))
    assert line == "compRangeBiasAndRxChanPhase -0.0123 1.00000 0.00000 0.50000 -0.25000"


@pytest.mark.parametrize("name", REGISTRY)
def test_range_bias_shifts_every_range_exactly(name, make_config, make_scene):
    """Contract: the rangeBias of the line shifts every reported range by exactly that amount
    (same detections, every other column unchanged)."""
    cfg = make_config(name, antenna_pattern="isotropic")
    sc = scene_at_snr(cfg, make_scene, [[30.0, 10.0, 0.0, 3.0, 30.0],
                                        [80.0, -25.0, 5.0, -6.0, 28.0]])
    adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(3))
    pc0 = pipeline.process_frame(cfg, adc)
    pc1 = pipeline.process_frame(cfg, adc, pipeline.ProcessingConfig().replace(range_bias_m=0.4321))
    assert len(pc0) >= 2
    np.testing.assert_allclose(pc1.range_m, pc0.range_m - 0.4321, rtol=0, atol=1e-9)
    for col in ("radial_velocity_mps", "azimuth_deg", "elevation_deg", "snr_db", "range_bin"):
        np.testing.assert_array_equal(pc1[col], pc0[col])


@pytest.mark.parametrize("name", REGISTRY)
def test_channel_correction_undoes_board_imbalance(name, make_config, make_scene):
    """A board whose virtual channels carry g_k g_r (up to 120 deg, 1.5 dB): with the
    coefficients conj(g) / |g|^2 x min|g| (what the calibration measures) every scheme reports
    a 30 dB target at its azimuth (within 1.5 deg, design.md's point-target tolerance) and its
    velocity (within a bin). The coefficients go through Q15."""
    ideal = make_config(name, antenna_pattern="isotropic")
    board = ideal.replace(**IMBALANCE)
    r, az, v = 60.0, 25.0, 4.0
    sc = scene_at_snr(ideal, make_scene, [[r, az, 0.0, v, 30.0]])
    adc = radarsim.simulate_frame(board, sc, np.random.default_rng(5))
    proc = pipeline.ProcessingConfig().replace(channel_comp=inverse_comp(board))
    coef = virtual_coefficients(board, proc.calibration.channel_comp)
    np.testing.assert_allclose(np.angle(coef * board_gain(board)), 0.0, atol=1e-3)
    best = best_near(pipeline.process_frame(board, adc, proc), r)
    assert best is not None
    assert abs(best.azimuth_deg - az) <= 1.5
    assert abs(best.radial_velocity_mps - v) <= ideal.velocity_resolution_mps


def test_implied_board_inverts_the_line(make_config):
    """The board a line calibrates: for a board whose channels are a Tx x Rx product, the
    exact inverse line (`inverse_comp`) gives back its phases and gains (to Q15's
    resolution: 3e-5 relative, 0.002 deg / 0.0003 dB); an identity line an ideal board."""
    from pipeline.compensation import implied_board
    board = make_config("tdma").replace(**IMBALANCE)
    got = implied_board(board, inverse_comp(board), 0.05)
    assert got["range_bias_m"] == 0.05
    for key in ("tx_phase_error_deg", "rx_phase_error_deg"):
        want = (np.asarray(getattr(board, key)) + 180) % 360 - 180
        np.testing.assert_allclose((np.asarray(got[key]) + 180) % 360 - 180, want, atol=0.01)
    for key in ("tx_gain_error_db", "rx_gain_error_db"):
        np.testing.assert_allclose(got[key], getattr(board, key), atol=0.01)
    ideal = implied_board(board, ((1.0, 0.0),) * 16)
    assert ideal["rx_phase_error_deg"] == (0.0,) * 4 and ideal["tx_gain_error_db"] == (0.0,) * 4
    assert implied_board(board, None) == {}


def test_simulated_capture_of_an_aop_profile_reads_back_at_its_angle(tmp_path):
    """An IWR6843 antenna-on-package demo profile carries ``1 0 -1 0 ...`` (Rx2 and Rx4 fed
    in antiphase): `simulate` builds that board, `process` applies the line, and a target at
    20 deg azimuth is reported there (within 1.5 deg), as it would not be on an ideal board."""
    from harness.cell.ti_profile import processing_from_profile, simulation_radar
    from radarsim.ti import parse_ti_cfg
    from tests.radarsim.profiles import profile_text
    prof = parse_ti_cfg(profile_text("xwr68_aop"))
    proc = processing_from_profile(prof).replace(tdma_disambiguation=False)
    assert proc.calibration.channel_comp[1] == (-1.0, 0.0)
    radar = simulation_radar(prof)
    assert radar.rx_phase_error_deg == (0.0, 180.0, 0.0, 180.0)
    sc = radarsim.Scatterers.from_spherical(np.array([3.0]), np.array([20.0]), np.zeros(1),
                                            np.zeros(1), np.array([0.01]))
    for board, ok in ((radar, True), (prof.radar, False)):
        adc = radarsim.simulate_frame(board, sc, np.random.default_rng(2))
        pc = pipeline.process_frame(prof.radar, adc, proc)
        best = pc.loc[pc.snr_db.idxmax()]
        assert (abs(best.azimuth_deg - 20.0) <= 1.5) == ok, best.azimuth_deg


@pytest.mark.parametrize("name", ["hann", "hamming", "blackman", "rect"])
def test_range_interpolation_is_unbiased_for_every_window(name):
    """A noise-free tone at fractional bin offsets -0.45..0.45 through each registered range
    window: the log-parabola alone is biased (Hann/Hamming 0.016 bin, rectangular 0.167); with
    the window's table (`stages._offset_table`) the offset is recovered to 1e-3 bin, which is
    what lets a calibration's rangeBias equal the board's and the reflector land at R."""
    from scipy.signal import get_window

    from pipeline.config import WINDOWS
    from pipeline.stages import interp_range
    n = 256
    w = get_window(WINDOWS[name], n, fftbins=True)
    for d in np.linspace(-0.45, 0.45, 19):
        x = w * np.exp(2j * np.pi * (40 + d) * np.arange(n) / n)
        p = np.abs(np.fft.fft(x)) ** 2
        got = interp_range(p[None, 39:42], np.array([40]), n, WINDOWS[name])[0]
        assert abs(got - (40 + d)) <= 1e-3, (name, d, got)
