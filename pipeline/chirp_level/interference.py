"""Interference detection and repair of the chirp-level chain (seed 004 section 2; TI SWRA725).

Interference mitigation, as TI documents it (with where this model assumes):

* Statistics per chirp and Rx (SWRA725 sec. 3.1): absSum = sum |x_n| and diffAbsSum =
  sum |x_n - x_{n-1}|, scaled to means and then by the ``intfMitigCfg`` SNRs into the thresholds
  AbsThreshold = mean |x| 10^(magSNRdB / 20) and AbsDiffThreshold = mean |dx| 10^(magDiffSNRdB
  / 20): the SDK's ``rangeProcHWADDMA_findIntfStatsStaticParams`` programs the HWA scale as
  10^(SNRdB / 20) / numSamples x 2^(8 + shift), i.e. an amplitude ratio over the mean.
  ``intfMitigCfg -1 15 18`` (the shipped profile, TI's defaults) gives 15 and 18 dB.
* Localisation (SWRA725 sec. 3.2; HWA_INTERFTHRESH_MODE_*): a sample whose |x| and/or |dx|
  exceeds its threshold gets an interference indicator bit. The DDM demo's RangeProc programs
  ``thresholdMode = MAGDIFF`` with per-Rx built-in statistics, so the default mode is
  "magdiff"; the other HWA modes are selectable (`INTF_THRESHOLD_MODES`).
* Mitigation (SWRA725 sec. 3.3; HWA_INTERFMITIGATION_PATH_*): the DDM demo's RangeProc
  (rangeprochwaDDMA.c, ``rangeProcHWA_ConfigHWA``, current MCU+ SDK) enables it
  (``interfMitigation.enable = 1``) on the windowed zero-out path with left/right hysteresis
  orders 3 and a count threshold of 1 (an older release left it disabled with a TODO), so the
  harness turns it on by default. ASSUMED here: the hysteresis extends every flagged run by
  `intf_hysteresis_samples` samples on each side and those samples are set to zero. The
  "windowed" part is a 5-sample taper (the demo programs samples 2-6 of a 16-point Hann in
  Q5, ``hwaInterfMitigWindow``), but where the HWA applies it is not documented publicly: it
  is not modelled (a hard zero).

References
----------
.. [1] TI SWRA725, "Interference Mitigation for AWR294x" (2021), sections 3.1-3.3.
.. [2] TI MMWAVE-MCUPLUS-SDK, DDM demo: ``MmwDemo_CLIIntfMitigCfg`` (mmw_cli.c),
       ``rangeProcHWADDMA_findIntfStatsStaticParams`` and the mitigation paramset of
       ``rangeProcHWA_ConfigHWA`` (rangeprochwaDDMA.c); the DPC's ``hwaInterfMitigWindow``;
       MCU+ SDK HWA driver ``HWA_PreProcessing.interfMitigation``.
"""
from __future__ import annotations

import threading
from collections.abc import Callable
from typing import NamedTuple

import numba
import numpy as np

from core.errors import BadInput

from ..config import INTF_THRESHOLD_MODES, ProcessingConfig
from ..interference_lowrank import (
    FastTimeBasis,
    GramOperands,
    burst_row_start,
    gram_operands,
    projections,
)
from ..interference_repair import (
    FrameRows,
    Mitigation,
    frame_basis,
    frame_has_reference,
    get_mitigation,
    lowrank_bursts,
    repair,
)
from ..threads import inline, run_parts, spans

__all__ = ["interference_flags", "zero_flagged", "flagged_rows", "repaired_rows", "RepairedRows",
           "DeferredLowrank", "INTF_THRESHOLD_MODES"]


