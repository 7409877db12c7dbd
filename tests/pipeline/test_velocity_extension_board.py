"""Why TDMA velocity extension moved a real IWR6843's static returns to +/-2 Vmax, and that a
calibrated board keeps a static scene static (issue 19).

Root cause (3 Tx TDM on the xWR68xx/18xx array: Tx1 and Tx3 in the horizontal row 2 lambda
apart, Tx2 raised): hypothesis v + 2 k Vmax multiplies slot s by exp(j 2 pi k s / 3). The raised
row is one slot, so its phase is absorbed by the free elevation phase wz of the whole-array
likelihood; only the horizontal row's two Tx groups (four elements apart) tell the hypotheses
apart, by the phase step between them: 0 for the truth, -/+120 deg for k = +/-1. A board's own
Tx-to-Tx phase error d adds to that step, so the wrong hypothesis wins as soon as |d| > 60 deg
(the step is then closer to the wrong hypothesis' 120 deg): uncalibrated boards have Tx phase
offsets of that size, and every static return moves. The margin at d = 0 is small (the truth
beats k = +/-1 by 1.03 dB of likelihood on a point target), so the fix is the channel
calibration applied before the hypotheses are scored (`pipeline.compensation`, hooked in
`pipeline.mimo.tdma.SlotChain.process`), not a different score.
"""
import warnings

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline.channel_calibration import measure_channel_calibration
from pipeline.kernels import array_layout
from pipeline.stages import array_dft, array_likelihood
from tests.pipeline.test_channel_calibration import x68  # noqa: F401 (fixture)


@pytest.mark.parametrize("d_deg, wins", [(0.0, 0), (50.0, 0), (-50.0, 0), (70.0, 1),
                                         (-70.0, -1)])
def test_tx_phase_error_beyond_60_deg_makes_a_wrong_hypothesis_win(x68, d_deg, wins):  # noqa: F811
    """Noise-free boresight echo, Tx3 phase error d: the whole-array likelihood of hypotheses
    k = -1, 0, +1 (v = 2 k Vmax) picks k = 0 for |d| < 60 deg and k = sign(d) beyond."""
    cfg, _ = x68
    assert cfg.tx_order == (1, 2, 3)  # slots: Tx1, Tx2 (raised), Tx3
    x = np.ones((cfg.n_tx, cfg.n_rx), complex)
    x[2] *= np.exp(1j * np.radians(d_deg))
    k = np.array([-1, 0, 1])
    slot_phase = np.exp(2j * np.pi * k[:, None] * np.arange(cfg.n_tx)[None, :] / cfg.n_tx)
    virt = (x[None] * slot_phase[:, :, None]).reshape(1, 3, -1).astype(np.complex64)
    az_pow = np.abs(virt @ array_dft(cfg, 512, "horizontal")) ** 2
    v_idx = array_layout(cfg.virtual_positions_m, cfg.wavelength_m).v_idx
    score = array_likelihood(cfg, virt, az_pow, v_idx)[0]
    assert k[np.argmax(score)] == wins
    if d_deg == 0.0:  # the margin of an ideal array, (8 + 4)^2 over the best wrong fit
        assert 10 * np.log10(score[1] / score[0]) == pytest.approx(1.03, abs=0.05)


def _static_scene(rng, n=25):
    r = rng.uniform(1.0, 9.0, n)
    az, el = rng.uniform(-50, 50, n), rng.uniform(-10, 10, n)
    return radarsim.Scatterers.from_spherical(r, az, el, np.zeros(n), 10 ** rng.uniform(-3.5, 0, n))


def test_calibrated_board_keeps_a_static_scene_static(x68):  # noqa: F811
    """A board with up to 75 deg of Tx and Rx phase error and 1.5 dB of gain spread, a static
    scene of 25 scatterers (1-9 m, +/-50 deg, SNR about 30-70 dB) per frame, extension on:
    uncalibrated, most static returns come out at +/-2 Vmax; with the line measured on a
    boresight reflector, at most 2 % do."""
    cfg, proc = x68
    assert proc.tdma_disambiguation
    board = cfg.replace(tx_phase_error_deg=(0.0, 25.0, -75.0), tx_gain_error_db=(0.0, 1.0, -1.0),
                        rx_phase_error_deg=(0.0, 30.0, -20.0, 50.0),
                        rx_gain_error_db=(0.0, -1.0, 0.5, 1.5), range_bias_m=0.05)
    rng = np.random.default_rng(11)
    r0 = 40 * cfg.range_resolution_m
    ref = radarsim.Scatterers.from_spherical(np.array([r0]), np.zeros(1), np.zeros(1),
                                             np.zeros(1), np.array([1e-3]))
    cal = measure_channel_calibration(cfg, [radarsim.simulate_frame(board, ref, rng)
                                            for _ in range(3)], r0, 0.2, proc)
    calibrated = proc.replace(range_bias_m=cal.range_bias_m, channel_comp=tuple(
        (c.real, c.imag) for c in cal.chip_coefficients))
    vmax = cfg.max_unambiguous_velocity_mps
    moved = {"raw": [0, 0], "cal": [0, 0]}
    for _ in range(6):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", radarsim.ADCSaturationWarning)
            adc = radarsim.simulate_frame(board, _static_scene(rng), rng)
        for key, p in (("raw", proc), ("cal", calibrated)):
            pc = pipeline.process_frame(cfg, adc, p)
            moved[key][0] += int(np.sum(np.abs(pc.radial_velocity_mps) > vmax))
            moved[key][1] += len(pc)
    assert moved["cal"][1] >= 60 and moved["raw"][1] >= 60
    assert moved["raw"][0] > 0.5 * moved["raw"][1], moved
    assert moved["cal"][0] <= 0.02 * moved["cal"][1], moved
