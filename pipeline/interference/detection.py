"""Interference detection of the chirp-level chain: statistics, thresholds and the flags of the
samples a burst hit ([TI-DAZ] section 2; TI SWRA725). The repair is `pipeline.interference.methods`.

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

from typing import NamedTuple

import numpy as np

from core.errors import BadInput

__all__ = ["interference_flags", "zero_flagged", "flagged_rows", "INTF_THRESHOLD_MODES",
           "IntfThresholdMode", "diff_statistics"]


class IntfThresholdMode(NamedTuple):
    """One HWA interference localisation mode (HWA_INTERFTHRESH_MODE_*): which statistics
    flag a sample and, with both, whether either or both must exceed their thresholds."""

    description: str
    magnitude: bool         # |x_n| > AbsThreshold
    difference: bool        # |x_n - x_{n-1}| > AbsDiffThreshold
    both_required: bool = False


#: Interference localisation modes by name, see `chirp_level`.
INTF_THRESHOLD_MODES = {
    "magdiff": IntfThresholdMode("|x_n - x_{n-1}| > AbsDiffThreshold (the DDM demo's RangeProc)",
                                 magnitude=False, difference=True),
    "mag": IntfThresholdMode("|x_n| > AbsThreshold", magnitude=True, difference=False),
    "mag_or_magdiff": IntfThresholdMode("either threshold", magnitude=True, difference=True),
    "mag_and_magdiff": IntfThresholdMode("both thresholds", magnitude=True, difference=True,
                                         both_required=True),
}


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
        d, thr = diff_statistics(a2, magdiff_snr_db)
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


def diff_statistics(a2: np.ndarray, snr_db: float) -> tuple[np.ndarray, np.ndarray]:
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


def flagged_rows(adc: np.ndarray, dc, intf) -> tuple[np.ndarray, np.ndarray]:
    """(chirp x Rx rows with a flagged sample, their (rows, n_samples) flags). A mode that
    uses the difference statistic alone (the demo's "magdiff") takes a fast path: a row is
    flagged iff its largest |dx| exceeds its threshold, and only those rows get their flags
    built. `intf`: the `InterferenceConfig` (its thresholds and mode)."""
    n = adc.shape[-1]
    a2 = adc.reshape(-1, n)
    if not INTF_THRESHOLD_MODES[intf.threshold_mode].magnitude:
        d, thr = diff_statistics(a2, intf.magdiff_snr_db)
        rows = np.flatnonzero(d.max(axis=-1) > thr)
        flags = np.zeros((rows.size, n), dtype=bool)
        np.greater(d[rows], thr[rows, None], out=flags[:, 1:])
        return rows, flags
    flags = interference_flags(adc, dc, intf.mag_snr_db, intf.magdiff_snr_db,
                               intf.threshold_mode).reshape(-1, n)
    rows = np.flatnonzero(flags.any(axis=-1))
    return rows, flags[rows]
