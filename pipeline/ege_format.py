"""The EGE block format of the HWA compression engine: k-array, header, output scale and code
budget (seed 000 section 5.2; TI MMWAVE-MCUPLUS-SDK DDM demo, rangeprochwaDDMA.c). Both the
processing config (which checks that a radar's blocks can be compressed at all) and the
chirp-level compression model (`pipeline.chirp_level.ege`) read it; it imports neither.
"""
from __future__ import annotations

import numpy as np

__all__ = ["HWA_OUTPUT_SCALE", "EGE_K_ARRAY", "EGE_HEADER_BITS", "ege_min_ratio",
           "ege_budget_bits"]

#: Range-FFT value -> 16-bit HWA output LSB: the demo's range FFT scales its last 3 butterfly
#: stages by 1/2 (butterflyScaling = 7), i.e. 1/8 of the unscaled FFT of the int16 samples.
HWA_OUTPUT_SCALE = 1.0 / 8.0
#: EGE orders of the k-array: EGEKarrayLength = 3 (8 entries), the values the DDM demo's
#: RangeProc programs (rangeprochwaDDMA.c, ``rangeProcHWA_ConfigHWACommon``: EGEKparam).
EGE_K_ARRAY = np.array([3, 4, 5, 7, 9, 11, 13, 15])
#: Block header: scale factor (scaleFactorBW = 4) + k index (3 bits).
EGE_HEADER_BITS = 4 + 3


def ege_budget_bits(n_rx: int, range_bins_per_block: int, ratio: float) -> int:
    """Code bits of one block (header excluded) at `ratio` of its 32-bit complex samples."""
    return int(np.floor(ratio * 32 * n_rx * range_bins_per_block)) - EGE_HEADER_BITS


def ege_min_ratio(n_rx: int, range_bins_per_block: int) -> float:
    """Smallest compression ratio whose budget holds a block of zeros: every one of its
    2 n_rx range_bins_per_block I/Q values needs 2 + k bits with the smallest k of the
    k-array, plus the header (0.32 for the demo's 4 Rx x 8 bins and k >= 3)."""
    n_val = 2 * n_rx * range_bins_per_block
    need = n_val * (2 + int(EGE_K_ARRAY.min())) + EGE_HEADER_BITS
    return need / (32 * n_rx * range_bins_per_block)