def interference_flags(adc: np.ndarray, dc: np.ndarray | None, mag_snr_db: float,
                       magdiff_snr_db: float, mode: str = "magdiff") -> np.ndarray:
    """Interference indicator bits (before hysteresis) of every sample.

    Parameters
    ----------
    adc : (n_chirps, n_rx, n_samples) int16 or float
    dc : (n_chirps, n_rx, 1) float or None
        DC estimate removed before the statistics (None: none).
    mag_snr_db, magdiff_snr_db : float
        ``intfMitigCfg`` magSNRdB and magDiffSNRdB: thresholds over the mean |x| and mean
        |x_n - x_{n-1}| of the same chirp and Rx, amplitude dB.
    mode : str
        Key of `INTF_THRESHOLD_MODES`.

    Returns
    -------
    (n_chirps, n_rx, n_samples) bool
        Sample 0 has no difference; in "magdiff" mode it is never flagged.
    """
    if mode not in INTF_THRESHOLD_MODES:
        raise BadInput(f"intf_threshold_mode={mode!r} is not one of "
                       f"{sorted(INTF_THRESHOLD_MODES)}")
    m = INTF_THRESHOLD_MODES[mode]
    n = adc.shape[-1]
    a2 = adc.reshape(-1, n)
    flags = None
    if m.difference:
        d, thr = _diff_statistics(a2, magdiff_snr_db)
        flags = np.zeros(a2.shape, dtype=bool)
        np.greater(d, thr[:, None], out=flags[:, 1:])
    if m.magnitude:
        x = a2.astype(np.complex64 if np.iscomplexobj(adc) else np.float32)  # I/Q: |complex|
        if dc is not None:
            x -= dc.reshape(-1, 1)
        a = np.abs(x)
        thr = a.sum(axis=-1, keepdims=True) * np.float32(10 ** (mag_snr_db / 20) / n)
        fm = a > thr
        if flags is None:
            flags = fm
        elif m.both_required:
            flags &= fm
        else:
            flags |= fm
    return flags.reshape(adc.shape)


def _diff_statistics(a2: np.ndarray, snr_db: float) -> tuple[np.ndarray, np.ndarray]:
    """|x_n - x_{n-1}| of (rows, n) samples and each row's threshold mean |dx| 10^(SNR/20),
    float32 (`interference_flags`). Real int16 rows are differenced in int16 when no
    difference can overflow it (four times cheaper than float32; the int32 row sums are below
    2^24, so the float32 threshold is the same), I/Q rows as complex64."""
    n = a2.shape[-1]
    if np.iscomplexobj(a2):
        d = np.abs(np.subtract(a2[:, 1:], a2[:, :-1], dtype=np.complex64))
    elif a2.dtype == np.int16 and int(a2.max()) - int(a2.min()) <= np.iinfo(np.int16).max:
        d = np.subtract(a2[:, 1:], a2[:, :-1])
        np.abs(d, out=d)
    else:
        d = np.abs(np.subtract(a2[:, 1:], a2[:, :-1], dtype=np.float32))
    total = d.sum(axis=-1, dtype=np.int32 if d.dtype.kind == "i" else np.float32)
    return d, total.astype(np.float32) * np.float32(10 ** (snr_db / 20) / n)


def zero_flagged(x: np.ndarray, flags: np.ndarray, hysteresis: int = 3) -> np.ndarray:
    """Zero the flagged samples, each flagged run widened by `hysteresis` on both sides.

    Parameters
    ----------
    x : (..., n_samples) float32
        DC-removed samples (modified in place and returned).
    flags : (..., n_samples) bool
    hysteresis : int
        Left and right hysteresis order, samples (the demo: 3): sample i is zeroed iff a flag
        lies in [i - hysteresis, i + hysteresis] of its own chirp.
    """
    n = x.shape[-1]
    f = np.flatnonzero(flags)  # flags are sparse: index arithmetic beats dilating the mask
    if f.size:
        col = f % n
        span = np.arange(-hysteresis, hysteresis + 1)
        np.put(x, (f - col)[:, None] + np.clip(col[:, None] + span, 0, n - 1), 0)
    return x


