"""The CFAR detector of the chains: the training cells of candidate cells gathered from a small
cyclic table, a mode's compiled detector run in parts on the cores where it has one."""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..kernels import local_max_mask
from ..threads import run_parts, spans
from .base import training_offsets
from .modes import CFAR_MODES, noise_estimate

__all__ = ["training_table", "candidate_cfar", "cfar_peaks"]


@lru_cache(maxsize=32)
def training_table(size: int, guard_cells: int, window_cells: int, stride: int = 1) -> np.ndarray:
    """(size, 2 x window_cells) int: the cyclic training positions of every position along a
    CFAR axis of `size` cells, lagging cells first (read-only, cached per configuration)."""
    lag, lead = training_offsets(guard_cells, window_cells, stride)
    table = (np.arange(size)[:, None] + np.concatenate([lag, lead])) % size
    table.flags.writeable = False
    return table


def candidate_cfar(power: np.ndarray, cand: tuple[np.ndarray, ...], axis: int,
                   guard_cells: int, window_cells: int, mode: str,
                   os_rank: int, stride: int = 1) -> np.ndarray:
    """Noise estimate of a CFAR along a cyclic `axis`, only at candidate cells.

    The cyclic training positions of every position along `axis` come from a small
    (size, 2 x window_cells) table, so each candidate's training cells are one flat `take`;
    they are reduced with `modes.noise_estimate`. Equals `modes.cfar_map(...)[cand]`.

    Parameters
    ----------
    power : (...) float
    cand : tuple of (n,) int arrays
        Indices of the candidate cells (as from np.nonzero).
    axis : int
        The cyclic CFAR axis.
    stride : int
        Training-cell spacing, bins.

    Returns
    -------
    (n,) float
    """
    power = np.ascontiguousarray(power)
    size = power.shape[axis]
    step = int(np.prod(power.shape[axis + 1:], dtype=np.int64))  # flat step along `axis`
    table = training_table(size, guard_cells, window_cells, stride)  # (size, 2W)
    pos = cand[axis]
    row_start = np.ravel_multi_index(cand, power.shape) - pos * step
    train = power.reshape(-1)[row_start[:, None] + table[pos] * step]  # (n, 2W)
    return noise_estimate(train, window_cells, mode, os_rank)


def cfar_peaks(power: np.ndarray, mode: str, alpha: float, guard_cells: int,
               window_cells: int, os_rank: int, stride: int, neighbours: dict[int, bool],
               first_bin: int = 0) -> tuple:
    """Detections of a cyclic CFAR along the last axis among local maxima.

    A cell is a detection when it is a local maximum (`local_max_mask`) along the last axis
    (cyclic) and along the other axes listed in `neighbours`, its index on axis 1 is at least
    `first_bin`, and it exceeds `alpha` x the noise estimate of its training cells
    (`candidate_cfar`). A mode with a compiled detector (`CfarMode.peaks`) runs it; the others
    take `candidate_mask`, local maxima and gathered training cells; both give the same cells.

    Parameters
    ----------
    power : (n0, n1, n_cfar) float32
        Square-law map (DDMA: (azimuth, range, Doppler)); the compiled detector reads a
        C-contiguous copy of a strided one.
    mode : str
        Key of `modes.CFAR_MODES`.
    neighbours : {axis: cyclic}
        Axes 0 and/or 1 to check for a local maximum too (the last axis always is).

    Returns
    -------
    cells : tuple of three (n,) int arrays
        Indices of the detections, C order.
    noise, peak : (n,) float32
        Noise estimate (the mode's statistic) and power of each.
    """
    cm = CFAR_MODES[mode]
    if cm.compiled_peaks:
        # Rows of axis 0 in parts on the cores (`pipeline.threads`), joined in C order. A
        # strided map (the slot chains' range-Doppler sum is a view in their spectra's order)
        # is copied first: the compiled loops read contiguous rows in about half the time
        # (TDMA's 192 x 192 map: 0.25 -> 0.12 ms), the same values.
        power = np.ascontiguousarray(power)
        table = training_table(power.shape[-1], guard_cells, window_cells, stride)
        flags = (0 in neighbours, neighbours.get(0, False), 1 in neighbours,
                 neighbours.get(1, False))

        def part(span):
            idx, noise = cm.peaks(power, alpha, table, os_rank, flags, first_bin, span)
            return idx, noise, power[tuple(idx)]

        found = run_parts([lambda span=span: part(span) for span in spans(power.shape[0])])
        cells = tuple(np.concatenate([f[0] for f in found], axis=1))
        noise, peak = (np.concatenate([f[i] for f in found]) for i in (1, 2))
        return cells, noise, peak
    mask = cm.candidate_mask(power, 2, alpha, os_rank)
    mask[:, :first_bin] = False
    local_max_mask(power, {**neighbours, 2: True}, mask=mask)
    cand = np.unravel_index(np.flatnonzero(mask), power.shape)
    noise = candidate_cfar(power, cand, 2, guard_cells, window_cells, mode, os_rank, stride)
    peak = power[cand]
    hit = peak > alpha * noise
    return tuple(c[hit] for c in cand), noise[hit], peak[hit]
