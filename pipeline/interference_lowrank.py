"""Low-rank fast-time reconstruction of the samples an interference burst destroys (the
``lowrank`` fill of `pipeline.interference_repair`).

Within one frame every echo is the same beat tone in every chirp and Rx: only its complex
amplitude changes from chirp to chirp (Doppler, the scheme's Tx code, the Rx phase). The
fast-time samples of all chirps of a frame therefore lie, up to noise, in one low-dimensional
subspace: span{cos 2 pi f_k t, sin 2 pi f_k t} over the strong echoes k (a guard rail, a
range-extended continuum, needs a few more dimensions; its eigenvalues fall off with its
time-bandwidth product). The chirps the burst did not hit give that subspace: its leading
right singular vectors (subspace iteration, Golub & Van Loan 8.2.4, started from the
reference rows themselves, then Rayleigh-Ritz), kept while their per-row energy exceeds the
noise by `snr_gate`: 10 dB by default, above the Marchenko-Pastur edge of white noise's
sample eigenvalues, sigma^2 (1 + sqrt(n / N))^2 = 6.9 dB for N = 256 reference rows of
n = 384 samples (a lower gate fits noise directions). Each hit chirp's coefficients are then
estimated from its kept samples alone, and the basis evaluated over the gap; the gap carries
the echoes, not the noise (the noise is not predictable).

The estimate is the linear MMSE (MAP under a Gaussian prior) one, Kay, Fundamentals of
Statistical Signal Processing I, 12.6 / 11.4: with B (n, k) orthonormal, K the kept samples,
prior variance lambda_i - sigma^2 per coefficient and white noise sigma^2,

    c = (B_K^H B_K + sigma^2 diag(1 / (lambda_i - sigma^2)))^{-1} B_K^H y_K,
    B_K^H B_K = I - B_G^H B_G            (G: the masked samples),

so the Gram matrix is one small masked sum per burst (a difference of running sums of the
basis' outer products per masked run), one k x k Cholesky factorisation per burst. The prior
keeps the directions the kept samples barely see (a smooth function concentrated in the gap)
at their prior mean 0 instead of amplifying noise into them. A constant column with an
unbounded prior takes the chirp's offset (the chip's DC estimate includes the burst). The
rows of one chirp share a burst: their masks are united, so one Gram matrix serves the n_rx
rows.

The flags of the difference statistic sit where the interfering sweep is fastest; its slow
middle and its edges under the IF filter pass unflagged. With the echoes modelled, what is
left of a kept sample is noise plus interference: kept samples within `grow_reach` of a mask
whose residual exceeds `grow_sigma` noise standard deviations are masked too, and the
affected chirps are fitted again. The mask therefore starts at the chip's flags (closed
and widened by the hysteresis only) and grows where the burst is, instead of a fixed margin
that would also cut into every echo.

Cost per frame: the basis (a few (N, n) x (n, k + 8) products), one (R, n) x (n, k) product
each way for the R hit rows, and k^3 / 3 per hit chirp; no loop over samples or chirps
outside the compiled per-burst solve.

References
----------
.. [1] S. M. Kay, Fundamentals of Statistical Signal Processing: Estimation Theory, Prentice
       Hall 1993, sections 11.4 and 12.6 (Bayesian linear model, LMMSE estimator).
.. [2] G. H. Golub, C. F. Van Loan, Matrix Computations, 4th ed., 2013, section 8.2.4
       (orthogonal / subspace iteration) and 8.1 (Rayleigh-Ritz).
.. [3] J. Bechter, C. Waldschmidt, "Automotive radar interference mitigation by reconstruction
       and cancellation of interference component", IEEE ICMIM 2015 (reconstruction of the
       zeroed samples from a model of the echoes).
"""
from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

__all__ = ["FastTimeBasis", "fast_time_basis", "lowrank_fill"]

#: Smallest ratio noise / prior variance of a coefficient (the constant's prior is unbounded).
SHRINK_FLOOR = 1e-6
#: Grown samples closed over gaps of up to this many samples to their mask (a burst is one
#: contiguous run; its weak middle can dip under the residual threshold)...
GROW_CLOSE_SAMPLES = 16
#: ... and widened by this many (the residual threshold cuts into the burst's skirts).
GROW_MARGIN_SAMPLES = 2


class FastTimeBasis(NamedTuple):
    """The frame's fast-time signal subspace."""

    vectors: np.ndarray    # (n, k) orthonormal columns, column 0 the constant 1 / sqrt(n)
    shrink: np.ndarray     # (k,) sigma^2 / prior variance of each coefficient, >= SHRINK_FLOOR
    noise_var: float       # sigma^2 per sample, the reference rows' power outside the subspace


