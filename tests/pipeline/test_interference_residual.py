"""pipeline.interference.residual: weak bursts on the low-rank residual, not the echoes."""
from __future__ import annotations

import numpy as np
import pytest

from pipeline.config import ProcessingConfig
from pipeline.interference.residual import residual_burst_flags, with_weak_bursts

N = 384
T = np.arange(N)


def _basis(*freqs):
    cols = [np.ones(N)] + [f(2 * np.pi * k * T / N) for k in freqs for f in (np.cos, np.sin)]
    return np.linalg.qr(np.column_stack(cols))[0].astype(np.float32)


def _burst(n=40, amp=6.0):
    """An interfering chirp crossing the IF band: its frequency sweeps through it."""
    t = np.arange(n)
    return amp * np.cos(np.pi * 0.9 * t ** 2 / n)


def test_a_weak_burst_is_flagged_where_it_is_and_nowhere_else():
    rng = np.random.default_rng(1)
    x = 40 * np.cos(2 * np.pi * 60.4 * T / N) + rng.standard_normal((8, N))
    x[3, 200:240] += _burst()                     # 13 dB in-burst INR: under the chip's 18 dB
    f = residual_burst_flags(x.astype(np.float32), _basis(60.4), 1.0, 11.0, 32)
    assert f.any(axis=1).tolist() == [False] * 3 + [True] + [False] * 4
    assert f[3, 200:240].all() and not f[3, :160].any() and not f[3, 280:].any()


def test_beating_echoes_are_no_burst():
    """Two strong echoes five bins apart beat in the envelope (a fast-time envelope CFAR's
    false alarm); both lie in the subspace, so the residual is noise."""
    rng = np.random.default_rng(2)
    x = 300 * (np.cos(2 * np.pi * 100.2 * T / N) + np.cos(2 * np.pi * 105.7 * T / N)) \
        + rng.standard_normal((64, N))
    f = residual_burst_flags(x.astype(np.float32), _basis(100.2, 105.7), 1.0, 11.0, 32)
    assert not f.any()


def test_a_residual_along_the_whole_row_is_no_burst():
    """What the subspace does not hold but lies along the row (a same-slope radar's tone)
    raises the row's own level, not one window."""
    rng = np.random.default_rng(3)
    x = 20 * np.cos(2 * np.pi * 33.3 * T / N) + rng.standard_normal((16, N))
    f = residual_burst_flags(x.astype(np.float32), _basis(), 1.0, 11.0, 32)
    assert not f.any()


