"""CFAR detectors (CA, CAGO, CASO, OS) along one cyclic axis, and their threshold design.

The noise estimate Y of a cell under test comes from `window_cells` training cells on each side,
`guard_cells` away from it; a detection is declared when the cell exceeds alpha * Y. The scale
alpha is derived from a false-alarm probability for cells that are sums of L independent
exponential (square-law) looks: L = 1 for a coherent map, L = number of channels for a
non-coherent sum. Pfa(alpha) = E_Y[ Q(L, alpha Y) ] is integrated numerically for every mode; for
L = 1 it reproduces Rohling's OS formula and the CA closed form (design.md section 8).

Each mode is a `CfarMode` object in the `CFAR_MODES` registry: the distribution of its noise
estimate (threshold design), the estimate itself (gathered training cells or a full map), and an
optional cheap necessary condition that the chain uses to skip cells before gathering training
cells. TI's ``cfarCfg`` averageMode codes name these modes in one table,
`radarsim.ti.codes.CFAR_AVERAGE_MODES`. A new CFAR mode is one `CfarMode` subclass (or
instance, `base`) in its module and one registry entry here; the module functions below only
look the name up.

References
----------
.. [1] H. Rohling, "Radar CFAR thresholding in clutter and multiple target situations",
       IEEE Trans. AES 19(4), 1983.
.. [2] M. A. Richards, Fundamentals of Radar Signal Processing, 2nd ed., sec. 6.5 (eq. 6.167).
.. [3] V. G. Hansen, J. H. Sawyers, "Detectability loss due to greatest-of selection in a
       cell-averaging CFAR", IEEE Trans. AES 16(1), 1980.
.. [4] TI, "CFAR algorithms in mmWave SDK" [TI-DPC]: CA, CAGO, CASO, OS, cyclic mode.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy import optimize, special

from core.errors import BadInput
from core.registry import Registry

from .base import CfarMode, integrate_looks, training_offsets
from .log_law import LOG_MODES
from .square_law import SQUARE_LAW_MODES

__all__ = ["CFAR_MODES", "cfar_mode", "cfar_scale", "noise_mean_factor", "pfa_of_scale",
           "pfa_numeric", "noise_estimate", "cfar_map"]


#: CFAR modes by the name `CfarConfig.mode` holds (TI codes: `radarsim.ti.codes`): the
#: square-law modes and TI's log-magnitude ones.
CFAR_MODES: Registry[CfarMode] = Registry("CFAR mode", field="mode", kind=CfarMode)
CFAR_MODES.register_all(SQUARE_LAW_MODES + LOG_MODES)


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
    return integrate_looks(lambda y: special.gammaincc(looks, scale * y) * pdf(y), looks)


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
