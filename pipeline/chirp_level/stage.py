"""The chirp-level range stage: DC removal, interference zeroing, windowed range FFT and EGE
compression/decompression in the order the R79 demo's RangeProc runs them (seed 004 section 2;
seed 000 section 5.1, table 5). `range_stage` is the hook the chains call instead of a bare
range FFT.

Work done once: inside `shared_range_stage()` the stage runs once per frame and chirp-level
setting. A sweep cell frame is processed by several result schemes and measured by the
noise-floor metric; the schemes of one MIMO scheme (TDMA and its raw variant) and the metric all
read the same range cube, so the harness wraps each frame in this scope instead of handing
cubes through every chain's signature.
"""
from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

import numpy as np
import scipy.fft

from radarsim.config import RadarConfig

from ..config import WINDOWS, ProcessingConfig
from ..kernels import range_fft, window, windowed
from ..threads import run_parts, spans
from .dc import remove_dc, window_spectrum
from .ege import ege_compress
from ..interference_repair import FrameRows, get_mitigation, repair
from .interference import flagged_rows

__all__ = ["range_stage", "shared_range_stage", "RANGE_STAGE_FIELDS"]

#: The `ProcessingConfig` fields the range stage reads: two settings equal on these give the
#: same range cube for the same frame.
RANGE_STAGE_FIELDS = ("range_window", "dc_removal", "interference_mitigation", "intf_mag_snr_db",
                      "intf_magdiff_snr_db", "intf_threshold_mode", "intf_hysteresis_samples",
                      "intf_mitigation", "compression", "compression_ratio",
                      "compression_range_bins_per_block", "dc_range_signature")

#: Range cubes of the current `shared_range_stage` scope by (frame id, n_samples, settings);
#: each entry keeps its frame alive, so an id cannot be reused while the scope lasts.
_SHARED: ContextVar[dict | None] = ContextVar("pipeline_shared_range_stage", default=None)


@contextmanager
def shared_range_stage() -> Iterator[None]:
    """Within the block, `range_stage` computes each (frame, `RANGE_STAGE_FIELDS`) pair once and
    returns the same read-only cube to every later caller (chains, `noise_floor_rise`).

    A frame is identified by its array object: the caller must not modify a frame in place
    inside the block (the harness never does: its ADC frames are written once by the front
    end). Scopes are per thread and per context (`contextvars`); nested scopes start empty.
    """
    token = _SHARED.set({})
    try:
        yield
    finally:
        _SHARED.reset(token)


def range_stage(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> np.ndarray:
    """The chirp-level chain: DC removal, interference mitigation, windowed range FFT,
    EGE compression/decompression, each as `proc` switches it.

    Parameters
    ----------
    cfg : RadarConfig
    adc : (n_chirps, n_rx, n_samples) int16, or complex64 I/Q (complex ADC modes)
    proc : ProcessingConfig

    Returns
    -------
    (n_chirps, n_rx, n_samples // 2) complex64, or (..., n_samples) for I/Q input
        With every switch off, exactly `kernels.range_fft(adc, window)`. Read-only inside
        `shared_range_stage`.
    """
    memo = _SHARED.get()
    if memo is None:
        return _dc_signature(_range_stage(cfg, adc, proc), proc)
    key = (id(adc), cfg.n_samples, *(getattr(proc, f) for f in RANGE_STAGE_FIELDS))
    hit = memo.get(key)
    if hit is not None and hit[0] is adc:
        return hit[1]
    rf = _dc_signature(_range_stage(cfg, adc, proc), proc)
    rf.flags.writeable = False
    memo[key] = (adc, rf)
    return rf


def _dc_signature(rf: np.ndarray, proc: ProcessingConfig) -> np.ndarray:
    """`rf` minus ``proc.dc_range_signature`` (TI's ``calibDcRangeSig``), or `rf` itself."""
    sig = proc.dc_range_signature
    return rf if sig is None else sig.subtract(rf)


def _chirp_statistics(adc: np.ndarray, proc: ProcessingConfig):
    """(DC estimate or None, flagged chirp x Rx rows, their flags or None) as `proc` switches
    them: `remove_dc` and `flagged_rows`, both per chirp and Rx, run on blocks of chirps on the
    cores (`pipeline.threads`) and joined in row order (the same values)."""
    n_rx = adc.shape[1]

    def block(lo: int, hi: int):
        a = adc[lo:hi]
        dc = remove_dc(a) if proc.dc_removal else None
        if not proc.interference_mitigation:
            return dc, np.zeros(0, dtype=np.intp), None
        rows, flags = flagged_rows(a, dc, proc)
        return dc, rows + lo * n_rx, flags

    parts = run_parts([lambda lo=lo, hi=hi: block(lo, hi) for lo, hi in spans(adc.shape[0])])
    dc = np.concatenate([p[0] for p in parts]) if proc.dc_removal else None
    rows = np.concatenate([p[1] for p in parts])
    flags = np.concatenate([p[2] for p in parts]) if proc.interference_mitigation else None
    return dc, rows, flags


def _range_stage(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> np.ndarray:
    """`range_stage` without the sharing."""
    cplx = np.iscomplexobj(adc)
    win = window(WINDOWS[proc.range_window], cfg.n_samples)
    if not (proc.dc_removal or proc.interference_mitigation or proc.compression):
        return range_fft(adc, win)
    dc, rows, flags = _chirp_statistics(adc, proc)
    if rows.size == 0:
        rf = range_fft(adc, win)
    else:
        # One FFT of the whole frame, the flagged chirps (DC removed, repaired by the
        # `proc.intf_mitigation` method; the chip zeroes) swapped in first.
        work = np.complex64 if cplx else np.float32
        x = windowed(adc, win, work)
        y = adc.reshape(-1, cfg.n_samples)[rows]
        y = y.astype(work) if dc is None else np.subtract(y, dc.reshape(-1, 1)[rows], dtype=work)
        repair(y, flags, win, proc.intf_hysteresis_samples, get_mitigation(proc.intf_mitigation),
               frame=FrameRows(adc.reshape(-1, cfg.n_samples), rows, cfg.n_rx))
        y *= win
        x.reshape(-1, cfg.n_samples)[rows] = y
        if cplx:
            rf = scipy.fft.fft(x, axis=-1, workers=-1, overwrite_x=True)
        else:
            rf = scipy.fft.rfft(x, axis=-1, workers=-1)[..., : cfg.n_samples // 2]
    if dc is not None:
        # FFT(w (x - m)) = FFT(w x) - m FFT(w): the window's spectrum has a few bins only.
        # The flagged chirps had their DC removed before the FFT.
        m = dc[..., 0]
        if rows.size:
            m = m.copy()
            m.reshape(-1)[rows] = 0
        for k, wk in window_spectrum(WINDOWS[proc.range_window], cfg.n_samples, cplx):
            rf[..., k] -= m * wk
    if proc.compression:
        rf, _ = ege_compress(rf, proc.compression_ratio, proc.compression_range_bins_per_block)
    return rf
