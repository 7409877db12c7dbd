"""Fast/slow chirp chain ([TI-VEXT] section 3): velocity unfolding by a second chirp period.

The frame holds a fast and a slow TDMA chirp set (`radarsim.mimo.fast_slow`). Range FFT ->
Doppler FFT per set and slot (n_dop = n_chirps / (2 n_tx) chirps at n_tx T) -> non-coherent
range-Doppler map of each set summed over the virtual channels -> CFAR on the fast map, then
[TI-VEXT]'s eight steps for every fast peak:

1. CFAR on the fast map: peak bin PeakIdx_fast and value PeakVal_fast.
2. The fast peak's (aliased) velocity Vel_fast.
3. Candidates V_hypo = Vel_fast + 2 k Vmax_fast covering +/- unfold_factor x Vmax_fast.
4. Each candidate's own aliased bin in the slow map, PeakIdx_slow_hypo.
5. The slow map's largest value within +/- `fast_slow_search_bins` of that bin (same range
   bin), PeakVal_slow_hypo.
6. A candidate survives if |PeakVal_slow_hypo / PeakVal_fast| is within
   `fast_slow_threshold_db` (both sets carry the same energy, so a true match has equal
   expected power).
7. Among the survivors, the one with the largest slow peak, Vel_candidate_max.
8. Its velocity is the detection's. A peak without a survivor keeps its aliased fast-set
   velocity, as TI's SRR demo does.

Beyond [TI-VEXT]: a candidate must also agree in array signature (`gate_coherence`,
``fast_slow_min_coherence``; 0 gives [TI-VEXT]'s power-only test), and a slow peak is given to
one fast peak at most (TI's demo consumes it once associated; here,
where two peaks of a range bin claim the same one, an optimal assignment on the spatial
coherence of the fast and slow array samples, `resolve_claims`).

Association is per peak, so targets in one range cell unfold independently. The angle comes
from the fast set's virtual array with the TDMA slot phase removed at the unfolded velocity
([TI-VEXT] eq. 8-10): with the true velocity known, this compensation is exact.

References
----------
.. [1] TI, "AWR1642 velocity disambiguation" [TI-VEXT]: section 3, figure 5, table 2, the
   eight-step algorithm; eq. 8-10 (Doppler-phase compensation of TDMA slots).
.. [2] TI, TIDEP-0092 short-range radar reference design (3 dB association threshold, +/-2
   bins search).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from radarsim.config import RadarConfig

from ..chirp_level import windowed_range_stage
from ..compensation import compensate
from ..config import WINDOWS, ProcessingConfig
from ..kernels import window
from ..stages import (
    RangeDopplerHits,
    array_dft,
    empty_cloud,
    hypothesis_cloud,
    noncoherent_hits,
)
from .base import DetectionMap, DopplerAzimuth, MimoChain, register_chain
from .tdma import remove_slot_phase, slot_spectra

__all__ = ["FastSlowMaps", "FastSlowChain", "fast_slow_maps", "Unfolding", "unfold_peaks",
           "gate_coherence", "resolve_claims", "slow_bin_of"]


class FastSlowMaps(NamedTuple):
    """Intermediate results of the fast/slow chain.

    Attributes
    ----------
    fast_power, slow_power : (n_range, n_dop) float32
        Non-coherent range-Doppler map of each set, summed over the n_tx x n_rx slot channels
        (n_virtual looks per cell).
    fast_virt, slow_virt : (n_range, n_dop, n_tx x n_rx) complex64
        Each set's per-slot Doppler spectra, slot-major (`tx_order`), before the slot
        Doppler-phase compensation.
    """

    fast_power: np.ndarray
    slow_power: np.ndarray
    fast_virt: np.ndarray
    slow_virt: np.ndarray


def fast_slow_maps(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> FastSlowMaps:
    """Range FFT of the frame, then each set's per-slot Doppler FFT and non-coherent map.

    Parameters
    ----------
    cfg : RadarConfig
        A fast/slow radar (`cfg.scheme.chirp_sets`).
    adc : (n_chirps, n_rx, n_samples) int16 or complex64
    proc : ProcessingConfig
    """
    sets = cfg.scheme.chirp_sets(cfg)
    # Each chirp's value of its set's Doppler window (chirp = n_tx c' + slot within a set).
    per_chirp = np.empty(cfg.n_chirps, np.float32)
    slots = np.repeat(window(WINDOWS[proc.doppler.window], sets.n_doppler_bins), cfg.n_tx)
    per_chirp[sets.fast] = slots
    per_chirp[sets.slow] = slots
    # (C, R, B): chirp-level chain + range FFT, times the window
    xw = windowed_range_stage(cfg, adc, proc, per_chirp)
    fast, slow = slot_spectra(xw[sets.fast], cfg.n_tx), slot_spectra(xw[sets.slow], cfg.n_tx)
    return FastSlowMaps(fast.power, slow.power, fast.virt, slow.virt)


def slow_bin_of(velocity_mps: np.ndarray, wavelength_m: float, slot_period_s: float,
                n_dop: int) -> np.ndarray:
    """Fractional Doppler bin (0 .. n_dop) at which a velocity aliases in a set whose Tx
    sample slow time every `slot_period_s`: f_D = -2 v / lambda, bin = f_D n_dop T mod n_dop.

    Examples
    --------
    >>> float(slow_bin_of(np.array(-1.0), 4e-3, 1e-4, 100))  # f_D 500 Hz: 0.05 cycles/sample
    5.0
    """
    return np.mod(-2 * velocity_mps / wavelength_m * n_dop * slot_period_s, n_dop)


class Unfolding(NamedTuple):
    """Result of the association test for n fast peaks over H candidates.

    Attributes
    ----------
    candidates_mps : (n, H) float
        Vel_fast + 2 k Vmax_fast for k = -(U // 2) - 1 .. U // 2 + 1 (column `native` is
        k = 0, the fast peak's own velocity).
    valid : (n, H) bool
        Candidates inside the unfolded span [-U Vmax_fast, U Vmax_fast).
    slow_peak : (n, H) float
        PeakVal_slow_hypo: the slow map's largest value within the search window.
    slow_bin : (n, H) int
        Where in the window that largest value sits (the slow peak a candidate claims).
    passed : (n, H) bool
        Valid candidates whose slow peak is within the threshold of the fast peak.
    best : (n,) int
        The chosen candidate: Vel_candidate_max, or `native` for a peak without one.
    associated : (n,) bool
        Whether the peak was unfolded (a passed candidate, its slow peak not claimed by
        another fast peak of the range bin).
    native : int
        Column of k = 0.
    """

    candidates_mps: np.ndarray
    valid: np.ndarray
    slow_peak: np.ndarray
    slow_bin: np.ndarray
    passed: np.ndarray
    best: np.ndarray
    associated: np.ndarray
    native: int

    @property
    def velocity_mps(self) -> np.ndarray:
        """(n,) the chosen candidate of each peak; the fast set's own (aliased) velocity where
        no candidate was associated."""
        return self.candidates_mps[np.arange(self.best.size), self.best]


def gate_coherence(unf: "Unfolding", coherence: np.ndarray, min_coherence: float) -> "Unfolding":
    """Keep only candidates whose fast and slow array samples agree: spatial coherence
    |x_f^H x_s|^2 / (|x_f|^2 |x_s|^2) >= `min_coherence`, then [TI-VEXT]'s choice (largest slow
    peak) among the rest.

    [TI-VEXT]'s test compares powers only, so a candidate landing on another echo's slow peak
    of similar power passes (two targets in one range cell, or the many returns of a guard
    rail, whose Doppler spreads with azimuth). The same echo has the same array signature in
    both sets once each set's slot phases are removed at the candidate velocity; another echo
    at another azimuth does not (two independent 16-element vectors: coherence Beta(1, 15),
    mean 1/16, above 0.2 with probability 0.8^15 = 3.5 %). For one echo at per-channel SNR s
    (both sets noisy) the true candidate's coherence is about (s / (1 + s))^2: 0.25 at 0 dB,
    0.44 at 3 dB, 0.69 at 6 dB per channel (detection SNR about 11, 14, 17 dB), so the
    default gate of 0.2 costs little where the fast-set CFAR detects at all, and a gate of
    0.5 would drop true candidates below 6 dB per channel.

    Parameters
    ----------
    unf : Unfolding
    coherence : (n, H) float
    min_coherence : float
        In (0, 1) (`ProcessingConfig.velocity.fast_slow_min_coherence`).

    Returns
    -------
    Unfolding
        `passed`, `best`, `associated` updated (unassociated peaks at `native`).
    """
    passed = unf.passed & (coherence >= min_coherence)
    assoc = passed.any(axis=1)
    best = np.where(assoc, np.argmax(np.where(passed, unf.slow_peak, -np.inf), axis=1),
                    unf.native)
    return unf._replace(passed=passed, best=best, associated=assoc)


#: Cost of a fast peak left without a slow peak in `resolve_claims` (costs are 1 - coherence,
#: in [0, 1]).
_UNMATCHED_COST = 1e6


def resolve_claims(unf: "Unfolding", range_bin: np.ndarray,
                   coherence: np.ndarray) -> "Unfolding":
    """Give each slow peak to one fast peak at most.

    Where the per-peak choice lets two fast peaks of one range bin claim the same slow peak
    (two targets in one range cell, one's candidate landing on the other's slow alias: the
    swapped pairing then explains both maps equally well, since a candidate k spans away lands
    on the other's alias exactly when the other's -k candidate lands on its), the peaks of that
    range bin are matched to slow peaks by an optimal assignment
    (`scipy.optimize.linear_sum_assignment`): as many peaks as possible associated, then the
    largest total spatial coherence between each fast peak and the slow peak it takes (the
    same target has the same array signature in both sets; another target at another azimuth
    does not). Peaks left over are not associated. TI's SRR ``disambiguateVel`` reaches the
    exclusivity greedily (a slow peak is zeroed once taken) and cannot undo a swap.

    Parameters
    ----------
    unf : Unfolding
        The per-peak result of `unfold_peaks`.
    range_bin : (n,) int
        Range bin of each fast peak.
    coherence : (n, H) float
        |x_f^H x_s|^2 / (|x_f|^2 |x_s|^2) of each candidate's fast and slow array samples, each
        with its slot phases removed at the candidate velocity, in [0, 1].

    Returns
    -------
    Unfolding
        With `best` and `associated` updated.
    """
    n_dop = int(unf.slow_bin.max()) + 1 if unf.slow_bin.size else 1
    key = range_bin[:, None] * n_dop + unf.slow_bin  # the slow peak each candidate claims
    rows = np.arange(unf.best.size)
    assoc, best = unf.associated, unf.best
    chosen = key[rows, best]
    _, inverse, counts = np.unique(chosen[assoc], return_inverse=True, return_counts=True)
    if not np.any(counts > 1):
        return unf
    clash_bins = np.unique(range_bin[assoc][counts[inverse] > 1])
    involved = np.flatnonzero(assoc & np.isin(range_bin, clash_bins))
    passed = unf.passed[involved]
    pi, ph = np.nonzero(passed)
    cols, col_of = np.unique(key[involved][pi, ph], return_inverse=True)
    cost = np.full((involved.size, cols.size), _UNMATCHED_COST)
    # Several candidates of one peak may claim one slow peak: keep the most coherent.
    np.minimum.at(cost, (pi, col_of), 1.0 - coherence[involved][pi, ph])
    r, c = linear_sum_assignment(cost)
    best, assoc = best.copy(), assoc.copy()
    assoc[involved] = False
    ok = cost[r, c] < _UNMATCHED_COST
    peak = involved[r[ok]]
    assoc[peak] = True
    claim = (key[peak] == cols[c[ok]][:, None]) & unf.passed[peak]
    best[peak] = np.argmax(np.where(claim, coherence[peak], -np.inf), axis=1)
    best = np.where(assoc, best, unf.native)
    return unf._replace(best=best, associated=assoc)


def unfold_peaks(v_fast_mps: np.ndarray, fast_peak: np.ndarray, slow_rows: np.ndarray, *,
                 native_vmax_mps: float, unfold_factor: int,
                 wavelength_m: float, slow_slot_period_s: float, threshold_db: float,
                 search_bins: int) -> Unfolding:
    """Steps 3-7 of [TI-VEXT]'s fast/slow algorithm for n fast-set peaks at once.

    Each candidate Vel_fast + 2 k Vmax_fast inside the span looks up the slow map's largest
    value within +/- `search_bins` of its own aliased bin; it survives if that value is within
    `threshold_db` of the fast peak; the survivor with the largest slow value wins (two
    fast peaks may still claim one slow peak: `resolve_claims`). A fast peak without a surviving
    candidate keeps its own aliased velocity, as TI's SRR demo does ("always allow the
    detections to go through even if the disambiguation process fails"), and is flagged
    not `associated`.

    Parameters
    ----------
    v_fast_mps : (n,) float
        Aliased velocity of each fast peak, in [-Vmax_fast, Vmax_fast), m/s.
    fast_peak : (n,) float
        PeakVal_fast, the fast map's power at the peak.
    slow_rows : (n, n_dop) float
        The slow map's Doppler row at each peak's range bin.
    native_vmax_mps : float
        Vmax_fast = lambda / (4 Nt T_f), m/s.
    unfold_factor : int
        Candidates cover +/- unfold_factor x Vmax_fast.
    wavelength_m, slow_slot_period_s : float
        Wavelength, m, and one Tx's slow-time period in the slow set (Nt T_s), s.
    threshold_db : float
        Largest |10 log10(slow peak / fast peak)| of a surviving candidate, dB.
    search_bins : int
        Half-width of the slow-map search window around each candidate's bin.

    Returns
    -------
    Unfolding

    References
    ----------
    .. [1] [TI-VEXT] section 3, steps 3-8; TI mmWave SDK SRR/MRR demo, DSS
       ``disambiguateVel`` (strongest associated slow peak, consumed once taken).
    """
    n, n_dop = slow_rows.shape
    k = np.arange(-(unfold_factor // 2) - 1, unfold_factor // 2 + 2)
    native = int(np.flatnonzero(k == 0)[0])
    cand = v_fast_mps[:, None] + 2 * native_vmax_mps * k[None, :]  # (n, H)
    span = unfold_factor * native_vmax_mps
    valid = (cand >= -span) & (cand < span)
    centre = np.rint(slow_bin_of(cand, wavelength_m, slow_slot_period_s, n_dop)).astype(np.intp)
    cols = (centre[..., None] + np.arange(-search_bins, search_bins + 1)) % n_dop  # (n, H, W)
    window = slow_rows[np.arange(n)[:, None, None], cols]
    at = np.argmax(window, axis=-1)
    slow_peak = np.take_along_axis(window, at[..., None], axis=-1)[..., 0]
    slow_bin = np.take_along_axis(cols, at[..., None], axis=-1)[..., 0]
    ratio_db = 10 * np.log10(np.maximum(slow_peak, 1e-30)
                             / np.maximum(fast_peak, 1e-30)[:, None])
    passed = valid & (np.abs(ratio_db) <= threshold_db)
    associated = passed.any(axis=1)
    best = np.where(associated, np.argmax(np.where(passed, slow_peak, -np.inf), axis=1),
                    native)
    return Unfolding(cand, valid, slow_peak, slow_bin, passed, best, associated, native)


class FastSlowChain(MimoChain):
    """Receive side of `radarsim.MIMO_SCHEMES["fast_slow"]` ([TI-VEXT] section 3)."""

    name = "fast_slow"
    mitigation_in_range_stage = True  # interference: through the range stage only

    def unfold(self, cfg: RadarConfig, maps: FastSlowMaps, hits: RangeDopplerHits,
               proc: ProcessingConfig) -> Unfolding:
        """Steps 2-7 for the fast-set CFAR hits of one frame (`unfold_peaks`, then
        `gate_coherence` and `resolve_claims`)."""
        sch, sets = cfg.scheme, cfg.scheme.chirp_sets(cfg)
        n_dop = sets.n_doppler_bins
        r, d = hits.range_bin, hits.doppler_bin
        d_signed = (d + hits.doppler_offset + n_dop / 2) % n_dop - n_dop / 2
        v_fast = -d_signed / (n_dop * cfg.n_tx * sets.fast_period_s) * cfg.wavelength_m / 2
        unf = unfold_peaks(v_fast, maps.fast_power[r, d], maps.slow_power[r],
                            native_vmax_mps=sch.native_max_velocity_mps(cfg),
                            unfold_factor=sch.unfold_factor, wavelength_m=cfg.wavelength_m,
                            slow_slot_period_s=cfg.n_tx * sets.slow_period_s,
                            threshold_db=proc.velocity.fast_slow_threshold_db,
                            search_bins=proc.velocity.fast_slow_search_bins)
        if r.size == 0:
            return unf
        coherence = self._coherence(cfg, maps, r, d, unf, sets)
        if proc.velocity.fast_slow_min_coherence > 0:
            unf = gate_coherence(unf, coherence, proc.velocity.fast_slow_min_coherence)
        return resolve_claims(unf, r, coherence) if r.size > 1 else unf

    def _coherence(self, cfg: RadarConfig, maps: FastSlowMaps, r: np.ndarray, d: np.ndarray,
                   unf: Unfolding, sets) -> np.ndarray:
        """(n, H) spatial coherence of each candidate: the fast peak's and the claimed slow
        peak's slot samples, each with its set's slot phases removed at the candidate."""
        n, n_h = unf.candidates_mps.shape
        v = unf.candidates_mps.ravel()
        x_f = self._compensated(cfg, np.repeat(maps.fast_virt[r, d], n_h, axis=0), v,
                                sets.fast_period_s)
        x_s = self._compensated(cfg, maps.slow_virt[np.repeat(r, n_h), unf.slow_bin.ravel()],
                                v, sets.slow_period_s)
        num = np.abs(np.sum(np.conj(x_f) * x_s, axis=-1)) ** 2
        den = np.sum(np.abs(x_f) ** 2, axis=-1) * np.sum(np.abs(x_s) ** 2, axis=-1)
        return (num / np.maximum(den, 1e-30)).reshape(n, n_h)

    def process(self, cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> pd.DataFrame:
        sets = cfg.scheme.chirp_sets(cfg)
        maps = fast_slow_maps(cfg, adc, proc)
        hits = noncoherent_hits(maps.fast_power, cfg.n_virtual, proc)  # step 1
        if hits.range_bin.size == 0:
            return empty_cloud()
        unf = self.unfold(cfg, maps, hits, proc)  # steps 2-7
        if not proc.velocity.fast_slow_keep_unassociated:
            keep = unf.associated
            if not keep.any():
                return empty_cloud()
            hits = hits._replace(**{f: getattr(hits, f)[keep] for f in hits._fields
                                    if f != "looks"})
            unf = unf._replace(**{f: getattr(unf, f)[keep] for f in unf._fields
                                  if f != "native"})
        velocity = unf.velocity_mps  # step 8 (unassociated peaks: their aliased velocity)
        virt = self._compensated(cfg, maps.fast_virt[hits.range_bin, hits.doppler_bin],
                                 velocity, sets.fast_period_s)
        virt = compensate(cfg, proc, virt)[:, None, :]  # compRangeBiasAndRxChanPhase; (n, 1, 16)
        az_pow = np.abs(virt @ array_dft(cfg, proc.angle.n_azimuth_bins, "horizontal")) ** 2
        # Doppler bin in the unfolded span: fast-set bins over unfold_factor native spans.
        n_span = cfg.scheme.unfold_factor * sets.n_doppler_bins
        d_true = np.rint(-2 * velocity / cfg.wavelength_m * sets.n_doppler_bins * cfg.n_tx
                         * sets.fast_period_s).astype(int)
        return hypothesis_cloud(cfg, proc, hits, virt, az_pow, np.zeros(velocity.size, int),
                                velocity, d_true % n_span)

    @staticmethod
    def _compensated(cfg: RadarConfig, virt: np.ndarray, velocity_mps: np.ndarray,
                     slot_period_s: float) -> np.ndarray:
        """(n, n_tx x n_rx) slot-major samples with the slot phases removed at `velocity_mps`
        (n,) (`tdma.remove_slot_phase`)."""
        slots = virt.reshape(virt.shape[0], cfg.n_tx, cfg.n_rx)
        return remove_slot_phase(slots, velocity_mps, cfg.wavelength_m,
                                 slot_period_s).reshape(virt.shape[0], -1)

    def detection_map(self, cfg: RadarConfig, adc: np.ndarray,
                      proc: ProcessingConfig) -> DetectionMap:
        return DetectionMap(fast_slow_maps(cfg, adc, proc).fast_power, cfg.n_virtual, 1)

    def doppler_azimuth(self, cfg: RadarConfig, adc: np.ndarray, range_bin: int,
                        proc: ProcessingConfig) -> DopplerAzimuth:
        """The fast set's per-slot spectrum, each bin compensated at its own native-span
        velocity, then the azimuth DFT (as TDMA's)."""
        sets = cfg.scheme.chirp_sets(cfg)
        virt = fast_slow_maps(cfg, adc, proc).fast_virt[range_bin]  # (D, S*R)
        n_dop = virt.shape[0]
        d_signed = (np.arange(n_dop) + n_dop / 2) % n_dop - n_dop / 2
        vel = -d_signed / (n_dop * cfg.n_tx * sets.fast_period_s) * cfg.wavelength_m / 2
        virt = compensate(cfg, proc, self._compensated(cfg, virt, vel, sets.fast_period_s))
        power = np.abs(virt @ array_dft(cfg, proc.angle.n_azimuth_bins, "horizontal")) ** 2
        return DopplerAzimuth(vel, power)

    def range_doppler_power(self, cfg: RadarConfig, adc: np.ndarray,
                            proc: ProcessingConfig) -> np.ndarray:
        return fast_slow_maps(cfg, adc, proc).fast_power


register_chain(FastSlowChain())
