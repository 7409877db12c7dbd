"""Empty-band DDMA chain of TI's R79 demo ([TI-DDMA] section 5).

Range FFT -> Doppler FFT over all chirps -> empty-band demodulation (cyclic sub-band sum,
table 11), which both separates the transmitters and unwraps the velocity over
+/- lambda / (4 Tc) -> zero-padded azimuth FFT of the horizontal virtual antennas ->
Doppler-azimuth map per range bin -> OS-CFAR along Doppler (cyclic) and a 4-neighbour local
maximum (figure 19) -> azimuth interpolation (table 14) and elevation (table 15).

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA]: section 5, tables 11, 14, 15, figure 19.
"""
from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np
import pandas as pd

from radarsim.config import RadarConfig

from ..cfar import cfar_peaks, noise_mean_factor
from ..chirp_level.stage import windowed_range_stage
from ..compensation import compensate, virtual_coefficients
from ..config import WINDOWS, ProcessingConfig
from ..ddma_kernels import AzimuthMap, azimuth_map, ddma_spectra_power
from ..kernels import estimate_angles, layout_of, rx_energy, slow_time_fft, window
from ..peak_refinement import neighbour_bins, peak_patches, refine_peaks_2d
from ..stages import (
    empty_cloud,
    interp_azimuth,
    interp_doppler,
    interp_range,
    point_cloud,
)
from .base import DetectionMap, DopplerAzimuth, MimoChain, register_chain
from .ddma_order import DdmaDetections, ddma_virtual, resolve_tx_order

__all__ = ["DdmaMaps", "DdmaChain", "full_doppler_spectrum", "ddma_maps", "ddma_virtual",
           "refine_ddma_peaks"]


class DdmaMaps(NamedTuple):
    """Intermediate results of the empty-band DDMA chain.

    Attributes
    ----------
    power : (n_az, n_range, n_dop) float32
        Coherent Doppler-azimuth maps after demodulation (Doppler last, so the CFAR runs along
        contiguous memory).
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler spectra over all chirps, before demodulation.
    energy : (n_chirps, n_range) float32
        `spec`'s energy summed over Rx.
    tx1_band : (n_dop, n_range) int
        Sub-band of the first Tx of `tx_order` per Doppler bin ([TI-DDMA] table 11).
    """

    power: np.ndarray
    spec: np.ndarray
    energy: np.ndarray
    tx1_band: np.ndarray


def full_doppler_spectrum(cfg: RadarConfig, adc: np.ndarray,
                          proc: ProcessingConfig) -> tuple[np.ndarray, np.ndarray]:
    """Range FFT, then Doppler FFT over all chirps (DDMA: every Tx fires every chirp).

    Returns
    -------
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler bins (natural order) first, in the range cube's layout.
    energy : (n_chirps, n_range) float32
        Summed over Rx.
    """
    # (C, R, B): chirp-level chain + range FFT, times the Doppler window
    xw = windowed_range_stage(cfg, adc, proc, window(WINDOWS[proc.doppler.window], cfg.n_chirps))
    spec = slow_time_fft(xw)  # (C, R, B)
    return spec, rx_energy(spec)


