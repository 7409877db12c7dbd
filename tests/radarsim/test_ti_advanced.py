"""Advanced frames (dfeDataOutputMode 3): one RadarConfig, CFAR and start time per sub-frame.

Hand computations for ``profiles/xwr68_advanced_subframes.cfg`` (c = 299792458 m/s):
sub-frame 0: profile 0, Tx1/Tx3 TDM, 2 chirps x 32 loops = 64 chirps of 7 + 24 = 31 us,
128 complex samples at 10 Msps, B = 100 MHz/us x 12.8 us = 1.28 GHz, dR = c / 2B = 0.117107 m;
sub-frame 1: profile 1, 2 x 16 = 32 chirps of 7 + 48 = 55 us, 256 samples at 8 Msps,
B = 30 MHz/us x 32 us = 0.96 GHz, dR = 0.156142 m, starts 40 ms into the 100 ms frame
(subFramePeriodicity 40 + 60 ms). Doppler CFAR thresholds 12 and 18 dB (cfarCfg 0 1 / 1 1).
"""
from __future__ import annotations

import pytest

from radarsim.ti import parse_ti_cfg, to_ti_cfg
from tests.radarsim.profiles import profile_text

C = 299_792_458.0
ADVANCED = profile_text("xwr68_advanced_subframes")


def test_each_subframe_is_its_own_radar():
    prof = parse_ti_cfg(ADVANCED)
    assert prof.is_advanced and len(prof.subframes) == 2
    assert prof.frame_period_s == pytest.approx(0.1)
    s0, s1 = prof.subframes
    assert (s0.radar.n_chirps, s0.radar.n_samples, s0.radar.n_tx, s0.radar.n_rx) == (64, 128, 2, 4)
    assert (s1.radar.n_chirps, s1.radar.n_samples) == (32, 256)
    assert s0.radar.chirp_period_s == pytest.approx(31e-6)
    assert s1.radar.chirp_period_s == pytest.approx(55e-6)
    assert s0.radar.range_resolution_m == pytest.approx(C / (2 * 100e12 * 12.8e-6))
    assert s1.radar.range_resolution_m == pytest.approx(C / (2 * 30e12 * 32e-6))
    assert (s0.subframe_start_s, s1.subframe_start_s) == (0.0, pytest.approx(0.04))
    assert (s0.cfar["doppler"].threshold_db, s1.cfar["doppler"].threshold_db) == (12.0, 18.0)
    assert s0.cfar["range"].peak_grouping is False and s1.cfar["range"].peak_grouping is True
    assert prof.radar == s0.radar and [p.subframe_index for p in prof.parts] == [0, 1]


def test_frame_mode_profile_has_one_part():
    prof = parse_ti_cfg(profile_text("xwr68_tx13"))
    assert not prof.is_advanced and prof.parts == (prof,)


def _edit(old: str, new: str) -> tuple[str, int]:
    assert old in ADVANCED
    text = ADVANCED.replace(old, new, 1)
    no = next(k for k, line in enumerate(text.splitlines(), 1) if line.startswith(new.split()[0])
              and new in line)
    return text, no


BAD = {
    "subframe_index_out_of_range": ("cfarCfg 1 1 0 4 2 3 1 18.0 1", "cfarCfg 2 1 0 4 2 3 1 18.0 1",
                                    r"subFrameIdx=2 is outside -1..1 \(advFrameCfg "
                                    r"numOfSubFrames=2"),
    "subframe_number_out_of_range": ("subFrameCfg 1 0 2 2 16 60 0 1 1 60",
                                     "subFrameCfg 2 0 2 2 16 60 0 1 1 60",
                                     r"subFrameNum=2 is outside 0..1"),
    "several_bursts": ("subFrameCfg 1 0 2 2 16 60 0 1 1 60", "subFrameCfg 1 0 2 2 16 60 0 2 1 60",
                       r"numOfBurst=2, numOfBurstLoops=1: a sub-frame of several bursts"),
    "period_shorter_than_burst": ("subFrameCfg 1 0 2 2 16 60 0 1 1 60",
                                  "subFrameCfg 1 0 2 2 16 60 0 1 1 50",
                                  r"subFramePeriodicity=50 ms must be >= burstPeriodicity=60"),
    "burst_longer_than_its_period": ("subFrameCfg 0 0 0 2 32 40 0 1 1 40",
                                     "subFrameCfg 0 0 0 2 32 1.5 0 1 1 40",
                                     r"burstPeriodicity=1.5 ms is shorter than the chirp burst"),
    "too_many_subframes": ("advFrameCfg 2 0 0 1 0", "advFrameCfg 5 0 0 1 0",
                           r"numOfSubFrames=5 is outside 1..4"),
    "force_profile": ("advFrameCfg 2 0 0 1 0", "advFrameCfg 2 1 0 1 0",
                      r"forceProfile=1 .* not modelled"),
    "duplicated_subframe_cfar": ("cfarCfg 1 0 2 8 4 3 0 15.0 1",
                                 "cfarCfg 1 1 0 4 2 3 1 15.0 1",
                                 r"line 26 \(cfarCfg\): duplicate of line 25 \(cfarCfg 1 1 0 4 2 3 "
                                 r"1 15.0 1\)"),
}


@pytest.mark.parametrize("kind", sorted(BAD))
def test_bad_advanced_frame_line_names_line_value_and_limit(kind):
    old, new, pattern = BAD[kind]
    text, no = _edit(old, new)
    with pytest.raises(ValueError, match=pattern) as err:
        parse_ti_cfg(text)
    assert f"line {no}" in str(err.value)


def test_missing_subframe_cfg_is_named():
    text = ADVANCED.replace("subFrameCfg 1 0 2 2 16 60 0 1 1 60\n", "")
    with pytest.raises(ValueError, match=r"no subFrameCfg for sub-frame\(s\) \[1\]"):
        parse_ti_cfg(text)


def test_advanced_frame_round_trips_through_the_writer():
    """to_ti_cfg writes advFrameCfg, one profileCfg / chirp block / subFrameCfg / cfarCfg set
    per sub-frame (SDK 3.x 9-argument cfarCfg on the xWR68xx): the same sub-frames come back."""
    prof = parse_ti_cfg(ADVANCED)
    text = to_ti_cfg(prof)
    assert "dfeDataOutputMode 3" in text and "advFrameCfg 2 0 0 1 0" in text
    assert "subFrameCfg 1 0 2 2 16 60 0 1 1 60" in text
    assert "cfarCfg 1 1 0 4 2 3 1 18 1" in text.splitlines()
    back = parse_ti_cfg(text)
    assert [p.radar for p in back.parts] == [p.radar for p in prof.parts]
    assert [p.cfar for p in back.parts] == [p.cfar for p in prof.parts]
    assert [p.subframe_start_s for p in back.parts] == [0.0, pytest.approx(0.04)]
