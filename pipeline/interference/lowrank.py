"""Low-rank fast-time reconstruction of the samples an interference burst destroys (the
``lowrank`` fill of `pipeline.interference.methods`).

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
for the R hit rows, the running sums of the basis' outer products (n k^2 / 2), and per hit
chirp one k x k Cholesky factorisation (k^3 / 6) plus k per masked or flank sample and row;
no loop over samples or chirps outside the compiled per-burst kernel, whose bursts run in
parts on the cores (`pipeline.threads`).

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
import scipy.linalg

from core.errors import BadInput

from ..threads import run_parts, spans

__all__ = ["FastTimeBasis", "fast_time_basis", "lowrank_fill", "burst_fill", "BurstFill",
           "GramOperands", "MaskRules", "gram_operands", "projections", "burst_row_start"]

#: Smallest ratio noise / prior variance of a coefficient (the constant's prior is unbounded).
SHRINK_FLOOR = 1e-6
#: Grown samples closed over gaps of up to this many samples to their mask (a burst is one
#: contiguous run; its weak middle can dip under the residual threshold)...
GROW_CLOSE_SAMPLES = 16
#: ... and widened by this many (the residual threshold cuts into the burst's skirts).
GROW_MARGIN_SAMPLES = 2
#: The conjugate basis the fits subtract with has a multiple of this many columns (zeros
#: beyond the k components): LLVM vectorises that loop 8 x 4 wide, k = 23 would stay scalar.
FIT_COLUMNS = 32


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
    xh = x.conj().T if np.iscomplexobj(x) else x.T  # no conjugated copy of real rows
    for _ in range(n_iter):  # LAPACK's QR in the rows' own precision (numpy's: in double)
        q = scipy.linalg.qr(xh @ (x @ q), mode="economic", overwrite_a=True,
                            check_finite=False)[0]
    # Rayleigh-Ritz: the eigenvectors w of the p x p Gram matrix (x q)^H (x q), in double
    # (the squares of the singular values span twice the dynamic range), are the right
    # singular vectors of x q; the basis is q w, largest eigenvalue first.
    b = (x @ q).astype(np.complex128 if np.iscomplexobj(x) else np.float64)
    ev, w = np.linalg.eigh(b.conj().T @ b)
    ev, w = ev[::-1], w[:, ::-1]
    lam = np.maximum(ev, 0.0) / len(x)
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
    v = q @ w[:, :k].astype(q.dtype)
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


def burst_runs(flags: np.ndarray, close: int, halfwidth: int) -> Runs:
    """The runs of each row of `flags` (B, n) closed over gaps of up to `close` samples, then
    widened by `halfwidth` on each side, clipped to the row and merged where they touch: the
    same samples as ``widen(close_gaps(flags, close), halfwidth)``, as runs (the compiled
    `_to_runs` the fill makes its masks with)."""
    n = flags.shape[-1]
    s_buf, e_buf = np.zeros(n + 1, np.int64), np.zeros(n + 1, np.int64)
    out = []
    for i, row in enumerate(np.ascontiguousarray(flags, dtype=bool)):  # a test helper
        m = _to_runs(row, close, halfwidth, s_buf, e_buf)
        out.append((np.full(m, i), s_buf[:m].copy(), e_buf[:m].copy()))
    return Runs(*(np.concatenate([o[j] for o in out]) if out else np.zeros(0, np.int64)
                  for j in range(3)))


def runs_mask(runs: Runs, n_bursts: int, n: int) -> np.ndarray:
    """(n_bursts, n) bool of the runs."""
    d = np.zeros((n_bursts, n + 1), dtype=np.int8)
    d[runs.burst, runs.start] = 1
    d[runs.burst, runs.end] = -1
    return np.cumsum(d[:, :n], axis=-1, dtype=np.int8) > 0


# The compiled kernels. Every float64 (complex128) value is computed by the same operations
# in the same order as the straightforward formulation (the Cholesky's and the solves'
# subtractions in increasing index order, the model summed over components in increasing
# order from 0): the loops are only arranged so that the innermost one runs over independent,
# contiguous elements (vectorised by the compiler) or over the rows of a burst (independent
# dependency chains), and the result does not depend on the arrangement. Inner loops run over
# unsigned indices: a signed index may be negative (numba wraps it around), which keeps LLVM
# from vectorising the loop.
_U = np.uint64

@numba.njit(cache=True, nogil=True)
def _gram_prefix(vec_c, vec):
    """(n + 1, k (k + 1) / 2) running sums over samples of the basis' outer products
    conj(b_i) b_j, i >= j, packed by j (row j holds i = j .. k - 1): the Gram matrix of the
    samples s .. e - 1 is prefix[e] - prefix[s]."""
    n, k = vec.shape
    prefix = np.zeros((n + 1, k * (k + 1) // 2), dtype=vec.dtype)
    for t in range(n):
        p = 0
        for j in range(k):
            bj = vec[t, j]
            for i in range(j, k):
                o = vec_c[t, i] * bj
                prefix[t + 1, p] = o if t == 0 else prefix[t, p] + o
                p += 1
    return prefix


@numba.njit(cache=True, nogil=True)
def _cholesky(prefix, shrink, run_s, run_e, n_runs, lt, acc):
    """lt (k, k) <- the Cholesky factor L of I - sum over the runs of (prefix[e] - prefix[s])
    + diag(shrink), transposed: lt[j, i] = L[i, j] for i >= j (the lower triangle of L, its
    columns as rows). The matrix is Hermitian positive definite: I minus the Gram matrix of
    part of an orthonormal basis, plus a positive diagonal. The runs' Gram sums are taken
    over the whole packed triangle at once (acc (k (k + 1) / 2,) scratch: one long loop the
    compiler vectorises, each element's subtractions in run order as before), then unpacked.
    Right-looking (each column updates the trailing rows of lt, contiguous), the subtractions
    of each element in the order of the left-looking textbook form (Golub & Van Loan
    4.2.5)."""
    k = lt.shape[0]
    uk = _U(k)
    n_p = _U(acc.shape[0])
    p0 = prefix[0]
    for p in range(n_p):
        acc[p] = p0[p]  # 0, in the prefix' type
    for q in range(n_runs):
        pe, ps = prefix[run_e[q]], prefix[run_s[q]]
        for p in range(n_p):
            acc[p] -= pe[p] - ps[p]
    p = _U(0)
    for j in range(uk):
        w = uk - j  # row j of the packed prefix: i = j .. k - 1
        for i in range(j, uk):
            lt[j, i] = acc[p + i - j]
        lt[j, j] += 1.0 + shrink[j]
        p += w
    # two columns m, m + 1 at a time: row m + 1 takes column m's update and is finished,
    # then the trailing rows take both updates in one pass (m's subtraction, then m + 1's:
    # the same order as one column at a time, half the passes over the trailing triangle)
    m = _U(0)
    while m < uk:
        lt[m, m] = np.sqrt(lt[m, m].real)
        d = lt[m, m]
        for i in range(m + _U(1), uk):
            lt[m, i] = lt[m, i] / d
        m1 = m + _U(1)
        if m1 == uk:
            break
        w = np.conj(lt[m, m1])
        for i in range(m1, uk):
            lt[m1, i] -= lt[m, i] * w
        lt[m1, m1] = np.sqrt(lt[m1, m1].real)
        d = lt[m1, m1]
        for i in range(m1 + _U(1), uk):
            lt[m1, i] = lt[m1, i] / d
        for j in range(m1 + _U(1), uk):
            wa, wb = np.conj(lt[m, j]), np.conj(lt[m1, j])
            for i in range(j, uk):
                lt[j, i] = (lt[j, i] - lt[m, i] * wa) - lt[m1, i] * wb
        m += _U(2)


@numba.njit(cache=True, nogil=True)
def _fit_rows(x, rhs, vec_c, lt, run_s, run_e, n_runs, r0, r1, y, c):
    """c[:, r - r0] (k,) <- LMMSE coefficients of rows r0 .. r1 - 1 from their kept samples:
    rhs[r] (the full row's projection on the basis) minus the masked runs' share (`vec_c`
    (n, kp) the conjugate basis, zero beyond column k), then the two triangular solves with
    `lt` (`_cholesky`). y (>= R4, kp) scratch; c (k, >= R4): R4 the burst's rows rounded up
    to a multiple of 4 (the solves run 4 rows at a time; what the padding rows hold is
    meaningless).

    The solves keep each value's running difference in a register, 4 rows side by side
    (independent dependency chains), instead of updating it in memory: the same subtractions
    in the same order (increasing m for both, as the column form of the forward solve takes
    them) and the same division."""
    uk = _U(lt.shape[0])
    kp = _U(vec_c.shape[1])  # >= k: zero columns, so that the loop over them vectorises
    nr = r1 - r0
    nr4 = (nr + 3) // 4 * 4
    if y.shape[0] < nr4 or c.shape[1] < nr4:
        raise BadInput("_fit_rows: y and c must hold the burst's rows rounded up to 4")
    for r in range(nr):
        for i in range(kp):
            y[r, i] = rhs[r0 + r, i] if i < uk else 0
    for r in range(nr):  # each row's samples in run order, as the samples' loop took them
        yr, xr = y[r], x[r0 + r]
        for q in range(n_runs):
            for t in range(_U(run_s[q]), _U(run_e[q])):
                xt = xr[t]
                for i in range(kp):
                    yr[i] -= xt * vec_c[t, i]
    for g in range(0, nr4, 4):
        g1, g2, g3 = g + 1, g + 2, g + 3
        # L y' = y: y'[i] = (y[i] - sum_m<i L[i, m] y'[m]) / L[i, i], in column form: once
        # y'[m] is known it is subtracted from every later element (a loop over contiguous,
        # independent elements), each element's subtractions in increasing m
        for m in range(uk):
            d = lt[m, m]
            v0, v1, v2, v3 = y[g, m] / d, y[g1, m] / d, y[g2, m] / d, y[g3, m] / d
            y[g, m], y[g1, m], y[g2, m], y[g3, m] = v0, v1, v2, v3
            for i in range(m + _U(1), uk):
                w = lt[m, i]
                y[g, i] -= w * v0
                y[g1, i] -= w * v1
                y[g2, i] -= w * v2
                y[g3, i] -= w * v3
        for ii in range(uk):  # L^H c = y', from the last coefficient back
            i = uk - _U(1) - ii
            s0, s1, s2, s3 = y[g, i], y[g1, i], y[g2, i], y[g3, i]
            for m in range(i + _U(1), uk):
                w = np.conj(lt[i, m])
                s0 -= w * c[m, g]
                s1 -= w * c[m, g1]
                s2 -= w * c[m, g2]
                s3 -= w * c[m, g3]
            d = lt[i, i]
            c[i, g], c[i, g1], c[i, g2], c[i, g3] = s0 / d, s1 / d, s2 / d, s3 / d


@numba.njit(cache=True, nogil=True)
def _evaluate(vec_t, c, nr, t0, t1, buf):
    """buf[r, t0:t1] <- the model with coefficients c[:, r] at samples t0 .. t1 - 1, rows
    r < nr (`vec_t` (k, n) the basis, transposed: the inner loop runs over contiguous
    samples). Each value is summed over the components in increasing order from 0; four rows
    at a time take a component's samples from one load (~3x faster than a pass per row and
    component, the same sums)."""
    a, b = _U(t0), _U(t1)
    for r in range(nr):
        for t in range(a, b):
            buf[r, t] = 0
    r4 = nr - nr % 4
    for r in range(0, r4, 4):
        for i in range(vec_t.shape[0]):
            c0, c1, c2, c3 = c[i, r], c[i, r + 1], c[i, r + 2], c[i, r + 3]
            for t in range(a, b):
                v = vec_t[i, t]
                buf[r, t] += c0 * v
                buf[r + 1, t] += c1 * v
                buf[r + 2, t] += c2 * v
                buf[r + 3, t] += c3 * v
    for r in range(r4, nr):
        for i in range(vec_t.shape[0]):
            ci = c[i, r]
            for t in range(a, b):
                buf[r, t] += ci * vec_t[i, t]


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
def _grow(x, r0, nr, vec_t, c, t0, t1, thr, buf, united):
    """Whether a sample t0 <= t < t1 of rows r0 .. r0 + nr - 1 of x is off the model with
    coefficients c (`_evaluate`, into buf) by more than `thr`; such samples are set in
    `united`."""
    grown = False
    if t1 <= t0:
        return grown
    _evaluate(vec_t, c, nr, t0, t1, buf)
    for r in range(nr):  # branch-free on unsigned indices: LLVM vectorises it
        for u in range(_U(t0), _U(t1)):
            hit = abs(x[r0 + r, u] - buf[r, u]) > thr
            united[u] |= hit
            grown |= hit
    return grown


@numba.njit(cache=True, nogil=True)
def _repair_bursts(x, flags, rhs, ops, row_start, rules, b0, b1, mask_out):
    """Bursts b0 .. b1 - 1: burst b's rows row_start[b] .. row_start[b + 1] - 1 of x (R, n)
    (modified in place) filled over its mask with their LMMSE model, from their projections
    `rhs` (R, k) and the basis' operands `ops` (`GramOperands`). The mask (`MaskRules`
    `rules`): the rows' `flags` (R, n) united, closed over `close` and widened by `halfwidth`
    (`_to_runs`); kept samples within `grow_reach` of it whose residual exceeds
    `grow_threshold` grow it (closed over `grow_close`, widened by `grow_margin`) and the burst
    is fitted again (threshold <= 0: never). mask_out (B, n) <- each burst's final mask.
    Bursts are independent: disjoint burst ranges can run at the same time.

    `ops` and `rules` come as plain tuples of their fields, in order (`BurstFill.run`):
    numba's cache index pickles a named tuple argument's class, and an index that names a
    class the source no longer defines fails to load (AttributeError) instead of being
    refreshed, so a checkout of older code would stop at the first kernel call."""
    vec_c, vec_t, prefix, shrink = ops
    close, halfwidth, thr, reach, grow_close, grow_margin = rules
    n, kp = vec_c.shape
    k = vec_t.shape[0]
    if b1 <= b0:
        return
    rows_max = np.max(row_start[b0 + 1:b1 + 1] - row_start[b0:b1])
    rows4 = (rows_max + 3) // 4 * 4  # `_fit_rows` solves 4 rows at a time
    lt = np.zeros((k, k), dtype=prefix.dtype)
    acc = np.zeros(prefix.shape[1], dtype=prefix.dtype)
    y = np.zeros((rows4, kp), dtype=prefix.dtype)
    c = np.zeros((k, rows4), dtype=prefix.dtype)
    buf = np.zeros((rows_max, n), dtype=prefix.dtype)
    s_buf = np.zeros(n + 1, dtype=np.int64)
    e_buf = np.zeros(n + 1, dtype=np.int64)
    united = np.zeros(n, dtype=np.bool_)
    for b in range(b0, b1):  # bursts (chirps), not samples: the work per burst is k^3 / 6
        r0, r1 = row_start[b], row_start[b + 1]
        nr = r1 - r0
        for t in range(_U(n)):
            united[t] = flags[r0, t]
        for r in range(r0 + 1, r1):
            for t in range(_U(n)):
                united[t] |= flags[r, t]
        n_runs = _to_runs(united, close, halfwidth, s_buf, e_buf)
        _cholesky(prefix, shrink, s_buf, e_buf, n_runs, lt, acc)
        _fit_rows(x, rhs, vec_c, lt, s_buf, e_buf, n_runs, r0, r1, y, c)
        mask = mask_out[b]
        for q in range(n_runs):
            mask[s_buf[q]:e_buf[q]] = True
        if thr > 0 and n_runs:
            # the unmasked samples within `reach` of a run (its flanks), gap by gap: the runs
            # are sorted and apart, so the gap [lo, hi) before run q holds run q - 1's right
            # flank [lo, right) and run q's left flank [left, hi) (an end gap only one of
            # them), the whole gap where they meet
            grown = False
            united[:] = mask  # the grown mask
            for q in range(n_runs + 1):
                lo = e_buf[q - 1] if q > 0 else np.int64(0)
                hi = s_buf[q] if q < n_runs else np.int64(n)
                right = min(lo + reach, hi) if q > 0 else lo
                left = max(hi - reach, lo) if q < n_runs else hi
                if right >= left:
                    grown |= _grow(x, r0, nr, vec_t, c, lo, hi, thr, buf, united)
                else:
                    grown |= _grow(x, r0, nr, vec_t, c, lo, right, thr, buf, united)
                    grown |= _grow(x, r0, nr, vec_t, c, left, hi, thr, buf, united)
            if grown:
                n_runs = _to_runs(united, grow_close, grow_margin, s_buf, e_buf)
                _cholesky(prefix, shrink, s_buf, e_buf, n_runs, lt, acc)
                _fit_rows(x, rhs, vec_c, lt, s_buf, e_buf, n_runs, r0, r1, y, c)
                mask[:] = False
                for q in range(n_runs):
                    mask[s_buf[q]:e_buf[q]] = True
        for q in range(n_runs):
            _evaluate(vec_t, c, nr, s_buf[q], e_buf[q], buf)
            for r in range(nr):
                for t in range(_U(s_buf[q]), _U(e_buf[q])):
                    x[r0 + r, t] = buf[r, t]


class MaskRules(NamedTuple):
    """How the per-burst kernel makes and grows a burst's mask (`_repair_bursts`)."""

    close: int             # the united flags closed over gaps of up to this many samples...
    halfwidth: int         # ... then widened by this many on each side
    grow_threshold: float  # kept samples whose residual exceeds this grow the mask (<= 0: never)
    grow_reach: int        # ... within this many samples of it
    grow_close: int        # grown samples closed over gaps of up to this many...
    grow_margin: int       # ... and widened by this many


