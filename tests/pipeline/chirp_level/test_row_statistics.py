"""The one-pass row statistics against the numpy functions they replace, bit for bit."""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim
from pipeline.chirp_level.dc import remove_dc
from pipeline.chirp_level.stage import _chip_statistics
from pipeline.interference import flagged_rows
from pipeline.interference.row_statistics import row_flags, row_statistics

from .helpers import empty, one_interferer


@pytest.mark.parametrize("itf", [False, True])
@pytest.mark.parametrize("snr_db", [18.0, 6.0])
def test_row_statistics_equal_remove_dc_and_magdiff_flagged_rows(cfg, itf, snr_db):
    adc = radarsim.simulate_frame(cfg.replace(adc_dc_offset_lsb=-150.0), empty(),
                                  np.random.default_rng(5), one_interferer() if itf else None)
    proc = pipeline.ProcessingConfig().replace(intf_magdiff_snr_db=snr_db)
    st = row_statistics(adc, snr_db)
    dc = remove_dc(adc)
    rows, flags = flagged_rows(adc, dc, proc.interference)
    assert st.dc.tobytes() == dc.tobytes()
    assert np.array_equal(st.flagged, rows) and (rows.size > 0) == (itf or snr_db < 10)
    dc2, rows2, flags2 = _chip_statistics(adc, proc)
    assert dc2.tobytes() == dc.tobytes() and np.array_equal(rows2, rows)
    assert flags2.tobytes() == flags.tobytes()


def test_row_statistics_leave_frames_spanning_more_than_int16_to_numpy(cfg):
    """numpy's difference path is float32 there (its sums may round): no fused pass."""
    adc = radarsim.simulate_frame(cfg, empty(), np.random.default_rng(6))
    adc[3, 1, 7], adc[9, 0, 2] = 32767, -32768
    assert row_statistics(adc, 18.0) is None
    proc = pipeline.ProcessingConfig()
    dc, rows, flags = _chip_statistics(adc, proc)
    want_rows, want_flags = flagged_rows(adc, remove_dc(adc), proc.interference)
    assert np.array_equal(rows, want_rows) and flags.tobytes() == want_flags.tobytes()


def test_row_flags_are_numpys_int16_difference_compared_in_float32():
    """The compiled flags of chosen rows against numpy's formulation (int16 difference, its
    absolute value, float32 comparison), bit for bit: differences up to the int16 limit, and
    thresholds equal to a row's |dx|, one float32 step below it and between integers."""
    g = np.random.default_rng(3)
    adc = g.integers(-16384, 16384, (12, 3, 64)).astype(np.int16)  # |dx| up to 32767
    adc[2, 1, 5:9] = (-16384, 16383, -16384, 16383)
    a2 = adc.reshape(-1, 64)
    d = np.abs(np.subtract(a2[:, 1:], a2[:, :-1]))
    thr = np.float32(0.9) * d.max(axis=-1).astype(np.float32)
    thr[7] = d[7, 10]                                  # a flag needs |dx| > threshold
    thr[8] = np.nextafter(np.float32(d[8, 3]), np.float32(0))
    thr[9], thr[10] = 0.5, 0.0
    rows = np.array([0, 7, 8, 9, 10, 20, 35])
    want = np.zeros((rows.size, 64), dtype=bool)
    np.greater(d[rows], thr[rows, None], out=want[:, 1:])
    got = row_flags(adc, rows, thr)
    assert got.dtype == bool and got.tobytes() == want.tobytes()
    assert not want[1, 11] and want[2, 4] and want[3].sum() == 63 - (d[9] == 0).sum()
    assert row_flags(adc, rows[:0], thr).shape == (0, 64)