def ddma_maps(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> DdmaMaps:
    """Range FFT, Doppler FFT, empty-band demodulation and the coherent detection map."""
    n_chirps = cfg.n_chirps
    n_dop = n_chirps // cfg.n_subbands
    n_az = proc.angle.n_azimuth_bins
    xw = windowed_range_stage(cfg, adc, proc, window(WINDOWS[proc.doppler.window], n_chirps))
    n_range = xw.shape[2]
    # Zero-padded azimuth FFT over the horizontal row and the power map.
    plan = _azimuth_map(cfg, n_az, proc.calibration.channel_comp)
    # Doppler FFT (`full_doppler_spectrum`'s), Rx energy, demodulation (Tx p of Doppler bin d
    # sits at chirp-bin d + n_dop (band + p) mod N; only the transmitters of the horizontal row
    # enter the map), azimuth map and power, by spans of range bins in one pass on the cores.
    spec, energy, power, tx1_band = ddma_spectra_power(xw, plan)
    power = power.reshape(n_az, n_range, n_dop)  # (A, B, D)
    return DdmaMaps(power=power, spec=spec, energy=energy, tx1_band=tx1_band)


@lru_cache(maxsize=32)
def _azimuth_map(cfg: RadarConfig, n_az: int, channel_comp: tuple | None) -> AzimuthMap:
    """The `AzimuthMap` of `ddma_maps`, configuration-only, computed once (~0.1 ms a frame
    inside the chain; read-only): the sub-band positions p of the horizontal row's
    transmitters, their virtual channels' horizontal positions (lambda/2; -1 for one not on
    the row) and compRangeBiasAndRxChanPhase's coefficients
    (`compensation.virtual_coefficients`)."""
    n_rx = cfg.n_rx
    layout = layout_of(cfg)
    tx_h = np.unique(layout.h_idx // n_rx)
    rows = (tx_h[:, None] * n_rx + np.arange(n_rx)).reshape(-1)
    positions = np.full(rows.size, -1)  # -1: a channel not on the row (`array_layout`)
    on_row = np.isin(rows, layout.h_idx)
    order = np.argsort(layout.h_idx)
    positions[on_row] = layout.h_pos[order][np.searchsorted(layout.h_idx[order], rows[on_row])]
    coef = virtual_coefficients(cfg, channel_comp)
    return azimuth_map(cfg.n_subbands, cfg.n_tx, tx_h, positions,
                       None if coef is None else coef[rows], n_az)


def doppler_velocity_mps(cfg: RadarConfig, k: np.ndarray) -> np.ndarray:
    """Radial velocity of (fractional) bins k of the full n_chirps-point Doppler FFT at Tc,
    wrapped to +/- lambda / (4 Tc), m/s (receding = negative Doppler frequency, design.md 3)."""
    k_signed = (k + cfg.n_chirps / 2) % cfg.n_chirps - cfg.n_chirps / 2
    return -k_signed / (cfg.n_chirps * cfg.chirp_period_s) * cfg.wavelength_m / 2


def refine_ddma_peaks(cfg: RadarConfig, spec: np.ndarray, r: np.ndarray, k_true: np.ndarray,
                      range_pos: np.ndarray, k_frac: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Range and Doppler of DDMA detections at the maximum of their windowed spectra
    (`pipeline.peak_refinement`), over the n_tx x n_rx channels: Tx p of a detection sits at
    chirp-bin k_true + n_dop p.

    Parameters
    ----------
    cfg : RadarConfig
    spec : (n_chirps, n_rx, n_range) complex64
        Doppler spectra over all chirps (`DdmaMaps.spec`).
    r, k_true : (n,) int
        Range bin and unwrapped Doppler bin (Tx1's) of each detection.
    range_pos, k_frac : (n,) float
        3-point estimates (fractional range bin, fractional Doppler bin): the starts.

    Returns
    -------
    range_pos, k_frac : (n,) float64
    """
    n_chirps, _, n_range = spec.shape
    n_dop = n_chirps // cfg.n_subbands
    r_idx, on = neighbour_bins(r, n_range, cyclic=False)                      # (n, Mr)
    d_idx, _ = neighbour_bins(k_true, n_chirps, cyclic=True)                  # (n, Md)
    d_idx = (d_idx[:, None, :] + n_dop * np.arange(cfg.n_tx)[None, :, None]) % n_chirps
    patch = peak_patches(spec, d_idx, r_idx)  # (n, T x R, Mr, Md)
    r_off, d_off = refine_peaks_2d(patch, on, range_pos - r, k_frac - k_true, cfg.n_samples,
                                   n_chirps)
    return r + r_off, k_true + d_off


def coherent_detections(power: np.ndarray, proc: ProcessingConfig):
    """CFAR (cyclic, along Doppler) and local maxima on (n_az, n_range, n_dop) coherent maps.

    Returns (a, r, d, noise, peak, power_az, power_range): azimuth, range and Doppler bins of
    the detections, the CFAR noise estimate (order statistic) and the peak power, each (n,),
    the azimuth spectrum of each, (n, n_az) (``power[:, r, d].T``), and the power at range
    bins r-1, r, r+1 (clipped) in its azimuth and Doppler bins, (n, 3)."""
    cf = proc.cfar
    n_range = power.shape[1]
    sidelobe_db = proc.angle.azimuth_sidelobe_db
    level = None if sidelobe_db is None else 10 ** (-sidelobe_db / 10)

    # Figure 19: 4-neighbour maximum in (azimuth, Doppler), optionally also along range.
    (a, r, d), noise, peak = cfar_peaks(
        power, cf.mode, cf.scale(looks=1), cf.guard_cells, cf.window_cells, cf.os_rank,
        cf.training_stride, {0: True, 1: False} if proc.range.peak_check else {0: True},
        proc.range.min_bin)
    # Per detection: the azimuth spectrum (for the sidelobe test and the caller), the range
    # neighbours, the sidelobe test.
    spectra = power[:, r, d]  # (n_az, n)
    pr = power[a[:, None], np.clip(r[:, None] + np.arange(-1, 2), 0, n_range - 1), d[:, None]]
    if level is not None:
        keep = peak >= spectra.max(axis=0) * level
        a, r, d, noise, peak, pr = a[keep], r[keep], d[keep], noise[keep], peak[keep], pr[keep]
        spectra = spectra[:, keep]
    return a, r, d, noise, peak, spectra.T, pr


def coherent_snr_db(proc: ProcessingConfig, noise: np.ndarray, peak: np.ndarray) -> np.ndarray:
    """Peak over the mean noise of a 1-look coherent map, from the CFAR's order statistic."""
    cf = proc.cfar
    noise_mean = noise / noise_mean_factor(cf.mode, cf.n_training, cf.os_rank, 1)
    return 10 * np.log10(peak / noise_mean)


class DdmaChain(MimoChain):
    """Empty-band DDMA receive chain ([TI-DDMA] section 5)."""

    name = "ddma"
    multi_azimuth_peaks = True  # coherent_detections keeps peaks within azimuth_sidelobe_db
    mitigation_in_range_stage = True  # interference: through the range stage only

    def process(self, cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> pd.DataFrame:
        maps = ddma_maps(cfg, adc, proc)
        power, energy, tx1_band = maps.power, maps.energy, maps.tx1_band
        n_az, n_range, n_dop = power.shape
        n_tx = cfg.n_tx
        a, r, d, noise, peak, power_az, pr = coherent_detections(power, proc)
        if r.size == 0:
            return empty_cloud()
        # The Tx order of each detection, decided again on the Rx beam at its own azimuth
        # (`ddma_order`): a weaker return one sub-band off in the same range bin is otherwise
        # read in the stronger one's order and reported at its velocity.
        det = resolve_tx_order(cfg, proc, maps.spec, energy,
                               DdmaDetections(a, r, d, tx1_band[d, r], noise, peak,
                                              power_az, pr))
        a, r, d, band, noise, peak = det.a, det.r, det.d, det.band, det.noise, det.peak
        if r.size == 0:
            return empty_cloud()

        # Range: interpolate on the coherent map at the same (Doppler, azimuth) cell.
        range_pos = interp_range(det.power_range, r, n_range, WINDOWS[proc.range.window])
        # Doppler: true bin d + n_dop x (Tx1 band); interpolate on the Rx-summed energy of all
        # Tx.
        k_true = d + n_dop * band
        offs = (k_true[:, None, None] + np.arange(-1, 2)[None, :, None]
                + n_dop * np.arange(n_tx)[None, None, :]) % cfg.n_chirps
        k_frac = k_true + interp_doppler(energy[offs, r[:, None, None]].sum(axis=-1),
                                         WINDOWS[proc.doppler.window], cfg.n_chirps)
        # Both refined to the maximum of the windowed spectrum of every Tx x Rx channel: the
        # 3-point estimates start the search.
        range_pos, k_frac = refine_ddma_peaks(cfg, maps.spec, r, k_true, range_pos, k_frac)
        velocity = doppler_velocity_mps(cfg, k_frac)
        # Angles.
        h_idx, h_pos, v_idx, v_pos, v_h = layout_of(cfg)
        sin_term = interp_azimuth(det.power_az, a)
        virt = compensate(cfg, proc, ddma_virtual(cfg, maps.spec, band, r, d))
        az, el = estimate_angles(virt, sin_term, h_idx, h_pos, v_idx, v_pos, v_h)
        snr_db = coherent_snr_db(proc, noise, peak)
        return point_cloud(cfg, proc, range_pos, velocity, az, el, snr_db,
                           {"range_bin": r, "doppler_bin": k_true % cfg.n_chirps,
                            "azimuth_bin": a})

    def detection_map(self, cfg: RadarConfig, adc: np.ndarray,
                      proc: ProcessingConfig) -> DetectionMap:
        power = ddma_maps(cfg, adc, proc).power
        return DetectionMap(np.ascontiguousarray(power.transpose(1, 0, 2)), 1, 2)

    def doppler_azimuth(self, cfg: RadarConfig, adc: np.ndarray, range_bin: int,
                        proc: ProcessingConfig) -> DopplerAzimuth:
        maps = ddma_maps(cfg, adc, proc)
        n_dop = maps.power.shape[2]
        k = np.arange(n_dop) + n_dop * maps.tx1_band[:, range_bin]
        return DopplerAzimuth(doppler_velocity_mps(cfg, k), maps.power[:, range_bin, :].T)

    def range_doppler_power(self, cfg: RadarConfig, adc: np.ndarray,
                            proc: ProcessingConfig) -> np.ndarray:
        return full_doppler_spectrum(cfg, adc, proc)[1].T


register_chain(DdmaChain())