def fast_time_basis(ref: np.ndarray, max_rank: int, snr_gate: float,
                    n_iter: int = 2) -> FastTimeBasis:
    """The strongest fast-time components of the reference rows.

    Parameters
    ----------
    ref : (N, n) float32 or complex64
        Rows without interference (any offset: each row's mean is removed here).
    max_rank : int
        At most this many components besides the constant.
    snr_gate : float
        A component is kept if its mean energy per row exceeds snr_gate x sigma^2 (linear).
    n_iter : int
        Subspace iterations.

    Returns
    -------
    FastTimeBasis
    """
    n = ref.shape[-1]
    x = ref - ref.mean(axis=-1, keepdims=True)
    p = min(max_rank + 8, len(x), n - 1)  # 8 oversampling columns
    q = x[np.linspace(0, len(x) - 1, p).astype(np.intp)].T  # started from the rows themselves
    for _ in range(n_iter):
        q, _ = np.linalg.qr(x.conj().T @ (x @ q))
    _, s, vh = np.linalg.svd(x @ q, full_matrices=False)
    lam = s.astype(np.float64) ** 2 / len(x)
    total = float(np.vdot(x.ravel(), x.ravel()).real) / len(x)
    m = min(max_rank, len(lam))
    # The mean removal took one dimension; the power outside the k kept components is noise
    # in n - 1 - k. k depends on the noise: start from all m, settle in a few rounds.
    k = m
    for _ in range(4):
        noise = max((total - lam[:k].sum()) / max(n - 1 - k, 1), 1e-30 * total)
        k_new = int(np.sum(lam[:m] > snr_gate * noise))
        if k_new == k:
            break
        k = k_new
    v = (q @ vh.conj().T)[:, :k]
    const = np.full((n, 1), 1 / np.sqrt(n), dtype=v.dtype)
    # the floor keeps the solve defined where a burst covers a whole chirp
    shrink = np.maximum(np.r_[0.0, noise / np.maximum(lam[:k] - noise, 1e-30 * noise)],
                        SHRINK_FLOOR)
    return FastTimeBasis(np.hstack([const, v]).astype(ref.dtype, copy=False), shrink, noise)


class Runs(NamedTuple):
    """Masked runs of the bursts: burst `burst[i]` has samples start[i] .. end[i] - 1 masked;
    two runs of one burst neither overlap nor touch."""

    burst: np.ndarray   # (M,) int
    start: np.ndarray   # (M,) int
    end: np.ndarray     # (M,) int, exclusive


def _runs_of(b: np.ndarray, s: np.ndarray, e: np.ndarray, n: int) -> Runs:
    """Runs (sorted by burst, then start, ends non-decreasing within a burst) clipped to the
    row, those of one burst that overlap or touch merged into one."""
    s, e = np.maximum(s, 0), np.minimum(e, n)
    new = np.r_[True, (b[1:] != b[:-1]) | (s[1:] > e[:-1])]
    first = np.flatnonzero(new)
    last = np.r_[first[1:] - 1, len(b) - 1]
    return Runs(b[first], s[first], e[last])


def burst_runs(flags: np.ndarray, close: int, halfwidth: int) -> Runs:
    """The runs of `flags` (B, n) closed over gaps of up to `close` samples, then widened by
    `halfwidth` on each side and clipped to the row: the same samples as
    ``widen(close_gaps(flags, close), halfwidth)``, as runs (flags are sparse)."""
    b, c = np.nonzero(flags)
    new = np.r_[True, (b[1:] != b[:-1]) | (c[1:] - c[:-1] - 1 > close)]
    first = np.flatnonzero(new)
    last = np.r_[first[1:] - 1, len(b) - 1]
    return _runs_of(b[first], c[first] - halfwidth, c[last] + halfwidth + 1, flags.shape[-1])


