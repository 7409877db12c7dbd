"""Empty-band DDMA's Tx-order decision with two returns one sub-band apart in one range bin
(the co-moving ghost of a guard rail), against the array model of design.md 3.

Two returns of one range bin whose velocities differ by exactly one sub-band (lambda / (4 Tc)
x 2 / N = 13.63 m/s on the R79 preset) fill each other's empty sub-bands: the Rx-summed metric
of [TI-DDMA] table 11 picks the stronger one's Tx order for the whole cell, and the weaker one,
read in that order, used to come out at the stronger one's velocity in its own direction.
"""
import doctest

import numpy as np
import pytest
from scipy import stats

import pipeline
import pipeline.mimo.ddma_order as ddma_order
import radarsim
from pipeline.ddma_kernels import ddma_metric
from pipeline.mimo.ddma_order import band_beams, beam_band_metric, coherence_floor
from tests.pipeline.test_chain import scene_at_snr


def _cell_spectrum(cfg, echoes, d=40):
    """Noise-free (n_chirps, n_rx, 1) Doppler spectrum of one range bin holding far-field
    echoes (amplitude, azimuth_deg, tx1_band) at intra-sub-band Doppler bin d: Tx p of an echo
    sits in sub-band (tx1_band + p) mod N with the virtual element's phase (design.md 3)."""
    n_dop = cfg.n_chirps // cfg.n_subbands
    pos = cfg.virtual_positions_m.reshape(cfg.n_tx, cfg.n_rx, 3)
    spec = np.zeros((cfg.n_chirps, cfg.n_rx, 1), complex)
    for amp, az_deg, band in echoes:
        u = np.array([np.cos(np.radians(az_deg)), np.sin(np.radians(az_deg)), 0.0])
        phase = 2 * np.pi / cfg.wavelength_m * pos @ u  # (P, Rx): +(t_k + r_r) . u
        for p in range(cfg.n_tx):
            spec[((band + p) % cfg.n_subbands) * n_dop + d, :, 0] += amp * np.exp(1j * phase[p])
    return spec


@pytest.fixture
def r79():
    return radarsim.presets.r79("ddma", antenna_pattern="isotropic"), pipeline.ProcessingConfig()


def test_rx_beam_takes_the_decision_the_rx_sum_cannot(r79):
    """A (band 0, -45 deg) 1.5 dB above B (band 5, -10 deg): the Rx-summed metric picks A's
    order for the whole cell, on nothing but Z_0 - Z_5 = n_rx (|A|^2 - |B|^2), the energy of
    A's Tx2 sub-band minus B's Tx1 sub-band (the other three are shared); the beam toward each
    return picks that return's own order, because the other one is 35 deg off and 4 Rx at
    lambda / 2 pass it at most -11 dB (array factor sin(2 u) / (4 sin(u / 2)), u the phase
    step)."""
    cfg, proc = r79
    amp_b = 10 ** (-1.5 / 20)
    spec = _cell_spectrum(cfg, [(1.0, -45.0, 0), (amp_b, -10.0, 5)])
    energy = (np.abs(spec[..., 0]) ** 2).sum(axis=1)  # (n_chirps,)
    z_sum = ddma_metric(energy, cfg.n_subbands, cfg.n_tx)[:, 40]
    assert np.argmax(z_sum) == 0
    assert z_sum[0] - z_sum[5] == pytest.approx(cfg.n_rx * (1 - amp_b ** 2), rel=1e-9)
    for az_deg, band in [(-45.0, 0), (-10.0, 5)]:
        sin_term = np.array([np.sin(np.radians(az_deg))])
        z = beam_band_metric(band_beams(cfg, proc, spec, np.array([0]), np.array([40]),
                                        sin_term))[0]
        assert np.argmax(z) == band
        # The other return leaks through the Rx pattern: Z of its order stays below 3/4 of the
        # winner plus that leakage (3 of 4 sub-bands shared).
        assert z[band] / np.sort(z)[-2] > 1.2


