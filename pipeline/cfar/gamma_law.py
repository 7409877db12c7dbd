"""The gamma law of a CFAR noise estimate, evaluated point by point without `scipy.stats`' cost.

The CFAR threshold design (`pipeline.cfar.cfar_scale`) integrates the density of the noise
estimate with `scipy.integrate.quad` inside a `scipy.optimize.brentq` search: about ten
thousand scalar evaluations of a gamma pdf / cdf / sf per (mode, N, k, looks). A frozen
`scipy.stats.gamma` spends ~0.25 ms of argument checking per scalar call (about 5 s CPU for the
TDMA OS threshold, paid once by every process that builds it); `Gamma` calls the same
`scipy.special` functions in the same order as `scipy.stats.gamma` does (scipy 1.17
``gamma_gen._pdf / _cdf / _sf`` and ``rv_continuous.pdf / cdf / sf``: ``x = (y - loc) /
scale``, the support masks), so every value is bit-identical to it (tests/pipeline/
test_gamma_law.py compares them bit for bit, edges included) at ~1/50 of the cost.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import special

from core.errors import BadInput

__all__ = ["Gamma"]


@dataclass(frozen=True, slots=True)
class Gamma:
    """Gamma law of shape `a` and scale `scale` (location 0): ``scipy.stats.gamma(a,
    scale=scale)`` for `pdf`, `cdf` and `sf`, bit for bit.

    Parameters
    ----------
    a : float
        Shape (> 0); for a CFAR estimate the number of exponential looks it sums.
    scale : float
        Scale (> 0); the mean is ``a * scale``.

    Examples
    --------
    >>> from scipy import stats
    >>> g = Gamma(16, scale=0.25)
    >>> bool(g.pdf(3.1) == stats.gamma(16, scale=0.25).pdf(3.1))
    True
    >>> float(g.cdf(0.0)), float(g.sf(0.0)), float(g.pdf(-1.0))
    (0.0, 1.0, 0.0)
    """

    a: float
    scale: float = 1.0

    def __post_init__(self) -> None:
        if not self.a > 0:
            raise BadInput(f"a={self.a!r} must be > 0")
        if not self.scale > 0:
            raise BadInput(f"scale={self.scale!r} must be > 0")

    def _x(self, y):
        return np.asarray(y, dtype=np.float64) / self.scale

    def pdf(self, y):
        """Density at `y` (scalar or array, float64); 0 below the support [0, inf]."""
        x = self._x(y)
        xs = np.maximum(x, 0.0)  # = x on the support (NaN kept); no warning below it
        # scipy: exp(xlogy(a - 1, x) - x - gammaln(a)) / scale on the closed support.
        v = np.exp(special.xlogy(self.a - 1.0, xs) - xs - special.gammaln(self.a)) / self.scale
        return np.where(x < 0, 0.0, v)[()]

    def cdf(self, y):
        """P(Y <= y): 0 for y <= 0, 1 for y = inf, NaN for NaN."""
        x = self._x(y)
        return np.where(x <= 0, 0.0, special.gammainc(self.a, x))[()]

    def sf(self, y):
        """P(Y > y): 1 for y <= 0, 0 for y = inf, NaN for NaN."""
        x = self._x(y)
        return np.where(x <= 0, 1.0, special.gammaincc(self.a, x))[()]
