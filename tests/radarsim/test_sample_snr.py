"""`radarsim.expected_sample_snr_db` and the range-FFT gain it documents: 10 log10(N / 2) for a
real ADC, 10 log10(N) for a complex one (not 2 N), measured on simulated frames."""
import numpy as np
import pytest

import radarsim
from radarsim.config import C_MPS


@pytest.mark.parametrize("mode, gain", [("real", 0.5), ("complex1x", 1.0)])
def test_range_fft_gain_over_the_sample_snr(mode, gain):
    """A tone on a range-bin centre at about 1 dB per sample (quantisation far below the
    thermal noise): bin SNR - sample SNR = 10 log10(gain x N), rectangular window. Tolerance:
    the noise estimate averages 4 frames x 64 chirps x 48 bins (12 288 exponential cells,
    0.04 dB) and the tone 256 cells at ~22 dB (0.03 dB): 0.3 dB."""
    cfg = radarsim.RadarConfig.from_fields(chip="AWR1843", adc_mode=mode, mimo="tdma", n_tx=1,
                                           tx_channels=(1,), n_rx=1, rx_channels=(1,), n_chirps=64,
                                           n_samples=256, adc_rate_sps=10e6, slope_hz_per_s=30e12,
                                           ramp_end_time_s=40e-6, chirp_period_s=45e-6,
                                           antenna_pattern="isotropic")
    n = cfg.n_samples
    r = (n // 8) * cfg.adc_rate_sps / n * C_MPS / (2 * cfg.slope_hz_per_s)
    sc = radarsim.Scatterers.from_spherical(np.array([r]), np.zeros(1), np.zeros(1),
                                            np.zeros(1), np.array([0.1]))
    sample_db = radarsim.expected_sample_snr_db(cfg, sc)[0]
    assert -2.0 < sample_db < 4.0
    p = np.concatenate([np.abs(np.fft.fft(radarsim.simulate_frame(
        cfg, sc, np.random.default_rng(seed)).astype(np.complex128), axis=-1)) ** 2
        for seed in range(4)]).reshape(-1, n)
    tone, noise = p[:, n // 8].mean(), p[:, 3 * n // 16: 3 * n // 8].mean()
    got = 10 * np.log10(tone / noise - 1) - sample_db
    assert got == pytest.approx(10 * np.log10(gain * n), abs=0.3)
