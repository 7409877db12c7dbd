"""TDMA baseline chain [TI-VEXT], and the slot-coded chain family it heads.

Range FFT -> Doppler FFT per slot (n_chirps / n_tx chirps at n_tx Tc) -> CFAR on the
non-coherent range-Doppler map summed over the virtual channels -> for every velocity hypothesis
v_est + 2 k Vmax: Doppler-phase compensation of the later slots (eq. 8-10) and transmitter
separation (`SlotChain.separate`: identity for TDMA, Hadamard decoding for BPM) -> the
hypothesis with the largest whole-array likelihood wins (section 4) -> the same angle
estimation as DDMA.

The hypotheses are scored on the virtual samples after the board's channel correction
(``compRangeBiasAndRxChanPhase``, `pipeline.compensation`): on a 3-Tx xWR68xx/18xx array the
raised Tx's slot phase is absorbed by the free elevation phase, and only the phase step between
the horizontal row's two Tx groups separates hypothesis k (step 120 k deg) from the truth (0),
so an uncorrected Tx-to-Tx phase error beyond 60 deg makes a wrong hypothesis win and moves
static returns to +/-2 Vmax (the real IWR6843's symptom; tests/pipeline/
test_velocity_extension_board.py). Returns of the radar's own hardware and mount (Tx-to-Rx
leakage, DC residue, near-field returns) fit no hypothesis and sit at zero Doppler: a
zero-Doppler detection is moved beyond +/-Vmax only if its winning hypothesis fits one
far-field echo as well as a real echo at its SNR does (`pipeline.mimo.extension`).

References
----------
.. [1] TI, AWR1642 TDM-MIMO velocity disambiguation [TI-VEXT]: eq. 8-12, section 4.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import fields
from functools import lru_cache
from typing import NamedTuple

import numpy as np
import pandas as pd

from radarsim.config import RadarConfig

from ..cfar import CFAR_MODES, CfarMode, noise_mean_factor
from ..chirp_level.stage import range_stage, windowed_range_stage
from ..compensation import compensate
from ..config import WINDOWS, ProcessingConfig
from ..fov import FOV_FIELDS, in_interval
from ..kernels import doppler_windowed, layout_of, rx_energy, slow_time_fft, window
from ..stages import (
    RangeDopplerHits,
    array_dft,
    array_likelihood,
    empty_cloud,
    hypothesis_cloud,
    noncoherent_hits,
    power_of,
    refine_hits,
)
from .base import DetectionMap, DopplerAzimuth, MimoChain, register_chain
from .extension import may_extend

__all__ = ["SlotMaps", "SlotDetections", "SlotChain", "detection_key", "TdmaChain", "slot_maps",
           "slot_spectra", "remove_slot_phase",
           "ZERO_DOPPLER_BINS"]

#: Half-width of the zero-Doppler region whose detections must pass the far-field fit test to
#: be extended, bins (the Doppler mainlobe of a static return: a Hann window's is +/-2 bins,
#: its -6 dB points +/-1).
ZERO_DOPPLER_BINS = 1.0


class SlotMaps(NamedTuple):
    """Intermediate results of a slot-coded chain (TDMA, BPM).

    Attributes
    ----------
    power : (n_range, n_dop) float
        Non-coherent map summed over the n_slots x n_rx channels (n_virtual looks per cell).
    virt : (n_range, n_dop, n_slots x n_rx) complex64
        Per-slot Doppler spectra, slot-major, before Doppler compensation and separation.
    """

    power: np.ndarray
    virt: np.ndarray

    @property
    def spec(self) -> np.ndarray:
        """(n_dop, n_slots x n_rx, n_range) complex64, C-contiguous: the spectra `virt` views."""
        return np.moveaxis(self.virt, 0, 2)


class SlotDetections(NamedTuple):
    """A slot chain's detections before the velocity hypotheses (`SlotChain.detect`)."""

    virt: np.ndarray      # (n_range, n_dop, n_slots x n_rx) complex64: `SlotMaps.virt`
    hits: RangeDopplerHits  # inside the field of view's velocity limits
    d_signed: np.ndarray  # (n,) aliased Doppler bin, signed, interpolated
    v_est: np.ndarray     # (n,) aliased radial velocity, m/s


def detection_key(proc: ProcessingConfig) -> tuple:
    """The settings `SlotChain.detect` reads, as values: every part of `proc` but the velocity
    disambiguation, which only the hypotheses after the detections read. Equal keys, the same
    detections of a frame."""
    return tuple(getattr(proc, f.name) for f in fields(proc) if f.name != "velocity")


