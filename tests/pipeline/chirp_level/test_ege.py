"""The EGE compression model: block budget, scale factor, error bound, SNR loss, ratio limits
([TI-DDMA] section 5.2)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import pipeline
from pipeline import chirp_level as cl


def test_ege_block_reproduces_the_hardware_ratio_and_error_bound():
    """One block of 4 Rx x 8 bins (32 complex 16-bit samples = 128 bytes) fits 64 bytes: the
    exact EG code length of the chosen (s, k) plus the 7-bit header is <= 512 bits, and every
    decompressed I/Q value is within 1.5 x 2^s LSB of the input (half a step of rounding, up
    to a step of triangular dither)."""
    rng = np.random.default_rng(11)
    budget = 64 * 8 - cl.EGE_HEADER_BITS
    for level in (10.0, 300.0, 3e4):  # noise-like, moderate, a strong echo in the block
        v = (rng.standard_normal((1, 4, 8)) + 1j * rng.standard_normal((1, 4, 8))) * 8.0
        v[0, 1, 3] += level * 8 * (1 + 1j)
        rf = (v / cl.HWA_OUTPUT_SCALE * cl.HWA_OUTPUT_SCALE / cl.HWA_OUTPUT_SCALE) \
            .astype(np.complex64)
        vin = rf.copy().view(np.float32).reshape(-1) * cl.HWA_OUTPUT_SCALE
        out, shift = cl.ege_compress(rf)
        s = int(shift[0, 0])
        vout = out.view(np.float32).reshape(-1) * cl.HWA_OUTPUT_SCALE
        err = np.abs(vout - vin).max()
        if s == 0:
            assert err <= 0.5  # s = 0: not requantised (cold) or rounded
        else:
            assert err <= 1.5 * 2.0 ** s + 1e-3
        q = np.rint(np.ldexp(vin, -s))
        bits = min(int(cl.ege_block_bits(q[None], k)[0]) for k in cl.EGE_K_ARRAY)
        assert bits <= budget
        assert (bits + cl.EGE_HEADER_BITS) / 8 <= 0.5 * 128
        if s > 0:  # a finer scale would not have fitted
            q1 = np.rint(np.ldexp(vin, -(s - 1)))
            assert min(int(cl.ege_block_bits(q1[None], k)[0]) for k in cl.EGE_K_ARRAY) \
                > budget


def _brute_force_shift(vin: np.ndarray, budget: int) -> np.ndarray:
    """Smallest s of each block (n_blocks, n_val) in HWA LSB whose best-k exact EG code length
    fits `budget`: every (s, k) tried."""
    s_all = np.arange(16)
    q = np.rint(np.ldexp(vin[:, None, :].astype(np.float64), -s_all[None, :, None]))
    bits = np.stack([cl.ege_block_bits(q, np.full(q.shape[:2], k)) for k in cl.EGE_K_ARRAY])
    fits = bits.min(axis=0) <= budget                                  # (blocks, s)
    return np.where(fits.any(axis=1), fits.argmax(axis=1), 15)


def test_ege_scale_factor_is_the_smallest_that_fits():
    """Pass 1 of the encoder model against an exhaustive search over every (s, k), on blocks of
    every kind: thermal noise at 2..200 LSB, noise with a strong echo, blocks at the edge of
    the unshifted budget (a mean |v| of 8..16 LSB) and rail-to-rail interference."""
    rng = np.random.default_rng(5)
    n_c, n_r, nb = 48, 4, 24
    sigma = np.exp(rng.uniform(np.log(2.0), np.log(200.0), (n_c, 1, nb, 1)))
    sigma[: n_c // 3] = rng.uniform(8.0, 16.0, (n_c // 3, 1, nb, 1)) * np.sqrt(np.pi / 2)
    v = rng.standard_normal((n_c, n_r, nb, 16)) * sigma
    echo = rng.random((n_c, 1, nb, 1)) < 0.3
    v += echo * rng.uniform(1e2, 3e4, (n_c, 1, nb, 1)) * (rng.random((n_c, n_r, nb, 16)) < 0.1)
    v[-4:] = rng.uniform(-32767, 32767, (4, n_r, nb, 16))
    rf = (v / cl.HWA_OUTPUT_SCALE).astype(np.float32).reshape(n_c, n_r, -1).view(np.complex64)
    vin = rf.view(np.float32).reshape(n_c, n_r, nb, 16).transpose(0, 2, 1, 3) \
        .reshape(n_c * nb, 64) * np.float32(cl.HWA_OUTPUT_SCALE)
    _, shift = cl.ege_compress(rf.copy())
    want = _brute_force_shift(vin, 64 * 8 - cl.EGE_HEADER_BITS)
    assert np.bincount(want).size > 8  # the blocks span the scale factors
    np.testing.assert_array_equal(shift.reshape(-1), want)


@pytest.mark.parametrize("diff_db", [40.0, 60.0, 70.0])  # 70 dB: the 16-bit output's span
def test_compression_loss_of_a_weak_target_next_to_a_strong_one(diff_db):
    """The block's scale factor s follows its strongest values; the weak target's SNR then
    loses 10 log10(1 + (2^(2s) / 4) / sigma^2) (triangular-dithered quantisation of I and Q
    with step 2^s HWA LSB: error variance step^2 / 4 whatever the signal, against the noise
    variance sigma^2 per component); the target's coherent power is kept. Five weak targets
    (bins 35-39 of the block) x 4 Rx give 20 looks; the tolerance is three standard deviations
    of the SNR estimate before and after (a bin of coherent SNR rho averaged over L looks has
    a relative power error of sqrt(2 / (L rho))) plus 0.1 dB."""
    n_c, n_b, sigma = 512, 192, 8.0  # sigma: noise per I/Q in HWA LSB
    weak_bins = [35, 36, 37, 38, 39]
    rng = np.random.default_rng(2)
    lsb = 1 / cl.HWA_OUTPUT_SCALE
    noise = (rng.standard_normal((n_c, 4, n_b)) + 1j * rng.standard_normal((n_c, 4, n_b))) \
        * sigma * lsb
    c = np.arange(n_c)
    k_weak, k_strong = 51, 154  # bin-centred Doppler tones
    weak = 10 * sigma * lsb * np.exp(2j * np.pi * k_weak / n_c * c)[:, None]
    strong = 10 * sigma * lsb * 10 ** (diff_db / 20) * \
        np.exp(2j * np.pi * k_strong / n_c * c)[:, None]
    rf = noise.copy()
    rf[:, :, weak_bins] += weak[:, :, None]
    for b, g in ((32, 0.5), (33, 1.0), (34, 0.5)):  # a Hann main lobe over three bins
        rf[:, :, b] += g * strong
    rf = rf.astype(np.complex64)

    def snr_db(x):
        p = np.abs(np.fft.fft(x[:, :, weak_bins], axis=0)) ** 2
        floor = np.delete(p, [k_weak], axis=0).mean()
        return 10 * np.log10((p[k_weak].mean() - floor) / floor)

    before = snr_db(rf)
    out, shift = cl.ege_compress(rf.copy())
    s4 = shift[:, 4].astype(float)  # block 4 holds bins 32..39
    s = int(np.median(s4))
    loss = before - snr_db(out)
    want = 10 * np.log10(1 + np.mean(4.0 ** s4 / 4) / sigma ** 2)
    looks, rho = 4 * len(weak_bins), n_c * 10 ** 2 / 2  # coherent bin SNR before compression
    sd_db = [10 / np.log(10) * np.sqrt(2 / (looks * r)) for r in (rho, rho / 10 ** (want / 10))]
    assert loss == pytest.approx(want, abs=0.1 + 3 * np.hypot(*sd_db))
    if diff_db >= 70:
        assert s >= 4 and loss > 1.0


@pytest.mark.parametrize("n_rx, bins, lowest", [(4, 8, (320 + 7) / 1024),
                                                (2, 4, (80 + 7) / 256), (3, 16, (480 + 7) / 1536)])
def test_compression_ratio_must_hold_the_shortest_code(make_config, n_rx, bins, lowest):
    """A block of n_rx x bins I/Q values needs 5 bits per value (k = 3, the demo's smallest
    order) plus the 7-bit header: a smaller ratio cannot be met by any scale factor. The
    radar-level check refuses it before any frame (as a sweep does for every cell), and
    `ege_compress` refuses it too; the ratio at the limit is accepted."""
    assert cl.ege_min_ratio(n_rx, bins) == pytest.approx(lowest)
    cfg = make_config(n_rx=n_rx, rx_channels=tuple(range(1, n_rx + 1)))
    proc = pipeline.ProcessingConfig().replace(compression_ratio=0.25,
                                     compression_range_bins_per_block=bins)
    with pytest.raises(ValueError, match="compression_ratio=0.25 is below"):
        proc.check_radar(cfg)
    rf = np.zeros((2, n_rx, 4 * bins), np.complex64)
    with pytest.raises(ValueError, match="compression_ratio=0.25 is below"):
        cl.ege_compress(rf, 0.25, bins)
    ok = proc.replace(compression_ratio=math.ceil(lowest * 1e4) / 1e4)
    ok.check_radar(cfg)
    assert not cl.ege_compress(rf, ok.compression.ratio, bins)[1].any()


def test_compression_blocks_must_tile_the_range_bins(make_config):
    """Blocks of 32 bins tile the R79 radar's 192 range bins; a radar of 100 bins is
    refused, naming the block size and the bin count."""
    proc = pipeline.ProcessingConfig().replace(compression_range_bins_per_block=32)
    proc.check_radar(make_config())
    with pytest.raises(ValueError, match="=32 does not divide the radar's 100 range bins"):
        proc.check_compression(4, 100)


def _reference_shift(v: np.ndarray, budget: int, kk: np.ndarray) -> int:
    """The encoder model's pass 1 as formulated before the exact search (main 324a798): a
    histogram of bit lengths L bounds each (s, k); an order whose lower bound exceeds the
    budget is skipped, one whose upper bound fits is taken unchecked (unless a value is at the
    clip L = 31), the others get the float32 exact length. v (n_val,) float32, HWA LSB."""
    n_val = v.size
    length = np.clip((np.abs(v).view(np.int32) >> 23) - 126, 0, 31)

    def f_sum(t):
        return int(np.sum(np.maximum(length - t, 0) + (length == t)))

    unbounded = bool((length == 31).any())
    for s in range(16):
        for k in kk:
            base = n_val * (2 + int(k))
            if base + 2 * f_sum(min(s + k + 1, 31)) > budget:
                continue
            if not unbounded and base + 2 * f_sum(s + k) <= budget:
                return s
            m = np.abs(np.rint(v * np.float32(2.0 ** -s))) + np.float32(2.0 ** k)
            if base + 2 * int(np.sum((m.view(np.int32) >> 23) - 127 - k)) <= budget:
                return s
    return 15


def _reference_dither(index: np.ndarray) -> np.ndarray:
    """The encoder's triangular dither (`ege._dither`) of flat positions `index`, in numpy."""
    with np.errstate(over="ignore"):
        z = index.astype(np.uint64) + np.uint64(0x9E3779B97F4A7C15)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    u1 = (z >> np.uint64(40)).astype(np.float32)
    u2 = ((z >> np.uint64(8)) & np.uint64(0xFFFFFF)).astype(np.float32)
    return (u1 + u2) * np.float32(2.0 ** -24) - np.float32(1.0)


