"""TI's DC range-signature calibration (``calibDcRangeSig``): the antenna-coupling signature
of the range bins around DC, averaged over the first chirps of a run and then subtracted.

The mmWave SDK TDM demos (``MmwDemo_dcRangeSignatureCompensation``, xwr16xx/xwr18xx/xwr68xx
data path) keep one complex mean per Tx slot (the chirp's position in the loop), Rx and range
bin for the bins ``0 .. positiveBinIdx`` and ``n_range + negativeBinIdx .. n_range - 1`` of the
range-FFT output:

- the first ``numAvg`` loops (``numAvg x n_slots`` chirps, counted across frames) are
  accumulated and NOT compensated;
- at the last of them the sums are divided by ``2^floor(log2(numAvg))`` (the CLI requires a
  power of two) and from the next chirp on every chirp's bins have their slot's mean
  subtracted;
- a ``numAvg`` below the frame's Doppler bins (loops per frame) makes the demo disable the
  feature (``dcRangeForcedDisableCntr``).

`DcRangeSignature` is the estimate (`ProcessingConfig.dc_range_signature`, subtracted by
`pipeline.chirp_level.range_stage` after the range FFT); `DcSignatureCalibrator` runs the
calibration over a capture's frames as the chip does.

References
----------
.. [1] TI mmWave SDK 2.x/3.x demo ``data_path.c`` ``MmwDemo_dcRangeSignatureCompensation`` and
       ``MmwDemo_dataPathTask`` (forced disable); SDK 3.x user guide, "calibDcRangeSig".
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from core.errors import BadInput

__all__ = ["DcRangeSignature", "DcSignatureCalibrator", "signature_bins"]


def signature_bins(negative_bin: int, positive_bin: int, n_range: int) -> np.ndarray:
    """(n_bins,) int range bins the signature covers: 0 .. positive_bin, then
    n_range + negative_bin .. n_range - 1 (TI's order)."""
    return np.concatenate([np.arange(positive_bin + 1),
                           np.arange(n_range + negative_bin, n_range)]).astype(np.intp)


@dataclass(frozen=True, eq=False)
class DcRangeSignature:
    """A measured DC range signature (hashed by identity: it keys the shared range stage).

    Attributes
    ----------
    bins : (n_bins,) int
        Range bins (`signature_bins`).
    mean : (n_slots, n_rx, n_bins) complex64
        Mean range-FFT value of each Tx slot, Rx and bin.
    first_loop : int
        Loops of the frame before this one are not compensated (the frame in which the
        calibration completes); 0 otherwise.
    """

    bins: np.ndarray
    mean: np.ndarray
    first_loop: int = 0

    def __post_init__(self) -> None:
        if self.mean.ndim != 3 or self.mean.shape[2] != self.bins.size:
            raise BadInput(f"mean shape {self.mean.shape} must be (n_slots, n_rx, "
                           f"{self.bins.size} bins)")
        if self.first_loop < 0:
            raise BadInput(f"first_loop={self.first_loop} must be >= 0")

    def subtract(self, rf: np.ndarray) -> np.ndarray:
        """(C, R, B) range-FFT frame with the signature subtracted from its bins, from loop
        `first_loop` on (a new array; `rf` is not modified).

        Raises
        ------
        ValueError
            A frame whose chirps, Rx or bins do not fit the signature.
        """
        n_slots, n_rx, _ = self.mean.shape
        c, r, b = rf.shape
        if c % n_slots or r != n_rx or self.bins.max() >= b:
            raise BadInput(f"a ({c}, {r}, {b}) range-FFT frame does not fit a DC range "
                           f"signature of {n_slots} slots x {n_rx} Rx up to bin "
                           f"{self.bins.max()}")
        out = np.array(rf, copy=True)
        loops = out.reshape(c // n_slots, n_slots, r, b)
        sel = loops[self.first_loop:, :, :, self.bins]
        loops[self.first_loop:, :, :, self.bins] = sel - self.mean[None]
        return out


class DcSignatureCalibrator:
    """The chip's calibration over one radar's frames, in order (`process`).

    Parameters
    ----------
    negative_bin, positive_bin, num_avg : int
        ``calibDcRangeSig`` arguments (checked by the TI reader).
    n_slots : int
        Chirps per loop (Tx slots).
    """

    def __init__(self, negative_bin: int, positive_bin: int, num_avg: int, n_slots: int):
        self.negative_bin, self.positive_bin = negative_bin, positive_bin
        self.num_avg, self.n_slots = num_avg, n_slots
        self._sum: np.ndarray | None = None
        self._loops = 0
        self._signature: DcRangeSignature | None = None

    @property
    def signature(self) -> DcRangeSignature | None:
        """The estimate once `num_avg` loops were seen (compensating whole frames)."""
        return self._signature

    def process(self, rf: np.ndarray) -> DcRangeSignature | None:
        """Take one frame's uncompensated (C, R, B) range-FFT output; return the signature to
        subtract from THIS frame (None while calibrating; `first_loop` > 0 in the frame in
        which the calibration completes)."""
        if self._signature is not None:
            return self._signature
        c, r, b = rf.shape
        loops = rf.reshape(c // self.n_slots, self.n_slots, r, b)
        bins = signature_bins(self.negative_bin, self.positive_bin, b)
        take = min(self.num_avg - self._loops, loops.shape[0])
        part = loops[:take][..., bins].astype(np.complex128).sum(axis=0)
        self._sum = part if self._sum is None else self._sum + part
        self._loops += take
        if self._loops < self.num_avg:
            return None
        # TI divides by 2^floor(log2(numAvg)) (a shift); the CLI requires a power of two.
        mean = (self._sum / 2 ** int(np.floor(np.log2(self.num_avg)))).astype(np.complex64)
        mean.setflags(write=False)
        self._signature = DcRangeSignature(bins, mean)
        if take == loops.shape[0]:
            return None  # the frame's last loop completed it: the next frame is compensated
        return DcRangeSignature(bins, mean, first_loop=take)