def slot_spectra(xw: np.ndarray, n_tx: int, mode: CfarMode | None = None) -> SlotMaps:
    """Per-slot Doppler spectra and the non-coherent map of a windowed slot cube.

    Parameters
    ----------
    xw : (n_chirps, n_rx, n_range) complex64, C-contiguous
        Range spectra times the Doppler window of each chirp's code period (chirp = n_tx c' +
        slot); overwritten by the spectra.
    n_tx : int
        Slots per code period.
    mode : CfarMode, optional
        Whose `combine_looks` makes a map cell of the n_tx x n_rx channel powers; None: their
        sum, as for every square-law mode.

    Returns
    -------
    SlotMaps
        ``power`` (n_range, n_dop) float32 C-contiguous; ``virt`` (n_range, n_dop,
        n_tx x n_rx) a view of the spectra, slot-major.
    """
    n_c, n_rx, n_range = xw.shape
    spec = slow_time_fft(xw.reshape(n_c // n_tx, n_tx * n_rx, n_range))  # (D, S x R, B)
    if mode is None or mode.sums_looks:
        # |x|^2 = re^2 + im^2 added channel after channel, in one pass over the spectra
        power = rx_energy(spec)
    else:
        power = mode.combine_looks(power_of(spec), axis=1)
    return SlotMaps(power=np.ascontiguousarray(power.T), virt=np.moveaxis(spec, 2, 0))


def slot_maps(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> SlotMaps:
    """Range FFT and per-slot Doppler FFT (chirp = n_tx c' + slot); the map combines the
    channels as the CFAR mode does (n_virtual looks per cell)."""
    n_tx = cfg.n_tx
    n_dop = cfg.n_chirps // n_tx
    if proc.doppler.clutter_removal:
        rf = range_stage(cfg, adc, proc)  # (C, R, B): chirp-level chain + range FFT
        rf = rf.reshape(n_dop, -1, rf.shape[-1])  # (D, S x R, B): chirp = n_tx c' + slot
        # TI's static clutter removal (clutterRemoval, SDK 3.x DopplerProc): the mean over the
        # frame's chirps of each slot, Rx and range bin -- the zero-Doppler return -- removed
        # before the Doppler FFT.
        xw = doppler_windowed(rf - rf.mean(axis=0, keepdims=True),
                              window(WINDOWS[proc.doppler.window], n_dop))
    else:
        # The same product with the window's value repeated for the slots of each period.
        xw = windowed_range_stage(cfg, adc, proc,
                                  _slot_window(WINDOWS[proc.doppler.window], n_dop, n_tx))
    return slot_spectra(xw.reshape(cfg.n_chirps, cfg.n_rx, -1), n_tx, CFAR_MODES[proc.cfar.mode])


def remove_slot_phase(slots: np.ndarray, velocity_mps: np.ndarray, wavelength_m: float,
                      slot_period_s: float) -> np.ndarray:
    """Slot samples with slot s's Doppler phase 2 pi f_D s T removed ([TI-VEXT] eq. 8-10),
    f_D = -2 v / lambda.

    Parameters
    ----------
    slots : (..., n_slots, n_rx) complex64
        Per-slot samples of one code period (slot-major).
    velocity_mps : (...) float
        The velocity to compensate each sample vector at, m/s (broadcast against the leading
        axes of `slots`).
    wavelength_m, slot_period_s : float
        Wavelength, m, and the time T between two slots, s.

    Returns
    -------
    (..., n_slots, n_rx) complex64
    """
    f_d = -2 * np.asarray(velocity_mps) / wavelength_m
    comp = np.exp(-2j * np.pi * f_d[..., None] * np.arange(slots.shape[-2]) * slot_period_s)
    return slots * comp[..., None].astype(np.complex64)


@lru_cache(maxsize=16)
def _slot_window(name: str, n_dop: int, n_tx: int) -> np.ndarray:
    """(n_dop x n_tx,) float32, read-only: each chirp's value of the n_dop-point Doppler window
    `name` (chirp = n_tx c' + slot takes window[c'])."""
    w = np.repeat(window(name, n_dop), n_tx)
    w.flags.writeable = False
    return w


class SlotChain(MimoChain):
    """Chain of the schemes that cycle through n_tx chirps per code period (TDMA, BPM).

    Subclasses override `separate` (slot samples -> virtual channels) and `noise_gain_of`.
    """

    removes_static_clutter = True
    mitigation_in_range_stage = True  # interference: through the range stage only
    #: ``cfarFovCfg`` Doppler applies to the aliased velocity, in the CFAR step (`process`).
    fov_fields = tuple(f for f in FOV_FIELDS if f != "velocity_mps")

    def noise_gain_of(self, cfg: RadarConfig) -> float:
        """Noise power of a separated virtual channel over that of one slot channel."""
        return 1.0

    def disambiguate(self, proc: ProcessingConfig) -> bool:
        """Whether to test velocity hypotheses beyond +/-Vmax."""
        return proc.velocity.tdma_disambiguation

    def score(self, cfg: RadarConfig, virt: np.ndarray, az_pow: np.ndarray,
              v_idx: np.ndarray) -> np.ndarray:
        """(n, H) likelihood of each velocity hypothesis (`stages.array_likelihood`, on the
        azimuth grid: TDMA's wrong hypotheses explain at most 84 % of the array's energy on
        the R79 array at any azimuth, far below the grid's off-grid loss)."""
        return array_likelihood(cfg, virt, az_pow, v_idx)

    def separate(self, cfg: RadarConfig, slots: np.ndarray) -> np.ndarray:
        """(..., n_slots, n_rx) Doppler-compensated slot samples -> (..., n_tx, n_rx) virtual
        channels in `tx_order` (TDMA: the slots are the channels)."""
        return slots

    def process(self, cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> pd.DataFrame:
        return self.finish(cfg, proc, self.detect(cfg, adc, proc))

    def process_variants(self, cfg: RadarConfig, adc: np.ndarray,
                         procs: Sequence[ProcessingConfig]) -> list[pd.DataFrame]:
        """Settings that differ only in the velocity disambiguation (TDMA and ``tdma_raw``)
        share their detections: maps, CFAR and peak refinement run once per
        `detection_key`."""
        detected: dict[tuple, SlotDetections] = {}
        clouds = []
        for proc in procs:
            key = detection_key(proc)
            if key not in detected:
                detected[key] = self.detect(cfg, adc, proc)
            clouds.append(self.finish(cfg, proc, detected[key]))
        return clouds

    def detect(self, cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig
               ) -> SlotDetections:
        """Slot maps, CFAR on the non-coherent map, peak refinement and the aliased velocity
        of every hit inside the field of view's velocity limits (read-only for `finish`)."""
        n_dop = cfg.n_chirps // cfg.n_tx
        maps = slot_maps(cfg, adc, proc)
        hits = noncoherent_hits(maps.power, cfg.n_virtual, proc)
        # range and Doppler at the maximum of the slot channels' windowed spectra
        hits = refine_hits(hits, maps.spec, cfg.n_samples)
        d_signed = (hits.doppler_bin + hits.doppler_offset + n_dop / 2) % n_dop - n_dop / 2
        t_slot = cfg.n_tx * cfg.chirp_period_s
        v_est = -d_signed / (n_dop * t_slot) * cfg.wavelength_m / 2
        # cfarFovCfg Doppler, where TI's CFAR DPU applies it: on the aliased Doppler, before
        # the hypotheses (a target at 1.6 m/s aliased to -0.5 m/s passes a +/-1 m/s limit).
        in_fov = in_interval(v_est, proc.fov.velocity_mps)
        if not in_fov.all():
            hits, d_signed, v_est = hits.select(in_fov), d_signed[in_fov], v_est[in_fov]
        return SlotDetections(maps.virt, hits, d_signed, v_est)

    def finish(self, cfg: RadarConfig, proc: ProcessingConfig, det: SlotDetections
               ) -> pd.DataFrame:
        """The velocity hypotheses of `detect`'s hits, their separation, scoring and angles:
        the point cloud."""
        n_tx = cfg.n_tx
        n_dop = cfg.n_chirps // n_tx
        n_az = proc.angle.n_azimuth_bins
        virt_all, hits, d_signed, v_est = det
        if hits.range_bin.size == 0:
            return empty_cloud()
        t_slot = n_tx * cfg.chirp_period_s
        r, d = hits.range_bin, hits.doppler_bin
        v_max = cfg.max_unambiguous_velocity_mps
        if self.disambiguate(proc):
            # Hypotheses v_est + 2 k Vmax covering the full +/- lambda / (4 Tc) span ([TI-VEXT]
            # eq. 12).
            k = np.arange(-(n_tx // 2) - 1, n_tx // 2 + 2)
            v_hyp = v_est[:, None] + 2 * k[None, :] * v_max  # (n, H)
            span = n_tx * v_max
            valid = (v_hyp >= -span) & (v_hyp < span)
        else:
            v_hyp = v_est[:, None]
            valid = np.ones_like(v_hyp, dtype=bool)
        _, _, v_idx, _, _ = layout_of(cfg)
        virt = virt_all[r, d].reshape(-1, 1, n_tx, cfg.n_rx)  # (n, 1, S, R)
        slots = remove_slot_phase(virt, v_hyp, cfg.wavelength_m, cfg.chirp_period_s)
        virt_h = self.separate(cfg, slots).reshape(r.size, v_hyp.shape[1], -1)  # (n, H, 16)
        virt_h = compensate(cfg, proc, virt_h)  # compRangeBiasAndRxChanPhase, before scoring
        az_pow = power_of(virt_h @ array_dft(cfg, n_az, "horizontal"))  # (n, H, A) float32
        score = self.score(cfg, virt_h, az_pow, v_idx)
        best = np.argmax(np.where(valid, score, -np.inf), axis=1)
        if self.disambiguate(proc):
            # A return of the radar's own hardware and mount (Tx-to-Rx leakage, DC residue,
            # near-field stand/bumper returns) sits at zero Doppler and is no far-field echo
            # through the array: move a zero-Doppler detection beyond +/-Vmax only if its
            # winning hypothesis fits one far-field echo as a real one at its SNR would
            # (`extension`); otherwise it keeps its measured velocity, 0.
            unextended = int(np.flatnonzero(k == 0)[0])
            moved = np.flatnonzero((best != unextended)
                                   & (np.abs(d_signed) <= ZERO_DOPPLER_BINS))
            cf = proc.cfar
            sigma2 = hits.noise[moved] * self.noise_gain_of(cfg) / (
                noise_mean_factor(cf.mode, cf.n_training, cf.os_rank, hits.looks) * hits.looks)
            keep = may_extend(cfg, virt_h[moved, best[moved]], sigma2)
            best[moved[~keep]] = unextended
        velocity = v_hyp[np.arange(r.size), best]
        d_true = np.rint(-2 * velocity / cfg.wavelength_m * n_dop * t_slot).astype(int)
        return hypothesis_cloud(cfg, proc, hits, virt_h, az_pow, best, velocity,
                                d_true % (n_tx * n_dop), self.noise_gain_of(cfg))

    def detection_map(self, cfg: RadarConfig, adc: np.ndarray,
                      proc: ProcessingConfig) -> DetectionMap:
        return DetectionMap(slot_maps(cfg, adc, proc).power, cfg.n_virtual, 1)

    def doppler_azimuth(self, cfg: RadarConfig, adc: np.ndarray, range_bin: int,
                        proc: ProcessingConfig) -> DopplerAzimuth:
        """Per-slot Doppler spectrum with the later slots' Doppler phase compensated at each
        bin's own (unaliased-hypothesis) velocity, separated, then the azimuth DFT."""
        lam, tc = cfg.wavelength_m, cfg.chirp_period_s
        virt = slot_maps(cfg, adc, proc).virt[range_bin]  # (D, S*R)
        n_dop = virt.shape[0]
        d_signed = (np.arange(n_dop) + n_dop / 2) % n_dop - n_dop / 2
        vel = -d_signed / (n_dop * cfg.n_tx * tc) * lam / 2
        slots = remove_slot_phase(virt.reshape(n_dop, cfg.n_tx, cfg.n_rx), vel, lam, tc)
        virt = compensate(cfg, proc, self.separate(cfg, slots).reshape(n_dop, -1))
        power = np.abs(virt @ array_dft(cfg, proc.angle.n_azimuth_bins, "horizontal")) ** 2
        return DopplerAzimuth(vel, power)

    def range_doppler_power(self, cfg: RadarConfig, adc: np.ndarray,
                            proc: ProcessingConfig) -> np.ndarray:
        return slot_maps(cfg, adc, proc).power


class TdmaChain(SlotChain):
    """TDMA baseline [TI-VEXT]: one Tx per slot, so separation is the identity. Variant
    ``tdma_raw``: the same frame without velocity disambiguation."""

    name = "tdma"
    variants = {"tdma_raw": {"velocity.tdma_disambiguation": False}}


register_chain(TdmaChain())