@pytest.mark.parametrize("n_rx, bins, ratio", [(4, 8, 0.5), (2, 16, 0.7), (3, 4, 0.45)],
                         ids=["demo", "2rx-16bins", "3rx-4bins"])
def test_ege_hot_blocks_equal_the_histogram_bounded_encoder_bit_for_bit(n_rx, bins, ratio):
    """Blocks that are not cold (`ege_blocks`' hot path: exact scale-factor search, then
    the dithered requantisation) against the formulation it replaced, bit for bit, values and
    scale factors: noise at 2..3e4 LSB (scale factors 0..12), strong echoes, rail-to-rail
    blocks, blocks with values at and beyond 2^24 LSB (where float32 logarithms round and the
    histogram bounds decide, up to the clip at 2^31 and inf), a chirp offset into the frame
    (the dither's position). Every block goes through the reference, cold or not: a cold
    block gets s = 0 there and is left as it was."""
    rng = np.random.default_rng(20)
    n_c, nb, n_val = 24, 12, 2 * n_rx * bins
    sigma = np.exp(rng.uniform(np.log(2.0), np.log(3e4), (n_c, 1, nb, 1)))
    v = rng.standard_normal((n_c, n_rx, nb, 2 * bins)) * sigma
    echo = rng.random((n_c, 1, nb, 1)) < 0.3
    v += echo * rng.uniform(1e2, 3e5, (n_c, 1, nb, 1)) \
        * (rng.random((n_c, n_rx, nb, 2 * bins)) < 0.1)
    v[-6:-4] = rng.uniform(-32767, 32767, (2, n_rx, nb, 2 * bins))
    big = rng.random((4, n_rx, nb, 2 * bins)) < 0.05  # saturation: values at and past 2^24
    v[-4:] = np.where(big, rng.choice([2.0 ** 24 - 0.5, 2.0 ** 24, 3.1e7, 2.0 ** 30, 3e9,
                                       np.inf], size=big.shape)
                      * rng.choice([-1, 1], size=big.shape), v[-4:])
    v[-1, :, :, 0] = 2.0 ** 24 - 1  # a whole column just below 2^24: the exact search
    scale = np.float32(cl.HWA_OUTPUT_SCALE)
    vv = (v / scale).astype(np.float32).reshape(n_c, n_rx, nb * 2 * bins)
    bins2, budget, kk, cold = cl.ege.ege_setup(n_rx, nb * bins, ratio, bins)
    c_base = 37
    got, shift = vv.copy(), np.zeros((n_c, nb), np.int8)
    cl.ege.ege_blocks(got, bins2, scale, budget, kk, cold, shift, 0, n_c, c_base)

    want, want_shift = vv.copy(), np.zeros((n_c, nb), np.int8)
    for c in range(n_c):
        for b in range(nb):
            blk = want[c, :, b * bins2:(b + 1) * bins2]
            x = (blk * scale).reshape(-1)
            s = _reference_shift(x, budget, kk)
            want_shift[c, b] = s
            if s:
                pos = ((c_base + c) * nb + b) * n_val + np.arange(n_val)
                q = np.rint(x * np.float32(2.0 ** -s) + _reference_dither(pos))
                blk[...] = (q * (np.float32(2.0 ** s) / scale)).reshape(blk.shape)
    assert np.bincount(want_shift.ravel()).size > 10 and (want_shift == 15).any()
    assert (want_shift > 0).any(axis=1).sum() > n_c // 2  # most chirps requantised
    np.testing.assert_array_equal(shift, want_shift)
    assert got.tobytes() == want.tobytes()


