"""The noise-floor rise metric against the closed-form burst energy."""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline import chirp_level as cl
from pipeline.chirp_level.noise_floor import _bin_members, _power_median
from pipeline.kernels import window
from radarsim import interference as itf_mod
from radarsim.frontend import IF_LOWPASS_HZ, IF_LOWPASS_ORDER

from .helpers import empty, one_interferer


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


def test_noise_floor_rise_without_mitigation_matches_burst_energy(cfg):
    """After the Doppler FFT the bursts spread over all cells: rise = 10 log10(1 + E_I / E_N)
    with E_I from the closed-form burst timing and one-way power, within 0.5 dB."""
    itf = one_interferer()
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(5), itf)
    proc = pipeline.ProcessingConfig().replace(dc_removal=True, interference_mitigation=False,
                                     compression=False)
    rise = cl.noise_floor_rise(cfg, adc, proc, range_stride=1)
    win = window("hann", cfg.n_samples)
    e_n = cfg.n_chirps * cfg.n_rx * cfg.noise_rms_lsb ** 2 * np.sum(win.astype(float) ** 2)
    want = 10 * np.log10(1 + _burst_energy(cfg, itf, win) / e_n)
    assert want > 3  # a real rise to check
    assert rise.doppler_db == pytest.approx(want, abs=0.5)
    clean = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(5))
    assert abs(cl.noise_floor_rise(cfg, clean, proc).doppler_db) < 0.2


@pytest.mark.parametrize("shape", [(768, 4, 192), (768, 4, 191), (5, 3, 2), (1, 1, 1), (2, 1, 1)])
def test_power_median_is_numpys_median_of_the_power_bit_for_bit(shape):
    """The floor's compiled power map + radix select equals numpy.median(re^2 + im^2)
    exactly: strided views (every 4th range bin, as the floor reads them), odd and even
    sizes, 60 dB of scale, ties, zeros, and the maps it hands to numpy (NaN, inf)."""
    g = np.random.default_rng(11)
    for trial in range(12):
        z = (g.standard_normal(shape) + 1j * g.standard_normal(shape)).astype(np.complex64)
        z *= np.float32(10 ** g.uniform(-15, 15))
        if trial % 3 == 1:
            z = (np.round(z.real) + 1j * np.round(z.imag)).astype(np.complex64)  # ties
        if trial % 4 == 2:
            z.reshape(-1)[: z.size // 3] = 0
        sub = z[:, :, 1::4] if shape[2] > 4 else z
        special = {5: np.nan, 9: np.inf}.get(trial)
        if special is not None:
            sub = sub.copy()
            sub.reshape(-1)[-1] = special
        want, got = np.median(sub.real ** 2 + sub.imag ** 2), _power_median(sub)
        assert type(got) is type(want)
        assert (np.isnan(want) and np.isnan(got)) or got == want, (trial, want, got)


def test_bin_members_are_numpys_masked_values_in_order():
    """The one-pass gather of one 12-bit bin's values equals numpy's boolean mask, order
    included, for the bin holding the median, an empty bin and the last element's bin."""
    g = np.random.default_rng(3)
    a = (g.standard_normal(10_001) ** 2).astype(np.float32)
    top = a.view(np.uint32) >> 20
    for b in (int(np.median(top)), int(top.max()) + 1, int(top[-1])):
        want = a[top == b]
        got = _bin_members(a, b, want.size)
        assert got.dtype == np.float32 and np.array_equal(got.view(np.uint32),
                                                           want.view(np.uint32))
