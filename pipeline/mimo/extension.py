"""Whether a slot-coded chain (TDMA, BPM) may move a detection beyond +/-Vmax.

Velocity extension ([TI-VEXT] section 4) scores hypotheses v_est + 2 k Vmax by how well the
virtual array, after each hypothesis' Doppler-phase compensation, fits one far-field echo, and
takes the best. That presumes the return IS a far-field echo through the array. Tx-to-Rx
leakage (it bypasses the antennas, and the channel calibration then rotates it further), DC
residue and near-field returns fit no hypothesis; the argmax among equally bad fits lands on
+/-2 Vmax about two times in three (a simulated board's leakage moved in 6 of 6
frames). Such returns come from the radar's own hardware and mount, so they sit at zero
Doppler; there (`pipeline.mimo.tdma.ZERO_DOPPLER_BINS`) a detection is moved only when its
winning hypothesis explains the array as one echo as well as a real echo at its SNR would;
otherwise it keeps the measured velocity. Not elsewhere: a cell of road or rail clutter holds
several scatterers and fits one echo no better than leakage does (rho 0.4-0.9 at 15-26 dB),
yet its hypotheses are right; the test applied at every Doppler refused such extensions on the
CI sweep (TDMA velocity-resolution failures 129 -> 142, ghost rate up to 3x on the R79 cases),
at zero Doppler it changes none of the sweep's numbers.

The statistic is the share of the array's energy the best single echo explains,
rho = max_{wx, wz} |a(wx, wz)^H x|^2 / (N ||x||^2) over the N elements that enter the
likelihood (`stages.array_likelihood`), evaluated at the interpolated peak so the azimuth grid
costs nothing. For one echo of array SNR S = N |alpha|^2 / sigma^2 in white noise, at its own
direction: the projected energy is sigma^2 / 2 x noncentral chi-square(2, 2 S), the rest
sigma^2 / 2 x chi-square(2 (N - 1)), so (N - 1) rho / (1 - rho) is noncentral F(2, 2 (N - 1),
2 S) (fitting the angle only raises rho: the bound is conservative). The floor is that law's
`EXTENSION_MISS` quantile at the detection's own SNR, estimated as ||x||^2 / sigma^2 - N
(unbiased, the same for every hypothesis: the compensation is unitary), times `FIT_ALLOWANCE`
for what white noise does not explain in a real return: a calibrated board's residual channel
errors (a few degrees: < 1 % of rho), element patterns, and above all the several scatterers
of a vehicle within one cell (the R79 sweep's correctly extended TDMA returns: rho median
0.97, 5 % below 0.74, some of them 1-4 % under the point-target floor at 20-37 dB). At high SNR
the floor tends to `FIT_ALLOWANCE`, which the simulated board's leakage (rho 0.82 at 100 dB,
calibrated) stays under.

References
----------
.. [1] TI, AWR1642 TDM-MIMO velocity disambiguation [TI-VEXT]: section 4.
.. [2] Kay, Fundamentals of Statistical Signal Processing vol. II (1998), section 7.6
       (GLRT for a signal of unknown amplitude and phase: noncentral F statistics).
"""
from __future__ import annotations

import numpy as np

from radarsim.config import RadarConfig

from ..kernels import layout_of
from ..stages import log_power, parabolic_offset
from .echo_law import echo_fit_quantile

__all__ = ["EXTENSION_MISS", "FIT_ALLOWANCE", "echo_fit", "fit_floor", "may_extend"]

#: Probability that a point echo in white noise is refused its extension by the fit test.
EXTENSION_MISS = 1e-3
#: Share of the noise-only floor a real return must reach (-0.46 dB: extended targets,
#: calibration residue; module docstring).
FIT_ALLOWANCE = 0.9


def echo_fit(cfg: RadarConfig, virt: np.ndarray, n_fft: int = 64) -> np.ndarray:
    """Share of the array's energy explained by the best single far-field echo.

    Parameters
    ----------
    virt : (n, n_virtual) complex
        Samples of one hypothesis per row, in `cfg.virtual_positions_m` order.
    n_fft : int
        Grid of the coarse search over wx (then refined by a parabola on the log statistic).

    Returns
    -------
    (n,) float in [0, 1]
        (|A_h(wx)| + |A_v(wx)|)^2 / (N ||x||^2) at the refined wx, A_h and A_v the beams of
        the horizontal and raised rows (wz free), N their element count.
    """
    h_idx, h_pos, v_idx, v_pos, _ = layout_of(cfg)
    idx = np.concatenate([h_idx, v_idx])
    x = virt[:, idx]
    n_h = h_idx.size
    pos = np.concatenate([h_pos, v_pos]).astype(float)

    def stat(wx: np.ndarray) -> np.ndarray:  # wx (n, K) -> (n, K)
        steer = np.exp(-1j * wx[..., None] * pos)  # (n, K, N)
        a_h = np.einsum("nkm,nm->nk", steer[..., :n_h], x[:, :n_h])
        a_v = np.einsum("nkm,nm->nk", steer[..., n_h:], x[:, n_h:])
        return (np.abs(a_h) + np.abs(a_v)) ** 2

    grid = 2 * np.pi * np.arange(n_fft) / n_fft
    coarse = stat(np.broadcast_to(grid, (len(x), n_fft)))
    k = np.argmax(coarse, axis=-1)
    rows = np.arange(len(x))
    y = log_power(coarse[rows[:, None], (k[:, None] + np.arange(-1, 2)) % n_fft])
    wx = 2 * np.pi * (k + parabolic_offset(y[:, 0], y[:, 1], y[:, 2])) / n_fft
    best = np.maximum(stat(wx[:, None])[:, 0], coarse[rows, k])
    energy = (np.abs(x) ** 2).sum(axis=-1)
    return best / (idx.size * np.maximum(energy, np.finfo(float).tiny))


def fit_floor(n_elements: int, snr: np.ndarray, miss: float = EXTENSION_MISS,
              allowance: float = FIT_ALLOWANCE) -> np.ndarray:
    """(n,) the `miss` quantile of `echo_fit` for one echo of array SNR `snr` (linear) on
    `n_elements` elements in white noise (`pipeline.mimo.echo_law`), times `allowance`.

    Examples
    --------
    >>> fit_floor(16, np.array([0.0, 10.0, 100.0, 1e3, 1e8]), allowance=1.0).round(3)
    array([0.   , 0.071, 0.743, 0.971, 1.   ])
    """
    return echo_fit_quantile(n_elements, snr, miss) * allowance


def may_extend(cfg: RadarConfig, virt: np.ndarray, sigma2: np.ndarray) -> np.ndarray:
    """(n,) bool: the winning hypothesis' array `virt` (n, n_virtual) fits one far-field echo
    at least as well as a real echo at its SNR does with probability 1 - `EXTENSION_MISS`;
    sigma2 : (n,) noise power per virtual channel."""
    if len(virt) == 0:  # most frames: no zero-Doppler detection moved
        return np.zeros(0, dtype=bool)
    h_idx, _, v_idx, _, _ = layout_of(cfg)
    idx = np.concatenate([h_idx, v_idx])
    energy = (np.abs(virt[:, idx]) ** 2).sum(axis=-1)
    snr = np.maximum(energy / sigma2 - idx.size, 0.0)
    return echo_fit(cfg, virt) >= fit_floor(idx.size, snr)
