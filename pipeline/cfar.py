"""CFAR detectors (CA, CAGO, CASO, OS) along one cyclic axis, and their threshold design.

The noise estimate Y of a cell under test comes from `window_cells` training cells on each side,
`guard_cells` away from it; a detection is declared when the cell exceeds alpha * Y. The scale
alpha is derived from a false-alarm probability for cells that are sums of L independent
exponential (square-law) looks: L = 1 for a coherent map, L = number of channels for a
non-coherent sum. Pfa(alpha) = E_Y[ Q(L, alpha Y) ] is integrated numerically for every mode; for
L = 1 it reproduces Rohling's OS formula and the CA closed form (DESIGN section 8).

Each mode is a `CfarMode` object in the `CFAR_MODES` registry: the distribution of its noise
estimate (threshold design), the estimate itself (gathered training cells or a full map), and an
optional cheap necessary condition that the chain uses to skip cells before gathering training
cells. TI's ``cfarCfg`` averageMode codes name these modes in one table,
`radarsim.ti.codes.CFAR_AVERAGE_MODES`. A new CFAR mode is one `CfarMode` subclass (or
instance) here and one registry entry; the module functions below only look the name up.

References
----------
.. [1] H. Rohling, "Radar CFAR thresholding in clutter and multiple target situations",
       IEEE Trans. AES 19(4), 1983.
.. [2] M. A. Richards, Fundamentals of Radar Signal Processing, 2nd ed., sec. 6.5 (eq. 6.167).
.. [3] V. G. Hansen, J. H. Sawyers, "Detectability loss due to greatest-of selection in a
       cell-averaging CFAR", IEEE Trans. AES 16(1), 1980.
.. [4] TI, "CFAR algorithms in mmWave SDK" (seed 003): CA, CAGO, CASO, OS, cyclic mode.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import ClassVar

import numba
import numpy as np
from scipy import integrate, ndimage, optimize, special

from core.errors import BadInput
from core.registry import Registry

from .gamma_law import Gamma

__all__ = ["CfarMode", "CellAveraging", "SideSelecting", "OrderStatistic", "CFAR_MODES",
           "cfar_mode", "cfar_scale", "noise_mean_factor", "pfa_of_scale", "pfa_numeric",
           "training_offsets", "noise_estimate", "cfar_map", "rohling_os_pfa"]


def training_offsets(guard_cells: int, window_cells: int,
                     stride: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Offsets of the lagging (negative) and leading (positive) training cells: `window_cells`
    cells every `stride` bins, starting `guard_cells` + 1 away from the cell under test.

    Returns
    -------
    lag, lead : (window_cells,) int
    """
    lead = guard_cells + 1 + stride * np.arange(window_cells)
    return -lead[::-1], lead


