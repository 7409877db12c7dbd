"""Interference repair methods (pipeline.interference.methods), each against its analytic effect."""
from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest
import scipy.signal

import pipeline
from pipeline import threads
from pipeline.interference import FrameRows, close_gaps, fills, widen, zero_flagged
from pipeline.interference import lowrank as lr
from pipeline.interference import methods as ir

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
    c = close_gaps(m, 4)
    assert c[0, 5:10].all() and not c[0, 10:30].any() and not c[0, :5].any()
    assert close_gaps(m, 20)[0, 5:31].all() and not close_gaps(m, 20)[0, 31:].any()


def test_mask_closes_then_widens():
    m = ir.ZeroRepair(name="x", description="", close_gap_samples=48, extend_samples=12)
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
    g = fills.taper_gain(widen(burst_flags(at=(100,)), 0), 5)[0]
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
    m = ir.ArRepair(name="ar24", description="", ar_order=24,
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
        pipeline.ProcessingConfig().replace(intf_mitigation="median")


@pytest.mark.parametrize("kind, field, value", [
    (ir.ZeroRepair, "close_gap_samples", -1), (ir.InterpolateRepair, "extend_samples", 1.5),
    (ir.ArRepair, "ar_order", True), (ir.TaperRepair, "taper_samples", -1),
    (ir.LowrankRepair, "rank_max", -2), (ir.LowrankRepair, "grow_reach_samples", 2.0),
    (ir.LowrankRepair, "rank_snr_gate_db", -3.0), (ir.LowrankRepair, "grow_sigma", float("nan"))])
def test_method_fields_validated(kind, field, value):
    with pytest.raises(ValueError, match=field):
        kind(name="x", description="", **{field: value})


@pytest.mark.parametrize("kind, field, value, limit", [
    (ir.LowrankRepair, "rank_snr_gate_db", 1e300, "150"), (ir.ArRepair, "ar_order", 10**6, "512"),
    (ir.LowrankRepair, "grow_sigma", 1e9, "100"), (ir.ZeroRepair, "cancel_tones", 10**4, "64"),
    (ir.LowrankRepair, "rank_max", 10**4, "256"),
    (ir.ZeroRepair, "close_gap_samples", 10**7, "65535"),
    (ir.InterpolateRepair, "extend_samples", 10**7, "65535"),
    (ir.TaperRepair, "taper_samples", 10**7, "65535"),
    (ir.LowrankRepair, "grow_reach_samples", 10**7, "65535")])
def test_method_fields_bounded(kind, field, value, limit):
    """rank_snr_gate_db=1e300 overflowed at the first interference frame; ar_order=10**6 ran
    for minutes (one Levinson step per order)."""
    with pytest.raises(ValueError, match=re.escape(f"{field}={value!r} exceeds {limit} (")):
        kind(name="x", description="", **{field: value})


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
    if isinstance(m, ir.ArRepair):
        assert np.max(np.abs(y - rows)[mask]) < 1e-2


# ------------------------------------------------------------------------------- lowrank
def frame_of(rows_clean, rows_hit, n_rx=4):
    """A FrameRows whose first len(rows_hit) rows are the hit ones (n_rx per chirp)."""
    samples = np.concatenate([rows_hit, rows_clean])
    return FrameRows(samples, np.arange(len(rows_hit)), n_rx)


def echo_rows(n_rows, freqs, amps, rng, noise=0.0):
    """Chirps carrying the same tones with random phases (Doppler, Tx code, Rx), plus
    white noise of rms `noise`, each row's mean removed (the chain's DC removal)."""
    ph = rng.uniform(0, 2 * np.pi, (n_rows, len(freqs)))
    rows = np.stack([tones(freqs, amps, p) for p in ph]) + noise * rng.standard_normal(
        (n_rows, N))
    return (rows - rows.mean(axis=-1, keepdims=True)).astype(np.float32)


@pytest.mark.parametrize("at", [(150, 190), (2,), (N - 3,)], ids=["inner", "start", "end"])
def test_lowrank_reconstructs_off_grid_tones_across_a_gap(at):
    """Echoes are the same tones in every chirp: learnt from the unhit chirps, the gap of a
    hit chirp is the LS continuation of its kept samples, exact (float32 precision) for any
    beat frequencies, off the FFT grid and closer than a bin (0.0310 / 0.0335 cycles per
    sample: 0.96 bin apart), also at a chirp's ends."""
    rng = np.random.default_rng(3)
    f, a = [0.0310, 0.0335, 0.1234, 0.3111], [1000.0, 300.0, 50.0, 20.0]
    clean, hit = echo_rows(300, f, a, rng), echo_rows(8, f, a, rng)
    flags = burst_flags(8, at)
    m = ir.MITIGATIONS["lowrank"]
    y = ir.repair(hit.copy(), flags, HANN, 3, m, frame=frame_of(clean, hit))
    mask = m.mask(flags, 3)
    err = np.sqrt(np.mean((y - hit)[mask] ** 2)) / np.sqrt(np.mean(hit ** 2))
    assert err < 1e-4
    assert np.max(np.abs(y - hit)[~mask]) < 1e-5 * np.abs(hit).max()  # kept (mean was 0)


def test_lowrank_errs_by_the_missing_noise():
    """With white noise of sigma, the gap holds the LMMSE estimate of the echoes (amplitude
    1000 sigma) without the noise: the error is the noise (rms sigma) plus the estimate's own
    error, a fraction k / n_kept of it: rms within 1.15 sigma."""
    rng = np.random.default_rng(0)
    f, a = [0.012, 0.07, 0.21], [1000.0, 300.0, 60.0]
    clean, hit = echo_rows(256, f, a, rng, 1.0), echo_rows(64, f, a, rng, 1.0)
    truth = hit.copy()
    flags = burst_flags(64)
    m = ir.MITIGATIONS["lowrank"]
    y = ir.repair(hit, flags, HANN, 3, m, frame=frame_of(clean, truth, n_rx=1))
    err = (y - truth)[m.mask(flags, 3)]
    assert np.sqrt(np.mean(err ** 2)) < 1.15
    assert np.sqrt(np.mean(err ** 2)) > 0.85  # the noise is not reconstructed


def test_lowrank_basis_keeps_the_echoes_and_measures_the_noise():
    """Three real tones span 6 dimensions (cos, sin): with noise sigma = 1 the basis keeps
    those 6 (plus the constant) and reads sigma^2 within 5 %."""
    rng = np.random.default_rng(1)
    ref = echo_rows(256, [0.05, 0.11, 0.3], [50.0, 20.0, 10.0], rng, 1.0)
    b = lr.fast_time_basis(ref, 24, 10.0)
    assert b.vectors.shape == (N, 7)
    assert b.vectors.T @ b.vectors == pytest.approx(np.eye(7), abs=1e-5)
    assert b.noise_var == pytest.approx(1.0, rel=0.05)
    assert b.shrink[0] == lr.SHRINK_FLOOR and (b.shrink[1:] < 1e-3).all()  # 40 dB echoes


def test_lowrank_unites_a_chirps_flags_and_grows_over_the_unflagged_burst():
    """A burst (amplitude 40 sigma) over samples 130-209 of both Rx of a chirp, flagged at 3
    samples of one Rx only: the chirp's rows share one mask, grown over the burst from the
    fit's residual, and the repaired rows are within the noise of the clean ones; without
    growing, the burst's unflagged skirt stays (error >> sigma)."""
    rng = np.random.default_rng(5)
    f, a = [0.02, 0.09], [500.0, 100.0]
    clean, truth = echo_rows(256, f, a, rng, 1.0), echo_rows(2, f, a, rng, 1.0)
    burst = np.zeros((2, N), np.float32)
    burst[:, 130:210] = 40 * np.cos(2 * np.pi * 0.37 * np.arange(80) ** 1.3)
    flags = np.zeros((2, N), bool)
    flags[0, [165, 168, 172]] = True
    frame = frame_of(clean, truth + burst, n_rx=2)
    grown = ir.repair((truth + burst), flags, HANN, 3, ir.MITIGATIONS["lowrank"], frame=frame)
    fixed = ir.repair((truth + burst), flags, HANN, 3,
                      dataclasses.replace(ir.MITIGATIONS["lowrank"], grow_sigma=0.0), frame=frame)
    rms = lambda d: float(np.sqrt(np.mean(d ** 2)))  # noqa: E731
    assert rms(grown - truth) < 1.0  # the noise in the gap is missing, the rest is kept
    assert rms(fixed - truth) > 5.0


def test_burst_runs_are_the_closed_and_widened_flags():
    rng = np.random.default_rng(7)
    flags = rng.random((50, N)) < 0.01
    runs = lr.burst_runs(flags, 48, 15)
    assert np.array_equal(lr.runs_mask(runs, 50, N), widen(close_gaps(flags, 48), 15))


@pytest.mark.parametrize("dtype", [np.float64, np.complex128])
def test_compiled_fit_is_the_masked_least_squares_solve(dtype):
    """The compiled per-burst Cholesky and triangular solves give numpy's solution of
    (I - B_G^H B_G + diag(d)) c = B_K^H y_K for each row of a burst (B orthonormal, G the
    masked runs, K the kept samples)."""
    rng = np.random.default_rng(2)
    n, k = 40, 6
    cplx = 1j if dtype is np.complex128 else 0
    b = np.linalg.qr(rng.standard_normal((n, k)) + cplx * rng.standard_normal((n, k)))[0]
    prefix = lr._gram_prefix(np.ascontiguousarray(b.conj()), b)
    shrink = np.r_[lr.SHRINK_FLOOR, rng.uniform(0, 1, k - 1)]
    run_s, run_e = np.array([3, 20]), np.array([9, 31])
    lt = np.zeros((k, k), dtype)
    lr._cholesky(prefix, shrink, run_s, run_e, 2, lt, np.zeros(prefix.shape[1], dtype))
    low = np.triu(lt).T
    # the rows in the chain's type (float32 / complex64: the product's compiled signature)
    x = (rng.standard_normal((3, n)) + cplx * rng.standard_normal((3, n))).astype(
        np.complex64 if cplx else np.float32)
    c = np.zeros((k, 4), dtype)  # 3 rows, padded to the 4 the solves take at a time
    lr._fit_rows(x, x @ b.conj(), np.ascontiguousarray(b.conj()), lt, run_s, run_e, 2, 0, 3,
                 np.zeros((4, k), dtype), c)
    kept = np.ones(n, bool)
    kept[3:9] = kept[20:31] = False
    a = b[kept].conj().T @ b[kept] + np.diag(shrink)
    assert low @ low.conj().T == pytest.approx(a, abs=1e-12)
    for r in range(3):
        assert c[:, r] == pytest.approx(np.linalg.solve(a, b[kept].conj().T @ x[r, kept]),
                                     rel=1e-10, abs=1e-12)


@pytest.mark.parametrize("dtype", [np.float64, np.complex128])
@pytest.mark.parametrize("nr", [3, 4, 5, 8])
def test_compiled_model_of_rows_together_is_the_model_of_each_row(dtype, nr):
    """The compiled model of a burst's rows (four rows at a time, then the rest) at samples
    t0 .. t1 - 1 is, bit for bit, each row's model on its own (the sum over the components
    from the first; for real rows numpy's); samples outside are left alone."""
    rng = np.random.default_rng(3)
    k, n, t0, t1 = 7, 50, 11, 37
    cplx = 1j if dtype is np.complex128 else 0
    vec_t = rng.standard_normal((k, n)) + cplx * rng.standard_normal((k, n))
    c = rng.standard_normal((k, 8)) + cplx * rng.standard_normal((k, 8))
    buf = np.full((nr, n), 5.0, dtype)
    lr._evaluate(vec_t, c, nr, t0, t1, buf)
    for r in range(nr):
        one = np.full((1, n), 5.0, dtype)
        lr._evaluate(vec_t, np.ascontiguousarray(c[:, r:r + 1]), 1, t0, t1, one)
        assert buf[r].tobytes() == one[0].tobytes()
        if not cplx:
            want = np.zeros(t1 - t0, dtype)
            for i in range(k):
                want += c[i, r] * vec_t[i, t0:t1]
            assert buf[r, t0:t1].tobytes() == want.tobytes()
    assert (buf[:, :t0] == 5).all() and (buf[:, t1:] == 5).all()


def test_lowrank_fill_is_the_same_in_one_part_and_in_two(monkeypatch):
    """The bursts are repaired in parts on the cores (`pipeline.threads`): the same bits and
    masks whether they run in one part (`threads.inline`) or two (forced, so a one-core
    machine tests the split too)."""
    monkeypatch.setattr(threads, "N_PARTS", 2)
    rng = np.random.default_rng(11)
    f, a = [0.02, 0.09, 0.31], [500.0, 100.0, 30.0]
    clean, hit = echo_rows(256, f, a, rng, 1.0), echo_rows(40, f, a, rng, 1.0)
    hit[:, 150:200] += 40 * rng.standard_normal((40, 50)).astype(np.float32)
    flags = np.zeros(hit.shape, bool)
    flags[:, [160, 175, 190]] = True
    basis = lr.fast_time_basis(clean, 24, 10.0)
    bursts = np.arange(40) // 4
    two = lr.lowrank_fill(hit.copy(), flags, bursts, basis, 48, 3, 5.0, 32)
    with threads.inline():
        one = lr.lowrank_fill(hit.copy(), flags, bursts, basis, 48, 3, 5.0, 32)
    assert two[0].tobytes() == one[0].tobytes() and np.array_equal(two[1], one[1])
    # The flags 160 / 175 / 190 closed over 48 samples and widened by 3 cover [157, 194), 37
    # samples; the burst covers [150, 200): the mask must grow over all of it in every row.
    assert two[1][:, 150:200].all()


def _fit_reference(x, rhs, vec_c, lt, runs, rows):
    """_fit_rows' values by its textbook loops in Python floats (each value updated in place:
    the masked runs subtracted sample by sample, the forward solve by columns, the backward
    solve by rows), the reference its register-held, 4-row solves must equal bit for bit."""
    k = lt.shape[0]
    out = []
    for r in rows:
        y = [rhs[r, i] for i in range(k)]
        for s, e in runs:
            for t in range(s, e):
                for i in range(k):
                    y[i] -= x[r, t] * vec_c[t, i]
        for m in range(k):
            y[m] = y[m] / lt[m, m]
            for i in range(m + 1, k):
                y[i] -= lt[m, i] * y[m]
        c = [0.0] * k
        for i in reversed(range(k)):
            c[i] = y[i]
            for m in range(i + 1, k):
                c[i] -= np.conj(lt[i, m]) * c[m]
            c[i] = c[i] / lt[i, i]
        out.append(c)
    return np.array(out).T


@pytest.mark.parametrize("n_rows", [1, 3, 4, 5])
def test_compiled_fit_is_its_textbook_loops_bit_for_bit(n_rows):
    """_fit_rows against the same operations in the textbook order, in Python floats: equal
    bit for bit for 1, 3, 4 and 5 rows (one group of 4 rows, padded, and one more), the rows
    taken from the middle of x."""
    rng = np.random.default_rng(5)
    n, k = 40, 6
    b = np.linalg.qr(rng.standard_normal((n, k)))[0]
    prefix = lr._gram_prefix(np.ascontiguousarray(b), b)
    shrink = np.r_[lr.SHRINK_FLOOR, rng.uniform(0, 1, k - 1)]
    run_s, run_e = np.array([3, 20]), np.array([9, 31])
    lt = np.zeros((k, k))
    lr._cholesky(prefix, shrink, run_s, run_e, 2, lt, np.zeros(prefix.shape[1]))
    # the chain's types (float32 rows, float64 projections): no test-only compilation
    x = (rng.standard_normal((n_rows + 4, n)) * 100).astype(np.float32)
    rhs = x.astype(np.float64) @ b
    pad = (n_rows + 3) // 4 * 4
    c = np.full((k, pad), np.nan)
    lr._fit_rows(x, rhs, np.ascontiguousarray(b), lt, run_s, run_e, 2, 2, 2 + n_rows,
                 np.zeros((pad, k)), c)
    want = _fit_reference(x, rhs, b, lt, list(zip(run_s, run_e)), range(2, 2 + n_rows))
    assert c[:, :n_rows].tobytes() == want.tobytes()
    with pytest.raises(ValueError, match="rounded up to 4"):
        lr._fit_rows(x, rhs, np.ascontiguousarray(b), lt, run_s, run_e, 2, 2, 2 + n_rows,
                     np.zeros((pad - 1, k)), c)
