"""The Tx-order (velocity) decision of empty-band DDMA, made per detection in its direction.

Empty-band demodulation ([TI-DDMA] table 11) picks, per (range, Doppler) cell, the sub-band j of
Tx1 that maximises Z_j, the energy of the n_tx sub-bands j..j+n_tx-1 summed over Rx. Two
returns in one range bin exactly one sub-band apart in velocity (a guard rail's continuous
Doppler spread makes it common; so does the range leakage of a strong return into the next
bin) fill the "empty" bands of each other, Z of the two hypotheses differs by only the
difference of their powers, and the cell's virtual array is read in the Tx order of the
stronger: the weaker return's Tx3, Tx4, Tx2 replicas then sit in the Tx1, Tx3, Tx4 slots. Its
azimuth spectrum peaks near the weaker return's direction, and that peak is reported at the
stronger return's velocity -- a point neither return has, at the same place every frame for a
rail seen from a moving car (a co-moving ghost a tracker confirms).

The cell holds the two returns in different directions, and the Rx array sees them apart. So
the decision is taken again at each detection, on the Rx beam pointed at the detection's own
azimuth: b_i = sum_r c_r e^{-j wx y_r} x_{i,r} for every sub-band i (y_r the Rx positions in
lambda/2, c_r the channel correction of the Tx each hypothesis puts there), and
Z_j(wx) = sum_p |b_{j+p}|^2. A single far-field echo at wx puts all its energy into the n_tx
bands of its own hypothesis, the beam only adds the Rx array gain (n_rx on the signal, 1 on the
noise: 10 log10 n_rx = 6 dB more decision SNR than the Rx-summed energy for 4 Rx), and any
return outside the Rx main lobe is attenuated by its pattern (4 Rx at lambda/2: -11 dB at
45 deg off). A detection whose direction-resolved hypothesis differs from its cell's is read
again in that Tx order: its azimuth is the nearest azimuth peak of the re-read array, its power
that peak's. It is kept only if that power still passes the CFAR threshold of its cell (a peak
that exists only as a mix of two Tx orders is not a detection), and only once (the split ghost
pair of one weaker return re-reads onto the same peak).

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA]: section 5, table 11 (empty-band
       demodulation), table 14 (azimuth interpolation).
"""
from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np
from scipy import stats

from radarsim.config import RadarConfig

from ..cfar import noise_mean_factor
from ..compensation import compensate, virtual_coefficients
from ..config import ProcessingConfig
from ..kernels import layout_of
from ..stages import array_dft, interp_azimuth
from .echo_law import echo_fit_quantile

__all__ = ["DdmaDetections", "ddma_virtual", "band_beams", "beam_band_metric",
           "coherence_floor", "resolve_tx_order", "TX_COHERENCE_MISS", "EMPTY_BAND_PFA"]

#: Probability that the Tx-coherence test rejects a far-field echo at the detection threshold.
TX_COHERENCE_MISS = 1e-3
#: Probability that noise alone makes a detection's empty sub-bands look occupied.
EMPTY_BAND_PFA = 1e-3


class DdmaDetections(NamedTuple):
    """CFAR detections of the DDMA chain with the Tx order each is read in.

    Attributes
    ----------
    a, r, d : (n,) int
        Azimuth, range and (intra-sub-band) Doppler bins.
    band : (n,) int
        Sub-band of Tx1 (the velocity hypothesis): true Doppler bin d + n_dop band.
    noise, peak : (n,) float
        CFAR noise estimate of the cell and the detection's power in the coherent map.
    power_az : (n, n_az) float
        Azimuth power spectrum the detection's azimuth is interpolated on.
    power_range : (n, 3) float
        Power at range bins r-1, r, r+1 (clipped at the edges) in the same azimuth bin and
        Doppler cell, for range interpolation.
    """

    a: np.ndarray
    r: np.ndarray
    d: np.ndarray
    band: np.ndarray
    noise: np.ndarray
    peak: np.ndarray
    power_az: np.ndarray
    power_range: np.ndarray

    def take(self, keep: np.ndarray) -> DdmaDetections:
        """The detections selected by `keep` (bool mask or index array)."""
        return DdmaDetections(*(x[keep] for x in self))