@dataclass(frozen=True, kw_only=True, slots=True)
class CfarMode:
    """One CFAR mode: how training cells become one noise estimate, and its statistics.

    Parameters
    ----------
    name : str
        Registry key (what `pipeline.CfarConfig.mode` holds).
    description : str

    Subclasses implement `estimate_pdf`, `noise_estimate` and `noise_map`; `closed_form_pfa`
    and `candidate_mask` have defaults (numerical integration; every cell a candidate).
    `ranked` says whether the mode uses an order-statistic rank k (`CfarConfig.os_rank`).
    """

    ranked: ClassVar[bool] = False
    #: True when `combine_looks` is the square-law sum (chains may then sum in any order).
    sums_looks: ClassVar[bool] = True
    #: True when `peaks` runs a compiled detector (else it returns None).
    compiled_peaks: ClassVar[bool] = False

    name: str
    description: str

    def estimate_pdf(self, n_cells: int, os_rank: int, looks: int) -> Callable:
        """pdf of the noise estimate Y for cells of `looks` unit-mean exponential looks."""
        raise NotImplementedError

    def closed_form_pfa(self, scale: float, n_cells: int, os_rank: int,
                        looks: int) -> float | None:
        """Pfa(alpha) in closed form where one exists, else None (numerical integration)."""
        return None

    def noise_estimate(self, train: np.ndarray, n_lag: int, os_rank: int) -> np.ndarray:
        """Noise estimate from gathered training cells ``train: (..., N)`` (lagging first)."""
        raise NotImplementedError

    def noise_map(self, power: np.ndarray, lag_fp: np.ndarray, lead_fp: np.ndarray,
                  window_cells: int, os_rank: int) -> np.ndarray:
        """Noise estimate of every cell (cyclic), from lag/lead footprints shaped for
        scipy.ndimage (a size-(2 h + 1) bool line along the CFAR axis)."""
        raise NotImplementedError

    def combine_looks(self, power: np.ndarray, axis) -> np.ndarray:
        """The map cell of `looks` channel powers along `axis`: their sum (square-law
        non-coherent integration). A mode on another statistic overrides it."""
        return power.sum(axis=axis)

    def scale_of_db(self, threshold_db: float) -> float:
        """Linear threshold scale of a threshold in dB over the noise estimate."""
        return 10 ** (threshold_db / 10)

    def mean_factor(self, n_cells: int, os_rank: int, looks: int) -> float:
        """E[Y] / E[cell] in homogeneous noise (`noise_mean_factor`), from `estimate_pdf`."""
        pdf = self.estimate_pdf(n_cells, os_rank, looks)
        return _integrate(lambda y: y * pdf(y), looks) / looks

    def candidate_mask(self, power: np.ndarray, axis: int, alpha: float,
                       os_rank: int) -> np.ndarray:
        """Cells that can pass the test at all: a cheap necessary condition (bool, `power`'s
        shape). Default: every cell."""
        return np.ones(power.shape, dtype=bool)

    def peaks(self, power: np.ndarray, alpha: float, train_idx: np.ndarray, os_rank: int,
              neighbours: tuple[bool, bool, bool, bool], first_bin: int,
              rows0: tuple[int, int] | None = None):
        """Compiled detector of `kernels.cfar_peaks` for this mode, or None (the numpy path:
        `candidate_mask`, local maxima, gathered training cells). rows0 = (lo, hi): only the
        cells with lo <= index < hi on axis 0 (their neighbours read from the whole map); a
        mode with a compiled detector sets `compiled_peaks`."""
        return None


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
                tix = train_idx[d]
                # The count without branches, the first half first: fewer than k - (n_train
                # - h) below there and the cell cannot reach k.
                below = 0
                for t in range(h):
                    below += alpha * row[tix[t]] < x
                if below + (n_train - h) < k:
                    continue
                for t in range(h, n_train):
                    below += alpha * row[tix[t]] < x
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


#: CFAR modes by the name `CfarConfig.mode` holds (TI codes: `radarsim.ti.codes`).
CFAR_MODES: Registry[CfarMode] = Registry("CFAR mode", field="mode", kind=CfarMode)
CFAR_MODES.register_all((
    CellAveraging(name="ca", description="cell averaging: mean of both windows"),
    SideSelecting(name="cago", greatest=True,
                  description="greatest-of: larger of the two window means"),
    SideSelecting(name="caso", greatest=False,
                  description="smallest-of: smaller of the two window means"),
    OrderStatistic(name="os",
                   description="ordered statistic: k-th smallest training cell"),
))


def cfar_mode(name: str) -> CfarMode:
    """The registered mode of that name.

    Raises
    ------
    ValueError
        ``mode='x' is not one of [...]``.

    Examples
    --------
    >>> from pipeline.cfar import cfar_mode
    >>> cfar_mode("os").name, cfar_mode("ca").description
    ('os', 'cell averaging: mean of both windows')
    >>> cfar_mode("median")
    Traceback (most recent call last):
    ...
    core.errors.BadInput: mode='median' is not one of [...]
    """
    return CFAR_MODES.lookup(name)


def _integrate(fn, looks: int) -> float:
    # The estimate concentrates near L (cells of L unit looks); split the range for accuracy.
    edges = [0.0, 0.25 * looks, looks, 4.0 * looks, 20.0 * looks, np.inf]
    return float(sum(integrate.quad(fn, a, b, limit=200, epsabs=0, epsrel=1e-10)[0]
                     for a, b in zip(edges[:-1], edges[1:])))


def pfa_of_scale(scale: float, mode: str, n_cells: int, os_rank: int = 0,
                 looks: int = 1) -> float:
    """False-alarm probability of threshold `scale` x Y in homogeneous noise.

    Parameters
    ----------
    scale : float
        alpha, the threshold over the noise estimate Y.
    mode : {"ca", "cago", "caso", "os"}
    n_cells : int
        Training cells (both sides together).
    os_rank : int
        k for OS (1-based: k-th smallest).
    looks : int
        Independent exponential looks summed in each cell (1 = coherent map).

    Notes
    -----
    Single-look OS and CA use their closed forms (Rohling 1983; (1 + a/N)^-N for the mean of
    the N cells); everything else integrates numerically (`pfa_numeric`), which the tests check
    against the closed forms.
    """
    closed = cfar_mode(mode).closed_form_pfa(scale, n_cells, os_rank, looks)
    return pfa_numeric(scale, mode, n_cells, os_rank, looks) if closed is None else closed