def flagged_rows(adc: np.ndarray, dc, proc: ProcessingConfig) -> tuple[np.ndarray, np.ndarray]:
    """(chirp x Rx rows with a flagged sample, their (rows, n_samples) flags). A mode that
    uses the difference statistic alone (the demo's "magdiff") takes a fast path: a row is
    flagged iff its largest |dx| exceeds its threshold, and only those rows get their flags
    built."""
    n = adc.shape[-1]
    a2 = adc.reshape(-1, n)
    if not INTF_THRESHOLD_MODES[proc.intf_threshold_mode].magnitude:
        d, thr = _diff_statistics(a2, proc.intf_magdiff_snr_db)
        rows = np.flatnonzero(d.max(axis=-1) > thr)
        flags = np.zeros((rows.size, n), dtype=bool)
        np.greater(d[rows], thr[rows, None], out=flags[:, 1:])
        return rows, flags
    flags = interference_flags(adc, dc, proc.intf_mag_snr_db, proc.intf_magdiff_snr_db,
                               proc.intf_threshold_mode).reshape(-1, n)
    rows = np.flatnonzero(flags.any(axis=-1))
    return rows, flags[rows]


class DeferredLowrank:
    """The "lowrank" repair of `repaired_rows(deferred=True)`: first its `steps` (the frame's
    basis; the rows' DC removal and flags; the basis' Gram sums; the rows' projections and
    the kernel's operands), each run once, then `run` on ranges of bursts (the rows of one
    chirp), each burst once. A step or `run` waits only for earlier steps: run in order, or
    taken in order by several threads (a queue), nothing waits for a step nobody took.

    Each step computes what `repaired_rows` computes eagerly (the frame's basis only: the
    frame must have its reference rows, `frame_has_reference`), so the rows come out the
    same whatever thread ran what.
    """

    def __init__(self, y: np.ndarray, frame: FrameRows, method: Mitigation, hysteresis: int,
                 make_rows: Callable[[], None], make_flags: Callable[[], np.ndarray]):
        self.y, self.frame, self.method, self.hysteresis = y, frame, method, hysteresis
        self._make_rows, self._make_flags = make_rows, make_flags
        self.row_start = burst_row_start(frame.rows // frame.n_rx)  # a burst: one chirp
        self._done = [threading.Event() for _ in range(4)]
        self._basis: FastTimeBasis | None = None
        self._flags: np.ndarray | None = None
        self._operands: GramOperands | None = None
        self._fill = None

    def steps(self) -> list[Callable[[], None]]:
        """The four steps, in the order they must be taken."""
        return [self._step_basis, self._step_rows, self._step_gram, self._step_fill]

    def prepare(self) -> None:
        """Every step, here, in order (no queue)."""
        for step in self.steps():
            step()

    def run(self, b0: int, b1: int) -> None:
        """Repair bursts b0 .. b1 - 1 (after the steps; nothing if one failed: its exception
        is the caller's to raise)."""
        self._done[3].wait()
        if self._fill is not None:
            self._fill.run(b0, b1)

    def _step_basis(self) -> None:
        try:
            self._basis = frame_basis(self.frame, self.y.dtype, self.method)
        finally:
            self._done[0].set()  # also on failure: no later step waits forever

    def _step_rows(self) -> None:
        try:
            with inline():  # a step's own passes run whole: it may be on either core
                self._make_rows()
                self._flags = self._make_flags()
        finally:
            self._done[1].set()

    def _step_gram(self) -> None:
        try:
            self._done[0].wait()
            if self._basis is not None:
                self._operands = gram_operands(self._basis)
        finally:
            self._done[2].set()

    def _step_fill(self) -> None:
        try:
            self._done[0].wait()
            self._done[1].wait()
            if self._basis is None or self._flags is None:
                return
            rhs = projections(self.y, self._basis)
            self._done[2].wait()
            if self._operands is not None:
                self._fill = lowrank_bursts(self.y, self._flags, self.hysteresis, self.method,
                                            self.frame, self._basis, self._operands, rhs)
        finally:
            self._done[3].set()


class RepairedRows(NamedTuple):
    """The flagged chirp x Rx rows of a frame, DC removed and repaired: what the range FFT
    takes in their place, times the range window (`repaired_rows`)."""

    rows: np.ndarray      # (R,) increasing row indices, chirp * n_rx + Rx
    samples: np.ndarray   # (R, n_samples) float32 (complex64 for I/Q): repaired, not windowed
    window: np.ndarray    # (n_samples,) float32 range window
    dc: np.ndarray | None  # (n_chirps, n_rx) DC estimates, the repaired rows' 0 (None: none)
    means: np.ndarray     # (R,) what the repair still subtracts from each row (0: nothing)
    fill: DeferredLowrank | None = None  # the repair still to run (`deferred=True`)

    def repair_chirps(self, c0: int, c1: int, n_rx: int) -> None:
        """Run the deferred repair (`fill`, after its steps) of the rows of chirps c0 .. c1 - 1
        and set their `means`; nothing without one. Each chirp exactly once, any order, any
        thread: until then those rows' `samples` and `means` are not the repaired ones."""
        if self.fill is None:
            return
        lo, hi = np.searchsorted(self.rows, (c0 * n_rx, c1 * n_rx))
        if hi > lo:  # a chirp's rows are one burst: lo and hi are where bursts start
            self.fill.run(*np.searchsorted(self.fill.row_start, (lo, hi)))
            self.samples[lo:hi].mean(axis=-1, out=self.means[lo:hi])

    def windowed(self) -> np.ndarray:
        """(R, n_samples) the repaired rows, their `means` subtracted, times the window
        (numpy's products; rows in parts on the cores)."""
        y = np.empty_like(self.samples)
        # (x - 0) is x bit for bit (-0 and NaN included): no subtraction pass without means
        centre = bool(self.means.any())

        def part(lo: int, hi: int) -> None:
            x = self.samples[lo:hi]
            if centre:
                x = np.subtract(x, self.means[lo:hi, None], out=y[lo:hi])
            np.multiply(x, self.window, out=y[lo:hi])
        run_parts([lambda lo=lo, hi=hi: part(lo, hi) for lo, hi in spans(len(y))])
        return y

    def windowed_block(self, adc: np.ndarray, c0: int, out: np.ndarray) -> np.ndarray:
        """The windowed samples of chirps c0 .. c0 + len(adc) - 1 into `out` and returned:
        `adc` (chirps, n_rx, n_samples) int16, those chirps of the frame, each row as
        float32 times the window (`kernels.samples_windowed`), the repaired rows' (real
        frames) in its place, as `windowed()` has them: one compiled pass, no row windowed
        twice."""
        n_rx, n = adc.shape[1], adc.shape[-1]
        if out.shape != adc.shape or not out.flags.c_contiguous:
            # a reshape of a strided `out` would be a copy: the results would be lost
            raise BadInput(f"out must be a C-contiguous {adc.shape} array, got {out.shape} "
                           f"(C-contiguous: {out.flags.c_contiguous})")
        lo, hi = np.searchsorted(self.rows, (c0 * n_rx, (c0 + len(adc)) * n_rx))
        _windowed_rows(adc.reshape(-1, n), self.samples, self.means, self.rows, self.window,
                       c0 * n_rx, lo, hi, out.reshape(-1, n))
        return out

    def without_dc(self, c0: int, c1: int) -> np.ndarray:
        """(c1 - c0, n_rx) the DC estimates of chirps c0 .. c1 - 1 with the repaired rows' set
        to 0 (their DC was removed before the FFT)."""
        return self.dc[c0:c1]


def repaired_rows(adc: np.ndarray, dc: np.ndarray | None, rows: np.ndarray,
                  flags: np.ndarray | Callable[[], np.ndarray], win: np.ndarray,
                  proc: ProcessingConfig, deferred: bool = False) -> RepairedRows:
    """The flagged rows, DC removed and repaired by ``proc.intf_mitigation`` (the chip
    zeroes), with the window they are multiplied by.

    Parameters
    ----------
    adc : (n_chirps, n_rx, n_samples) int16, or complex64 I/Q
    dc : (n_chirps, n_rx, 1) float or None
        DC estimates (None: no DC removal).
    rows : (R,) int
        Increasing flagged rows (`flagged_rows`).
    flags : (R, n_samples) bool, or a function returning them
        Their interference flags (a function: called once, maybe beside other work on
        another core, where its own passes run whole, `pipeline.threads.inline`).
    win : (n_samples,) float32
        The range window.
    proc : ProcessingConfig
    deferred : bool
        Where the repair is the "lowrank" fill of real rows and the frame has its reference
        rows, leave all of it to the caller: the DC removal, the flags and the basis to
        ``fill.steps()`` (`DeferredLowrank`), then the per-chirp work and the rows' means to
        `RepairedRows.repair_chirps` on every chirp once (so the steps run side by side and
        a chirp's repair next to its range FFT); elsewhere ignored.

    Returns
    -------
    RepairedRows
    """
    n_rx, n = adc.shape[1], adc.shape[-1]
    a2 = adc.reshape(-1, n)
    y = np.empty((len(rows), n), np.complex64 if np.iscomplexobj(adc) else np.float32)
    parts = spans(len(rows))  # elementwise passes in parts on the cores: the same values

    compiled = dc is not None and a2.dtype == np.int16

    def dc_removed(lo: int, hi: int) -> None:
        if compiled:  # one pass: gather, convert and subtract (numpy's float32 steps)
            _dc_removed_rows(a2, rows, dc.reshape(-1).astype(np.float32, copy=False), y, lo, hi)
        elif dc is None:
            y[lo:hi] = a2[rows[lo:hi]]
        else:
            np.subtract(a2[rows[lo:hi]], dc.reshape(-1, 1)[rows[lo:hi]], out=y[lo:hi],
                        dtype=y.dtype)

    method = get_mitigation(proc.intf_mitigation)
    # "lowrank" leaves its rows' means to the window product (one pass less over the rows)
    centre = method.fill == "lowrank" and y.dtype == np.float32
    frame = FrameRows(a2, rows, n_rx)
    make_flags = flags if callable(flags) else lambda: flags
    means = np.zeros(len(rows), y.dtype)
    fill = None
    if deferred and centre and len(rows) and frame_has_reference(frame):
        # The frame's basis (BLAS and LAPACK on one core, ~1.5 ms) needs neither the rows nor
        # their flags: the caller's queue runs the steps side by side.
        fill = DeferredLowrank(y, frame, method, proc.intf_hysteresis_samples,
                               lambda: dc_removed(0, len(rows)), make_flags)
    else:
        flags = make_flags()
        run_parts([lambda lo=lo, hi=hi: dc_removed(lo, hi) for lo, hi in parts])
        repair(y, flags, win, proc.intf_hysteresis_samples, method, frame=frame,
               remove_mean=not centre)
        if centre:
            run_parts([lambda lo=lo, hi=hi: y[lo:hi].mean(axis=-1, out=means[lo:hi])
                       for lo, hi in parts])
    dc0 = None
    if dc is not None:
        dc0 = dc[..., 0].copy()
        dc0.reshape(-1)[rows] = 0
    return RepairedRows(rows, y, win, dc0, means, fill)


@numba.njit(cache=True, nogil=True)
def _windowed_rows(a2, y, means, rows, w, row0, lo, hi, out):
    """out[r] <- w x (y[i] - means[i] if rows[i] == row0 + r for an i in lo .. hi - 1, else
    float32(a2[r])), float32 differences and products (numpy's ``np.subtract`` and
    ``np.multiply`` of each pair, element by element); rows[lo:hi] increasing, within
    row0 .. row0 + len(a2) - 1."""
    n = np.uint64(a2.shape[1])  # unsigned: lets LLVM vectorise the loops
    i = lo
    for r in range(a2.shape[0]):
        o = out[r]
        if i < hi and rows[i] == row0 + r:
            s = y[i]
            m = means[i]
            for t in range(n):
                o[t] = (s[t] - m) * w[t]
            i += 1
        else:
            a = a2[r]
            for t in range(n):
                o[t] = np.float32(a[t]) * w[t]


@numba.njit(cache=True, nogil=True)
def _dc_removed_rows(a2, rows, dc, out, lo, hi):
    """out[i] <- float32(a2[rows[i]]) - dc[rows[i]] for i in lo .. hi - 1 (int16 rows, float32
    DC estimates: numpy's ``np.subtract(a, dc, dtype=float32)``, element by element)."""
    n = a2.shape[1]
    for i in range(lo, hi):
        r = rows[i]
        d = dc[r]
        for t in range(n):
            out[i, t] = np.float32(a2[r, t]) - d
