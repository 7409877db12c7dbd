"""What the repair methods put into the masked samples (`pipeline.interference.methods`): the
edge taper's gain, the straight line, linear prediction by a Burg AR model forward and backward,
and the strongest echoes fitted per chirp and continued across the gap. Pure numpy kernels on
(R, n) rows of samples and their (R, n) bool masks.

References
----------
.. [1] M. Toth et al., "Interference mitigation for automotive FMCW radar with Burg-based
       autoregressive signal reconstruction", IEEE ICASSP 2018.
.. [2] S. M. Kay, Modern Spectral Estimation, Prentice Hall 1988, ch. 7 (linear prediction,
       covariance method).
"""
from __future__ import annotations

import numpy as np
import scipy.signal

__all__ = ["taper_gain", "linear_fill", "ar_fill", "tone_frequencies", "cancel_tones",
           "AR_FIT_ROWS"]


def taper_gain(mask: np.ndarray, taper: int) -> np.ndarray:
    """(R, n) float32 gain: 0 on the mask, rising over `taper` samples on each side along
    samples 2 .. taper + 1 of a Hann window (the DPC's 16-point Hann, samples 2-6, for
    taper = 5; 2 (taper + 3) points otherwise)."""
    n_hann = 16 if taper == 5 else 2 * (taper + 3)
    h = scipy.signal.get_window("hann", n_hann, fftbins=False)[2:2 + taper]
    # distance (in samples) of every sample to the nearest masked sample of its row
    n = mask.shape[-1]
    idx = np.broadcast_to(np.arange(n), mask.shape)
    big = 10 * n
    left = idx - np.maximum.accumulate(np.where(mask, idx, -big), axis=-1)
    right = np.minimum.accumulate(np.where(mask, idx, big)[:, ::-1], axis=-1)[:, ::-1] - idx
    d = np.minimum(left, right)  # 0 on the mask
    ramp = np.r_[0.0, h, 1.0]  # d = 0 -> 0, d = 1..taper -> h, beyond -> 1
    return ramp[np.minimum(d, taper + 1)].astype(np.float32)