def _reference_flags(x, v, noise_var, threshold_db, window, block=4):
    """The flags in numpy's straightforward form: block sums by ``sum(axis=-1)``, window sums
    of consecutive blocks, the row median of windows a window apart."""
    r = x - (x @ v) @ v.T
    p = r * r
    b = p.reshape(len(p), -1, block).sum(axis=-1)
    nb = window // block
    e = sum(b[:, k:b.shape[1] - nb + 1 + k] for k in range(nb))
    sub = e[:, ::nb]
    med = np.partition(sub, sub.shape[1] // 2, axis=1)[:, sub.shape[1] // 2]
    hit = e > np.maximum(med, np.float32(window * noise_var))[:, None] \
        * np.float32(10 ** (threshold_db / 10))
    blk = np.zeros(b.shape, dtype=bool)
    for k in range(nb):
        blk[:, k:b.shape[1] - nb + 1 + k] |= hit
    return np.repeat(blk, block, axis=1)


@pytest.mark.parametrize("threshold_db, window", [(2.0, 8), (6.0, 32), (9.0, 64)])
def test_flags_are_the_straightforward_energy_test(threshold_db, window):
    """The fast form (block sums as vector additions, the residual squared in place) flags
    the samples numpy's straightforward form flags, at thresholds where many windows lie
    near the line."""
    rng = np.random.default_rng(4)
    v = _basis(60.4, 130.2)
    x = (rng.standard_normal((300, N)) * 3 + 50 * np.cos(2 * np.pi * 60.4 * T / N)).astype(
        np.float32)
    for r in rng.integers(0, 300, 60):
        a = rng.integers(0, N - 40)
        x[r, a:a + 40] += _burst(amp=rng.uniform(5, 60)).astype(np.float32)
    want = _reference_flags(x, v, 9.0, threshold_db, window)
    got = residual_burst_flags(x, v, 9.0, threshold_db, window)
    assert want.any() and not want.all() and (got == want).all()


def _numpy_flags(x, v, noise_var, threshold_db, window, block=4):
    """The flags as numpy computed them before the compiled pass: the residual squared in
    place (|r|^2 = re^2 + im^2 for I/Q), block sums as vector additions with the last
    n mod block samples joining the last block, the window sums by Python's sum, the median
    by np.partition."""
    n = x.shape[-1]
    nb, n_blocks = window // block, n // block
    r = (x @ v) @ v.conj().T
    np.subtract(x, r, out=r)
    p = r.real ** 2 + r.imag ** 2 if np.iscomplexobj(r) else np.multiply(r, r, out=r)
    q = p[:, :n_blocks * block].reshape(len(p), n_blocks, block)
    b = q[..., 0] + q[..., 1]
    for j in range(2, block):
        b += q[..., j]
    b[:, -1] += p[:, n_blocks * block:].sum(axis=-1)
    e = sum(b[:, k:n_blocks - nb + 1 + k] for k in range(nb))
    sub = e[:, ::nb]
    mid = sub.shape[1] // 2
    ref = np.maximum(np.partition(sub, mid, axis=1)[:, mid], np.float32(window * noise_var))
    hit = e > ref[:, None] * np.float32(10 ** (threshold_db / 10))
    blk = np.zeros((len(x), n_blocks), dtype=bool)
    for k in range(nb):
        blk[:, k:n_blocks - nb + 1 + k] |= hit
    return np.concatenate([np.repeat(blk, block, axis=1),
                           np.repeat(blk[:, -1:], n - n_blocks * block, axis=1)], axis=1)


@pytest.mark.parametrize("n, cplx", [(384, False), (130, False), (384, True), (67, True)])
def test_the_compiled_pass_flags_what_numpy_flagged(n, cplx):
    """`_burst_windows` gives numpy's flags bit for bit, I/Q rows and rows whose length is no
    multiple of the block included, at thresholds where many windows lie near the line."""
    rng = np.random.default_rng(n)
    dt = np.complex64 if cplx else np.float32
    z = (lambda *s: rng.standard_normal(s) + 1j * rng.standard_normal(s)) if cplx \
        else (lambda *s: rng.standard_normal(s))
    v = np.linalg.qr(z(n, 5))[0].astype(dt)
    x = 3 * z(200, n)
    for r in rng.integers(0, 200, 50):
        a = rng.integers(0, n - 20)
        x[r, a:a + 20] += rng.uniform(3, 30)
    x = x.astype(dt)
    for threshold_db, window in ((1.0, 4), (3.0, 16), (2.0, 32)):
        want = _numpy_flags(x, v, 9.0, threshold_db, window)
        got = residual_burst_flags(x, v, 9.0, threshold_db, window)
        assert want.any() and not want.all() and (got == want).all()


def test_noise_alone_raises_no_flag():
    """Chi-square of 32 degrees of freedom over 32 exceeds 11 dB (12.6) with far below 1e-10
    per window: 4000 rows of noise, none flagged."""
    x = np.random.default_rng(4).standard_normal((4000, N)).astype(np.float32)
    assert not residual_burst_flags(x, _basis(), 1.0, 11.0, 32).any()


def _frame(rng, burst_rows=(), chip_rows=()):
    """(n_chirps, n_rx, N) int16 with one echo, weak bursts in `burst_rows` and strong ones
    (the chip's) in `chip_rows` (row = chirp x n_rx + rx)."""
    x = 200 * np.cos(2 * np.pi * 50.2 * T / N + rng.uniform(0, 6.3, (512, 1))) \
        + 8 * rng.standard_normal((512, N))
    for r in burst_rows:
        x[r, 100:140] += 8 * _burst()
    for r in chip_rows:
        x[r, 300:340] += 400 * _burst()
    return np.round(x).astype(np.int16).reshape(128, 4, N)


def test_rows_the_chip_missed_are_added_in_order():
    rng = np.random.default_rng(5)
    adc = _frame(rng, burst_rows=(7, 130), chip_rows=(40,))
    chip_flags = np.zeros((1, N), dtype=bool)
    chip_flags[0, 300:340] = True
    rows, flags = with_weak_bursts(adc, None, np.array([40]), chip_flags, 11.0, 32)
    assert rows.tolist() == [7, 40, 130]
    assert flags[1].tolist() == chip_flags[0].tolist()   # the chip's flags kept
    assert flags[0, 100:140].all() and flags[2, 100:140].all()


def test_a_frame_the_chip_flagged_nothing_in_is_left_alone():
    rng = np.random.default_rng(6)
    adc = _frame(rng, burst_rows=(7,))
    rows, flags = np.zeros(0, dtype=np.intp), np.zeros((0, N), dtype=bool)
    out = with_weak_bursts(adc, None, rows, flags, 11.0, 32)
    assert out[0] is rows and out[1] is flags


@pytest.mark.parametrize("window", [3, 0])
def test_window_not_a_multiple_of_the_block_is_refused(window):
    with pytest.raises(ValueError, match="window"):
        residual_burst_flags(np.zeros((1, N), np.float32), _basis(), 1.0, 11.0, window)


def test_the_chirp_statistics_add_them_unless_switched_off():
    from pipeline.chirp_level.stage import chirp_statistics
    adc = _frame(np.random.default_rng(7), burst_rows=(7, 130), chip_rows=(40,))
    _, rows, _ = chirp_statistics(adc, ProcessingConfig())
    assert {7, 40, 130} <= set(rows.tolist())
    _, off, _ = chirp_statistics(adc, ProcessingConfig().replace(
        **{"interference.weak_burst_snr_db": None}))
    assert 40 in off and 7 not in off and 130 not in off
