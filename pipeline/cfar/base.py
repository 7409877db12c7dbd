"""The CFAR mode's interface (`CfarMode`): how training cells become one noise estimate, and the
statistics of that estimate the threshold design integrates (`integrate_looks`)."""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from scipy import integrate

__all__ = ["CfarMode", "training_offsets", "integrate_looks"]


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
        return integrate_looks(lambda y: y * pdf(y), looks) / looks

    def candidate_mask(self, power: np.ndarray, axis: int, alpha: float,
                       os_rank: int) -> np.ndarray:
        """Cells that can pass the test at all: a cheap necessary condition (bool, `power`'s
        shape). Default: every cell."""
        return np.ones(power.shape, dtype=bool)

    def peaks(self, power: np.ndarray, alpha: float, train_idx: np.ndarray, os_rank: int,
              neighbours: tuple[bool, bool, bool, bool], first_bin: int,
              rows0: tuple[int, int] | None = None):
        """Compiled detector of `peaks.cfar_peaks` for this mode, or None (the numpy path:
        `candidate_mask`, local maxima, gathered training cells). rows0 = (lo, hi): only the
        cells with lo <= index < hi on axis 0 (their neighbours read from the whole map); a
        mode with a compiled detector sets `compiled_peaks`."""
        return None


def integrate_looks(fn, looks: int) -> float:
    # The estimate concentrates near L (cells of L unit looks); split the range for accuracy.
    edges = [0.0, 0.25 * looks, looks, 4.0 * looks, 20.0 * looks, np.inf]
    return float(sum(integrate.quad(fn, a, b, limit=200, epsabs=0, epsrel=1e-10)[0]
                     for a, b in zip(edges[:-1], edges[1:])))
