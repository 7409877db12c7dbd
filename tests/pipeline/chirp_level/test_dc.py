"""DC estimation and removal per chirp and Rx ([TI-DAZ] section 2)."""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline import chirp_level as cl

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
