"""DC estimation and removal per chirp and Rx ([TI-DAZ] section 2)."""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline import chirp_level as cl
from pipeline.chirp_level.dc import subtract_dc, window_spectrum

from .helpers import OFF, empty


@pytest.mark.parametrize("win", ["rect", "hann", "blackman"])
def test_dc_removal_leaves_no_dc_bin(cfg, win):
    """A 500 LSB offset: after removal the rect-window DC bin is zero, and with any window the
    spectrum equals that of the offset-free frame with its own mean removed."""
    adc0 = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(3))
    adc1 = radarsim.simulate_frame(cfg.replace(adc_dc_offset_lsb=500.0), empty(),
                                   np.random.default_rng(3))
    proc = pipeline.ProcessingConfig().replace(range_window=win, dc_removal=True,
                                     interference_mitigation=False, compression=False)
    rf0, rf1 = cl.range_stage(cfg, adc0, proc), cl.range_stage(cfg, adc1, proc)
    raw = cl.range_stage(cfg, adc1, pipeline.ProcessingConfig().replace(range_window=win, **OFF))
    noise_bin = np.sqrt(np.mean(np.abs(raw[..., 10:]) ** 2))
    assert np.abs(raw[..., 0]).mean() > 100 * noise_bin       # the offset is there
    assert np.abs(rf1 - rf0).max() < 1e-3 * noise_bin * 100   # rounding ties only
    if win == "rect":
        assert np.abs(rf1[..., 0]).max() < 1e-3 * noise_bin


def test_subtract_dc_is_numpy_complex64_arithmetic_bit_for_bit():
    """`subtract_dc` against ``rf[..., k] -= m * w`` per window bin: random spectra and DC
    estimates over eight decades, signed zeros and an infinite estimate included, on a whole
    rFFT output (the Nyquist bin untouched)."""
    fix = window_spectrum("blackman", 64, False)
    bins = np.array([k for k, _ in fix], np.int64)
    weights = np.array([w for _, w in fix], np.complex64)
    g = np.random.default_rng(7)
    rf = (g.standard_normal((9, 3, 33)) * 10.0 ** g.uniform(-3, 5, (9, 3, 1))
          + 1j * g.standard_normal((9, 3, 33))).astype(np.complex64)
    m = (g.standard_normal((9, 3)) * 10.0 ** g.uniform(-3, 5, (9, 3))).astype(np.float32)
    m[0, :3] = (0.0, -0.0, np.inf)
    rf[0, 0, 0], rf[0, 1, 1] = complex(0.0, -0.0), complex(-0.0, 0.0)
    want = rf.copy()
    with np.errstate(invalid="ignore"):
        for k, w in fix:
            want[..., k] -= m * w
    subtract_dc(rf, m, bins, weights)
    assert bins.size >= 3 and rf.tobytes() == want.tobytes()