def ddma_virtual(cfg: RadarConfig, spec: np.ndarray, tx1_band: np.ndarray, r: np.ndarray,
                 d: np.ndarray) -> np.ndarray:
    """(n, n_virtual) demodulated virtual-antenna samples at range bins r, Doppler bins d, in
    the order Tx1Rx1..Rx4, Tx3.., Tx4.., Tx2.. ([TI-DDMA] section 5.4).

    tx1_band : (n_dop, n_range) int, or (n,) int already taken at (d, r)."""
    n_dop = cfg.n_chirps // cfg.n_subbands
    b = tx1_band[d, r] if tx1_band.ndim == 2 else tx1_band
    band = (b[:, None] + np.arange(cfg.n_tx)) % cfg.n_subbands  # (n, P)
    chirp_bin = band * n_dop + d[:, None]
    return spec[chirp_bin[:, :, None], np.arange(cfg.n_rx)[None, None, :],
                r[:, None, None]].reshape(r.size, -1)


def band_beams(cfg: RadarConfig, proc: ProcessingConfig, spec: np.ndarray, r: np.ndarray,
               d: np.ndarray, sin_az_cos_el: np.ndarray) -> np.ndarray:
    """Rx beam of every sub-band, pointed at each detection, with each Tx's channel correction.

    Parameters
    ----------
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler spectra over all chirps, before demodulation.
    r, d : (n,) int
        Range bin and intra-sub-band Doppler bin of each detection.
    sin_az_cos_el : (n,) float
        wx / pi of each detection (the interpolated azimuth of the coherent map).

    Returns
    -------
    (n, n_tx, n_subbands) complex
        [k, p, i]: sum_r c_{p,r} e^{-j wx y_r} x_{i,r}, the beam of sub-band i as Tx p (in
        `tx_order`) would be read there; y_r the Rx positions in lambda/2, c the
        ``compRangeBiasAndRxChanPhase`` coefficients (1 without).
    """
    n_sb, n_tx, n_rx = cfg.n_subbands, cfg.n_tx, cfg.n_rx
    n_dop = cfg.n_chirps // n_sb
    chirp_bin = np.arange(n_sb) * n_dop + d[:, None]  # (n, N)
    x = spec[chirp_bin[:, None, :], np.arange(n_rx)[None, :, None], r[:, None, None]]
    y_rx = _geometry(cfg).y_rx  # (Rx,) lambda/2 units
    steer = np.exp(-1j * np.pi * sin_az_cos_el[:, None] * y_rx[None, :])  # (n, Rx)
    coef = virtual_coefficients(cfg, proc.calibration.channel_comp)
    coef = np.ones((n_tx, n_rx)) if coef is None else coef.reshape(n_tx, n_rx)
    return np.einsum("nr,pr,nri->npi", steer, coef, x)


class _Geometry(NamedTuple):
    """Configuration-only arrays of the Tx-order decision (read-only)."""

    y_rx: np.ndarray   # (n_rx,) Rx positions, lambda/2 units
    row: np.ndarray    # (P_h,) Tx of the horizontal row (positions in tx_order)
    t_row: np.ndarray  # (P_h,) their positions, lambda/2 units


