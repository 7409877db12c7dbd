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
at their prior mean 0 instead of amplifying noise into them. A constant column with an unbounded prior takes the
chirp's offset (the chip's DC estimate includes the burst). The rows of one chirp share a
burst: their masks are united, so one Gram matrix serves the n_rx rows.

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
def _solve_bursts(gap: np.ndarray, shrink: np.ndarray, rhs: np.ndarray,
                  row_start: np.ndarray) -> np.ndarray:
    """(R, k) solutions of (I - gap[b] + diag(shrink)) c = rhs[r] for the rows r of every
    burst b (rows row_start[b] .. row_start[b + 1] - 1): one Cholesky factorisation per burst
    (the matrix is Hermitian positive definite: I minus a Gram matrix of part of an
    orthonormal basis, plus a non-negative diagonal), two triangular solves per row."""
    n_b, k = gap.shape[0], gap.shape[1]
    out = np.empty_like(rhs)
    low = np.zeros((k, k), dtype=gap.dtype)
    y = np.zeros(k, dtype=gap.dtype)
    for bi in range(n_b):  # bursts, not samples: k^3 / 3 per burst
        for i in range(k):
            for j in range(i + 1):
                acc = -gap[bi, i, j]
                if i == j:
                    acc += 1.0 + shrink[i]
                for m in range(j):
                    acc -= low[i, m] * np.conj(low[j, m])
                if i == j:
                    low[i, i] = np.sqrt(acc.real)
                else:
                    low[i, j] = acc / low[j, j]
        for r in range(row_start[bi], row_start[bi + 1]):
            for i in range(k):
                acc = rhs[r, i]
                for m in range(i):
                    acc -= low[i, m] * y[m]
                y[i] = acc / low[i, i]
            for i in range(k - 1, -1, -1):
                acc = y[i]
                for m in range(i + 1, k):
                    acc -= np.conj(low[m, i]) * out[r, m]
                out[r, i] = acc / low[i, i]
    return out


def _coefficients(x: np.ndarray, mask: np.ndarray, row_start: np.ndarray, runs: Runs,
                  basis: FastTimeBasis, prefix: np.ndarray) -> np.ndarray:
    """(R, k) LMMSE coefficients of the rows from their kept samples (`mask` (R, n) the
    masked ones; the rows of burst b are row_start[b] .. row_start[b + 1] - 1, its masked
    samples `runs`; module docstring). `prefix` (n + 1, k, k): running sums of the basis'
    outer products, so a run's Gram matrix is one difference."""
    b = basis.vectors
    k = b.shape[1]
    n_b = len(row_start) - 1
    wide = np.complex128 if np.iscomplexobj(b) else np.float64
    # runs come sorted by burst; a burst without a run (no flag) has no gap
    per_run = np.concatenate([prefix[runs.end] - prefix[runs.start],
                              np.zeros((1, k, k), prefix.dtype)])
    gap = np.add.reduceat(per_run, np.searchsorted(runs.burst, np.arange(n_b)), axis=0)
    gap[np.bincount(runs.burst, minlength=n_b) == 0] = 0
    rhs = np.where(mask, 0, x) @ (b.conj() if np.iscomplexobj(b) else b)
    return _solve_bursts(gap.astype(wide), basis.shrink, rhs.astype(wide),
                         row_start).astype(b.dtype)


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
    bursts = np.asarray(bursts)
    new = np.r_[True, bursts[1:] != bursts[:-1]]
    burst = np.cumsum(new) - 1  # 0 .. B - 1 per row
    starts = np.flatnonzero(new)
    n_b = len(starts)
    row_start = np.r_[starts, len(x)]
    b = basis.vectors
    k = b.shape[1]
    prefix = np.zeros((n + 1, k, k), dtype=b.dtype)
    np.cumsum(b.conj()[:, :, None] * b[:, None, :], axis=0, out=prefix[1:])
    runs = burst_runs(_united(flags, starts), close, halfwidth)
    mask_b = runs_mask(runs, n_b, n)
    c = _coefficients(x, mask_b[burst], row_start, runs, basis, prefix)
    if grow_sigma > 0:
        near = runs_mask(_runs_of(runs.burst, runs.start - grow_reach, runs.end + grow_reach,
                                  n), n_b, n) & ~mask_b
        res = np.abs(x - c @ b.T) > grow_sigma * np.sqrt(basis.noise_var)
        out = _united(near[burst] & res, starts)
        hit = np.flatnonzero(out.any(axis=-1))
        if hit.size:
            grown = burst_runs(mask_b[hit] | out[hit], GROW_CLOSE_SAMPLES, GROW_MARGIN_SAMPLES)
            mask_b[hit] = runs_mask(grown, hit.size, n)
            rows = np.flatnonzero(np.isin(burst, hit))
            counts = row_start[hit + 1] - row_start[hit]
            c[rows] = _coefficients(x[rows], mask_b[burst[rows]], np.r_[0, np.cumsum(counts)],
                                    grown, basis, prefix)
    m = mask_b[burst]
    np.copyto(x, c @ b.T, where=m, casting="same_kind")
    x -= x.mean(axis=-1, keepdims=True)
    return x, m
