"""TI's CFAR on the log-magnitude detection matrix: the CA family of the mmWave SDK demos.

The TDM demos (mmWave SDK 3.x xwr16xx/18xx/68xx, MCU+ SDK AWR294x TDM) do not CFAR the
square-law sum of the virtual channels: their detection matrix holds, per range-Doppler cell,
the sum over the Nv virtual antennas of log2 |X_i| (Q8), scaled by 2^-ceil(log2 Nv), and the CLI
threshold is converted with ``MmwDemo_convertCfarToLinear``:
threshold = dB x (256 / 6) x Nv / 2^ceil(log2 Nv) in the same units. A cell is detected when it
exceeds the average of the training cells (CA; the greater/smaller one-sided average for
CAGO/CASO) by that threshold, i.e. when

    mean_i log2 |X_i|(cell) - mean over training cells of mean_i log2 |X_i| > dB / 6

One log2 unit of amplitude is 20 log10 2 = 6.02 dB of power, so the test is on the
average-of-logs statistic with a threshold of dB x 6.02 / 6 (`TI_DB_PER_CLI_DB`) real dB. The
average of logs is not the log of the average: in noise it sits gamma = 0.577 nepers (2.5 dB)
below it, which is why applying the CLI value to linear power (the harness's earlier reading)
was about 2.4 dB stricter than the chip.

Here the statistic is kept in linear units so every chain and kernel works unchanged: a cell of
L channel powers is their geometric mean G = exp(mean_i ln P_i) (`combine_looks`), a noise
estimate the geometric mean of the training cells (of each side for CAGO/CASO), and the test
G > alpha Y with alpha = 10^(TI_DB_PER_CLI_DB x dB / 10) is the chip's.

False-alarm probability in homogeneous noise (exponential channel powers of mean s^2): ln P_i =
ln s^2 + ln E_i with E_i unit exponential, whose characteristic function is Gamma(1 + j t). The
cell's statistic C is the mean of L such terms (cf Gamma(1 + j t / L)^L), each training side's
the mean of (N / 2) L; s^2 cancels, and Pfa(alpha) = P(C - M > ln alpha) with M the mean of both
sides (CA), or the greater / smaller (CAGO / CASO). The densities are inverted from the
characteristic functions by FFT on a grid (`_log_mean_density`).

References
----------
.. [1] TI, mmWave SDK 3.x demo ``mss/mmw_cli.c`` (``MmwDemo_CLICfarCfg``: dB x 100 encoding) and
       ``mss_main.c`` (``MmwDemo_convertCfarToLinear``); MCU+ SDK AWR294x TDM demo, same code.
.. [2] TI, mmWave SDK ``cfarcaproc`` DPU documentation (detection matrix of log2 magnitudes).
.. [3] J. Gil-Pelaez, "Note on the inversion theorem", Biometrika 38 (1951) (CF inversion).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import ClassVar

import numpy as np
from scipy import ndimage, special

from .base import CfarMode

__all__ = ["LogCellAveraging", "LOG_MODES", "TI_DB_PER_CLI_DB", "TI_LOG_MODES", "ti_log_mode",
           "log_cfar_pfa"]

#: Real dB of power per dB of the CLI threshold: the demo divides by 6 for one log2 unit of
#: amplitude, which is 20 log10(2) = 6.0206 dB.
TI_DB_PER_CLI_DB = 20 * np.log10(2.0) / 6.0
#: Tiny power floor before the logarithm (an exactly zero sample: a zeroed cell).
_FLOOR = np.float32(1e-30)

# FFT inversion grid of the log-mean densities: ln of a unit exponential lies in [-30, 6] but for
# 1e-13 of its mass; 2^15 points (dx = 1.1e-3) resolve the narrowest density (mean of 1000s).
_X0, _X1, _K = -30.0, 6.0, 2 ** 15


@lru_cache(maxsize=64)
def _log_mean_density(m: int) -> tuple[np.ndarray, np.ndarray]:
    """Grid x and density of the mean of m iid ln E (E unit exponential), by FFT inversion of
    the characteristic function Gamma(1 + j t / m)^m."""
    dx = (_X1 - _X0) / _K
    x = _X0 + dx * np.arange(_K)
    dt = 2 * np.pi / (_K * dx)
    t = (np.arange(_K) - _K // 2) * dt
    phi = np.exp(m * special.loggamma(1 + 1j * t / m)) * np.exp(-1j * t * _X0)
    f = (dt / (2 * np.pi)) * np.real(np.fft.fft(phi) * (-1.0) ** np.arange(_K))
    f = np.maximum(f, 0.0)
    f /= f.sum() * dx
    x.setflags(write=False)
    f.setflags(write=False)
    return x, f


@lru_cache(maxsize=64)
def _pfa_tables(looks: int, n_cells: int, side: str):
    """(x, survival of the cell's statistic C, density of the noise statistic M)."""
    x, f_c = _log_mean_density(looks)
    dx = x[1] - x[0]
    surv = 1.0 - np.cumsum(f_c) * dx + 0.5 * f_c * dx
    if side == "both":
        _, p_m = _log_mean_density(n_cells * looks)
    else:
        _, p_h = _log_mean_density(n_cells // 2 * looks)
        cdf_h = np.clip(np.cumsum(p_h) * dx - 0.5 * p_h * dx, 0.0, 1.0)
        p_m = 2 * (cdf_h if side == "greatest" else 1.0 - cdf_h) * p_h
    return x, np.clip(surv, 0.0, 1.0), p_m


def log_cfar_pfa(scale: float, n_cells: int, looks: int, side: str = "both") -> float:
    """False-alarm probability of the log-domain CA-family CFAR at linear threshold `scale`:
    P(C - M > ln scale) (module docstring), for cells of `looks` channels and `n_cells`
    training cells (both sides together)."""
    x, surv, p_m = _pfa_tables(int(looks), int(n_cells), side)
    dx = x[1] - x[0]
    s = np.interp(x + np.log(scale), x, surv, left=1.0, right=0.0)
    return float(np.sum(p_m * s) * dx)


@dataclass(frozen=True, kw_only=True, slots=True)
class LogCellAveraging(CfarMode):
    """TI's CA / CAGO / CASO on the average-of-logs statistic (geometric means in linear units).

    Parameters
    ----------
    side : {"both", "greatest", "smallest"}
        Both windows averaged (CA), or the greater / smaller one-sided average (CAGO / CASO).
    """

    sums_looks: ClassVar[bool] = False

    side: str

    def combine_looks(self, power, axis):
        """Geometric mean of the channel powers along `axis` (float32)."""
        lg = np.log(np.maximum(power, _FLOOR), dtype=np.float32)
        return np.exp(lg.mean(axis=axis, dtype=np.float32))

    def scale_of_db(self, threshold_db):
        """The CLI's dB are log2 units x 6: 10^(6.02 / 6 x dB / 10) on the linear statistic."""
        return 10 ** (TI_DB_PER_CLI_DB * threshold_db / 10)

    def _select(self, lag, lead):
        if self.side == "both":
            return 0.5 * (lag + lead)
        return np.maximum(lag, lead) if self.side == "greatest" else np.minimum(lag, lead)

    def noise_estimate(self, train, n_lag, os_rank):
        lg = np.log(np.maximum(train, _FLOOR))
        return np.exp(self._select(lg[..., :n_lag].mean(axis=-1), lg[..., n_lag:].mean(axis=-1)))

    def noise_map(self, power, lag_fp, lead_fp, window_cells, os_rank):
        lg = np.log(np.maximum(power, _FLOOR))
        lag = ndimage.correlate(lg, lag_fp / window_cells, mode="wrap")
        lead = ndimage.correlate(lg, lead_fp / window_cells, mode="wrap")
        return np.exp(self._select(lag, lead))

    def closed_form_pfa(self, scale, n_cells, os_rank, looks):
        return log_cfar_pfa(scale, n_cells, looks, self.side)

    def estimate_pdf(self, n_cells, os_rank, looks):
        raise NotImplementedError(f"{self.name}: the noise estimate is a geometric mean; "
                                  "its statistics come from log_cfar_pfa and mean_factor")

    def mean_factor(self, n_cells, os_rank, looks):
        """E[Y] / E[cell of `looks` unit looks]: Y = exp(M), E[exp(M)] over M's density
        (CA: Gamma(1 + 1 / (N L))^(N L) exactly)."""
        x, _, p_m = _pfa_tables(int(looks), int(n_cells), self.side)
        dx = x[1] - x[0]
        return float(np.sum(np.exp(x) * p_m) * dx) / looks


#: TI averageMode name -> the log-domain mode the TDM demos run (OS has no log form here: the
#: DDM demo's HWA OS-CFAR stays linear).
TI_LOG_MODES = {"ca": "ti_log_ca", "cago": "ti_log_cago", "caso": "ti_log_caso"}

#: TI's log-magnitude modes (`modes.CFAR_MODES` registers them).
LOG_MODES = (
    LogCellAveraging(name="ti_log_ca", side="both",
                     description="TI demos' CA on the average of log magnitudes"),
    LogCellAveraging(name="ti_log_cago", side="greatest",
                     description="TI demos' CAGO on the average of log magnitudes"),
    LogCellAveraging(name="ti_log_caso", side="smallest",
                     description="TI demos' CASO on the average of log magnitudes"),
)


def ti_log_mode(mode: str) -> str:
    """The mode a TI TDM demo's ``cfarCfg`` averageMode runs: the log-domain variant of the CA
    family, OS unchanged."""
    return TI_LOG_MODES.get(mode, mode)
