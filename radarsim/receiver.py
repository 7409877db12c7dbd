"""Receiver model shared by the echo and interference paths: the IF anti-alias low-pass.

The chip's IF chain low-passes the beat signal before the ADC; both the front end
(`radarsim.frontend`, echoes) and the interference model (`radarsim.interference`, chirped
bursts sweeping through the passband) weight their signals with the same filter, so it lives
here, below both.

References
----------
.. [1] TI, AWR2944 data sheet (SWRS273), receive subsystem: IF bandwidth and filters.
.. [2] S. Butterworth, "On the theory of filter amplifiers", Wireless Engineer 7, 1930
       (maximally flat magnitude |H|^2 = 1 / (1 + (f / f_c)^(2n))).
"""
from __future__ import annotations

import numpy as np

__all__ = ["IF_LOWPASS_HZ", "IF_LOWPASS_ORDER", "if_filter_gain", "if_corner_hz"]

#: -3 dB corner of the AWR2944's IF anti-alias low-pass, Hz: just above the 15 MHz usable IF
#: band, so targets up to ~240 m lose < 0.2 dB and echoes beyond the 253 m Nyquist range are
#: attenuated (-7.5 dB at 300 m, -31 dB at 400 m) rather than aliasing at full strength. Each
#: chip's corner is `radarsim.chips.Chip.if_lowpass_hz`.
IF_LOWPASS_HZ = 16.5e6
#: Butterworth order of that low-pass.
IF_LOWPASS_ORDER = 10


def if_filter_gain(beat_hz: np.ndarray, corner_hz: float = IF_LOWPASS_HZ) -> np.ndarray:
    """Power gain of the IF anti-alias low-pass (Butterworth magnitude), linear.

    Parameters
    ----------
    beat_hz : (K,) float
        Beat frequency, Hz.
    corner_hz : float
        -3 dB corner, Hz (default the AWR2944's).
    """
    return 1.0 / (1.0 + (np.abs(beat_hz) / corner_hz) ** (2 * IF_LOWPASS_ORDER))


def if_corner_hz(cfg) -> float:
    """-3 dB corner of the receive chain's anti-alias low-pass of a `radarsim.RadarConfig`, Hz.

    The analog IF filter's (`radarsim.chips.Chip.if_lowpass_hz`, just above the chip's IF
    bandwidth) or, when the ADC samples a narrower band, 1.1 x that band (real: f_s / 2,
    complex: f_s): the chip's decimation filter follows the sampling rate, so an echo beyond
    the max range is attenuated before it aliases. For the R79 waveform both are 16.5 MHz."""
    return min(cfg.chip_spec.if_lowpass_hz, 1.1 * cfg.max_beat_frequency_hz)