@pytest.mark.parametrize("a, b", [
    # (range offset bins, azimuth deg, velocity m/s, SNR dB) of A; B: (azimuth, SNR), B is one
    # sub-band faster than A, in A's range bin.
    ((0.0, -45.0, 0.0, 33.0), (-10.0, 31.0)),   # the rail case: A 2 dB stronger
    ((0.0, -45.0, 0.0, 31.0), (-10.0, 31.0)),   # equal
    ((0.0, 30.0, 5.0, 35.0), (-10.0, 30.0)),
    ((-1.0, -45.0, 0.0, 45.0), (-10.0, 31.0)),  # A strong in the previous bin, leaking
    ((0.0, 0.0, -20.0, 32.0), (20.0, 32.0)),
    ((0.0, -40.0, 3.0, 30.0), (0.0, 33.0)),     # B stronger
], ids=["rail", "equal", "right", "leak", "ahead", "b_stronger"])
def test_two_returns_one_subband_apart_reported_where_they_are(r79, make_scene, a, b):
    """Every point within a range bin of the pair is one of the two returns (velocity within
    a Doppler bin, 0.11 m/s, azimuth within 2 deg: a few CRBs at these SNRs, plus the other
    return's sidelobe), and both are found (each SNR >= 30 dB, far above the threshold)."""
    cfg, proc = r79
    sub_band = 2 * cfg.wavelength_m / (4 * cfg.chirp_period_s) / cfg.n_subbands
    r0 = 60 * cfg.range_resolution_m
    dr, az_a, v_a, snr_a = a
    az_b, snr_b = b
    v_b = v_a + sub_band
    sc = scene_at_snr(cfg, make_scene, [[r0 + dr * cfg.range_resolution_m, az_a, 0, v_a, snr_a],
                                        [r0 + 0.3, az_b, 0, v_b, snr_b]])
    for seed in range(2):
        pc = pipeline.process_frame(cfg, radarsim.simulate_frame(
            cfg, sc, np.random.default_rng(seed)), proc)
        near = pc[(pc.range_m - r0).abs() < 1.5 * cfg.range_resolution_m]
        is_a = ((near.radial_velocity_mps - v_a).abs() < 0.11) & \
            ((near.azimuth_deg - az_a).abs() < 2.0)
        is_b = ((near.radial_velocity_mps - v_b).abs() < 0.11) & \
            ((near.azimuth_deg - az_b).abs() < 2.0)
        assert (is_a | is_b).all(), near[~(is_a | is_b)]
        assert is_a.any() and is_b.any()


def test_coherence_floor_matches_the_echo_statistics():
    """Monte Carlo of the derivation in `coherence_floor`: Tx beams of one echo at coherent
    SNR S (3 Tx of the R79 row at 0, 4, 8 lambda/2, any direction) plus unit complex noise;
    the share with coherence below the floor is the design miss rate 1e-3 (200 000 draws:
    200 expected, within 4 binomial sigma)."""
    rng = np.random.default_rng(22)
    n, n_tx, snr = 200_000, 3, 10 ** 1.3345
    steer = np.exp(1j * 0.7 * np.array([0, 4, 8]))
    amp = np.sqrt(snr / n_tx) * np.exp(2j * np.pi * rng.random((n, 1)))
    noise = (rng.standard_normal((n, n_tx)) + 1j * rng.standard_normal((n, n_tx))) / np.sqrt(2)
    beams = amp * steer + noise
    rho = np.abs((beams * steer.conj()).sum(-1)) ** 2 / (n_tx * (np.abs(beams) ** 2).sum(-1))
    expected = n * 1e-3
    assert abs(np.sum(rho < coherence_floor(n_tx, snr)) - expected) < 4 * np.sqrt(expected)
    # Noise alone: rho ~ Beta(1, n_tx - 1), the F(2, 2 (n_tx - 1)) law at S = 0.
    rho0 = np.abs((noise * steer.conj()).sum(-1)) ** 2 / (n_tx * (np.abs(noise) ** 2).sum(-1))
    assert stats.kstest(rho0, stats.beta(1, n_tx - 1).cdf).pvalue > 1e-3


def test_coherence_floor_needs_two_tx():
    assert coherence_floor(1, 100.0) == 0.0


def test_docstring_examples_run():
    assert doctest.testmod(ddma_order).failed == 0
