"""Repair of the ADC samples the interference statistics flag: the chip's zeroing and better
methods, as a registry (`MITIGATIONS`, chosen by ``ProcessingConfig.intf_mitigation``).

The chip (TI SWRA725 sec. 3.3, the DDM demo's RangeProc) sets the flagged samples, widened by
its hysteresis, to zero. Zeroing removes the burst but also a piece of every echo of that chirp:
the chirps hit by a burst carry every echo with less amplitude (and, off-bin, a slightly turned
phase), a slow-time modulation that spreads each strong echo over Doppler, where CFAR finds
new peaks (issue 21: ghost rate 0.003 -> 0.107 on the head-on interference case). The methods:

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
    where the fit's residual shows the burst (`pipeline.interference_lowrank`). Exact for any
    echo the subspace holds, off-grid tones and range-extended ones (a guard rail) alike.

Every method but the chip's first closes the gaps of up to `close_gap_samples` between the
flagged samples of a chirp: an interfering chirp sweeps through the IF band, so its burst is
fastest (largest |dx|) at the band edges and slowest near 0 Hz, where the difference statistic
misses it (duration of the burst 2 B_IF / |S_v - S_i|, DESIGN 6).

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
from typing import NamedTuple

import numpy as np
import scipy.signal

from core.errors import BadInput
from core.registry import Registry

from .interference_lowrank import (
    BurstFill,
    FastTimeBasis,
    GramOperands,
    burst_fill,
    fast_time_basis,
)

__all__ = ["Mitigation", "MITIGATIONS", "get_mitigation", "widen", "close_gaps", "repair",
           "lowrank_bursts", "frame_basis", "frame_has_reference", "FrameRows",
           "CLOSE_GAP_SAMPLES", "EXTEND_SAMPLES", "REFERENCE_ROWS"]


def widen(flags: np.ndarray, hysteresis: int) -> np.ndarray:
    """(R, n) bool: sample i is masked iff a flag lies in [i - hysteresis, i + hysteresis] of
    its own row (the chip's hysteresis)."""
    if hysteresis <= 0 or not flags.any():
        return flags.copy()
    n = flags.shape[-1]
    c = np.cumsum(np.pad(flags, ((0, 0), (hysteresis + 1, hysteresis)), constant_values=False),
                  axis=-1, dtype=np.int32)
    return (c[:, 2 * hysteresis + 1:] - c[:, :n]) > 0


def close_gaps(mask: np.ndarray, max_gap: int) -> np.ndarray:
    """(R, n) bool: `mask` with every run of unmasked samples of length <= `max_gap` that lies
    between two masked samples of the same row masked too (a morphological closing)."""
    if max_gap <= 0 or not mask.any():
        return mask.copy()
    n = mask.shape[-1]
    idx = np.broadcast_to(np.arange(n), mask.shape)
    last = np.maximum.accumulate(np.where(mask, idx, -n - max_gap - 2), axis=-1)
    nxt = np.minimum.accumulate(np.where(mask, idx, 2 * n + max_gap + 2)[:, ::-1],
                                axis=-1)[:, ::-1]
    return mask | ((nxt - last - 1 <= max_gap) & (last >= 0) & (nxt < n))


#: What a method can put into the masked samples (`Mitigation.fill`).
FILLS = ("zero", "taper", "linear", "ar", "lowrank")


class FrameRows(NamedTuple):
    """Where the repaired rows sit in their frame (for the methods that learn from the frame)."""

    samples: np.ndarray   # (N, n) every chirp x Rx row of the frame, as sampled (any offset)
    rows: np.ndarray      # (R,) increasing indices of the repaired rows in `samples`
    n_rx: int             # rows per chirp: row i is chirp i // n_rx, Rx i % n_rx


#: Unflagged rows of the frame (evenly spread) the "lowrank" subspace is estimated from...
REFERENCE_ROWS = 256
#: ... if the frame has at least this many (else the repaired rows, their gaps zeroed).
MIN_REFERENCE_ROWS = 64


def _spread(idx: np.ndarray) -> np.ndarray:
    """Up to REFERENCE_ROWS of the indices `idx`, evenly spread."""
    return idx[np.linspace(0, len(idx) - 1, min(REFERENCE_ROWS, len(idx))).astype(np.intp)]


def _frame_reference(frame: FrameRows, dtype: np.dtype) -> np.ndarray | None:
    """(N, n) up to REFERENCE_ROWS unflagged rows of the frame, evenly spread, as `dtype`;
    None if it has fewer than MIN_REFERENCE_ROWS."""
    clean = np.ones(len(frame.samples), dtype=bool)
    clean[frame.rows] = False
    idx = np.flatnonzero(clean)
    if len(idx) < MIN_REFERENCE_ROWS:
        return None
    return frame.samples[_spread(idx)].astype(dtype, copy=False)


def _reference(x: np.ndarray, frame: FrameRows | None, mask) -> np.ndarray:
    """(N, n) rows without interference: up to REFERENCE_ROWS unflagged rows of the frame,
    evenly spread; without a frame (or with too few clean rows), the repaired rows with their
    masked samples (`mask()`, (R, n) bool) zeroed."""
    ref = None if frame is None else _frame_reference(frame, x.dtype)
    if ref is not None:
        return ref
    idx = _spread(np.arange(len(x)))
    return np.where(mask()[idx], 0, x[idx])


@dataclass(frozen=True, kw_only=True, slots=True)
class Mitigation:
    """One repair method (see the module docstring).

    Parameters
    ----------
    name : str
    description : str
    fill : str
        "zero", "taper", "linear", "ar" or "lowrank": what goes into the masked samples.
    compensate : bool
        Scale each repaired chirp by sum(w) / sum(w x kept fraction).
    close_gap_samples : int
        Close gaps of up to this many samples between flagged samples (0: the chip's flags).
    extend_samples : int
        Samples masked beyond the chip's hysteresis on each side of a (closed) run: the
        burst's rising and falling edges under the IF filter, which no statistic flags.
    ar_order : int
        Order of the linear predictor of "ar".
    taper_samples : int
        Length of each edge taper of "taper".
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
        metres over every Doppler bin). "lowrank" ignores it: the constant column of its model
        estimates the offset jointly with the echoes (the mean of the kept samples is biased
        by a low beat frequency's partial periods), and each repaired row's mean is removed.
    rank_max : int
        "lowrank": at most this many fast-time components (besides the constant).
    rank_snr_gate_db : float
        "lowrank": a component is kept if its energy per row exceeds the noise's by this much.
    grow_sigma : float
        "lowrank": kept samples near the mask whose residual from the fit exceeds this many
        noise standard deviations are masked too (0: never).
    grow_reach_samples : int
        "lowrank": how far from the mask a sample may be grown.
    """

    name: str
    description: str
    fill: str = "zero"
    compensate: bool = False
    close_gap_samples: int = 0
    extend_samples: int = 0
    ar_order: int = 64
    taper_samples: int = 5
    recentre: bool = False
    cancel_tones: int = 0
    rank_max: int = 24
    rank_snr_gate_db: float = 10.0
    grow_sigma: float = 0.0
    grow_reach_samples: int = 32

    def __post_init__(self) -> None:
        if self.fill not in FILLS:
            raise BadInput(f"fill={self.fill!r} is not one of {', '.join(FILLS)}")
        for f in ("rank_snr_gate_db", "grow_sigma"):
            v = getattr(self, f)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) \
                    or v < 0:
                raise BadInput(f"{f}={v!r} must be a finite number >= 0")
        if not isinstance(self.recentre, bool) or not isinstance(self.compensate, bool):
            raise BadInput(f"recentre={self.recentre!r} and compensate="
                           f"{self.compensate!r} must be true or false")
        for f in ("close_gap_samples", "extend_samples", "ar_order", "taper_samples",
                  "cancel_tones", "rank_max", "grow_reach_samples"):
            v = getattr(self, f)
            if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                raise BadInput(f"{f}={v!r} must be an integer >= 0")

    def mask(self, flags: np.ndarray, hysteresis: int) -> np.ndarray:
        """(R, n) bool of the samples to repair: the flags closed over `close_gap_samples`,
        then widened by `hysteresis` + `extend_samples`."""
        return widen(close_gaps(flags, self.close_gap_samples), hysteresis + self.extend_samples)


