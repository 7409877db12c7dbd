"""pipeline.peak_refinement: the windowed spectrum's maximum between bins, against analytic
tones and the Cramer-Rao bound."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize_scalar
from scipy.signal import get_window

from pipeline.peak_refinement import (
    HALF_WIDTH,
    combine_channels,
    dirichlet,
    neighbour_bins,
    peak_patches,
    refine_offset,
    refine_peaks_2d,
)
from pipeline.stages import RangeDopplerHits, refine_hits

N = 384


def _hann_spectrum(freq_bins, n=N, phase=0.0):
    w = get_window("hann", n, fftbins=True)
    return np.fft.fft(w * np.exp(1j * phase + 2j * np.pi * freq_bins * np.arange(n) / n))


def _dirichlet_sum(y, n):
    """The N-point Dirichlet kernel as its defining sum (1/N) sum_n exp(j 2 pi y (n - (N-1)/2)
    / N), real."""
    t = np.arange(n) - (n - 1) / 2
    return np.real(np.exp(2j * np.pi * np.multiply.outer(y, t) / n).mean(axis=-1))


@pytest.mark.parametrize("n", [64, 192, 768])
def test_dirichlet_and_its_derivatives_match_the_sum_and_its_differences(n):
    """Value against the defining sum; D' and D'' against central differences of the sum
    (step 1e-4 bin: truncation ~1e-8, rounding ~1e-12 / 1e-8 of the values), across the
    eleven bins, close to and exactly at a bin (the Taylor branch) and at its boundary."""
    h = 1e-4
    ys = np.concatenate([np.linspace(-5.75, 5.75, 233), [0.0, 3e-5, -9.9e-5, 1.0001e-4, 2.0]])
    got = np.array([dirichlet(float(y), n) for y in ys])
    ref, up, down = _dirichlet_sum(ys, n), _dirichlet_sum(ys + h, n), _dirichlet_sum(ys - h, n)
    np.testing.assert_allclose(got[:, 0], ref, atol=1e-12)
    np.testing.assert_allclose(got[:, 1], (up - down) / (2 * h), atol=1e-6)
    np.testing.assert_allclose(got[:, 2], (up - 2 * ref + down) / h ** 2, atol=1e-4)


@pytest.mark.parametrize("offset", [-0.49, -0.3, 0.0, 0.17, 0.45])
def test_noise_free_hann_tone_is_found_within_truncation_error(offset):
    """Eleven bins of a Hann spectrum reproduce its maximum to < 1e-3 bin (the Dirichlet
    interpolation's truncation; the 3-point start is off by up to 0.02 bin)."""
    k = 100
    x = _hann_spectrum(k + offset)
    idx, _ = neighbour_bins(np.array([k]), N, cyclic=True)
    got = refine_offset(x[idx], np.array([0.0]), N)
    assert got[0] == pytest.approx(offset, abs=1e-3)


def test_newton_reaches_the_maximum_of_the_interpolated_spectrum():
    """Whatever the truncation does, the steps land on the maximum of the eleven-bin
    interpolation itself (a bounded scalar search on the same sum, which resolves the flat
    maximum to ~1e-8 bin), from a start 0.2 bin off, on noisy tones."""
    rng = np.random.default_rng(3)
    k, m = 100, np.arange(-HALF_WIDTH, HALF_WIDTH + 1)
    for offset in rng.uniform(-0.45, 0.45, 6):
        x = _hann_spectrum(k + offset) + 3.0 * (rng.standard_normal(N)
                                                + 1j * rng.standard_normal(N))
        b = x[k + m]

        def power(d):
            return abs(sum(b[i] * dirichlet(d - mi, N)[0] * np.exp(1j * np.pi * mi * (N - 1) / N)
                           for i, mi in enumerate(m))) ** 2
        best = minimize_scalar(lambda d: -power(d), bounds=(offset - 0.3, offset + 0.3),
                               method="bounded", options={"xatol": 1e-11}).x
        got = refine_offset(b[None], np.array([offset + 0.2]), N)[0]
        assert got == pytest.approx(best, abs=1e-6)


def test_channels_with_own_phases_combine_coherently():
    k, offset = 50, 0.31
    chans = np.stack([_hann_spectrum(k + offset, phase=p) for p in (0.0, 1.0, 2.5, -2.0)])
    idx, _ = neighbour_bins(np.array([k]), N, cyclic=True)
    b = combine_channels(chans[:, idx[0]][None])
    assert refine_offset(b, np.array([0.0]), N)[0] == pytest.approx(offset, abs=1e-3)


def test_too_few_bins_on_the_axis_keep_the_start():
    idx, on = neighbour_bins(np.array([1, 100]), 192, cyclic=False)
    assert not on[0, :HALF_WIDTH - 1].any() and on[1].all()
    x = _hann_spectrum(1.2, n=N)[idx]
    b = np.where(on, x, 0.0)
    got = refine_offset(b, np.array([0.1, 0.1]), N)
    assert got[0] == 0.1  # one bin below the peak: fewer than MIN_HALF_WIDTH


def test_two_dimensional_tone_found_on_both_axes():
    nr, nd, r, d, dr, dd = 64, 128, 20, 40, -0.27, 0.38
    wr = get_window("hann", nr, fftbins=True)
    wd = get_window("hann", nd, fftbins=True)
    sig = (wd[:, None] * wr[None, :] * np.exp(2j * np.pi * ((d + dd) * np.arange(nd)[:, None] / nd
                                                          + (r + dr) * np.arange(nr) / nr)))
    spec = np.fft.fft2(sig).T  # (range, Doppler)
    ri, on = neighbour_bins(np.array([r]), nr, cyclic=False)
    di, _ = neighbour_bins(np.array([d]), nd, cyclic=True)
    patch = spec[ri[:, :, None], di[:, None, :]][:, None]  # (1, 1, Mr, Md)
    off_r, off_d = refine_peaks_2d(patch, on, np.array([0.0]), np.array([0.0]), nr, nd)
    assert off_r[0] == pytest.approx(dr, abs=2e-3) and off_d[0] == pytest.approx(dd, abs=2e-3)


def test_two_dimensional_range_edge_keeps_the_start_or_refines_with_enough_bins():
    """Range bins off the axis count as zeros: one bin below the peak (r = 1) keeps the range
    start, two (r = 2, `MIN_HALF_WIDTH`) refine it; Doppler (cyclic) is refined in both."""
    nr, nd, d, dr, dd = 64, 128, 40, 0.21, -0.33
    wr = get_window("hann", nr, fftbins=True)
    wd = get_window("hann", nd, fftbins=True)
    for r, refined in ((1, False), (2, True)):
        sig = wd[:, None] * wr[None, :] * np.exp(2j * np.pi * (
            (d + dd) * np.arange(nd)[:, None] / nd + (r + dr) * np.arange(nr) / nr))
        spec = np.fft.fft2(sig).T
        ri, on = neighbour_bins(np.array([r]), nr, cyclic=False)
        di, _ = neighbour_bins(np.array([d]), nd, cyclic=True)
        patch = spec[ri[:, :, None], di[:, None, :]][:, None]
        off_r, off_d = refine_peaks_2d(patch, on, np.array([0.1]), np.array([0.0]), nr, nd)
        assert off_d[0] == pytest.approx(dd, abs=2e-3)
        if refined:
            # Two bins below the peak: the truncation moves it by up to ~4e-3 bin.
            assert off_r[0] == pytest.approx(dr, abs=5e-3)
        else:
            assert off_r[0] == 0.1


def test_peak_patches_are_the_cube_at_the_neighbour_bins():
    """`peak_patches`: each peak's transmitters' Doppler rows, every Rx, at its neighbour range
    bins (clipped at the range axis' ends), as numpy's fancy indexing reads them."""
    rng = np.random.default_rng(3)
    spec = (rng.standard_normal((96, 3, 40)) + 1j * rng.standard_normal((96, 3, 40))
            ).astype(np.complex64)
    r = np.array([0, 17, 39, 3])
    r_idx, _ = neighbour_bins(r, 40, cyclic=False)
    d_idx, _ = neighbour_bins(np.array([5, 90, 47, 0]), 96, cyclic=True)
    chirps = (d_idx[:, None, :] + 24 * np.arange(4)[None, :, None]) % 96  # (n, T, Md)
    want = spec[chirps[:, :, None, None, :], np.arange(3)[None, None, :, None, None],
                r_idx[:, None, None, :, None]].reshape(4, 12, r_idx.shape[1], d_idx.shape[1])
    got = peak_patches(spec, chirps, r_idx)
    assert got.flags.c_contiguous and got.dtype == np.complex64
    assert got.tobytes() == want.tobytes()


def test_refine_hits_reads_the_slot_spectra_as_fancy_indexing_does():
    """`stages.refine_hits` on a slot chain's (D, C, B) spectra (`peak_patches`, the channels
    as one transmitter) gives the offsets of `refine_peaks_2d` on the patches numpy's fancy
    indexing reads from the (B, D, C) view, bit for bit (range edges, Doppler wrap)."""
    rng = np.random.default_rng(5)
    spec = (rng.standard_normal((48, 8, 40)) + 1j * rng.standard_normal((48, 8, 40))
            ).astype(np.complex64)
    r, d = np.array([0, 17, 39, 3]), np.array([5, 47, 20, 0])
    hits = RangeDopplerHits(r, d, np.ones(4, np.float32), r + rng.uniform(-0.4, 0.4, 4),
                            rng.uniform(-0.4, 0.4, 4), 8)
    got = refine_hits(hits, spec, 80)
    cube = np.moveaxis(spec, 2, 0)  # (B, D, C)
    r_idx, on = neighbour_bins(r, 40, cyclic=False)
    d_idx, _ = neighbour_bins(d, 48, cyclic=True)
    patch = np.moveaxis(cube[r_idx[:, :, None], d_idx[:, None, :]], 3, 1)
    r_off, d_off = refine_peaks_2d(patch, on, hits.range_pos - r, hits.doppler_offset, 80, 48)
    assert got.range_pos.tobytes() == (r + r_off).tobytes()
    assert got.doppler_offset.tobytes() == d_off.tobytes()


def test_monte_carlo_rmse_near_the_hann_ml_and_unbiased():
    """At 20 dB detection SNR a single Hann-windowed tone's windowed-periodogram maximum has an
    RMSE of 1.25 x the CRB of that SNR (Kay 1993, linearised; the 3-point log-parabola 1.5 x):
    bound 1.35 for 2000 trials (standard error of an RMSE ratio ~1.6 %); the mean error within
    four of its standard errors of zero."""
    rng = np.random.default_rng(7)
    n_trials, k, snr_db = 2000, 100, 20.0
    w = get_window("hann", N, fftbins=True)
    gain = w.sum() ** 2 / np.sum(w ** 2)
    amp = np.sqrt(10 ** (snr_db / 10) / gain)
    d = rng.uniform(-0.5, 0.5, n_trials)
    x = amp * np.exp(2j * np.pi * (k + d)[:, None] * np.arange(N) / N) + (
        rng.standard_normal((n_trials, N)) + 1j * rng.standard_normal((n_trials, N))) / np.sqrt(2)
    spec = np.fft.fft(x * w, axis=1)
    peak = k - 2 + np.argmax(np.abs(spec[:, k - 2:k + 3]), axis=1)
    idx, _ = neighbour_bins(peak, N, cyclic=True)
    est = peak + refine_offset(spec[np.arange(n_trials)[:, None], idx], np.zeros(n_trials), N)
    err = est - (k + d)
    crb = np.sqrt(3) / (np.pi * np.sqrt(2 * 10 ** (snr_db / 10)))
    assert np.sqrt(np.mean(err ** 2)) / crb < 1.35
    assert abs(err.mean()) < 4 * err.std() / np.sqrt(n_trials)
