"""Board imperfections of the front end: per-channel Tx/Rx gain and phase imbalance (virtual
channel (k, r) carries g_k g_r) and a range bias b (every echo delayed by 2 b / c). The default
board is ideal."""
import numpy as np
import pytest

import pipeline
import radarsim
from pipeline.channel_calibration import static_virtual_samples
from pipeline.chirp_level import range_stage
from pipeline.stages import interp_range
from tests.pipeline.test_compensation import IMBALANCE, board_gain

RAW = pipeline.ProcessingConfig().replace(dc_removal=False, interference_mitigation=False,
                                compression=False)


def _scene(r, az=15.0):
    return radarsim.Scatterers.from_spherical(np.array([r]), np.array([az]), np.zeros(1),
                                              np.zeros(1), np.array([1e4]))


def test_default_board_is_ideal(make_config):
    cfg = make_config("tdma")
    assert cfg.rx_phase_error_deg == (0.0,) * 4 and cfg.rx_gain_error_db == (0.0,) * 4
    assert cfg.range_bias_m == 0.0


@pytest.mark.parametrize("name", ["tdma", "ddma", "bpm"])
def test_virtual_channels_carry_tx_times_rx_gain(name, make_config):
    """Same scene, same noise: the board's demodulated virtual samples over the ideal board's
    are g_k g_r (to the thermal noise of a 70 dB echo, unclipped)."""
    ideal = make_config(name, antenna_pattern="isotropic")
    board = ideal.replace(**IMBALANCE)
    x = []
    for cfg in (ideal, board):
        adc = radarsim.simulate_frame(cfg, _scene(20.0), np.random.default_rng(0))
        xs, _ = static_virtual_samples(cfg, range_stage(cfg, adc, RAW))
        x.append(xs)
    b = int(np.argmax((np.abs(x[0]) ** 2).sum(axis=(0, 1))))
    ratio = (x[1][:, :, b] / x[0][:, :, b]).reshape(-1)
    np.testing.assert_allclose(ratio, board_gain(board), rtol=2e-3, atol=0)


def test_range_bias_delays_every_echo(make_config):
    """A board with range bias b and a target at R puts the echo where an ideal board puts a
    target at R + b: the interpolated peak of the range profile moves by b / dR bins (the
    amplitude still follows the true range R)."""
    ideal = make_config("tdma", antenna_pattern="isotropic")
    b = 0.37
    board = ideal.replace(range_bias_m=b)

    def peak_bin(cfg, r):
        adc = radarsim.simulate_frame(cfg, _scene(r), np.random.default_rng(1))
        p = (np.abs(range_stage(cfg, adc, RAW)) ** 2).sum(axis=(0, 1))
        k = int(np.argmax(p))
        return float(interp_range(p[None, k - 1: k + 2], np.array([k]), p.size)[0])

    dr = ideal.range_resolution_m
    assert abs(peak_bin(board, 30.0) - peak_bin(ideal, 30.0 + b)) <= 1e-3
    assert abs(peak_bin(board, 30.0) - peak_bin(ideal, 30.0) - b / dr) <= 0.03


@pytest.mark.parametrize("kw, match", [
    (dict(rx_phase_error_deg=(0.0, 1.0)), r"rx_phase_error_deg must hold 4 finite values "
                                          r"\(one per Rx\)"),
    (dict(rx_gain_error_db=(0.0, 0.0, 0.0, 99.0)),
     r"rx_gain_error_db=.* must be a list of finite numbers in \[-400, 40\] \(one per Rx\)"),
    (dict(range_bias_m=11.0), r"range_bias_m=11.0 must be finite and within \+/-10 m"),
    (dict(range_bias_m=float("nan")), r"range_bias_m=nan must be finite"),
    (dict(range_bias_m="0.1"), r"range_bias_m='0.1' must be a number"),
])
def test_bad_board_imperfections(kw, match, make_config):
    with pytest.raises(ValueError, match=match):
        make_config("tdma", **kw)


def test_rx_errors_follow_n_rx(make_config):
    cfg = make_config("tdma", rx_phase_error_deg=(0.0, 10.0, 20.0, 30.0))
    assert cfg.replace(n_rx=2).rx_phase_error_deg == (0.0, 0.0)
