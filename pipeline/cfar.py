"""CFAR detectors (CA, CAGO, CASO, OS) along one cyclic axis, and their threshold design.

The noise estimate Y of a cell under test comes from `window_cells` training cells on each side,
`guard_cells` away from it; a detection is declared when the cell exceeds alpha * Y. The scale
alpha is derived from a false-alarm probability for cells that are sums of L independent
exponential (square-law) looks: L = 1 for a coherent map, L = number of channels for a
non-coherent sum. Pfa(alpha) = E_Y[ Q(L, alpha Y) ] is integrated numerically for every mode; for
L = 1 it reproduces Rohling's OS formula and the CA closed form (DESIGN section 8).

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

from functools import lru_cache

import numpy as np
from scipy import integrate, optimize, special, stats

__all__ = ["CFAR_MODES", "cfar_scale", "noise_mean_factor", "pfa_of_scale", "pfa_numeric",
           "training_offsets", "noise_estimate", "cfar_map", "rohling_os_pfa"]

#: CFAR modes: how the training cells become one noise estimate.
CFAR_MODES = {
    "ca": "cell averaging: mean of both windows",
    "cago": "greatest-of: larger of the two window means",
    "caso": "smallest-of: smaller of the two window means",
    "os": "ordered statistic: k-th smallest training cell",
}


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


def _stat_pdf(mode: str, n_cells: int, os_rank: int, looks: int):
    """pdf of the noise estimate Y for unit-mean-per-look Gamma(L, 1) cells, and its support."""
    gam = stats.gamma(looks)
    half = n_cells // 2
    if mode == "ca":
        return stats.gamma(n_cells * looks, scale=1.0 / n_cells).pdf
    if mode in ("cago", "caso"):
        mean_half = stats.gamma(half * looks, scale=1.0 / half)
        if mode == "cago":
            return lambda y: 2 * mean_half.cdf(y) * mean_half.pdf(y)
        return lambda y: 2 * mean_half.sf(y) * mean_half.pdf(y)
    if mode == "os":
        n, k = n_cells, os_rank
        log_c = special.gammaln(n + 1) - special.gammaln(k) - special.gammaln(n - k + 1)

        def pdf(y):
            cdf = np.clip(gam.cdf(y), 1e-300, 1.0)
            sf = np.clip(gam.sf(y), 1e-300, 1.0)
            return np.exp(log_c + (k - 1) * np.log(cdf) + (n - k) * np.log(sf)) * gam.pdf(y)
        return pdf
    raise ValueError(f"mode={mode!r} is not one of {sorted(CFAR_MODES)}")


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
    if looks == 1 and mode == "os":
        return rohling_os_pfa(scale, n_cells, os_rank)
    if looks == 1 and mode == "ca":
        return float((1.0 + scale / n_cells) ** -n_cells)
    return pfa_numeric(scale, mode, n_cells, os_rank, looks)


def pfa_numeric(scale: float, mode: str, n_cells: int, os_rank: int = 0,
                looks: int = 1) -> float:
    """`pfa_of_scale` by numerical integration of E_Y[Q(L, scale Y)] for every mode."""
    pdf = _stat_pdf(mode, n_cells, os_rank, looks)
    return _integrate(lambda y: special.gammaincc(looks, scale * y) * pdf(y), looks)


@lru_cache(maxsize=256)
def cfar_scale(pfa: float, mode: str, n_cells: int, os_rank: int = 0, looks: int = 1) -> float:
    """Threshold scale alpha giving false-alarm probability `pfa` (solved with brentq on log Pfa).

    For L = 1: CA gives N (Pfa^(-1/N) - 1); OS reproduces Rohling (N=24, k=18, Pfa=1e-6:
    alpha = 16.29).
    """
    if not 0 < pfa < 1:
        raise ValueError(f"pfa={pfa!r} must be in (0, 1)")
    target = np.log(pfa)

    def f(a: float) -> float:
        return np.log(max(pfa_of_scale(a, mode, n_cells, os_rank, looks), 1e-300)) - target

    hi = 1.0
    while f(hi) > 0:
        hi *= 2.0
        if hi > 1e6:
            raise ValueError(f"pfa={pfa!r} is unreachable for mode={mode}, N={n_cells}")
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
    pdf = _stat_pdf(mode, n_cells, os_rank, looks)
    return _integrate(lambda y: y * pdf(y), looks) / looks


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
    if mode == "os":
        train.partition(os_rank - 1, axis=-1)
        return train[..., os_rank - 1]
    if mode not in CFAR_MODES:
        raise ValueError(f"mode={mode!r} is not one of {sorted(CFAR_MODES)}")
    lag = train[..., :n_lag].mean(axis=-1)
    lead = train[..., n_lag:].mean(axis=-1)
    if mode == "ca":
        return 0.5 * (lag + lead)
    return np.maximum(lag, lead) if mode == "cago" else np.minimum(lag, lead)


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
    from scipy import ndimage

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
    if mode == "os":
        fp = (lag_fp | lead_fp).reshape(shape)
        return ndimage.rank_filter(power, os_rank - 1, footprint=fp, mode="wrap")
    # The footprint is centred on the cell; ndimage correlates with a mirrored footprint,
    # which is symmetric in the two-sided case and swaps lag/lead for one side.
    lag = ndimage.correlate(power, (lag_fp / window_cells).reshape(shape), mode="wrap")
    lead = ndimage.correlate(power, (lead_fp / window_cells).reshape(shape), mode="wrap")
    if mode == "ca":
        return 0.5 * (lag + lead)
    if mode == "cago":
        return np.maximum(lag, lead)
    if mode == "caso":
        return np.minimum(lag, lead)
    raise ValueError(f"mode={mode!r} is not one of {sorted(CFAR_MODES)}")
