"""The square-law CFAR modes: cell averaging (CA), greatest-of / smallest-of (CAGO, CASO) and
ordered statistic (OS, with its compiled detector), on cells of L exponential looks.

References
----------
.. [1] H. Rohling, "Radar CFAR thresholding in clutter and multiple target situations",
       IEEE Trans. AES 19(4), 1983.
.. [2] V. G. Hansen, J. H. Sawyers, "Detectability loss due to greatest-of selection in a
       cell-averaging CFAR", IEEE Trans. AES 16(1), 1980.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numba
import numpy as np
from scipy import ndimage, special

from .base import CfarMode
from .gamma_law import Gamma

__all__ = ["CellAveraging", "SideSelecting", "OrderStatistic", "rohling_os_pfa",
           "SQUARE_LAW_MODES"]


def _half_means(train: np.ndarray, n_lag: int) -> tuple[np.ndarray, np.ndarray]:
    return train[..., :n_lag].mean(axis=-1), train[..., n_lag:].mean(axis=-1)


def _half_maps(power, lag_fp, lead_fp, window_cells):
    # The footprint is centred on the cell; ndimage correlates with a mirrored footprint,
    # which is symmetric in the two-sided case and swaps lag/lead for one side.
    lag = ndimage.correlate(power, lag_fp / window_cells, mode="wrap")
    lead = ndimage.correlate(power, lead_fp / window_cells, mode="wrap")
    return lag, lead


@dataclass(frozen=True, kw_only=True, slots=True)
class CellAveraging(CfarMode):
    """CA: the mean of both training windows (Richards eq. 6.167 for L = 1)."""

    def estimate_pdf(self, n_cells, os_rank, looks):
        return Gamma(n_cells * looks, scale=1.0 / n_cells).pdf

    def closed_form_pfa(self, scale, n_cells, os_rank, looks):
        return float((1.0 + scale / n_cells) ** -n_cells) if looks == 1 else None

    def noise_estimate(self, train, n_lag, os_rank):
        lag, lead = _half_means(train, n_lag)
        return 0.5 * (lag + lead)

    def noise_map(self, power, lag_fp, lead_fp, window_cells, os_rank):
        lag, lead = _half_maps(power, lag_fp, lead_fp, window_cells)
        return 0.5 * (lag + lead)


@dataclass(frozen=True, kw_only=True, slots=True)
class SideSelecting(CfarMode):
    """CAGO / CASO: the greater (or smaller) of the two window means (Hansen & Sawyers).

    Parameters
    ----------
    greatest : bool
        True: greatest-of (CAGO); False: smallest-of (CASO).
    """

    greatest: bool

    def estimate_pdf(self, n_cells, os_rank, looks):
        half = n_cells // 2
        mean_half = Gamma(half * looks, scale=1.0 / half)
        if self.greatest:
            return lambda y: 2 * mean_half.cdf(y) * mean_half.pdf(y)
        return lambda y: 2 * mean_half.sf(y) * mean_half.pdf(y)

    def _select(self, lag, lead):
        return np.maximum(lag, lead) if self.greatest else np.minimum(lag, lead)

    def noise_estimate(self, train, n_lag, os_rank):
        return self._select(*_half_means(train, n_lag))

    def noise_map(self, power, lag_fp, lead_fp, window_cells, os_rank):
        return self._select(*_half_maps(power, lag_fp, lead_fp, window_cells))


@dataclass(frozen=True, kw_only=True, slots=True)
class OrderStatistic(CfarMode):
    """OS: the k-th smallest training cell (Rohling 1983)."""

    ranked: ClassVar[bool] = True

    def estimate_pdf(self, n_cells, os_rank, looks):
        gam = Gamma(looks)
        n, k = n_cells, os_rank
        log_c = special.gammaln(n + 1) - special.gammaln(k) - special.gammaln(n - k + 1)

        def pdf(y):
            cdf = np.clip(gam.cdf(y), 1e-300, 1.0)
            sf = np.clip(gam.sf(y), 1e-300, 1.0)
            return np.exp(log_c + (k - 1) * np.log(cdf) + (n - k) * np.log(sf)) * gam.pdf(y)
        return pdf

    def closed_form_pfa(self, scale, n_cells, os_rank, looks):
        return rohling_os_pfa(scale, n_cells, os_rank) if looks == 1 else None

    def noise_estimate(self, train, n_lag, os_rank):
        """OS partitions `train` in place."""
        train.partition(os_rank - 1, axis=-1)
        return train[..., os_rank - 1]

    def noise_map(self, power, lag_fp, lead_fp, window_cells, os_rank):
        return ndimage.rank_filter(power, os_rank - 1, footprint=lag_fp | lead_fp, mode="wrap")

    def candidate_mask(self, power, axis, alpha, os_rank):
        """Exact necessary condition: the k-th smallest of a subset of the line along `axis`
        is >= the k-th smallest of the whole line, so alpha x that bounds the threshold."""
        col_k = np.take(np.partition(power, os_rank - 1, axis=axis), [os_rank - 1], axis=axis)
        return power > alpha * col_k

    compiled_peaks = True

    def peaks(self, power, alpha, train_idx, os_rank, neighbours, first_bin, rows0=None):
        """One compiled pass: local maximum, then the OS test as a count (the k-th smallest
        training cell y_(k) satisfies alpha y_(k) < x iff at least k cells do, alpha y rounded
        as the numpy path rounds it), the k-th value itself only for the hits."""
        lo, hi = (0, power.shape[0]) if rows0 is None else rows0
        return _os_peaks(power, power.dtype.type(alpha), train_idx, os_rank, *neighbours,
                         first_bin, lo, hi)


@numba.njit(cache=True, nogil=True)
def _os_peaks(p, alpha, train_idx, k, check0, cyclic0, check1, cyclic1, first1, lo0, hi0):
    """(a, r, d, noise) of the cells of p (n0, n1, n_cfar) that are local maxima along the
    last axis (cyclic) and along axis 0 / 1 where checked (cyclic or not; the test of
    `kernels.local_max_mask`: greater than the previous cell, not less than the next), have
    index >= first1 on axis 1, and exceed alpha x the k-th smallest of their training cells
    train_idx[d] (n_cfar, N) along the last axis; only rows lo0 <= a < hi0 of axis 0."""
    n0, n1, n2 = p.shape
    n_train = train_idx.shape[1]
    h = n_train // 2
    out = []
    train = np.empty(n_train, p.dtype)
    none = np.full(n2, -np.inf, p.dtype)  # a missing neighbour: every cell exceeds it
    ok = np.empty(n2, np.bool_)
    cand = np.empty(n2, np.int64)
    for a in range(lo0, hi0):
        a_prev = a - 1 if a > 0 else (n0 - 1 if cyclic0 else -1)
        a_next = a + 1 if a < n0 - 1 else (0 if cyclic0 else -1)
        for r in range(first1, n1):
            r_prev = r - 1 if r > 0 else (n1 - 1 if cyclic1 else -1)
            r_next = r + 1 if r < n1 - 1 else (0 if cyclic1 else -1)
            row = p[a, r]
            pa = p[a_prev, r] if check0 and a_prev >= 0 else none
            na = p[a_next, r] if check0 and a_next >= 0 else none
            pr = p[a, r_prev] if check1 and r_prev >= 0 else none
            nr = p[a, r_next] if check1 and r_next >= 0 else none
            # Branch-free local-maximum test of the whole row (vectorised by LLVM): the cells
            # are random under noise, so a test per branch mispredicts half the time.
            for d in range(n2):
                x = row[d]
                ok[d] = (x > pa[d]) & ~(na[d] > x) & (x > pr[d]) & ~(nr[d] > x)
            for d in range(1, n2 - 1):
                ok[d] &= (row[d] > row[d - 1]) & ~(row[d + 1] > row[d])
            ok[0] &= (row[0] > row[n2 - 1]) & ~(row[1 % n2] > row[0])
            ok[n2 - 1] &= (row[n2 - 1] > row[n2 - 2 if n2 > 1 else 0]) & ~(row[0] > row[n2 - 1])
            # The candidates' positions, compressed without a branch per cell (a local
            # maximum is rare and random: a branch would mispredict on each).
            nc = 0
            for d in range(n2):
                cand[nc] = d
                nc += ok[d]
            for ci in range(nc):
                d = cand[ci]
                x = row[d]
                # The count without branches, the first half first: fewer than k - (n_train
                # - h) below there and the cell cannot reach k. The training positions are
                # read from the table in place: a view train_idx[d] per candidate costs numba
                # an array structure each (R79 DDMA map, 90 k candidates: 3.2 -> 2.4 ms).
                below = 0
                for t in range(h):
                    below += alpha * row[train_idx[d, t]] < x
                if below + (n_train - h) < k:
                    continue
                for t in range(h, n_train):
                    below += alpha * row[train_idx[d, t]] < x
                if below < k:
                    continue
                for t in range(n_train):
                    train[t] = row[train_idx[d, t]]
                out.append((a, r, d, np.sort(train)[k - 1]))
    m = len(out)
    idx = np.empty((3, m), np.int64)
    noise = np.empty(m, p.dtype)
    for i in range(m):
        idx[0, i], idx[1, i], idx[2, i], noise[i] = out[i]
    return idx, noise


def rohling_os_pfa(scale: float, n_cells: int, os_rank: int) -> float:
    """Rohling's closed form for OS-CFAR on exponential cells (design.md 8):
    Pfa = k C(N,k) Gamma(k) Gamma(a+N-k+1) / Gamma(a+N+1)."""
    n, k, a = n_cells, os_rank, scale
    log_p = (np.log(k) + special.gammaln(n + 1) - special.gammaln(k + 1)
             - special.gammaln(n - k + 1) + special.gammaln(k)
             + special.gammaln(a + n - k + 1) - special.gammaln(a + n + 1))
    return float(np.exp(log_p))


#: The square-law modes (`modes.CFAR_MODES` registers them).
SQUARE_LAW_MODES = (
    CellAveraging(name="ca", description="cell averaging: mean of both windows"),
    SideSelecting(name="cago", greatest=True,
                  description="greatest-of: larger of the two window means"),
    SideSelecting(name="caso", greatest=False,
                  description="smallest-of: smaller of the two window means"),
    OrderStatistic(name="os",
                   description="ordered statistic: k-th smallest training cell"),
)
