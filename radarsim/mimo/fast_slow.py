"""Fast/slow chirp velocity unfolding ([TI-VEXT] section 3, figure 5): the transmit side.

One frame holds two chirp sets of equal chirp count and different chirp period, a fast set at
T_f and a slow set at T_s = r T_f, each a TDMA cycle of the transmitters (`tx_order`). A
target's velocity aliases differently in the two sets (native spans 2 V_f and 2 V_s with
V = lambda / (4 Nt T)); the receiver (`pipeline.mimo.fast_slow`) unfolds each fast-set peak
into candidates v_f + 2 k V_f and keeps the candidate whose own aliased bin in the slow map
holds a matching peak.

The config's `chirp_period_s` (and `idle_time_s`) is the MEAN chirp of the frame, so
`frame_time_s` = n_chirps x chirp_period_s still holds: T_f = 2 T / (1 + r), T_s = r T_f, the
ramp is shared and the two sets differ in their idle time only, as TI's SRR profiles do
([TI-VEXT] table 2: idle 3 and 14.8 us on a 56 us ramp, T_s / T_f = 70.8 / 59 = 6 / 5).

Why the registered ratio unfolds +/-40.9 m/s: with T_s / T_f = q / p in lowest terms the pair
of aliases (v mod 2 V_f, v mod 2 V_s) is unique over p fast spans (2 V_f = q u, 2 V_s = p u:
lcm = p q u = p 2 V_f, Chinese remainder theorem), so `unfold_factor` must stay below p + 1;
any two candidates d fast spans apart land d r n_dop (mod n_dop) slow bins apart, which must
be at least one Doppler resolution cell. The R79 preset keeps 768 chirps of mean period
23.81 us (so the R79 frame time), r = 6 / 5 (TI's SRR ratio): T_f = 21.645 us (idle 2.835 us),
T_s = 25.975 us (idle 7.165 us), V_f = 11.24 m/s, and unfold_factor = 4 spans +/-44.97 m/s
with candidates at least 19.2 of the 96 slow Doppler bins apart.

References
----------
.. [1] TI, "AWR1642 velocity disambiguation" [TI-VEXT], section 3, figure 5, table 2 and the
   eight-step algorithm; TI TIDEP-0092 (SRR reference design: 59 / 70.8 us chirps, 3 dB
   association threshold, +/-2 bins, 3x native Vmax).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from core.errors import BadInput

from .schemes import ChirpTiming, SlowTimeLayout, TdmaScheme, TransmitCode, register_scheme

if TYPE_CHECKING:
    from ..radar_config import RadarConfig

__all__ = ["FastSlowScheme", "ChirpSets", "hypothesis_separation_bins"]


class ChirpSets(NamedTuple):
    """The two chirp sets of a fast/slow frame.

    Attributes
    ----------
    fast, slow : slice
        Chirps of each set in the frame (contiguous blocks, [TI-VEXT] figure 5).
    fast_period_s, slow_period_s : float
        Chirp period of each set, s.
    n_doppler_bins : int
        Doppler bins per Tx in each set (chirps per set / n_tx).
    """

    fast: slice
    slow: slice
    fast_period_s: float
    slow_period_s: float
    n_doppler_bins: int


def hypothesis_separation_bins(ratio: float, n_doppler_bins: int, unfold_factor: int) -> float:
    """Smallest circular distance, in slow-set Doppler bins, between the slow-map positions of
    two unfolding candidates inside the span.

    Candidates d fast spans apart (d = 1 .. unfold_factor - 1) differ by 2 d V_f in velocity,
    i.e. by d r n_dop slow bins (2 V_f / 2 V_s = r = T_s / T_f), taken modulo n_dop.

    Parameters
    ----------
    ratio : float
        T_s / T_f.
    n_doppler_bins : int
        Doppler bins per Tx in the slow set.
    unfold_factor : int
        Fast spans the unfolding covers (span +/- unfold_factor x V_f).

    Returns
    -------
    float
        Bins; inf for unfold_factor = 1 (nothing to tell apart).

    Examples
    --------
    >>> round(hypothesis_separation_bins(1.2, 96, 4), 6)
    19.2
    >>> hypothesis_separation_bins(1.5, 96, 4)  # two spans apart: 2 x 1.5 x 96 = 3 x 96
    0.0
    """
    d = np.arange(1, unfold_factor)
    if d.size == 0:
        return math.inf
    off = np.mod(d * ratio * n_doppler_bins, n_doppler_bins)
    return float(np.min(np.minimum(off, n_doppler_bins - off)))


@dataclass(frozen=True)
class FastSlowScheme(TdmaScheme):
    """Two TDMA chirp sets of periods T_f < T_s in one frame ([TI-VEXT] section 3).

    Attributes
    ----------
    slow_period_ratio : float
        T_s / T_f, > 1 (TI's SRR: 70.8 / 59 = 1.2).
    unfold_factor : int
        Native fast-set spans the unfolding covers: the scheme reports velocities in
        +/- unfold_factor x V_f (TI's SRR: 3, "3x native Vmax").
    slow_first : bool
        Interleaving of the two sets: False fires the fast set first ([TI-VEXT] figure 5).

    Both sets fire every active Tx in `tx_order`, one per chirp (TDMA), n_chirps / 2 chirps
    each: the receiver compares their peak powers, so the sets must carry equal energy.
    """

    slow_period_ratio: float = 1.2
    unfold_factor: int = 4
    slow_first: bool = False

    def __post_init__(self) -> None:
        r = self.slow_period_ratio
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not math.isfinite(r) \
                or not 1 < r <= 4:
            raise BadInput(f"slow_period_ratio={r!r} must be in (1, 4] (T_s / T_f; TI's SRR "
                           "uses 70.8 / 59 = 1.2)")
        u = self.unfold_factor
        if isinstance(u, bool) or not isinstance(u, int) or not 1 <= u <= 16:
            raise BadInput(f"unfold_factor={u!r} must be an integer in 1..16 (native fast "
                           "spans covered)")
        if not isinstance(self.slow_first, bool):
            raise BadInput(f"slow_first={self.slow_first!r} must be true or false")

    # ------------------------------------------------------------------ timing
    def chirp_sets(self, cfg: "RadarConfig") -> ChirpSets:
        """The two sets of `cfg`'s frame: which chirps, which periods."""
        half = cfg.n_chirps // 2
        t_f = 2 * cfg.chirp_period_s / (1 + self.slow_period_ratio)
        first, second = slice(0, half), slice(half, cfg.n_chirps)
        fast, slow = (second, first) if self.slow_first else (first, second)
        return ChirpSets(fast, slow, t_f, self.slow_period_ratio * t_f, half // cfg.n_tx)

    def chirp_timing(self, cfg: "RadarConfig") -> ChirpTiming:
        """Ramp starts: one block of n_chirps / 2 chirps at each period."""
        sets = self.chirp_sets(cfg)
        period = np.empty(cfg.n_chirps)
        period[sets.fast] = sets.fast_period_s
        period[sets.slow] = sets.slow_period_s
        start = np.concatenate([[0.0], np.cumsum(period[:-1])])
        return ChirpTiming(start, start - (start[0] + start[-1]) / 2)

    def idle_times_s(self, cfg: "RadarConfig") -> tuple[float, float]:
        """Idle time of the fast and of the slow chirp, s (the ramp is shared)."""
        sets = self.chirp_sets(cfg)
        return (sets.fast_period_s - cfg.ramp_end_time_s,
                sets.slow_period_s - cfg.ramp_end_time_s)

    # ------------------------------------------------------------------ configuration
    def chirps_per_period(self, cfg: "RadarConfig") -> int:
        return 2 * cfg.n_tx

    def validate(self, cfg: "RadarConfig") -> None:
        """Two equal sets of whole TDMA cycles, a positive fast idle time and candidates that
        land in distinct slow Doppler cells over the whole span.

        Raises
        ------
        ValueError
            Naming the field, its value and the limit.
        """
        if cfg.n_chirps % (2 * cfg.n_tx):
            raise BadInput(f"n_chirps={cfg.n_chirps} must be divisible by 2 x n_tx="
                           f"{2 * cfg.n_tx} for {self.name} (two chirp sets of equal count, "
                           "whole TDMA cycles each: the association compares their peaks)")
        idle_f, _ = self.idle_times_s(cfg)
        if idle_f <= 0:
            raise BadInput(f"idle_time_s={cfg.idle_time_s:g} (mean of the two sets): the fast "
                           f"chirp's idle time 2 T / (1 + slow_period_ratio) - ramp_end_time_s "
                           f"= {idle_f:g} s must be > 0")
        sep = self.candidate_separation_bins(cfg)
        if sep < 1.0:
            raise BadInput(
                f"slow_period_ratio={self.slow_period_ratio:g} makes the unfolding ambiguous "
                f"over unfold_factor={self.unfold_factor} (+/-"
                f"{self.max_unambiguous_velocity_mps(cfg):.4g} m/s): two candidates land "
                f"{sep:.3g} slow Doppler bins apart, below the limit of 1 bin")

    def candidate_separation_bins(self, cfg: "RadarConfig") -> float:
        """Slow-map bins between two unfolding candidates (R79: 19.2)."""
        return hypothesis_separation_bins(self.slow_period_ratio,
                                          self.chirp_sets(cfg).n_doppler_bins,
                                          self.unfold_factor)

    # ------------------------------------------------------------------ transmit side
    def transmit_code(self, cfg: "RadarConfig") -> TransmitCode:
        """Each set a TDMA cycle over `tx_order` (sets hold whole cycles, so the slot of chirp
        c is c mod n_tx in both)."""
        return super().transmit_code(cfg)

    def layout(self, cfg: "RadarConfig") -> SlowTimeLayout:
        return SlowTimeLayout(cfg.n_tx, tuple(cfg.subband_of_tx[t]
                                              for t in range(1, cfg.n_tx + 1)),
                              self.slow_time_period_s(cfg), self.n_doppler_bins(cfg))

    # ------------------------------------------------------------------ promises
    def slow_time_period_s(self, cfg: "RadarConfig") -> float:
        """One Tx's slow-time period in the fast set, n_tx T_f, s."""
        return cfg.n_tx * self.chirp_sets(cfg).fast_period_s

    def native_max_velocity_mps(self, cfg: "RadarConfig") -> float:
        """V_f = lambda / (4 Nt T_f): the fast set's own unambiguous velocity, m/s."""
        return cfg.wavelength_m / (4 * self.slow_time_period_s(cfg))

    def max_unambiguous_velocity_mps(self, cfg: "RadarConfig") -> float:
        """The unfolded span: unfold_factor x V_f, m/s (R79 preset: 44.97)."""
        return self.unfold_factor * self.native_max_velocity_mps(cfg)

    def n_doppler_bins(self, cfg: "RadarConfig") -> int:
        """Doppler bins per Tx in each set (R79: 96)."""
        return cfg.n_chirps // (2 * cfg.n_tx)

    def velocity_failure_step_mps(self, cfg: "RadarConfig") -> float:
        """A wrong candidate is off by a multiple of the fast set's span 2 V_f, m/s."""
        return 2 * self.native_max_velocity_mps(cfg)

    def velocity_resolution_mps(self, cfg: "RadarConfig") -> float:
        """lambda / (2 n_dop Nt T_f): one set's Doppler bin, m/s (R79: 0.234)."""
        return cfg.wavelength_m / (2 * (cfg.n_chirps // 2) * self.chirp_sets(cfg).fast_period_s)

    # ------------------------------------------------------------------ TI CLI
    def to_ti(self, cfg, n_tx_chip):
        """No single ``frameCfg`` loop: two chirp periods need two profiles, which
        `radarsim.ti.to_ti_cfg` writes as an advanced frame of two sub-frames
        (`radarsim.ti.fast_slow`)."""
        raise BadInput(f"mimo={self.name!r} has no TI mmWave SDK CLI form as one frameCfg "
                       "loop (two chirp periods: radarsim.ti.to_ti_cfg writes an advanced "
                       "frame of two sub-frames)")

    def from_ti(self, tx_masks, n_tx, tx_mask, ddm_order):
        """A one-profile loop is never a fast/slow frame (`radarsim.ti.fast_slow.pair_radar`
        reads the two-sub-frame form)."""
        return None


register_scheme(FastSlowScheme(
    "fast_slow", "fast/slow chirp unfolding ([TI-VEXT] sec. 3): two TDMA chirp sets of periods "
                 "T_f and 1.2 T_f, fast-set peaks unfolded by their slow-set match"))