class GramOperands(NamedTuple):
    """The basis' operands of the per-burst kernel (`gram_operands`), in its wide type."""

    vec_c: np.ndarray    # (n, kp) the conjugate basis, zero beyond column k
    vec_t: np.ndarray    # (k, n) the basis, transposed
    prefix: np.ndarray   # `_gram_prefix` of the basis
    shrink: np.ndarray   # (k,) float64, sigma^2 / prior variance of each coefficient


class BurstFill(NamedTuple):
    """The "lowrank" fill of rows x (R, n) prepared up to its per-burst work (`burst_fill`):
    `run` repairs any range of bursts, each exactly once, in any order and on any thread."""

    x: np.ndarray          # (R, n) the rows, repaired in place by `run`
    flags: np.ndarray      # (R, n) bool, C-contiguous
    rhs: np.ndarray        # (R, k) the rows' projections on the conjugate basis
    ops: GramOperands
    row_start: np.ndarray  # (B + 1,) burst b is rows row_start[b] .. row_start[b + 1] - 1
    rules: MaskRules
    mask: np.ndarray       # (B, n) bool, each burst's final mask once `run` has run on it

    def run(self, b0: int, b1: int) -> None:
        """Repair bursts b0 .. b1 - 1 (rows row_start[b0] .. row_start[b1] - 1 of x) in
        place; the same values whatever the ranges the bursts are run in."""
        _repair_bursts(self.x, self.flags, self.rhs, tuple(self.ops), self.row_start,
                       tuple(self.rules), b0, b1, self.mask)

    def run_all(self, remove_mean: bool = True) -> None:
        """Every burst, in parts on the cores (`pipeline.threads`), each part's rows' means
        removed after it if `remove_mean` (row by row: the same in any part)."""
        def part(lo: int, hi: int) -> None:
            self.run(lo, hi)
            if remove_mean:
                rows = self.x[self.row_start[lo]:self.row_start[hi]]
                rows -= rows.mean(axis=-1, keepdims=True)
        run_parts([lambda lo=lo, hi=hi: part(lo, hi)
                   for lo, hi in spans(len(self.row_start) - 1)])