def pfa_numeric(scale: float, mode: str, n_cells: int, os_rank: int = 0,
                looks: int = 1) -> float:
    """`pfa_of_scale` by numerical integration of E_Y[Q(L, scale Y)] for every mode."""
    pdf = cfar_mode(mode).estimate_pdf(n_cells, os_rank, looks)
    return _integrate(lambda y: special.gammaincc(looks, scale * y) * pdf(y), looks)


@lru_cache(maxsize=256)
def cfar_scale(pfa: float, mode: str, n_cells: int, os_rank: int = 0, looks: int = 1) -> float:
    """Threshold scale alpha giving false-alarm probability `pfa` (solved with brentq on log Pfa).

    For L = 1: CA gives N (Pfa^(-1/N) - 1); OS reproduces Rohling (N=24, k=18, Pfa=1e-6:
    alpha = 16.29).
    """
    if not 0 < pfa < 1:
        raise BadInput(f"pfa={pfa!r} must be in (0, 1)")
    target = np.log(pfa)

    def f(a: float) -> float:
        return np.log(max(pfa_of_scale(a, mode, n_cells, os_rank, looks), 1e-300)) - target

    hi = 1.0
    while f(hi) > 0:
        hi *= 2.0
        if hi > 1e6:
            raise BadInput(f"pfa={pfa!r} is unreachable for mode={mode}, N={n_cells}")
    return float(optimize.brentq(f, 1e-9, hi, xtol=1e-10, rtol=1e-10))


def rohling_os_pfa(scale: float, n_cells: int, os_rank: int) -> float:
    """Rohling's closed form for OS-CFAR on exponential cells (DESIGN 8):
    Pfa = k C(N,k) Gamma(k) Gamma(a+N-k+1) / Gamma(a+N+1)."""
    n, k, a = n_cells, os_rank, scale
    log_p = (np.log(k) + special.gammaln(n + 1) - special.gammaln(k + 1)
             - special.gammaln(n - k + 1) + special.gammaln(k)
             + special.gammaln(a + n - k + 1) - special.gammaln(a + n + 1))
    return float(np.exp(log_p))


@lru_cache(maxsize=256)
def noise_mean_factor(mode: str, n_cells: int, os_rank: int = 0, looks: int = 1) -> float:
    """E[Y] / E[cell] in homogeneous noise: divides a CFAR estimate into a mean-power estimate.

    CA: 1; OS on exponential cells: sum_{i=N-k+1}^{N} 1/i (e.g. 1.3 for N=16, k=12)."""
    return cfar_mode(mode).mean_factor(n_cells, os_rank, looks)


def noise_estimate(train: np.ndarray, n_lag: int, mode: str, os_rank: int) -> np.ndarray:
    """Noise estimate from gathered training cells.

    Parameters
    ----------
    train : (..., N) float
        Training cells of each cell under test: the `n_lag` lagging cells, then the leading
        ones. OS partitions this array in place.
    n_lag : int
        Number of lagging cells (the CA family compares the two sides).
    mode : {"ca", "cago", "caso", "os"}
    os_rank : int
        k (1-based) for OS.

    Returns
    -------
    (...) float
    """
    return cfar_mode(mode).noise_estimate(train, n_lag, os_rank)


def cfar_map(power: np.ndarray, axis: int, guard_cells: int, window_cells: int, mode: str,
             os_rank: int, stride: int = 1) -> np.ndarray:
    """Noise estimate for every cell of `power` along a cyclic `axis` (full-map reference).

    Uses scipy.ndimage rank and uniform filters with `mode="wrap"`, so the result equals the
    gathered per-candidate estimate used in the chain.

    Parameters
    ----------
    power : (...) float
        Square-law map.
    axis : int
        Cyclic axis (Doppler).

    Returns
    -------
    (...) float, same shape as `power`.
    """
    power = np.asarray(power)
    lag, lead = training_offsets(guard_cells, window_cells, stride)
    half = int(lead[-1])
    size = 2 * half + 1
    shape = [1] * power.ndim
    shape[axis] = size
    lag_fp = np.zeros(size, bool)
    lag_fp[lag + half] = True
    lead_fp = np.zeros(size, bool)
    lead_fp[lead + half] = True
    return cfar_mode(mode).noise_map(power, lag_fp.reshape(shape), lead_fp.reshape(shape),
                                     window_cells, os_rank)