def _taper_gain(mask: np.ndarray, taper: int) -> np.ndarray:
    """(R, n) float32 gain: 0 on the mask, rising over `taper` samples on each side along
    samples 2 .. taper + 1 of a Hann window (the DPC's 16-point Hann, samples 2-6, for
    taper = 5; 2 (taper + 3) points otherwise)."""
    n_hann = 16 if taper == 5 else 2 * (taper + 3)
    h = scipy.signal.get_window("hann", n_hann, fftbins=False)[2:2 + taper]
    # distance (in samples) of every sample to the nearest masked sample of its row
    n = mask.shape[-1]
    idx = np.broadcast_to(np.arange(n), mask.shape)
    big = 10 * n
    left = idx - np.maximum.accumulate(np.where(mask, idx, -big), axis=-1)
    right = np.minimum.accumulate(np.where(mask, idx, big)[:, ::-1], axis=-1)[:, ::-1] - idx
    d = np.minimum(left, right)  # 0 on the mask
    ramp = np.r_[0.0, h, 1.0]  # d = 0 -> 0, d = 1..taper -> h, beyond -> 1
    return ramp[np.minimum(d, taper + 1)].astype(np.float32)


def _linear_fill(x: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Masked samples replaced by the line between the nearest kept samples of the row (the
    nearest kept one at a row's ends)."""
    n = x.shape[-1]
    idx = np.broadcast_to(np.arange(n), x.shape)
    left = np.maximum.accumulate(np.where(mask, -1, idx), axis=-1)
    right = np.minimum.accumulate(np.where(mask, n, idx)[:, ::-1], axis=-1)[:, ::-1]
    lc, rc = np.clip(left, 0, n - 1), np.clip(right, 0, n - 1)
    xl, xr = np.take_along_axis(x, lc, -1), np.take_along_axis(x, rc, -1)
    xl = np.where(left < 0, xr, xl)
    xr = np.where(right >= n, xl, xr)
    t = np.where((left >= 0) & (right < n), (idx - left) / np.maximum(right - left, 1), 0.0)
    return np.where(mask, xl + (xr - xl) * t, x).astype(x.dtype)


#: Rows per Rx used to fit its predictor (ample: each gives ~n - p error terms per order).
AR_FIT_ROWS = 64


def _ar_coefficients(x: np.ndarray, mask: np.ndarray, groups: np.ndarray,
                     order: int) -> np.ndarray:
    """Burg predictors a (G, order), one per group of rows: x[t] ~ -sum_k a_k x[t-k].

    Burg's method (Kay ch. 7.4) with the reflection coefficient of each order pooled over the
    group's rows and over the error terms whose order + 1 samples are all kept (masked
    samples never enter). Every |k_m| < 1, so the model is minimum phase: stable forward, and
    its conjugate is the backward predictor. The recursion runs over the model order (a
    Levinson update per order), vectorised over rows and samples. The first `AR_FIT_ROWS`
    rows of each group are used.
    """
    n_g = int(groups.max()) + 1
    order_rows = np.argsort(groups, kind="stable")
    g_sorted = groups[order_rows]
    rank = np.arange(len(g_sorted)) - np.searchsorted(g_sorted, g_sorted)
    fit = order_rows[rank < AR_FIT_ROWS]
    g = groups[fit]
    f = x[fit].astype(np.complex128 if np.iscomplexobj(x) else np.float64)
    bk = f.copy()
    valid = ~mask[fit]
    a = np.zeros((n_g, order), dtype=f.dtype)
    cplx = np.iscomplexobj(f)
    for m in range(order):  # model order, not samples
        ff, bb = f[:, 1:], bk[:, :-1]
        v = valid[:, 1:] & valid[:, :-1]
        if cplx:
            num = np.where(v, ff * bb.conj(), 0).sum(-1)
            den = np.where(v, np.abs(ff) ** 2 + np.abs(bb) ** 2, 0).sum(-1)
        else:  # the same numbers without the copies: conj is the identity, |x|**2 is x * x
            num = np.where(v, ff * bb, 0).sum(-1)
            den = np.where(v, ff * ff + bb * bb, 0).sum(-1)
        k = -2 * np.bincount(g, num.real, n_g)
        if cplx:
            k = k - 2j * np.bincount(g, num.imag, n_g)
        d = np.bincount(g, den, n_g)
        k = np.where(d > 0, k / np.where(d > 0, d, 1) * (1 - 1e-9), 0)
        # Levinson: a_j <- a_j + k conj(a_{m-j}), a_m <- k
        prev = a[:, :m].copy()
        a[:, :m] = prev + k[:, None] * prev[:, ::-1].conj()
        a[:, m] = k
        kr = k[g][:, None]
        f, bk = ff + kr * bb, bb + kr.conj() * ff
        valid = v
    return a


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Masked runs: (row, start, end exclusive) of every run of True in each row."""
    d = np.diff(np.pad(mask.astype(np.int8), ((0, 0), (1, 1))), axis=-1)
    r0, s = np.nonzero(d == 1)
    _, e = np.nonzero(d == -1)
    return r0, s, e


def _predict(x: np.ndarray, a: np.ndarray, model: np.ndarray, rows: np.ndarray,
             starts: np.ndarray, length: int) -> np.ndarray:
    """(N, length) forward predictions of rows `rows` (N,) from position `starts` on, gap i
    with the predictor a[model[i]] (a (G, p), one per group): the AR recursion
    y[t] = -sum_k a_k y[t-k] is an all-pole filter (b = [1]) run on zeros from the state the
    p samples before the gap leave. In the DF-II transposed form scipy.signal.lfilter uses,
    that state is z_k = -sum_{j=k+1}^{p} a_j y[k-j] (y[-1] the sample just before the gap).
    One lfilter call per predictor used."""
    p = a.shape[-1]
    past = x[rows[:, None], starts[:, None] - np.arange(1, p + 1)]  # y[-1] .. y[-p]
    hank = np.arange(p)[:, None] + np.arange(p)[None, :]  # coefficient index j - 1 = k + m
    coef = np.where(hank < p, a[:, np.minimum(hank, p - 1)], 0)[model]  # (N, p, p)
    zi = -np.einsum("gkm,gm->gk", coef, past)
    out = np.zeros((len(rows), length), dtype=np.result_type(x.dtype, a.dtype))
    for u in np.unique(model):  # one per Rx model
        sel = np.flatnonzero(model == u)
        out[sel] = scipy.signal.lfilter([1.0], np.r_[1.0, a[u]], out[sel], axis=-1,
                                        zi=zi[sel])[0]
    return out


def _ar_fill(x: np.ndarray, mask: np.ndarray, groups: np.ndarray, order: int) -> np.ndarray:
    """Masked runs reconstructed from the AR predictor of their row's group: forward from the
    left, backward from the right (the conjugate predictor on the time-reversed row, exact for
    Burg's minimum-phase model), linearly cross-faded; a run with no room for p samples on one
    side takes the other."""
    n = x.shape[-1]
    a = _ar_coefficients(x, mask, groups, order)
    rows, s, e = _runs(mask)
    if not rows.size:
        return x
    length = int((e - s).max())
    fwd_ok, bwd_ok = s >= order, e + order <= n
    model = groups[rows]
    fwd = np.zeros((len(rows), length), dtype=np.result_type(x.dtype, a.dtype))
    bwd = np.zeros_like(fwd)
    if fwd_ok.any():
        fwd[fwd_ok] = _predict(x, a, model[fwd_ok], rows[fwd_ok], s[fwd_ok], length)
    if bwd_ok.any():
        xr = x[:, ::-1]
        bwd[bwd_ok] = _predict(xr, a.conj(), model[bwd_ok], rows[bwd_ok], n - e[bwd_ok],
                               length)
    i = np.arange(length)[None, :]
    ln = (e - s)[:, None]
    t = (i + 1) / (ln + 1)  # weight of the backward prediction
    t = np.where(fwd_ok[:, None] & ~bwd_ok[:, None], 0.0, t)
    t = np.where(~fwd_ok[:, None] & bwd_ok[:, None], 1.0, t)
    none = ~fwd_ok & ~bwd_ok
    # the backward prediction of gap sample i is its element ln - 1 - i
    b_idx = np.clip(ln - 1 - i, 0, length - 1)
    val = (1 - t) * fwd + t * np.take_along_axis(bwd, b_idx, axis=-1)
    val[none] = 0
    inside = i < ln
    r_idx = np.broadcast_to(rows[:, None], val.shape)[inside]
    c_idx = (s[:, None] + i)[inside]
    out = x.copy()
    out[r_idx, c_idx] = val[inside].real.astype(x.dtype) if not np.iscomplexobj(x) else \
        val[inside].astype(x.dtype)
    return out


def _tone_frequencies(x: np.ndarray, mask: np.ndarray, groups: np.ndarray, k: int,
                      n_fft: int = 8) -> np.ndarray:
    """(G, k) beat frequencies, cycles per sample, of the k strongest echoes per group: peaks
    of the mean power spectrum of the groups' rows (masked samples zeroed, Hann window,
    zero-padded n_fft times; the full spectrum for I/Q rows), refined by a parabola through
    the log powers."""
    n = x.shape[-1]
    w = np.hanning(n)
    transform = np.fft.fft if np.iscomplexobj(x) else np.fft.rfft  # I/Q rows: both sides
    spec = np.abs(transform(np.where(mask, 0, x) * w, n * n_fft, axis=-1)) ** 2
    n_g = int(groups.max()) + 1
    n_f = spec.shape[-1]
    # sum of each group's rows in row order from 0, as np.add.at does, in one pass
    p = np.bincount((groups[:, None] * n_f + np.arange(n_f)).ravel(), spec.ravel(),
                    n_g * n_f).reshape(n_g, n_f)
    lp = np.log(p + 1e-30)
    peak = np.zeros_like(lp, dtype=bool)
    peak[:, 1:-1] = (lp[:, 1:-1] > lp[:, :-2]) & (lp[:, 1:-1] >= lp[:, 2:])
    score = np.where(peak, lp, -np.inf)
    idx = np.argsort(score, axis=-1)[:, ::-1][:, :k]  # (G, k)
    ym, y0, yp = (np.take_along_axis(lp, np.clip(idx + d, 0, lp.shape[-1] - 1), -1)
                  for d in (-1, 0, 1))
    off = 0.5 * (ym - yp) / np.where(ym - 2 * y0 + yp == 0, -1e-12, ym - 2 * y0 + yp)
    return (idx + np.clip(off, -0.5, 0.5)) / (n * n_fft)


def _cancel(x: np.ndarray, mask: np.ndarray, freqs: np.ndarray,
            groups: np.ndarray) -> np.ndarray:
    """(R, n) per-row least-squares fit, on the kept samples, of the tones of the row's
    group's frequencies (G, k) (cosine and sine, real rows; complex exponentials, I/Q rows;
    `groups` (R,) the row's group), evaluated over the whole row."""
    n = x.shape[-1]
    t = np.arange(n)
    ph = 2 * np.pi * freqs[:, :, None] * t  # (G, k, n): the bases, once per group
    if np.iscomplexobj(x):
        basis = np.exp(1j * ph)[groups]
        bkc = (basis * (~mask)[:, None, :]).conj()
    else:
        basis = np.concatenate([np.cos(ph), np.sin(ph)], axis=1)[groups]  # (R, 2k, n)
        bkc = basis * (~mask)[:, None, :]  # real: its own conjugate
    gram = np.einsum("rin,rjn->rij", bkc, basis)
    rhs = np.einsum("rin,rn->ri", bkc, x.astype(basis.dtype))
    load = 1e-9 * np.abs(np.trace(gram, axis1=1, axis2=2))[:, None, None] + 1e-30
    coef = np.linalg.solve(gram + load * np.eye(gram.shape[-1]), rhs[..., None])[..., 0]
    model = np.einsum("ri,rin->rn", coef, basis)
    return (model if np.iscomplexobj(x) else model.real).astype(x.dtype)


def repair(x: np.ndarray, flags: np.ndarray, window_: np.ndarray, hysteresis: int,
           method: Mitigation, groups: np.ndarray | None = None,
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
    method : Mitigation
    groups : (R,) int, optional
        Row group (the Rx) whose rows share one AR model (default: the Rx of `frame`'s rows,
        else one group).
    frame : FrameRows, optional
        The frame the rows come from: "lowrank" learns the echoes from its unflagged rows and
        unites the masks of the rows of one chirp (without it: from the repaired rows, each
        row its own mask).
    remove_mean : bool
        "lowrank" removes each repaired row's mean (its model's constant column takes the
        offset); False leaves that to the caller (``x - x.mean(axis=-1, keepdims=True)`` gives
        the same values). The other methods ignore it.

    Returns
    -------
    (R, n) same dtype as x
    """
    if method.fill == "lowrank":
        return _lowrank(x, flags, hysteresis, method, frame, remove_mean)
    mask = method.mask(flags, hysteresis)
    if groups is None and frame is not None:
        groups = frame.rows % frame.n_rx
    if method.recentre:
        kept = ~mask
        n_kept = np.maximum(kept.sum(-1, keepdims=True), 1)
        x -= (np.where(kept, x, 0).sum(-1, keepdims=True) / n_kept).astype(x.dtype)
    tones = None
    if method.cancel_tones:
        g = np.zeros(len(x), dtype=np.intp) if groups is None else np.asarray(groups)
        freqs = _tone_frequencies(x, mask, g, method.cancel_tones)
        tones = _cancel(x, mask, freqs, g)
        x -= tones
    if method.fill == "zero":
        x[mask] = 0
    elif method.fill == "taper":
        x *= _taper_gain(mask, method.taper_samples)
    elif method.fill == "linear":
        x[...] = _linear_fill(x, mask)
    else:
        x[...] = _ar_fill(x, mask, np.zeros(len(x), dtype=np.intp) if groups is None
                          else np.asarray(groups), method.ar_order)
    if tones is not None:
        x += tones
    if method.compensate:
        w = window_.astype(np.float64)
        kept = (~mask) @ w if method.fill == "zero" else \
            (_taper_gain(mask, method.taper_samples) @ w if method.fill == "taper" else w.sum())
        x *= (w.sum() / np.maximum(kept, 1e-3 * w.sum())).astype(np.float32)[:, None]
    return x


def _lowrank(x: np.ndarray, flags: np.ndarray, hysteresis: int, method: Mitigation,
             frame: FrameRows | None, remove_mean: bool = True) -> np.ndarray:
    """`repair` with the "lowrank" fill (`pipeline.interference_lowrank`)."""
    if len(x):
        lowrank_bursts(x, flags, hysteresis, method, frame).run_all(remove_mean)
    return x


def lowrank_bursts(x: np.ndarray, flags: np.ndarray, hysteresis: int, method: Mitigation,
                   frame: FrameRows | None, basis: FastTimeBasis | None = None,
                   operands: GramOperands | None = None,
                   rhs: np.ndarray | None = None) -> BurstFill:
    """`repair` of rows x (at least one) with the "lowrank" fill `method`, prepared up to its
    per-burst work (a burst: the rows of one chirp of `frame`, else one row): the frame's
    basis (`frame_basis`, unless given), the rows' projections on it and its Gram sums
    (`burst_fill`, unless given). ``.run(b0, b1)`` then repairs bursts b0 .. b1 - 1 in place,
    each burst once, ``.run_all(remove_mean)`` all of them (`repair`'s values; the means are
    not removed by `run`). Arguments as `repair`."""
    if basis is None:
        basis = _basis(_reference(x, frame, lambda: method.mask(flags, hysteresis)), method)
    bursts = np.arange(len(x)) if frame is None else frame.rows // frame.n_rx
    return burst_fill(x, flags, bursts, basis, method.close_gap_samples,
                      hysteresis + method.extend_samples, method.grow_sigma,
                      method.grow_reach_samples, operands, rhs)


def frame_has_reference(frame: FrameRows) -> bool:
    """Whether the "lowrank" basis of rows repaired in `frame` comes from the frame's unflagged
    rows (`frame_basis`), not from the repaired rows and their flags."""
    return len(frame.samples) - len(frame.rows) >= MIN_REFERENCE_ROWS


def frame_basis(frame: FrameRows, dtype: np.dtype, method: Mitigation) -> FastTimeBasis | None:
    """The "lowrank" `method`'s basis for rows of `dtype` repaired in `frame`, where the
    frame's unflagged rows give it (`lowrank_bursts` computes the same one): it needs neither
    the repaired rows nor their flags, so it can be computed beside them. None where the
    frame has too few unflagged rows (the basis then comes from the repaired rows)."""
    ref = _frame_reference(frame, dtype)
    return None if ref is None else _basis(ref, method)


def _basis(ref: np.ndarray, method: Mitigation) -> FastTimeBasis:
    """The "lowrank" `method`'s basis of reference rows `ref` (N, n)."""
    return fast_time_basis(ref, method.rank_max, 10 ** (method.rank_snr_gate_db / 10))


#: Gaps closed between flagged samples by the methods that improve on the chip, samples: an
#: interfering chirp's burst lasts 2 B_IF / |S_v - S_i| (DESIGN 6), 1.6 us = 48 samples at
#: 30 Msps for the head-on case's 30 MHz/us front radar, and its slow middle is where the
#: difference statistic misses it.
CLOSE_GAP_SAMPLES = 48
#: Extra samples masked on each side beyond the chip's hysteresis: the burst's edges under
#: the IF filter's response (about 10 samples on the head-on case's bursts, whose flags sit
#: only where the sweep is fastest).
EXTEND_SAMPLES = 12

#: Repair methods by name (``ProcessingConfig.intf_mitigation``).
MITIGATIONS: Registry[Mitigation] = Registry(
    "interference mitigation", field="intf_mitigation", kind=Mitigation).register_all((
    Mitigation(name="zero", description="the chip: flagged samples and the hysteresis "
               "zeroed (SWRA725 3.3)"),
    Mitigation(name="zero_compensated", description="zeroed, the chirp's gain restored by "
               "sum(w) / sum(w kept)", compensate=True, close_gap_samples=CLOSE_GAP_SAMPLES,
               extend_samples=EXTEND_SAMPLES, recentre=True),
    Mitigation(name="windowed_zero", description="zeroed with 5-sample Hann edges (the "
               "demo's windowed zero-out)", fill="taper", close_gap_samples=CLOSE_GAP_SAMPLES,
               extend_samples=EXTEND_SAMPLES, recentre=True),
    Mitigation(name="interpolate", description="masked samples linearly interpolated",
               fill="linear", close_gap_samples=CLOSE_GAP_SAMPLES,
               extend_samples=EXTEND_SAMPLES, recentre=True),
    Mitigation(name="ar", description="the 4 strongest echoes per Rx fitted per chirp and "
               "continued across the gap, the rest predicted by a per-Rx Burg AR(64) model "
               "forward and backward, cross-faded", fill="ar", ar_order=64, cancel_tones=4,
               close_gap_samples=CLOSE_GAP_SAMPLES,
               extend_samples=EXTEND_SAMPLES, recentre=True),
    Mitigation(name="lowrank", description="the masked samples of each chirp predicted from "
               "its kept ones by the frame's fast-time signal subspace (up to 24 components "
               "of the unhit chirps, LMMSE), the Rx of a chirp sharing one mask, grown where "
               "the fit's residual shows the burst", fill="lowrank",
               close_gap_samples=CLOSE_GAP_SAMPLES, extend_samples=0, grow_sigma=5.0),
))


def get_mitigation(name: str) -> Mitigation:
    """The registered method.

    Raises
    ------
    ValueError
        Unknown name, with the known ones.
    """
    return MITIGATIONS.lookup(name)
