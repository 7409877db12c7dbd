"""Classic DDMA chain: N = Nt sub-bands, no empty band ([TI-DDMA] section 3.2).

Every Doppler bin d of a sub-band holds one echo of each Tx, in sub-bands j, j+1, ... (mod N)
for some unknown j: the energy pattern is the same for every j, so the empty-band metric of
table 11 cannot tell which sub-band holds Tx1, and with it the velocity (Tx1 sits at the true
Doppler). Range FFT -> Doppler FFT over all chirps -> CFAR on the non-coherent map summed over
Rx and sub-bands (n_virtual looks, as TDMA) -> for each of the N cyclic Tx-to-sub-band
assignments, the virtual array it implies is scored by the whole-array likelihood
(`stages.array_likelihood`, as the TDMA chain scores its velocity hypotheses) -> the winner
gives the Tx separation and the velocity d + j n_dop -> angles.

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA]: section 3.2 (table 1, figure 4), 5.
.. [2] TI, AWR1642 TDM-MIMO velocity disambiguation [TI-VEXT]: section 4.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

from radarsim.config import RadarConfig

from ..cfar import CFAR_MODES
from ..compensation import compensate
from ..config import ProcessingConfig
from ..kernels import layout_of
from ..stages import (
    array_dft,
    array_likelihood,
    empty_cloud,
    hypothesis_cloud,
    noncoherent_hits,
    power_of,
)
from .base import DetectionMap, DopplerAzimuth, MimoChain, register_chain
from .ddma import doppler_velocity_mps, full_doppler_spectrum

__all__ = ["ClassicDdmaMaps", "ClassicDdmaChain", "classic_ddma_maps", "assignment_scores"]


class ClassicDdmaMaps(NamedTuple):
    """Intermediate results of the classic-DDMA chain.

    Attributes
    ----------
    power : (n_range, n_dop) float32
        Energy summed over Rx and the N sub-bands per Doppler bin of a sub-band.
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler spectra over all chirps.
    energy : (n_chirps, n_range) float32
        `spec`'s energy summed over Rx.
    """

    power: np.ndarray
    spec: np.ndarray
    energy: np.ndarray


def classic_ddma_maps(cfg: RadarConfig, adc: np.ndarray,
                      proc: ProcessingConfig) -> ClassicDdmaMaps:
    """Full Doppler spectrum and the sub-band-summed non-coherent map."""
    spec, energy = full_doppler_spectrum(cfg, adc, proc)
    n_range = energy.shape[1]
    mode = CFAR_MODES[proc.cfar.mode]
    if mode.sums_looks:  # the square-law sum: from the Rx-summed energy, sub-bands in order
        power = energy.reshape(cfg.n_subbands, -1, n_range).sum(axis=0).T
    else:  # the mode's statistic over every (Rx, sub-band) channel, (range, Rx, band, Doppler)
        per = power_of(np.ascontiguousarray(spec.transpose(2, 1, 0))) \
            .reshape(n_range, cfg.n_rx, cfg.n_subbands, -1)
        power = mode.combine_looks(per, axis=(1, 2))
    return ClassicDdmaMaps(power=power, spec=spec, energy=energy)


def _band_samples(cfg: RadarConfig, spec: np.ndarray, r: np.ndarray,
                  d: np.ndarray) -> np.ndarray:
    """(n, N, n_rx) samples of Doppler bin d of every sub-band at range bins r."""
    n_dop = cfg.n_chirps // cfg.n_subbands
    k = d[:, None] + n_dop * np.arange(cfg.n_subbands)  # (n, N)
    return spec[k, :, r[:, None]]  # advanced indices first: (n, N, R)


def assignment_scores(cfg: RadarConfig, bands: np.ndarray, n_az: int,
                      proc: ProcessingConfig | None = None):
    """Virtual arrays and likelihoods of the N cyclic Tx-to-sub-band assignments.

    Parameters
    ----------
    bands : (n, N, n_rx) complex
        Samples of one Doppler bin in each sub-band.

    Returns
    -------
    virt : (n, N, n_virtual) complex
        Hypothesis j: Tx `tx_order[i]` read from sub-band (j + i) mod N.
    az_pow : (n, N, n_az) float
        Horizontal-row azimuth power of each hypothesis.
    score : (n, N) float
        Whole-array likelihood (`stages.array_likelihood`).
    """
    virt, az_pow = _assignment_arrays(cfg, bands, n_az, proc)
    _, _, v_idx, _, _ = layout_of(cfg)
    return virt, az_pow, array_likelihood(cfg, virt, az_pow, v_idx)


def _assignment_arrays(cfg: RadarConfig, bands: np.ndarray, n_az: int,
                       proc: ProcessingConfig | None = None) -> tuple[np.ndarray, np.ndarray]:
    """`assignment_scores` without the likelihood: (virt, az_pow), the virtual channels
    compensated by ``proc.calibration.channel_comp`` (`pipeline.compensation`) when `proc` is
    given."""
    n_sb = cfg.n_subbands
    idx = (np.arange(n_sb)[:, None] + np.arange(cfg.n_tx)[None, :]) % n_sb  # (H, P)
    virt = bands[:, idx].reshape(bands.shape[0], n_sb, -1)  # (n, H, P*R)
    if proc is not None:
        virt = compensate(cfg, proc, virt)
    return virt, _azimuth_power(cfg, virt, n_az)


def _azimuth_power(cfg: RadarConfig, virt: np.ndarray, n_az: int) -> np.ndarray:
    """(..., n_az) horizontal-row azimuth power of virtual arrays (..., n_virtual)."""
    return np.abs(virt @ array_dft(cfg, n_az, "horizontal")) ** 2


class ClassicDdmaChain(MimoChain):
    """Classic-DDMA receive chain (N = Nt, Tx assignment by hypothesis test).

    The likelihood is maximised over a `score_bins`-point azimuth grid: on the 48-point
    detection grid the scalloping of the true hypothesis (up to 0.9 dB) lets a wrong one win
    at high SNR (model: 15 % failures at 30 dB with the R79 order on 48 points, 4.8 % on 256).
    """

    name = "ddma_classic"
    mitigation_in_range_stage = True  # interference: through the range stage only
    #: Azimuth grid of the assignment likelihood.
    score_bins = 256

    def process(self, cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> pd.DataFrame:
        maps = classic_ddma_maps(cfg, adc, proc)
        rd = maps.power
        n_dop = rd.shape[1]
        hits = noncoherent_hits(rd, cfg.n_virtual, proc)
        if hits.range_bin.size == 0:
            return empty_cloud()
        r, d = hits.range_bin, hits.doppler_bin

        bands = _band_samples(cfg, maps.spec, r, d)
        virt, _, score = assignment_scores(cfg, bands, self.score_bins, proc)
        best = np.argmax(score, axis=1)
        az_pow = _azimuth_power(cfg, virt, proc.angle.n_azimuth_bins)
        k_true = d + n_dop * best
        velocity = doppler_velocity_mps(cfg, k_true + hits.doppler_offset)
        return hypothesis_cloud(cfg, proc, hits, virt, az_pow, best, velocity,
                                k_true % cfg.n_chirps)

    def detection_map(self, cfg: RadarConfig, adc: np.ndarray,
                      proc: ProcessingConfig) -> DetectionMap:
        return DetectionMap(classic_ddma_maps(cfg, adc, proc).power, cfg.n_virtual, 1)

    def doppler_azimuth(self, cfg: RadarConfig, adc: np.ndarray, range_bin: int,
                        proc: ProcessingConfig) -> DopplerAzimuth:
        """Each Doppler bin of a sub-band at the velocity and array of its best assignment."""
        maps = classic_ddma_maps(cfg, adc, proc)
        n_dop = maps.power.shape[1]
        d = np.arange(n_dop)
        r = np.full(n_dop, range_bin)
        bands = _band_samples(cfg, maps.spec, r, d)
        virt, _, score = assignment_scores(cfg, bands, self.score_bins, proc)
        best = np.argmax(score, axis=1)
        az_pow = _azimuth_power(cfg, virt, proc.angle.n_azimuth_bins)
        return DopplerAzimuth(doppler_velocity_mps(cfg, d + n_dop * best),
                              az_pow[np.arange(n_dop), best])

    def range_doppler_power(self, cfg: RadarConfig, adc: np.ndarray,
                            proc: ProcessingConfig) -> np.ndarray:
        return full_doppler_spectrum(cfg, adc, proc)[1].T


register_chain(ClassicDdmaChain())
