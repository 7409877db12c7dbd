"""The EGE block format of the HWA compression engine: k-array, header, output scale and code
budget ([TI-DDMA] section 5.2; TI MMWAVE-MCUPLUS-SDK DDM demo, rangeprochwaDDMA.c). Both the
processing config (which checks that a radar's blocks can be compressed at all) and the
chirp-level compression model (`pipeline.chirp_level.ege`) read it; it imports neither.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from core.checks import require
from core.errors import BadInput

__all__ = ["HWA_OUTPUT_SCALE", "EGE_K_ARRAY", "EGE_HEADER_BITS", "ege_min_ratio",
           "ege_budget_bits", "CompressionConfig"]

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



@dataclass(frozen=True, kw_only=True, slots=True)
class CompressionConfig:
    """EGE compression/decompression of the range-FFT cube (``compressionCfg``).

    Parameters
    ----------
    enabled : bool
        Compress and decompress (default on).
    ratio : float
        Compressed / raw size, in [0.25, 1) (the demo: 0.5); a radar also needs at least
        `ege_min_ratio` for its block (0.32 for 4 Rx x 8 bins), which
        `pipeline.ProcessingConfig.check_radar` tests.
    range_bins_per_block : int
        Range bins per block (blocks hold all Rx; the demo: 8), a power of 2 in 1..32.
    """

    enabled: bool = True
    ratio: float = 0.5
    range_bins_per_block: int = 8

    def __post_init__(self) -> None:
        require(self, "enabled", "bool")
        require(self, "ratio", ge=0.25, lt=1)
        b = self.range_bins_per_block
        if isinstance(b, bool) or not isinstance(b, int) or b not in (1, 2, 4, 8, 16, 32):
            raise BadInput(f"range_bins_per_block={b!r} must be a power of 2 in 1..32")

    def check_cube(self, n_rx: int, n_range_bins: int) -> None:
        """Raise if the blocks cannot tile a radar's range bins, or the ratio leaves no room
        for the shortest EG code of the demo's k-array (`ege_min_ratio`); nothing when off."""
        if not self.enabled:
            return
        b = self.range_bins_per_block
        if n_range_bins % b:
            raise BadInput(f"compression_range_bins_per_block={b} does not divide the "
                           f"radar's {n_range_bins} range bins")
        lo = ege_min_ratio(n_rx, b)
        if self.ratio < lo:
            raise BadInput(f"compression_ratio={self.ratio:g} is below {lo:.4f}, the smallest "
                           f"a block of {n_rx} Rx x {b} range bins fits with the demo's EG "
                           "k-array (k >= 3: at least 5 bits per I/Q value)")
