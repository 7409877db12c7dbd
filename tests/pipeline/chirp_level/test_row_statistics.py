"""The one-pass row statistics against the numpy functions they replace, bit for bit."""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline.chirp_level.dc import remove_dc
from pipeline.chirp_level.interference import flagged_rows
from pipeline.chirp_level.row_statistics import row_statistics
from pipeline.chirp_level.stage import _chirp_statistics

from .helpers import empty, one_interferer


@pytest.mark.parametrize("itf", [False, True])
@pytest.mark.parametrize("snr_db", [18.0, 6.0])
def test_row_statistics_equal_remove_dc_and_magdiff_flagged_rows(cfg, itf, snr_db):
    adc = radarsim.simulate_frame(cfg.replace(adc_dc_offset_lsb=-150.0), empty(),
                                  np.random.default_rng(5), one_interferer() if itf else None)
    proc = pipeline.ProcessingConfig().replace(intf_magdiff_snr_db=snr_db)
    st = row_statistics(adc, snr_db)
    dc = remove_dc(adc)
    rows, flags = flagged_rows(adc, dc, proc)
    assert st.dc.tobytes() == dc.tobytes()
    assert np.array_equal(st.flagged, rows) and (rows.size > 0) == (itf or snr_db < 10)
    dc2, rows2, flags2 = _chirp_statistics(adc, proc)
    assert dc2.tobytes() == dc.tobytes() and np.array_equal(rows2, rows)
    assert flags2.tobytes() == flags.tobytes()


def test_row_statistics_leave_frames_spanning_more_than_int16_to_numpy(cfg):
    """numpy's difference path is float32 there (its sums may round): no fused pass."""
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(6))
    adc[3, 1, 7], adc[9, 0, 2] = 32767, -32768
    assert row_statistics(adc, 18.0) is None
    proc = pipeline.ProcessingConfig()
    dc, rows, flags = _chirp_statistics(adc, proc)
    want_rows, want_flags = flagged_rows(adc, remove_dc(adc), proc)
    assert np.array_equal(rows, want_rows) and flags.tobytes() == want_flags.tobytes()