def _united(rows: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """(B, n) bool: OR of the (R, n) bool `rows` over each burst's rows (consecutive, from
    `starts`), 8 samples per word where the row length allows."""
    if rows.shape[-1] % 8 == 0 and rows.flags.c_contiguous:
        return np.bitwise_or.reduceat(rows.view(np.uint64), starts, axis=0).view(bool)
    return np.logical_or.reduceat(rows, starts, axis=0)


def runs_mask(runs: Runs, n_bursts: int, n: int) -> np.ndarray:
    """(n_bursts, n) bool of the runs."""
    d = np.zeros((n_bursts, n + 1), dtype=np.int8)
    d[runs.burst, runs.start] = 1
    d[runs.burst, runs.end] = -1
    return np.cumsum(d[:, :n], axis=-1, dtype=np.int8) > 0


@numba.njit(cache=True, nogil=True)
def _cholesky(prefix, shrink, run_s, run_e, n_runs, low):
    """low (k, k) <- the lower Cholesky factor of I - sum over the runs of (prefix[e] -
    prefix[s]) + diag(shrink) (Hermitian positive definite: I minus the Gram matrix of part
    of an orthonormal basis, plus a positive diagonal). Only the lower triangle is written."""
    k = low.shape[0]
    for i in range(k):
        for j in range(i + 1):
            acc = prefix[0, i, j]  # 0, in the prefix' type
            for q in range(n_runs):
                acc -= prefix[run_e[q], i, j] - prefix[run_s[q], i, j]
            if i == j:
                acc += 1.0 + shrink[i]
            for m in range(j):
                acc -= low[i, m] * np.conj(low[j, m])
            if i == j:
                low[i, i] = np.sqrt(acc.real)
            else:
                low[i, j] = acc / low[j, j]


@numba.njit(cache=True, nogil=True)
def _fit_rows(x, rhs, vec_c, low, run_s, run_e, n_runs, r0, r1, c, y):
    """c[r - r0] (k,) <- LMMSE coefficients of rows r0 .. r1 - 1 from their kept samples:
    rhs[r] (the full row's projection on the basis) minus the masked runs' share (`vec_c`
    (n, k) the conjugate basis), then the two triangular solves with `low`. Inner loops run
    over contiguous, independent elements (vectorised by the compiler)."""
    k = low.shape[0]
    for r in range(r0, r1):
        y[:] = rhs[r]
        for q in range(n_runs):
            for t in range(run_s[q], run_e[q]):
                xt = x[r, t]
                for i in range(k):
                    y[i] -= xt * vec_c[t, i]
        for i in range(k):
            acc = y[i]
            for m in range(i):
                acc -= low[i, m] * y[m]
            y[i] = acc / low[i, i]
        for i in range(k - 1, -1, -1):
            acc = y[i]
            for m in range(i + 1, k):
                acc -= np.conj(low[m, i]) * c[r - r0, m]
            c[r - r0, i] = acc / low[i, i]


@numba.njit(cache=True, nogil=True)
def _evaluate(vec_t, c, t0, t1, buf):
    """buf[t0:t1] <- the model with coefficients c (k,) at samples t0 .. t1 - 1 (`vec_t`
    (k, n) the basis, transposed: the inner loop runs over contiguous samples)."""
    buf[t0:t1] = 0
    for i in range(vec_t.shape[0]):
        ci = c[i]
        for t in range(t0, t1):
            buf[t] += ci * vec_t[i, t]


@numba.njit(cache=True, nogil=True)
def _to_runs(mask, close, margin, run_s, run_e):
    """Runs of `mask` (n,) bool, closed over gaps of up to `close` samples, widened by
    `margin` and merged where they then touch; their count."""
    n = mask.shape[0]
    n_runs = 0
    last = -n - close - 2
    for t in range(n):
        if not mask[t]:
            continue
        if n_runs and t - last - 1 <= close:
            run_e[n_runs - 1] = t + 1
        else:
            run_s[n_runs] = t
            run_e[n_runs] = t + 1
            n_runs += 1
        last = t
    out = 0
    for q in range(n_runs):
        s0, e0 = max(run_s[q] - margin, 0), min(run_e[q] + margin, n)
        if out and s0 <= run_e[out - 1]:
            run_e[out - 1] = e0
        else:
            run_s[out] = s0
            run_e[out] = e0
            out += 1
    return out


@numba.njit(cache=True, nogil=True)
def _repair_bursts(x, rhs, vec_c, vec_t, prefix, shrink, row_start, run_start, runs_s, runs_e,
                   thr, reach, close, margin, mask_out):
    """Every burst's rows (row_start[b] .. row_start[b + 1] - 1 of x (R, n), modified in
    place) filled over its runs (runs_s/e[run_start[b] .. run_start[b + 1] - 1]) with their
    LMMSE model; kept samples within `reach` of a run whose residual exceeds `thr` grow the
    mask (closed over `close`, widened by `margin`) and the burst is fitted again (thr <= 0:
    never). mask_out (B, n) <- each burst's final mask."""
    n_b = len(row_start) - 1
    n, k = vec_c.shape
    low = np.zeros((k, k), dtype=prefix.dtype)
    buf = np.zeros(n, dtype=prefix.dtype)
    y = np.zeros(k, dtype=prefix.dtype)
    rows_max = np.max(row_start[1:] - row_start[:-1])
    c = np.zeros((rows_max, k), dtype=prefix.dtype)
    s_buf = np.zeros(n + 1, dtype=np.int64)
    e_buf = np.zeros(n + 1, dtype=np.int64)
    grow = np.zeros(n, dtype=np.bool_)
    for b in range(n_b):  # bursts (chirps), not samples: the work per burst is k^3 / 3
        n_runs = run_start[b + 1] - run_start[b]
        s_buf[:n_runs] = runs_s[run_start[b]:run_start[b + 1]]
        e_buf[:n_runs] = runs_e[run_start[b]:run_start[b + 1]]
        r0, r1 = row_start[b], row_start[b + 1]
        _cholesky(prefix, shrink, s_buf, e_buf, n_runs, low)
        _fit_rows(x, rhs, vec_c, low, s_buf, e_buf, n_runs, r0, r1, c, y)
        mask = mask_out[b]
        for q in range(n_runs):
            mask[s_buf[q]:e_buf[q]] = True
        if thr > 0:
            grow[:] = mask
            grown = False
            for q in range(2 * n_runs):  # the flanks of each run
                t0 = max(s_buf[q // 2] - reach, 0) if q % 2 == 0 else e_buf[q // 2]
                t1 = s_buf[q // 2] if q % 2 == 0 else min(e_buf[q // 2] + reach, n)
                for r in range(r0, r1):
                    _evaluate(vec_t, c[r - r0], t0, t1, buf)
                    for t in range(t0, t1):
                        if not mask[t] and abs(x[r, t] - buf[t]) > thr:
                            grow[t] = True
                            grown = True
            if grown:
                n_runs = _to_runs(grow, close, margin, s_buf, e_buf)
                _cholesky(prefix, shrink, s_buf, e_buf, n_runs, low)
                _fit_rows(x, rhs, vec_c, low, s_buf, e_buf, n_runs, r0, r1, c, y)
                mask[:] = False
                for q in range(n_runs):
                    mask[s_buf[q]:e_buf[q]] = True
        for r in range(r0, r1):
            for q in range(n_runs):
                _evaluate(vec_t, c[r - r0], s_buf[q], e_buf[q], buf)
                for t in range(s_buf[q], e_buf[q]):
                    x[r, t] = buf[t]


def lowrank_fill(x: np.ndarray, flags: np.ndarray, bursts: np.ndarray, basis: FastTimeBasis,
                 close: int, halfwidth: int, grow_sigma: float,
                 grow_reach: int) -> tuple[np.ndarray, np.ndarray]:
    """Masked samples replaced by the rows' low-rank LMMSE model, each row's mean removed.

    Parameters
    ----------
    x : (R, n) float32 or complex64
        Rows to repair (modified in place).
    flags : (R, n) bool
        Interference flags.
    bursts : (R,) int, non-decreasing
        Rows with the same id were hit by one burst (the Rx of one chirp): their flags are
        united before the mask is made.
    basis : FastTimeBasis
    close, halfwidth : int
        The mask: the united flags closed over gaps of up to `close` samples, then widened by
        `halfwidth` samples on each side (`burst_runs`).
    grow_sigma : float
        Kept samples within `grow_reach` of the mask whose residual from the fit exceeds
        grow_sigma x sigma are masked too, and their chirps refitted (0: never).
    grow_reach : int
        Samples.

    Returns
    -------
    (x, mask) : the repaired rows and the (R, n) mask finally used.
    """
    n = x.shape[-1]
    if not len(x):
        return x, np.zeros(x.shape, dtype=bool)
    bursts = np.asarray(bursts)
    new = np.r_[True, bursts[1:] != bursts[:-1]]
    starts = np.flatnonzero(new)
    b = basis.vectors
    k = b.shape[1]
    wide = np.complex128 if np.iscomplexobj(b) else np.float64
    prefix = np.zeros((n + 1, k, k), dtype=wide)
    np.cumsum(b.conj()[:, :, None].astype(wide) * b[:, None, :], axis=0, out=prefix[1:])
    runs = burst_runs(_united(flags, starts), close, halfwidth)
    mask_b = np.zeros((len(starts), n), dtype=bool)
    vec_c = np.ascontiguousarray(b.conj(), dtype=wide)
    rhs = (x @ vec_c.astype(b.dtype)).astype(wide)
    thr = grow_sigma * np.sqrt(basis.noise_var) if grow_sigma > 0 else 0.0
    _repair_bursts(x, rhs, vec_c, np.ascontiguousarray(b.T, dtype=wide), prefix,
                   basis.shrink.astype(np.float64), np.r_[starts, len(x)],
                   np.searchsorted(runs.burst, np.arange(len(starts) + 1)), runs.start,
                   runs.end, thr, grow_reach, GROW_CLOSE_SAMPLES, GROW_MARGIN_SAMPLES, mask_b)
    x -= x.mean(axis=-1, keepdims=True)
    return x, mask_b[np.cumsum(new) - 1]
