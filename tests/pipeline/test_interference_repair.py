"""Interference repair methods (pipeline.interference_repair), each against its analytic effect."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.signal

import pipeline
from pipeline import interference_repair as ir
from pipeline.chirp_level.interference import zero_flagged

N = 384
T = np.arange(N)
HANN = scipy.signal.get_window("hann", N).astype(np.float32)


def tones(freqs_cyc, amps=None, phases=None):
    amps = np.ones(len(freqs_cyc)) if amps is None else amps
    phases = np.zeros(len(freqs_cyc)) if phases is None else phases
    return sum(a * np.cos(2 * np.pi * f * T + p)
               for f, a, p in zip(freqs_cyc, amps, phases)).astype(np.float32)


def burst_flags(rows=1, at=(150, 190)):
    f = np.zeros((rows, N), dtype=bool)
    f[:, list(at)] = True
    return f


def test_zero_is_the_chips_zeroing_bit_for_bit():
    rng = np.random.default_rng(1)
    x = rng.normal(size=(6, N)).astype(np.float32)
    flags = rng.random((6, N)) < 0.02
    flags[0, :2] = flags[1, -2:] = True
    a = zero_flagged(x.copy(), flags, 3)
    b = ir.repair(x.copy(), flags, HANN, 3, ir.MITIGATIONS["zero"])
    assert np.array_equal(a, b)


def test_close_gaps_closes_short_inner_gaps_only():
    m = np.zeros((1, 40), dtype=bool)
    m[0, [5, 9, 30]] = True  # gaps of 3 and 20 samples
    c = ir.close_gaps(m, 4)
    assert c[0, 5:10].all() and not c[0, 10:30].any() and not c[0, :5].any()
    assert ir.close_gaps(m, 20)[0, 5:31].all() and not ir.close_gaps(m, 20)[0, 31:].any()


def test_mask_closes_then_widens():
    m = ir.Mitigation(name="x", description="", close_gap_samples=48, extend_samples=12)
    mask = m.mask(burst_flags(), 3)
    assert np.flatnonzero(mask[0]).tolist() == list(range(150 - 15, 190 + 16))


def test_zero_compensated_restores_an_on_bin_echo():
    """Zeroing a run of samples scales an on-bin tone's range-FFT peak by sum(w kept) /
    sum(w); the compensated method multiplies that back. What remains is the tone's
    negative-frequency image leaking through the gap: |sum over the gap of w e^{-j 2 pi 2 k0 t
    / N}| / sum(w kept) relative, the tolerance."""
    k0 = 60
    x = tones([k0 / N])[None]
    clean = np.abs(np.fft.rfft(x * HANN)[0, k0])
    flags = burst_flags()
    for name in ("zero", "zero_compensated"):
        mask = ir.MITIGATIONS[name].mask(flags, 3)[0]
        kept = HANN[~mask].sum()
        image = np.abs(np.sum(HANN[mask] * np.exp(-2j * np.pi * 2 * k0 * T[mask] / N)))
        tol = image / kept + 1e-5
        y = ir.repair(x.copy(), flags, HANN, 3, ir.MITIGATIONS[name])
        gain = np.abs(np.fft.rfft(y * HANN)[0, k0]) / clean
        expected = 1.0 if ir.MITIGATIONS[name].compensate else kept / HANN.sum()
        assert gain == pytest.approx(expected, abs=tol), name
        assert (y[0, mask] == 0).all()


def test_windowed_zero_tapers_with_the_demos_hann_edges():
    g = ir._taper_gain(ir.widen(burst_flags(at=(100,)), 0), 5)[0]
    h16 = scipy.signal.get_window("hann", 16, fftbins=False)
    assert g[100] == 0 and (g[:94] == 1).all() and (g[107:] == 1).all()
    assert g[101:106] == pytest.approx(h16[2:7], rel=1e-6)
    assert g[99:94:-1] == pytest.approx(h16[2:7], rel=1e-6)


def test_windowed_zero_leaks_less_than_a_hard_zero():
    """A tapered gap's spectrum falls off faster: a strong echo left in the chirp spills less
    energy into range bins far from its own."""
    k0 = 60
    x = tones([k0 / N], [1000.0])[None]
    flags = burst_flags()
    far = np.r_[0:k0 - 30, k0 + 30:N // 2]

    def leak(name):
        y = ir.repair(x.copy(), flags, HANN, 3, ir.MITIGATIONS[name])
        return np.sum(np.abs(np.fft.rfft(y * HANN)[0, far]) ** 2)
    assert leak("windowed_zero") < 0.5 * leak("zero_compensated")


def test_interpolate_reconstructs_a_line_exactly():
    """A line through the gap is reconstructed exactly (after the recentring every non-chip
    method applies: the mean of the kept samples is the chirp's new DC)."""
    m = ir.MITIGATIONS["interpolate"]
    x = (0.5 * T + 3.0).astype(np.float32)[None]
    kept = ~m.mask(burst_flags(), 3)
    y = ir.repair(x.copy(), burst_flags(), HANN, 3, m)
    assert y == pytest.approx(x - x[kept].mean(), abs=1e-3)


@pytest.mark.parametrize("at", [(150, 190), (2,), (N - 3,)], ids=["inner", "start", "end"])
def test_ar_reconstructs_a_sum_of_tones(at):
    """A sum of K real tones obeys an AR(2K) recursion exactly: the predictor fitted on the
    kept samples of chirps that carry the same tones with other phases (Doppler) reconstructs
    the gap to float precision (also at a chirp's ends, from one side)."""
    rng = np.random.default_rng(3)
    ph = rng.uniform(0, 2 * np.pi, (16, 4))
    rows = np.stack([tones([0.031, 0.13, 0.31, 0.42], [1.0, 0.5, 2.0, 0.3], p) for p in ph])
    rows -= rows.mean(axis=-1, keepdims=True)  # as the chain's DC removal leaves them
    flags = burst_flags(16, at)
    m = ir.Mitigation(name="ar24", description="", fill="ar", ar_order=24,
                      close_gap_samples=ir.CLOSE_GAP_SAMPLES, extend_samples=ir.EXTEND_SAMPLES)
    y = ir.repair(rows.copy(), flags, HANN, 3, m)
    mask = m.mask(flags, 3)
    err = np.sqrt(np.mean((y - rows)[mask] ** 2)) / np.sqrt(np.mean(rows ** 2))
    assert err < 1e-3
    assert np.array_equal(y[~mask], rows[~mask])


def test_ar_with_noise_errs_by_about_the_noise():
    """With white noise of sigma the gap is filled with the predicted echoes only: the error
    is the missing noise (rms ~ sigma), not the echo (amplitude 100 sigma)."""
    rng = np.random.default_rng(0)
    x = tones([0.07, 0.21], [100.0, 60.0])
    rows = (x + rng.normal(size=(8, N))).astype(np.float32)
    flags = burst_flags(8)
    y = ir.repair(rows.copy(), flags, HANN, 3, ir.MITIGATIONS["ar"])
    mask = ir.MITIGATIONS["ar"].mask(flags, 3)
    err = (y - rows)[mask]
    assert np.sqrt(np.mean(err ** 2)) < 3.0


def test_registry_lookup_names_the_known_methods():
    with pytest.raises(ValueError, match=r"intf_mitigation='median' is not one of \['ar'"):
        ir.get_mitigation("median")


def test_processing_config_validates_the_method():
    with pytest.raises(ValueError, match="intf_mitigation"):
        pipeline.ProcessingConfig(intf_mitigation="median")


@pytest.mark.parametrize("field, value", [("fill", "median"), ("close_gap_samples", -1),
                                          ("extend_samples", 1.5), ("ar_order", True)])
def test_method_fields_validated(field, value):
    with pytest.raises(ValueError, match=field):
        ir.Mitigation(name="x", description="", **{field: value})


@pytest.mark.parametrize("name", sorted(ir.MITIGATIONS))
def test_every_method_repairs_iq_rows(name):
    """Complex (I/Q) chirps: a complex tone outside the gap is left as it was and the gap is
    filled with finite values (the tone for `ar`)."""
    rng = np.random.default_rng(2)
    ph = rng.uniform(0, 2 * np.pi, 8)
    rows = np.exp(1j * (2 * np.pi * 0.17 * T[None] + ph[:, None])).astype(np.complex64)
    flags = burst_flags(8)
    m = ir.MITIGATIONS[name]
    y = ir.repair(rows.copy(), flags, HANN, 3, m)
    mask = m.mask(flags, 3)
    assert np.isfinite(y).all()
    if m.fill == "ar":
        assert np.max(np.abs(y - rows)[mask]) < 1e-2
