"""The chirp-level range stage: DC removal, interference zeroing, windowed range FFT and EGE
compression/decompression in the order the R79 demo's RangeProc runs them ([TI-DAZ] section 2;
[TI-DDMA] section 5.1, table 5). `range_stage` is the hook the chains call instead of a bare
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
from ..interference import INTF_THRESHOLD_MODES, RepairedRows, flagged_rows, repaired_rows
from ..interference.residual import with_weak_bursts
from ..interference.row_statistics import row_flags, row_statistics
from ..kernels import doppler_windowed, range_fft, samples_windowed, window, windowed
from ..threads import fft_workers, run_parts, spans
from .dc import remove_dc, subtract_dc, window_spectrum
from .ege import HWA_OUTPUT_SCALE, ege_blocks, ege_compress, ege_setup

__all__ = ["range_stage", "windowed_range_stage", "shared_range_stage", "range_stage_key",
           "blockwise_range_stage", "chirp_statistics", "idle_mitigation", "CHIRP_BLOCK"]

def range_stage_key(proc: ProcessingConfig) -> tuple:
    """The settings the range stage reads, as values: its sub-configs (range window and DC
    removal, interference, compression, the calibration's DC range signature). Two settings
    with equal keys give the same range cube for the same frame."""
    return (proc.range, proc.interference, proc.compression, proc.calibration)


#: The range cubes of the current `shared_range_stage` scope, as (frame, `_cube_key`, cube):
#: a frame is found by identity (`is`), and the entry keeps it alive while the scope lasts.
_SHARED: ContextVar[list | None] = ContextVar("pipeline_shared_range_stage", default=None)


@contextmanager
def shared_range_stage() -> Iterator[None]:
    """Within the block, `range_stage` computes each (frame, `range_stage_key`) pair once and
    returns the same read-only cube to every later caller (chains, `noise_floor_rise`).

    A frame is identified by its array object: the caller must not modify a frame in place
    inside the block (the harness never does: its ADC frames are written once by the front
    end). Scopes are per thread and per context (`contextvars`); nested scopes start empty.
    """
    token = _SHARED.set([])
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
    shared = _SHARED.get()
    if shared is None:
        return _dc_signature(_range_stage(cfg, adc, proc)[0], proc)
    rf = _shared_cube(shared, cfg, adc, proc)
    if rf is None:
        rf, n_flagged = _range_stage(cfg, adc, proc)
        rf = _keep(shared, cfg, adc, proc, _dc_signature(rf, proc), n_flagged)
    return rf


def _cube_key(cfg: RadarConfig, proc: ProcessingConfig) -> tuple:
    return (cfg.n_samples, *range_stage_key(proc))


def _shared_cube(shared: list, cfg: RadarConfig, adc: np.ndarray,
                 proc: ProcessingConfig) -> np.ndarray | None:
    """The cube of frame `adc` (this very array) and these settings kept in the scope, or
    None."""
    key = _cube_key(cfg, proc)
    return next((rf for a, k, rf in shared if a is adc and k == key), None)


def _keep(shared: list, cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig,
          rf: np.ndarray, n_flagged: int) -> np.ndarray:
    """`rf`, made read-only and kept in the scope as frame `adc`'s cube of these settings;
    where their mitigation flagged none (`n_flagged` rows) of its samples also as the cube of
    ``proc.unmitigated`` (the same bits, `idle_mitigation`): an interference case's
    mitigation reference reads it."""
    rf.flags.writeable = False
    shared.append((adc, _cube_key(cfg, proc), rf))
    if proc.interference.enabled and n_flagged == 0:
        shared.append((adc, _cube_key(cfg, proc.unmitigated), rf))
    return rf


#: Chirps per block of `windowed_range_stage`: a block's float32 samples, range spectra and
#: windowed output (~400 kB each for 4 Rx x 384 samples) stay in cache, and the per-call costs
#: of the rFFT and the compiled loops stay small (measured: 64-128 chirps best, 16 worst).
CHIRP_BLOCK = 64


def windowed_range_stage(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig,
                         chirp_window: np.ndarray) -> np.ndarray:
    """`range_stage` times a slow-time window: the input of the Doppler FFT.

    Parameters
    ----------
    cfg, adc, proc
        As `range_stage`.
    chirp_window : (n_chirps,) float32
        The Doppler window's value at each chirp (a slot-coded chain repeats each value for
        the slots of a code period).

    Returns
    -------
    (n_chirps, n_rx, n_bins) complex64, C-contiguous
        Chirp c of `range_stage`'s cube times chirp_window[c], as numpy's complex64 product
        (`kernels.doppler_windowed`), bit for bit.

    Notes
    -----
    For real samples without a DC range signature, the whole stage runs per block of
    `CHIRP_BLOCK` chirps (the flagged rows repaired first and windowed in place of theirs),
    blocks in parts on the cores: window, rFFT, DC correction, EGE and the slow-time window
    one after the other on data that stays in cache, instead of five passes over the frame,
    each with its own hand-off to the cores. Each step does what `range_stage` does on those
    chirps (the rFFT of each row is the same transform in any batch; EGE's dither is indexed
    by the chirp's place in the frame), so the cube is the same. Inside
    `shared_range_stage` the unwindowed cube is kept for the other readers too. Otherwise
    (I/Q frames, a DC range signature, every switch off) `range_stage` and the window
    product.
    """
    shared = _SHARED.get()
    kept = None if shared is None else _shared_cube(shared, cfg, adc, proc)
    if kept is not None:
        return doppler_windowed(kept, chirp_window)
    if (np.iscomplexobj(adc) or proc.calibration.dc_range_signature is not None
            or not (proc.range.dc_removal or proc.interference.enabled
                    or proc.compression.enabled)):
        return doppler_windowed(range_stage(cfg, adc, proc), chirp_window)
    dc, rows, flags = chirp_statistics(adc, proc)
    rep = repaired_rows(adc, dc, rows, flags, window(WINDOWS[proc.range.window], cfg.n_samples),
                        proc.interference) if rows.size else None
    keep = np.empty((adc.shape[0], adc.shape[1], cfg.n_samples // 2), np.complex64) \
        if shared is not None else None
    out = blockwise_range_stage(cfg, adc, proc, dc, chirp_window, keep, rep)
    if shared is not None:
        _keep(shared, cfg, adc, proc, keep, rows.size)
    return out


def blockwise_range_stage(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig,
                          dc: np.ndarray | None, chirp_window: np.ndarray,
                          keep: np.ndarray | None,
                          rep: RepairedRows | None = None) -> np.ndarray:
    """`windowed_range_stage` of a real frame, per block of chirps, the flagged rows `rep`
    (DC removed, repaired) windowed in place of theirs; the range cube before the slow-time
    window also into `keep` if given. Blocks in parts on the cores (`pipeline.threads`)."""
    n_c, n_rx, n_s = adc.shape
    n_b = n_s // 2
    win = window(WINDOWS[proc.range.window], n_s)
    fix = window_spectrum(WINDOWS[proc.range.window], n_s, False) if dc is not None else ()
    fix_bins = np.array([k for k, _ in fix], np.int64)
    fix_weights = np.array([w for _, w in fix], np.complex64)
    ege = ege_setup(n_rx, n_b, proc.compression.ratio, proc.compression.range_bins_per_block) \
        if proc.compression.enabled else None
    out = np.empty((n_c, n_rx, n_b), np.complex64)

    def block(c0: int, c1: int) -> None:
        x = np.empty((c1 - c0, n_rx, n_s), np.float32)
        if rep is None:
            samples_windowed(adc[c0:c1], win, x)
        else:  # the repaired rows in place of theirs
            rep.windowed_block(adc[c0:c1], c0, x)
        # The whole rFFT output (n_b + 1 bins), C-contiguous, to the DC fix, EGE and the
        # window product, which read its first n_b bins in place: the compiled loops on a view
        # of those bins would copy each row or not vectorise (a 64-chirp R79 block: EGE 120 ->
        # 90 us, the window product 26 -> 14 us).
        rf = scipy.fft.rfft(x, axis=-1, workers=1)
        if fix:
            subtract_dc(rf, dc[c0:c1, :, 0] if rep is None else rep.without_dc(c0, c1),
                        fix_bins, fix_weights)
        if ege is not None:
            bins2, budget, kk, cold = ege
            shift = np.zeros((c1 - c0, n_b * 2 // bins2), np.int8)
            ege_blocks(rf.view(np.float32), bins2, np.float32(HWA_OUTPUT_SCALE), budget, kk,
                        cold, shift, 0, c1 - c0, c0)
        if keep is not None:
            keep[c0:c1] = rf[..., :n_b]
        doppler_windowed(rf, chirp_window[c0:c1], out=out[c0:c1], split=False)

    def part(lo: int, hi: int) -> None:
        for c0 in range(lo, hi, CHIRP_BLOCK):
            block(c0, min(c0 + CHIRP_BLOCK, hi))

    run_parts([lambda lo=lo, hi=hi: part(lo, hi) for lo, hi in spans(n_c, multiple=CHIRP_BLOCK)])
    return out


def _dc_signature(rf: np.ndarray, proc: ProcessingConfig) -> np.ndarray:
    """`rf` minus ``proc.calibration.dc_range_signature`` (TI's ``calibDcRangeSig``), or `rf`
    itself."""
    sig = proc.calibration.dc_range_signature
    return rf if sig is None else sig.subtract(rf)


def chirp_statistics(adc: np.ndarray, proc: ProcessingConfig):
    """(DC estimate or None, flagged chirp x Rx rows, their flags or None) as `proc` switches
    them: the chip's (`_chip_statistics`), then, where it flagged a row, the weak bursts it
    missed (``proc.interference.weak_burst_snr_db``, `with_weak_bursts`)."""
    dc, rows, flags = _chip_statistics(adc, proc)
    intf = proc.interference
    if intf.weak_burst_snr_db is None or not intf.enabled or not rows.size:
        return dc, rows, flags
    rows, flags = with_weak_bursts(adc, dc, rows, flags, intf.weak_burst_snr_db,
                                   intf.weak_burst_window_samples)
    return dc, rows, flags


def _chip_statistics(adc: np.ndarray, proc: ProcessingConfig):
    """The chip's (DC estimate or None, flagged chirp x Rx rows, their flags or None) as `proc`
    switches them: `remove_dc` and `flagged_rows`, both per chirp and Rx, run on blocks of
    chirps on the cores (`pipeline.threads`) and joined in row order (the same values)."""
    n_rx = adc.shape[1]
    if not (proc.range.dc_removal or proc.interference.enabled):  # nothing to measure
        return None, np.zeros(0, dtype=np.intp), None
    fused = _fused_statistics(adc, proc)
    if fused is not None:
        return fused

    def block(lo: int, hi: int):
        a = adc[lo:hi]
        dc = remove_dc(a) if proc.range.dc_removal else None
        if not proc.interference.enabled:
            return dc, np.zeros(0, dtype=np.intp), None
        rows, flags = flagged_rows(a, dc, proc.interference)
        return dc, rows + lo * n_rx, flags

    parts = run_parts([lambda lo=lo, hi=hi: block(lo, hi) for lo, hi in spans(adc.shape[0])])
    dc = np.concatenate([p[0] for p in parts]) if proc.range.dc_removal else None
    rows = np.concatenate([p[1] for p in parts])
    flags = np.concatenate([p[2] for p in parts]) if proc.interference.enabled else None
    return dc, rows, flags


def idle_mitigation(adc: np.ndarray, proc: ProcessingConfig) -> bool:
    """Whether `proc`'s interference mitigation is on and has nothing to repair in frame `adc`:
    the chip's statistics flag none of its samples. Then neither the weak-burst search nor a
    repair runs, and the range stage gives the cube of ``proc.unmitigated`` bit for bit: the
    DC estimates are the same with and without the statistics (`_fused_statistics`), and no
    row is swapped for a repaired one. Costs one statistics pass over the frame."""
    return proc.interference.enabled and _chip_statistics(adc, proc)[1].size == 0


def _fused_statistics(adc: np.ndarray, proc: ProcessingConfig):
    """`_chip_statistics` from one compiled pass (`row_statistics`) where it gives
    `remove_dc`'s and the magdiff `flagged_rows`' values bit for bit (an int16 frame, a
    difference-only threshold mode), else None. The flags of the flagged rows are
    `flagged_rows`' (`row_flags`)."""
    intf = proc.interference.enabled
    if intf and INTF_THRESHOLD_MODES[proc.interference.threshold_mode].magnitude:
        return None
    st = row_statistics(adc, proc.interference.magdiff_snr_db)
    if st is None:
        return None
    dc = st.dc if proc.range.dc_removal else None
    if not intf:
        return dc, np.zeros(0, dtype=np.intp), None
    return dc, st.flagged, row_flags(adc, st.flagged, st.threshold)


def _range_stage(cfg: RadarConfig, adc: np.ndarray,
                 proc: ProcessingConfig) -> tuple[np.ndarray, int]:
    """`range_stage` without the sharing, and the number of rows its mitigation flagged."""
    win = window(WINDOWS[proc.range.window], cfg.n_samples)
    if not (proc.range.dc_removal or proc.interference.enabled or proc.compression.enabled):
        return range_fft(adc, win), 0
    dc, rows, flags = chirp_statistics(adc, proc)
    return _range_cube(cfg, adc, proc, dc, rows, flags), rows.size


def _range_cube(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig, dc: np.ndarray | None,
                rows: np.ndarray, flags: np.ndarray | None) -> np.ndarray:
    """`_range_stage` after the chirp statistics (`chirp_statistics`)."""
    cplx = np.iscomplexobj(adc)
    win = window(WINDOWS[proc.range.window], cfg.n_samples)
    if rows.size == 0:
        rf = range_fft(adc, win)
    else:
        # One FFT of the whole frame, the flagged chirps (DC removed, repaired by the
        # `proc.interference.repair` method; the chip zeroes) swapped in first.
        x = windowed(adc, win, np.complex64 if cplx else np.float32)
        rep = repaired_rows(adc, dc, rows, flags, win, proc.interference)
        x.reshape(-1, cfg.n_samples)[rep.rows] = rep.windowed()
        if cplx:
            rf = scipy.fft.fft(x, axis=-1, workers=fft_workers(), overwrite_x=True)
        else:
            rf = scipy.fft.rfft(x, axis=-1, workers=fft_workers())[..., : cfg.n_samples // 2]
    if dc is not None:
        # FFT(w (x - m)) = FFT(w x) - m FFT(w): the window's spectrum has a few bins only.
        # The flagged chirps had their DC removed before the FFT.
        m = dc[..., 0]
        if rows.size:
            m = m.copy()
            m.reshape(-1)[rows] = 0
        for k, wk in window_spectrum(WINDOWS[proc.range.window], cfg.n_samples, cplx):
            rf[..., k] -= m * wk
    if proc.compression.enabled:
        rf, _ = ege_compress(rf, proc.compression.ratio, proc.compression.range_bins_per_block)
    return rf