def gram_operands(basis: FastTimeBasis) -> GramOperands:
    """The conjugate basis (padded to `FIT_COLUMNS`), the transposed basis, the running sums
    of its outer products (compiled) and the shrinkage, in the kernel's wide type."""
    b = basis.vectors
    n, k = b.shape
    wide = np.complex128 if np.iscomplexobj(b) else np.float64
    vec_c = np.zeros((n, -(-k // FIT_COLUMNS) * FIT_COLUMNS), dtype=wide)
    vec_c[:, :k] = b.conj()
    return GramOperands(vec_c, np.ascontiguousarray(b.T, dtype=wide),
                        _gram_prefix(vec_c, np.ascontiguousarray(b, dtype=wide)),
                        basis.shrink.astype(np.float64))


def projections(x: np.ndarray, basis: FastTimeBasis) -> np.ndarray:
    """(R, k) the rows' projections on the conjugate basis (BLAS), in the kernel's wide type."""
    b = basis.vectors
    return (x @ b.conj()).astype(np.complex128 if np.iscomplexobj(b) else np.float64)


def burst_row_start(bursts: np.ndarray) -> np.ndarray:
    """(B + 1,) where each burst's rows start, then the row count: rows of equal consecutive
    `bursts` ((R,) int, e.g. their chirps) form one burst, rows row_start[b] .. [b + 1] - 1."""
    bursts = np.asarray(bursts)
    return np.r_[np.flatnonzero(np.r_[True, bursts[1:] != bursts[:-1]]), len(bursts)]


def burst_fill(x: np.ndarray, flags: np.ndarray, bursts: np.ndarray, basis: FastTimeBasis,
               close: int, halfwidth: int, grow_sigma: float, grow_reach: int) -> BurstFill:
    """`lowrank_fill`'s work up to the bursts: the rows' projections on the basis and the
    basis' Gram sums, side by side on the cores (`projections`, `gram_operands`), the
    kernel's operands. Arguments as `lowrank_fill`; x must hold at least one row."""
    n = x.shape[-1]
    row_start = burst_row_start(bursts)
    rhs, operands = run_parts([lambda: projections(x, basis), lambda: gram_operands(basis)])
    thr = float(grow_sigma * np.sqrt(basis.noise_var)) if grow_sigma > 0 else 0.0
    rules = MaskRules(int(close), int(halfwidth), thr, int(grow_reach), GROW_CLOSE_SAMPLES,
                      GROW_MARGIN_SAMPLES)
    return BurstFill(x, np.ascontiguousarray(flags, dtype=bool), rhs, operands, row_start,
                     rules, np.zeros((len(row_start) - 1, n), dtype=bool))


def lowrank_fill(x: np.ndarray, flags: np.ndarray, bursts: np.ndarray, basis: FastTimeBasis,
                 close: int, halfwidth: int, grow_sigma: float, grow_reach: int,
                 remove_mean: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Masked samples replaced by the rows' low-rank LMMSE model, each row's mean removed
    (``rows -= rows.mean(axis=-1, keepdims=True)``; with `remove_mean` False that is left to
    the caller, who may fuse it into a later pass).

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
        `halfwidth` samples on each side (per burst in the compiled `_to_runs`; `burst_runs`
        is the same mask in numpy).
    grow_sigma : float
        Kept samples within `grow_reach` of the mask whose residual from the fit exceeds
        grow_sigma x sigma are masked too, and their chirps refitted (0: never).
    grow_reach : int
        Samples.

    Returns
    -------
    (x, mask) : the repaired rows and the (R, n) mask finally used.

    Notes
    -----
    The bursts are independent; they run in parts on the cores (`pipeline.threads`: the
    same values whatever the number of parts).
    """
    if not len(x):
        return x, np.zeros(x.shape, dtype=bool)
    fill = burst_fill(x, flags, bursts, basis, close, halfwidth, grow_sigma, grow_reach)
    fill.run_all(remove_mean)
    return x, fill.mask[np.repeat(np.arange(len(fill.mask)), np.diff(fill.row_start))]
