"""Repair of the ADC samples the interference statistics flag: the chip's zeroing and better
methods, as subclasses of `RepairMethod` in one registry (`MITIGATIONS`, chosen by
``ProcessingConfig.interference.repair``): each method repairs by itself, nothing looks at its name.

The chip (TI SWRA725 sec. 3.3, the DDM demo's RangeProc) sets the flagged samples, widened by
its hysteresis, to zero. Zeroing removes the burst but also a piece of every echo of that chirp:
the chirps hit by a burst carry every echo with less amplitude (and, off-bin, a slightly turned
phase), a slow-time modulation that spreads each strong echo over Doppler, where CFAR finds
new peaks (ghost rate 0.003 -> 0.107 on the head-on interference case). The methods:

``zero``
    The chip: flagged samples and `hysteresis` neighbours set to 0 (the model of the chip).
``zero_compensated``
    The same zeroing, then each repaired chirp scaled by sum(w) / sum(w over the kept samples)
    (w the range window): an echo's range-FFT peak keeps its clean amplitude, so the slow-time
    amplitude modulation is gone to first order.
``windowed_zero``
    The demo's windowed zero-out: the zeroed run's edges taper over 5 samples (samples 2-6 of
    the 16-point Hann the DPC programs, ``hwaInterfMitigWindow``) instead of a step, which
    narrows the mask's spectrum (the range leakage of what is left).
``interpolate``
    The masked samples replaced by the straight line between the kept samples on either side
    (good for echoes whose beat period is long against the gap).
``ar``
    The masked samples reconstructed by linear prediction: an autoregressive model of order
    `ar_order` per Rx, fitted by Burg's method on the kept samples of the repaired chirps (the
    echoes are the same tones in every chirp of an Rx: only their phases change), predicts each
    gap forward from its left and backward from its right; the two are cross-faded. A sum of
    fewer than ar_order / 2 real tones is reconstructed exactly; noise is not (the gap is
    filled with the echoes only).
``lowrank``
    The masked samples predicted from the chirp's kept samples by the frame's fast-time
    signal subspace (the strongest components of the chirps no burst hit: every echo is the
    same tone in every chirp), linear MMSE, the Rx of a chirp sharing one mask that grows
    where the fit's residual shows the burst (`pipeline.interference.lowrank`). Exact for any
    echo the subspace holds, off-grid tones and range-extended ones (a guard rail) alike.

Every method but the chip's first closes the gaps of up to `close_gap_samples` between the
flagged samples of a chirp: an interfering chirp sweeps through the IF band, so its burst is
fastest (largest |dx|) at the band edges and slowest near 0 Hz, where the difference statistic
misses it (duration of the burst 2 B_IF / |S_v - S_i|, design.md 6).

References
----------
.. [1] TI SWRA725, "Interference Mitigation for AWR294x" (2021), section 3.3.
.. [2] J. Bechter, C. Waldschmidt, "Automotive radar interference mitigation by reconstruction
       and cancellation of interference component", IEEE ICMIM 2015 (zeroing and its
       side effects); M. Toth et al., "Interference mitigation for automotive FMCW radar
       with Burg-based autoregressive signal reconstruction", IEEE ICASSP 2018 (AR
       reconstruction).
.. [3] S. M. Kay, Modern Spectral Estimation, Prentice Hall 1988, ch. 7 (linear prediction,
       covariance method).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from core.errors import BadInput
from core.registry import Registry
from radarsim.chips import MAX_CHIP_ADC_SAMPLES

from .fills import ar_fill, cancel_tones, linear_fill, taper_gain, tone_frequencies
from .lowrank import FastTimeBasis, burst_fill, fast_time_basis
from .masks import (
    FrameRows,
    close_gaps,
    reference_rows,
    widen,
)

__all__ = ["RepairMethod", "ZeroRepair", "TaperRepair", "InterpolateRepair", "ArRepair",
           "LowrankRepair", "MITIGATIONS", "get_mitigation", "repair", "CLOSE_GAP_SAMPLES",
           "EXTEND_SAMPLES"]


#: Upper limit of each method parameter, and why (beyond it: minutes per frame, an overflow).
_LIMITS = {**dict.fromkeys(("close_gap_samples", "extend_samples", "taper_samples",
                            "grow_reach_samples"), (MAX_CHIP_ADC_SAMPLES, "samples per chirp")),
           "ar_order": (512, "half the samples of the longest shipped chirp"),
           "cancel_tones": (64, "echoes per chirp"), "rank_max": (256, "fast-time components"),
           "rank_snr_gate_db": (150.0, "96 dB of 16-bit range + 48 dB of row gain"),
           "grow_sigma": (100.0, "noise standard deviations")}


def _check_counts(obj, names: tuple[str, ...]) -> None:
    for f in names:
        v = getattr(obj, f)
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise BadInput(f"{f}={v!r} must be an integer >= 0")
        _check_limit(f, v)


def _check_limit(name: str, value) -> None:
    """`_LIMITS`: an AR order of 10**6 ran for minutes, a gate of 1e300 dB overflowed."""
    hi, why = _LIMITS[name]
    if value > hi:
        raise BadInput(f"{name}={value!r} exceeds {hi:g} ({why})")


@dataclass(frozen=True, kw_only=True, slots=True)
class RepairMethod:
    """One repair method (see the module docstring): how it masks, then `fill`, the hook each
    subclass fills the masked samples with.

    Parameters
    ----------
    name : str
    description : str
    compensate : bool
        Scale each repaired chirp by sum(w) / sum(w x kept fraction) (`kept_weight`).
    close_gap_samples : int
        Close gaps of up to this many samples between flagged samples (0: the chip's flags).
    extend_samples : int
        Samples masked beyond the chip's hysteresis on each side of a (closed) run: the
        burst's rising and falling edges under the IF filter, which no statistic flags.
    cancel_tones : int
        Before the fill, the `cancel_tones` strongest echoes of each Rx (beat frequencies
        from the repaired rows' kept samples, refined between FFT bins) are fitted per chirp
        on the kept samples (least squares), subtracted over the whole chirp and added back
        after the fill: a pure tone is continued exactly across the gap, and the fill only
        has to predict the weak rest.
    recentre : bool
        Re-estimate the chirp's DC from the kept samples before the repair: the chip's DC
        estimate is the mean of the whole chirp, burst included, and the offset it leaves in
        the repaired chirps only is a slow-time modulation at range bin 0-1 (ghosts at a few
        metres over every Doppler bin).
    """

    #: The method leaves each repaired row's mean to the caller's window product
    #: (`repair(remove_mean=False)`; `pipeline.interference.rows.repaired_rows`).
    centres_rows: ClassVar[bool] = False

    name: str
    description: str
    compensate: bool = False
    close_gap_samples: int = 0
    extend_samples: int = 0
    recentre: bool = False
    cancel_tones: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.recentre, bool) or not isinstance(self.compensate, bool):
            raise BadInput(f"recentre={self.recentre!r} and compensate="
                           f"{self.compensate!r} must be true or false")
        _check_counts(self, ("close_gap_samples", "extend_samples", "cancel_tones"))

    def mask(self, flags: np.ndarray, hysteresis: int) -> np.ndarray:
        """(R, n) bool of the samples to repair: the flags closed over `close_gap_samples`,
        then widened by `hysteresis` + `extend_samples`."""
        return widen(close_gaps(flags, self.close_gap_samples), hysteresis + self.extend_samples)

    def fill(self, x: np.ndarray, mask: np.ndarray, groups: np.ndarray | None) -> None:
        """Fill the masked samples of rows `x` (R, n) in place; `groups` (R,) int or None:
        rows sharing one model (the Rx)."""
        raise NotImplementedError

    def kept_weight(self, mask: np.ndarray, w: np.ndarray) -> np.ndarray | float:
        """Window weight left in each repaired row, sum over n of w x (what the fill keeps of
        an echo) (the compensation's denominator); a fill that restores the echo: sum(w)."""
        return w.sum()

    def repair(self, x: np.ndarray, flags: np.ndarray, window_: np.ndarray, hysteresis: int,
               groups: np.ndarray | None = None, frame: FrameRows | None = None,
               remove_mean: bool = True) -> np.ndarray:
        """Repair flagged rows of DC-removed samples in place and return them (`repair`)."""
        mask = self.mask(flags, hysteresis)
        if groups is None and frame is not None:
            groups = frame.rows % frame.n_rx
        if self.recentre:
            kept = ~mask
            n_kept = np.maximum(kept.sum(-1, keepdims=True), 1)
            x -= (np.where(kept, x, 0).sum(-1, keepdims=True) / n_kept).astype(x.dtype)
        tones = None
        if self.cancel_tones:
            g = np.zeros(len(x), dtype=np.intp) if groups is None else np.asarray(groups)
            freqs = tone_frequencies(x, mask, g, self.cancel_tones)
            tones = cancel_tones(x, mask, freqs, g)
            x -= tones
        self.fill(x, mask, groups)
        if tones is not None:
            x += tones
        if self.compensate:
            w = window_.astype(np.float64)
            kept = self.kept_weight(mask, w)
            x *= (w.sum() / np.maximum(kept, 1e-3 * w.sum())).astype(np.float32)[:, None]
        return x


@dataclass(frozen=True, kw_only=True, slots=True)
class ZeroRepair(RepairMethod):
    """The masked samples set to 0 (the chip's zeroing)."""

    def fill(self, x: np.ndarray, mask: np.ndarray, groups: np.ndarray | None) -> None:
        x[mask] = 0

    def kept_weight(self, mask: np.ndarray, w: np.ndarray) -> np.ndarray:
        return (~mask) @ w


@dataclass(frozen=True, kw_only=True, slots=True)
class TaperRepair(RepairMethod):
    """The masked samples zeroed, each run's edges tapered over `taper_samples` samples of a
    Hann window (`fills.taper_gain`)."""

    taper_samples: int = 5

    def __post_init__(self) -> None:
        RepairMethod.__post_init__(self)
        _check_counts(self, ("taper_samples",))

    def fill(self, x: np.ndarray, mask: np.ndarray, groups: np.ndarray | None) -> None:
        x *= taper_gain(mask, self.taper_samples)

    def kept_weight(self, mask: np.ndarray, w: np.ndarray) -> np.ndarray:
        return taper_gain(mask, self.taper_samples) @ w


@dataclass(frozen=True, kw_only=True, slots=True)
class InterpolateRepair(RepairMethod):
    """The masked samples replaced by the straight line between their kept neighbours."""

    def fill(self, x: np.ndarray, mask: np.ndarray, groups: np.ndarray | None) -> None:
        x[...] = linear_fill(x, mask)


@dataclass(frozen=True, kw_only=True, slots=True)
class ArRepair(RepairMethod):
    """The masked samples predicted by a Burg AR model of order `ar_order` per row group (the
    Rx), forward and backward, cross-faded (`fills.ar_fill`)."""

    ar_order: int = 64

    def __post_init__(self) -> None:
        RepairMethod.__post_init__(self)
        _check_counts(self, ("ar_order",))

    def fill(self, x: np.ndarray, mask: np.ndarray, groups: np.ndarray | None) -> None:
        x[...] = ar_fill(x, mask, np.zeros(len(x), dtype=np.intp) if groups is None
                         else np.asarray(groups), self.ar_order)


@dataclass(frozen=True, kw_only=True, slots=True)
class LowrankRepair(RepairMethod):
    """The masked samples predicted from the chirp's kept samples by the frame's fast-time
    signal subspace (`pipeline.interference.lowrank`). It ignores `recentre`: the constant
    column of its model estimates the offset jointly with the echoes (the mean of the kept
    samples is biased by a low beat frequency's partial periods), and each repaired row's mean
    is removed.

    Parameters
    ----------
    rank_max : int
        At most this many fast-time components (besides the constant).
    rank_snr_gate_db : float
        A component is kept if its energy per row exceeds the noise's by this much.
    grow_sigma : float
        Kept samples near the mask whose residual from the fit exceeds this many noise
        standard deviations are masked too (0: never).
    grow_reach_samples : int
        How far from the mask a sample may be grown.
    """

    centres_rows: ClassVar[bool] = True

    rank_max: int = 24
    rank_snr_gate_db: float = 10.0
    grow_sigma: float = 0.0
    grow_reach_samples: int = 32

    def __post_init__(self) -> None:
        for f in ("rank_snr_gate_db", "grow_sigma"):
            v = getattr(self, f)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) \
                    or v < 0:
                raise BadInput(f"{f}={v!r} must be a finite number >= 0")
            _check_limit(f, v)
        RepairMethod.__post_init__(self)
        _check_counts(self, ("rank_max", "grow_reach_samples"))

    def repair(self, x: np.ndarray, flags: np.ndarray, window_: np.ndarray, hysteresis: int,
               groups: np.ndarray | None = None, frame: FrameRows | None = None,
               remove_mean: bool = True) -> np.ndarray:
        """`RepairMethod.repair`: the frame's unflagged rows give the basis, the rows of one
        chirp of `frame` share one mask (without a frame: the repaired rows, each row its
        own mask)."""
        if not len(x):
            return x
        basis = self.basis_of(reference_rows(x, frame, lambda: self.mask(flags, hysteresis)))
        bursts = np.arange(len(x)) if frame is None else frame.rows // frame.n_rx
        burst_fill(x, flags, bursts, basis, self.close_gap_samples,
                   hysteresis + self.extend_samples, self.grow_sigma,
                   self.grow_reach_samples).run_all(remove_mean)
        return x

    def basis_of(self, ref: np.ndarray) -> FastTimeBasis:
        """The basis of reference rows `ref` (N, n)."""
        return fast_time_basis(ref, self.rank_max, 10 ** (self.rank_snr_gate_db / 10))


def repair(x: np.ndarray, flags: np.ndarray, window_: np.ndarray, hysteresis: int,
           method: RepairMethod, groups: np.ndarray | None = None,
           frame: FrameRows | None = None, remove_mean: bool = True) -> np.ndarray:
    """Repair flagged rows of DC-removed samples in place and return them.

    Parameters
    ----------
    x : (R, n) float32 (complex64 for I/Q)
        The flagged chirp x Rx rows, DC removed, before the range window.
    flags : (R, n) bool
        Interference indicator bits (before hysteresis).
    window_ : (n,) float
        The range window (for the gain compensation).
    hysteresis : int
        The chip's hysteresis order, samples.
    method : RepairMethod
    groups : (R,) int, optional
        Row group (the Rx) whose rows share one AR model (default: the Rx of `frame`'s rows,
        else one group).
    frame : FrameRows, optional
        The frame the rows come from: "lowrank" learns the echoes from its unflagged rows and
        unites the masks of the rows of one chirp (without it: from the repaired rows, each
        row its own mask).
    remove_mean : bool
        A method with `centres_rows` removes each repaired row's mean (its model's constant
        column takes the offset); False leaves that to the caller (``x - x.mean(axis=-1,
        keepdims=True)`` gives the same values). The other methods ignore it.

    Returns
    -------
    (R, n) same dtype as x
    """
    return method.repair(x, flags, window_, hysteresis, groups, frame, remove_mean)


#: Gaps closed between flagged samples by the methods that improve on the chip, samples: an
#: interfering chirp's burst lasts 2 B_IF / |S_v - S_i| (design.md 6), 1.6 us = 48 samples at
#: 30 Msps for the head-on case's 30 MHz/us front radar, and its slow middle is where the
#: difference statistic misses it.
CLOSE_GAP_SAMPLES = 48
#: Extra samples masked on each side beyond the chip's hysteresis: the burst's edges under
#: the IF filter's response (about 10 samples on the head-on case's bursts, whose flags sit
#: only where the sweep is fastest).
EXTEND_SAMPLES = 12

#: Repair methods by name (``ProcessingConfig.interference.repair``).
MITIGATIONS: Registry[RepairMethod] = Registry(
    "interference mitigation", field="intf_mitigation", kind=RepairMethod).register_all((
    ZeroRepair(name="zero", description="the chip: flagged samples and the hysteresis "
               "zeroed (SWRA725 3.3)"),
    ZeroRepair(name="zero_compensated", description="zeroed, the chirp's gain restored by "
               "sum(w) / sum(w kept)", compensate=True, close_gap_samples=CLOSE_GAP_SAMPLES,
               extend_samples=EXTEND_SAMPLES, recentre=True),
    TaperRepair(name="windowed_zero", description="zeroed with 5-sample Hann edges (the "
                "demo's windowed zero-out)", close_gap_samples=CLOSE_GAP_SAMPLES,
                extend_samples=EXTEND_SAMPLES, recentre=True),
    InterpolateRepair(name="interpolate", description="masked samples linearly interpolated",
                      close_gap_samples=CLOSE_GAP_SAMPLES, extend_samples=EXTEND_SAMPLES,
                      recentre=True),
    ArRepair(name="ar", description="the 4 strongest echoes per Rx fitted per chirp and "
             "continued across the gap, the rest predicted by a per-Rx Burg AR(64) model "
             "forward and backward, cross-faded", ar_order=64, cancel_tones=4,
             close_gap_samples=CLOSE_GAP_SAMPLES, extend_samples=EXTEND_SAMPLES, recentre=True),
    LowrankRepair(name="lowrank", description="the masked samples of each chirp predicted from "
                  "its kept ones by the frame's fast-time signal subspace (up to 24 components "
                  "of the unhit chirps, LMMSE), the Rx of a chirp sharing one mask, grown where "
                  "the fit's residual shows the burst", close_gap_samples=CLOSE_GAP_SAMPLES,
                  extend_samples=0, grow_sigma=5.0),
))


def get_mitigation(name: str) -> RepairMethod:
    """The registered method.

    Raises
    ------
    ValueError
        Unknown name, with the known ones.
    """
    return MITIGATIONS.lookup(name)
