"""How well one far-field echo in white noise fits its own steering vector: the law both MIMO
hypothesis tests (DDMA Tx order, TDMA/BPM velocity extension) take their floors from.

An echo of SNR S (linear, summed over the n elements, over the noise power per element) seen
on n elements gives x = s a + w. The energy projected on the steering a, |a^H x|^2 / n, is
sigma^2 / 2 times a noncentral chi-square with 2 degrees of freedom and noncentrality 2 S; the
energy orthogonal to a is sigma^2 / 2 times a central chi-square with 2 (n - 1). Hence the fit
rho = |a^H x|^2 / (n ||x||^2) = X / (X + Y), and (n - 1) rho / (1 - rho) is a noncentral
F(2, 2 (n - 1), 2 S) variable [1]_.

References
----------
.. [1] S. M. Kay, "Fundamentals of Statistical Signal Processing, Vol. II: Detection Theory",
   Prentice Hall, 1998, sections 2.2.4 (noncentral chi-square) and 7.3 (F statistics).
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy import special, stats

__all__ = ["echo_fit_quantile"]


def echo_fit_quantile(n_elements: int, snr, miss: float) -> np.ndarray:
    """The lower `miss` quantile of one echo's fit rho on `n_elements` elements.

    Parameters
    ----------
    n_elements : int
        n >= 1 elements the echo is fitted on (1 element: rho is 1, the quantile 0 by
        convention, i.e. no test).
    snr : float or (m,) array
        S, the echo's SNR (linear) as defined in the module docstring.
    miss : float
        Probability that a real echo fits worse than the quantile.

    Returns
    -------
    (m,) or () float array
        rho_q with P(rho < rho_q) = `miss`. Where the noncentral F quantile does not converge
        (S above about 1e4) the joint bound X_q / (X_q + Y_q) is used: X_q = S + 1 - z
        sqrt(2 S + 1), the normal approximation of the projected energy's `miss` quantile,
        Y_q the orthogonal noise's upper `miss` quantile.

    Examples
    --------
    >>> echo_fit_quantile(16, np.array([0.0, 10.0, 100.0, 1e3, 1e8]), 1e-3).round(3)
    array([0.   , 0.071, 0.743, 0.971, 1.   ])
    >>> round(float(echo_fit_quantile(3, 10 ** 1.3345, 1e-3)), 3)  # 3 Tx at 13.3 dB
    0.616
    """
    snr = np.asarray(snr, dtype=float)
    if n_elements < 2:
        return np.zeros_like(snr)
    dfd = 2 * (n_elements - 1)
    f_q = special.ncfdtri(2, dfd, 2 * snr, miss)
    rho_q = f_q / (n_elements - 1 + f_q)
    z, y_q = _bound_quantiles(n_elements, miss)
    x_q = np.maximum(snr + 1 - z * np.sqrt(2 * snr + 1), 0.0)
    bound = x_q / (x_q + y_q)
    return np.where(np.isfinite(rho_q), rho_q, bound)


@lru_cache(maxsize=64)
def _bound_quantiles(n_elements: int, miss: float) -> tuple[float, float]:
    """(z, Y_q) of `echo_fit_quantile`'s joint bound: the normal upper `miss` quantile and the
    orthogonal noise's (gamma, n - 1) upper `miss` quantile; configuration-only, so computed
    once per (n, miss) (scipy.stats evaluates each in ~0.1 ms)."""
    return stats.norm.isf(miss), stats.gamma.isf(miss, n_elements - 1)