def linear_fill(x: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Masked samples replaced by the line between the nearest kept samples of the row (the
    nearest kept one at a row's ends)."""
    n = x.shape[-1]
    idx = np.broadcast_to(np.arange(n), x.shape)
    left = np.maximum.accumulate(np.where(mask, -1, idx), axis=-1)
    right = np.minimum.accumulate(np.where(mask, n, idx)[:, ::-1], axis=-1)[:, ::-1]
    lc, rc = np.clip(left, 0, n - 1), np.clip(right, 0, n - 1)
    xl, xr = np.take_along_axis(x, lc, -1), np.take_along_axis(x, rc, -1)
    xl = np.where(left < 0, xr, xl)
    xr = np.where(right >= n, xl, xr)
    t = np.where((left >= 0) & (right < n), (idx - left) / np.maximum(right - left, 1), 0.0)
    return np.where(mask, xl + (xr - xl) * t, x).astype(x.dtype)


#: Rows per Rx used to fit its predictor (ample: each gives ~n - p error terms per order).
AR_FIT_ROWS = 64


def ar_coefficients(x: np.ndarray, mask: np.ndarray, groups: np.ndarray,
                     order: int) -> np.ndarray:
    """Burg predictors a (G, order), one per group of rows: x[t] ~ -sum_k a_k x[t-k].

    Burg's method (Kay ch. 7.4) with the reflection coefficient of each order pooled over the
    group's rows and over the error terms whose order + 1 samples are all kept (masked
    samples never enter). Every |k_m| < 1, so the model is minimum phase: stable forward, and
    its conjugate is the backward predictor. The recursion runs over the model order (a
    Levinson update per order), vectorised over rows and samples. The first `AR_FIT_ROWS`
    rows of each group are used.
    """
    n_g = int(groups.max()) + 1
    order_rows = np.argsort(groups, kind="stable")
    g_sorted = groups[order_rows]
    rank = np.arange(len(g_sorted)) - np.searchsorted(g_sorted, g_sorted)
    fit = order_rows[rank < AR_FIT_ROWS]
    g = groups[fit]
    f = x[fit].astype(np.complex128 if np.iscomplexobj(x) else np.float64)
    bk = f.copy()
    valid = ~mask[fit]
    a = np.zeros((n_g, order), dtype=f.dtype)
    cplx = np.iscomplexobj(f)
    for m in range(order):  # model order, not samples
        ff, bb = f[:, 1:], bk[:, :-1]
        v = valid[:, 1:] & valid[:, :-1]
        if cplx:
            num = np.where(v, ff * bb.conj(), 0).sum(-1)
            den = np.where(v, np.abs(ff) ** 2 + np.abs(bb) ** 2, 0).sum(-1)
        else:  # the same numbers without the copies: conj is the identity, |x|**2 is x * x
            num = np.where(v, ff * bb, 0).sum(-1)
            den = np.where(v, ff * ff + bb * bb, 0).sum(-1)
        k = -2 * np.bincount(g, num.real, n_g)
        if cplx:
            k = k - 2j * np.bincount(g, num.imag, n_g)
        d = np.bincount(g, den, n_g)
        k = np.where(d > 0, k / np.where(d > 0, d, 1) * (1 - 1e-9), 0)
        # Levinson: a_j <- a_j + k conj(a_{m-j}), a_m <- k
        prev = a[:, :m].copy()
        a[:, :m] = prev + k[:, None] * prev[:, ::-1].conj()
        a[:, m] = k
        kr = k[g][:, None]
        f, bk = ff + kr * bb, bb + kr.conj() * ff
        valid = v
    return a


def mask_runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Masked runs: (row, start, end exclusive) of every run of True in each row."""
    d = np.diff(np.pad(mask.astype(np.int8), ((0, 0), (1, 1))), axis=-1)
    r0, s = np.nonzero(d == 1)
    _, e = np.nonzero(d == -1)
    return r0, s, e


def predict(x: np.ndarray, a: np.ndarray, model: np.ndarray, rows: np.ndarray,
             starts: np.ndarray, length: int) -> np.ndarray:
    """(N, length) forward predictions of rows `rows` (N,) from position `starts` on, gap i
    with the predictor a[model[i]] (a (G, p), one per group): the AR recursion
    y[t] = -sum_k a_k y[t-k] is an all-pole filter (b = [1]) run on zeros from the state the
    p samples before the gap leave. In the DF-II transposed form scipy.signal.lfilter uses,
    that state is z_k = -sum_{j=k+1}^{p} a_j y[k-j] (y[-1] the sample just before the gap).
    One lfilter call per predictor used."""
    p = a.shape[-1]
    past = x[rows[:, None], starts[:, None] - np.arange(1, p + 1)]  # y[-1] .. y[-p]
    hank = np.arange(p)[:, None] + np.arange(p)[None, :]  # coefficient index j - 1 = k + m
    coef = np.where(hank < p, a[:, np.minimum(hank, p - 1)], 0)[model]  # (N, p, p)
    zi = -np.einsum("gkm,gm->gk", coef, past)
    out = np.zeros((len(rows), length), dtype=np.result_type(x.dtype, a.dtype))
    for u in np.unique(model):  # one per Rx model
        sel = np.flatnonzero(model == u)
        out[sel] = scipy.signal.lfilter([1.0], np.r_[1.0, a[u]], out[sel], axis=-1,
                                        zi=zi[sel])[0]
    return out


def ar_fill(x: np.ndarray, mask: np.ndarray, groups: np.ndarray, order: int) -> np.ndarray:
    """Masked runs reconstructed from the AR predictor of their row's group: forward from the
    left, backward from the right (the conjugate predictor on the time-reversed row, exact for
    Burg's minimum-phase model), linearly cross-faded; a run with no room for p samples on one
    side takes the other."""
    n = x.shape[-1]
    a = ar_coefficients(x, mask, groups, order)
    rows, s, e = mask_runs(mask)
    if not rows.size:
        return x
    length = int((e - s).max())
    fwd_ok, bwd_ok = s >= order, e + order <= n
    model = groups[rows]
    fwd = np.zeros((len(rows), length), dtype=np.result_type(x.dtype, a.dtype))
    bwd = np.zeros_like(fwd)
    if fwd_ok.any():
        fwd[fwd_ok] = predict(x, a, model[fwd_ok], rows[fwd_ok], s[fwd_ok], length)
    if bwd_ok.any():
        xr = x[:, ::-1]
        bwd[bwd_ok] = predict(xr, a.conj(), model[bwd_ok], rows[bwd_ok], n - e[bwd_ok],
                               length)
    i = np.arange(length)[None, :]
    ln = (e - s)[:, None]
    t = (i + 1) / (ln + 1)  # weight of the backward prediction
    t = np.where(fwd_ok[:, None] & ~bwd_ok[:, None], 0.0, t)
    t = np.where(~fwd_ok[:, None] & bwd_ok[:, None], 1.0, t)
    none = ~fwd_ok & ~bwd_ok
    # the backward prediction of gap sample i is its element ln - 1 - i
    b_idx = np.clip(ln - 1 - i, 0, length - 1)
    val = (1 - t) * fwd + t * np.take_along_axis(bwd, b_idx, axis=-1)
    val[none] = 0
    inside = i < ln
    r_idx = np.broadcast_to(rows[:, None], val.shape)[inside]
    c_idx = (s[:, None] + i)[inside]
    out = x.copy()
    out[r_idx, c_idx] = val[inside].real.astype(x.dtype) if not np.iscomplexobj(x) else \
        val[inside].astype(x.dtype)
    return out


def tone_frequencies(x: np.ndarray, mask: np.ndarray, groups: np.ndarray, k: int,
                      n_fft: int = 8) -> np.ndarray:
    """(G, k) beat frequencies, cycles per sample, of the k strongest echoes per group: peaks
    of the mean power spectrum of the groups' rows (masked samples zeroed, Hann window,
    zero-padded n_fft times; the full spectrum for I/Q rows), refined by a parabola through
    the log powers."""
    n = x.shape[-1]
    w = np.hanning(n)
    transform = np.fft.fft if np.iscomplexobj(x) else np.fft.rfft  # I/Q rows: both sides
    spec = np.abs(transform(np.where(mask, 0, x) * w, n * n_fft, axis=-1)) ** 2
    n_g = int(groups.max()) + 1
    n_f = spec.shape[-1]
    # sum of each group's rows in row order from 0, as np.add.at does, in one pass
    p = np.bincount((groups[:, None] * n_f + np.arange(n_f)).ravel(), spec.ravel(),
                    n_g * n_f).reshape(n_g, n_f)
    lp = np.log(p + 1e-30)
    peak = np.zeros_like(lp, dtype=bool)
    peak[:, 1:-1] = (lp[:, 1:-1] > lp[:, :-2]) & (lp[:, 1:-1] >= lp[:, 2:])
    score = np.where(peak, lp, -np.inf)
    idx = np.argsort(score, axis=-1)[:, ::-1][:, :k]  # (G, k)
    ym, y0, yp = (np.take_along_axis(lp, np.clip(idx + d, 0, lp.shape[-1] - 1), -1)
                  for d in (-1, 0, 1))
    off = 0.5 * (ym - yp) / np.where(ym - 2 * y0 + yp == 0, -1e-12, ym - 2 * y0 + yp)
    return (idx + np.clip(off, -0.5, 0.5)) / (n * n_fft)


def cancel_tones(x: np.ndarray, mask: np.ndarray, freqs: np.ndarray,
            groups: np.ndarray) -> np.ndarray:
    """(R, n) per-row least-squares fit, on the kept samples, of the tones of the row's
    group's frequencies (G, k) (cosine and sine, real rows; complex exponentials, I/Q rows;
    `groups` (R,) the row's group), evaluated over the whole row."""
    n = x.shape[-1]
    t = np.arange(n)
    ph = 2 * np.pi * freqs[:, :, None] * t  # (G, k, n): the bases, once per group
    if np.iscomplexobj(x):
        basis = np.exp(1j * ph)[groups]
        bkc = (basis * (~mask)[:, None, :]).conj()
    else:
        basis = np.concatenate([np.cos(ph), np.sin(ph)], axis=1)[groups]  # (R, 2k, n)
        bkc = basis * (~mask)[:, None, :]  # real: its own conjugate
    gram = np.einsum("rin,rjn->rij", bkc, basis)
    rhs = np.einsum("rin,rn->ri", bkc, x.astype(basis.dtype))
    load = 1e-9 * np.abs(np.trace(gram, axis1=1, axis2=2))[:, None, None] + 1e-30
    coef = np.linalg.solve(gram + load * np.eye(gram.shape[-1]), rhs[..., None])[..., 0]
    model = np.einsum("ri,rin->rn", coef, basis)
    return (model if np.iscomplexobj(x) else model.real).astype(x.dtype)