@lru_cache(maxsize=32)
def _geometry(cfg: RadarConfig) -> _Geometry:
    """`_Geometry` of a radar, computed once per configuration (the positions are properties
    recomputed on every access: ~0.1 ms a frame inside the chain)."""
    row = np.unique(layout_of(cfg).h_idx // cfg.n_rx)
    geo = _Geometry(cfg.rx_positions_m[:, 1] / (cfg.wavelength_m / 2), row,
                    cfg.tx_positions_m[np.array(cfg.tx_order) - 1][row, 1]
                    / (cfg.wavelength_m / 2))
    for a in geo:
        a.flags.writeable = False
    return geo


def _slots(cfg: RadarConfig, band: np.ndarray) -> np.ndarray:
    """(..., n_tx) sub-band of each Tx (in `tx_order`) when Tx1 sits in `band` (...)."""
    return (np.asarray(band)[..., None] + np.arange(cfg.n_tx)) % cfg.n_subbands


def beam_band_metric(beams: np.ndarray) -> np.ndarray:
    """Empty-band metric on the Rx beams (`band_beams`): (n, n_tx, N) -> (n, N), Z_j(wx) =
    sum_p |beam[p, (j + p) mod N]|^2, the beam energy of the n_tx sub-bands of hypothesis j
    (Tx1 in sub-band j; [TI-DDMA] table 11 with the Rx sum replaced by the beam)."""
    n_tx, n_sb = beams.shape[1:]
    p = np.arange(n_tx)
    slot = (np.arange(n_sb)[:, None] + p[None, :]) % n_sb  # (N, P)
    return (np.abs(beams[:, p[None, :], slot]) ** 2).sum(axis=-1)


def _nearest_peak(power_az: np.ndarray, a: np.ndarray) -> np.ndarray:
    """(n,) the local maximum of each cyclic spectrum row nearest (cyclically) to bin a."""
    n_az = power_az.shape[-1]
    is_max = (power_az > np.roll(power_az, 1, axis=-1)) & \
        (power_az >= np.roll(power_az, -1, axis=-1))
    dist = np.abs((np.arange(n_az)[None, :] - a[:, None] + n_az // 2) % n_az - n_az // 2)
    return np.argmin(np.where(is_max, dist, n_az), axis=-1)


@lru_cache(maxsize=32)
def coherence_floor(n_tx_row: int, threshold_snr: float, miss: float = TX_COHERENCE_MISS) -> float:
    """Smallest Tx coherence a far-field echo at the detection threshold shows with
    probability 1 - `miss`.

    At its own direction a single echo of coherent-map SNR S gives the Tx beams
    b_p = s e^{j wx t_p} + noise (P = `n_tx_row` Tx); its coherence
    rho = |sum_p e^{-j wx t_p} b_p|^2 / (P sum |b_p|^2) is one echo's fit on P elements, whose
    law `pipeline.mimo.echo_law` gives. Evaluated at S = `threshold_snr` (linear, over the
    mean noise).

    Examples
    --------
    >>> round(coherence_floor(3, 10 ** 1.3345), 3)  # 3 Tx, OS-CFAR Pfa 1e-6: 13.3 dB
    0.616
    """
    return float(echo_fit_quantile(n_tx_row, threshold_snr, miss))


def resolve_tx_order(cfg: RadarConfig, proc: ProcessingConfig, spec: np.ndarray,
                     energy: np.ndarray, det: DdmaDetections) -> DdmaDetections:
    """Each detection read in the Tx order its own direction's beam prefers, and kept only if
    it is a far-field echo in that order where another order's return shares its direction.

    Parameters
    ----------
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler spectra over all chirps, before demodulation.
    energy : (n_chirps, n_range) float
        `spec`'s energy summed over Rx.
    det : DdmaDetections
        Detections of the coherent map, `band` the cell's (Rx-summed) empty-band decision.

    Returns
    -------
    DdmaDetections
        In the CFAR's order: the detections whose cell decision their beam confirms; the
        others re-read in their beam's Tx order (band, azimuth bin, peak, spectra) if the
        re-read peak passes the CFAR threshold and the azimuth-sidelobe test; at most one per
        (range, Doppler, band,
        azimuth) cell; without those whose empty sub-bands hold a return (`EMPTY_BAND_PFA`)
        while their Tx beams do not add up as one echo's (`coherence_floor`).
    """
    alpha = proc.cfar.scale(looks=1)
    sin_term = interp_azimuth(det.power_az, det.a)
    beams = band_beams(cfg, proc, spec, det.r, det.d, sin_term)
    band = np.argmax(beam_band_metric(beams), axis=-1)
    moved = np.flatnonzero(band != det.band)
    if moved.size:
        det = _reread(cfg, proc, spec, det, moved, band[moved])
        keep = np.ones(len(det.a), dtype=bool)
        keep[moved] = det.peak[moved] > alpha * det.noise[moved]
        # the map's sidelobe test, on the re-read row
        if proc.angle.azimuth_sidelobe_db is not None:
            keep[moved] &= det.peak[moved] >= det.power_az[moved].max(axis=-1) * 10 ** (
                -proc.angle.azimuth_sidelobe_db / 10)
        # One detection per (range, Doppler, band, azimuth): the first in the CFAR's order.
        idx = np.flatnonzero(keep)
        key = np.stack([det.r, det.d, det.band, det.a], axis=-1)[idx]
        _, first = np.unique(key, axis=0, return_index=True)
        det = det.take(np.sort(idx[first]))
        sin_term = interp_azimuth(det.power_az, det.a)
        beams = band_beams(cfg, proc, spec, det.r, det.d, sin_term)
    n_dop = cfg.n_chirps // cfg.n_subbands
    band_energy = energy[np.arange(cfg.n_subbands) * n_dop + det.d[:, None], det.r[:, None]]
    return det.take(_single_echo(cfg, proc, det, beams, band_energy, sin_term))


def _reread(cfg: RadarConfig, proc: ProcessingConfig, spec: np.ndarray, det: DdmaDetections,
            moved: np.ndarray, band: np.ndarray) -> DdmaDetections:
    """`det` with detections `moved` read in Tx order `band`: the nearest azimuth peak of the
    re-read array, its power, azimuth spectrum and range neighbours."""
    n_az, n_range = det.power_az.shape[-1], spec.shape[2]
    r, d = det.r[moved], det.d[moved]
    # Azimuth spectra of the re-read array at r-1, r, r+1 (range interpolation) -> (m, 3, A).
    rr = np.clip(r[:, None] + np.arange(-1, 2), 0, n_range - 1)
    virt = ddma_virtual(cfg, spec, np.repeat(band, 3), rr.reshape(-1), np.repeat(d, 3))
    az = np.abs(compensate(cfg, proc, virt) @ array_dft(cfg, n_az, "horizontal")) ** 2
    az = az.reshape(moved.size, 3, n_az)
    a = _nearest_peak(az[:, 1], det.a[moved])
    rows = np.arange(moved.size)
    new = DdmaDetections(*(x.copy() for x in det))
    new.a[moved], new.band[moved], new.peak[moved] = a, band, az[rows, 1, a]
    new.power_az[moved] = az[:, 1]
    new.power_range[moved] = az[rows, :, a]
    return new


@lru_cache(maxsize=32)
def _empty_band_quantile(dof: int) -> float:
    """Upper `EMPTY_BAND_PFA` quantile of the empty sub-bands' energy in units of one cell's
    noise (gamma, `dof` complex cells); configuration-only, computed once per `dof`."""
    return stats.gamma.isf(EMPTY_BAND_PFA, dof)


def _single_echo(cfg: RadarConfig, proc: ProcessingConfig, det: DdmaDetections,
                 beams: np.ndarray, energy: np.ndarray, sin_term: np.ndarray) -> np.ndarray:
    """(n,) bool: not (empty sub-bands occupied and Tx coherence below `coherence_floor`).

    beams : (n, n_tx, N) `band_beams` at the detections; energy : (n, N) Rx-summed energy of
    each sub-band at the detection's range and Doppler bin; sin_term : (n,) wx / pi.

    A peak of the coherent map that only exists as the mix of a return read in its own Tx
    order and another read in the wrong one (the second's Tx3, Tx4, Tx2 replicas in the Tx1,
    Tx3, Tx4 slots) is a local maximum of the sum over the horizontal row, but the energy of
    the Tx beams in its direction does not add up as one echo's: most of it is orthogonal to
    the Tx steering. Only cells holding another Tx order's return are tested (their empty
    sub-bands are not empty): two echoes of one order never cost each other a point there.
    """
    cf = proc.cfar
    noise_mean = det.noise / noise_mean_factor(cf.mode, cf.n_training, cf.os_rank, 1)
    _, row, t = _geometry(cfg)
    n_row = row.size
    slots = _slots(cfg, det.band)  # (n, P)
    n = np.arange(det.a.size)
    b = beams[n[:, None], np.arange(cfg.n_tx)[None, :], slots][:, row]  # (n, P_h)
    proj = np.abs((b * np.exp(-1j * np.pi * sin_term[:, None] * t[None, :])).sum(-1)) ** 2
    rho = proj / (n_row * np.maximum((np.abs(b) ** 2).sum(-1), np.finfo(float).tiny))
    # The cell holds another Tx order's return when its empty sub-bands (Rx-summed energy,
    # n_out x n_rx complex noise cells of power sigma^2 / n_rx each; the map's noise is that of
    # n_row Tx beams summed coherently, so sigma^2 per beam is its mean over n_row) are not
    # noise.
    empty = np.ones((det.a.size, cfg.n_subbands), dtype=bool)
    empty[n[:, None], slots] = False
    e_out = (energy * empty).sum(-1)
    dof = (cfg.n_subbands - cfg.n_tx) * cfg.n_rx
    occupied = e_out > noise_mean / n_row / cfg.n_rx * _empty_band_quantile(dof)
    floor = coherence_floor(n_row, cf.scale(looks=1) * noise_mean_factor(
        cf.mode, cf.n_training, cf.os_rank, 1))
    return ~(occupied & (rho < floor))