def test_ege_blocks_of_longer_rows_leave_the_tail():
    """`ege_blocks` on rows longer than its blocks (a whole rFFT output: the Nyquist bin after
    the n_range bins) codes the same blocks, bit for bit, and leaves the tail as it was: the
    blocks of a row are shift's columns, not the row's length."""
    rng = np.random.default_rng(21)
    n_c, n_rx, nb, bins = 6, 4, 3, 8
    bins2, budget, kk, cold = cl.ege.ege_setup(n_rx, nb * bins, 0.5, bins)
    scale = np.float32(cl.HWA_OUTPUT_SCALE)
    v = (rng.standard_normal((n_c, n_rx, nb * bins2)) * 3e3 / scale).astype(np.float32)
    want, want_shift = v.copy(), np.zeros((n_c, nb), np.int8)
    cl.ege.ege_blocks(want, bins2, scale, budget, kk, cold, want_shift, 0, n_c, 5)
    tail = rng.standard_normal((n_c, n_rx, 2)).astype(np.float32)
    got, shift = np.concatenate([v, tail], axis=-1), np.zeros((n_c, nb), np.int8)
    cl.ege.ege_blocks(got, bins2, scale, budget, kk, cold, shift, 0, n_c, 5)
    assert (want_shift > 0).any()
    np.testing.assert_array_equal(shift, want_shift)
    assert got[..., :-2].tobytes() == want.tobytes()
    assert got[..., -2:].tobytes() == tail.tobytes()
