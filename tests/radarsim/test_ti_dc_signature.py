"""``calibDcRangeSig`` read as the SDK 3.x demo's CLI reads it, and run by
``radar-harness process`` as the chip runs it (`pipeline.dc_range_signature`)."""
import numpy as np
import pandas as pd
import pytest

import radarsim
from harness.cli import main
from radarsim.capture import write_capture
from radarsim.ti import parse_ti_cfg, to_ti_cfg
from tests.radarsim.profiles import profile_text

OFF = "calibDcRangeSig -1 0 -5 8 256"


def _tx13(line: str) -> str:
    text = profile_text("xwr68_tx13")
    assert OFF in text
    return text.replace(OFF, line)


def test_enabled_line_gives_bins_loops_and_slots():
    """xwr68_tx13: 2 Tx TDM, 16 loops per frame; numAvg 32 >= 16 runs."""
    prof = parse_ti_cfg(_tx13("calibDcRangeSig -1 1 -5 8 32"))
    assert prof.dc_range_signature == (-5, 8, 32, 2)
    assert parse_ti_cfg(to_ti_cfg(prof)).dc_range_signature == (-5, 8, 32, 2)
    assert not any("calibDcRangeSig" in n for n in prof.notes)
    assert parse_ti_cfg(_tx13(OFF)).dc_range_signature is None


def test_num_avg_below_the_doppler_bins_is_disabled_as_the_demo_does():
    prof = parse_ti_cfg(_tx13("calibDcRangeSig -1 1 -5 8 8"))
    assert prof.dc_range_signature is None
    assert any("numAvg=8 is below the 16 Doppler bins" in n and "disables it" in n
               for n in prof.notes)


@pytest.mark.parametrize("line, match", [
    ("calibDcRangeSig -1 1 2 8 32", r"negativeBinIdx=2 .*0"),
    ("calibDcRangeSig -1 1 -20 20 32", r"bins -20\.\.20 are 41; the demo takes at most 32"),
    ("calibDcRangeSig -1 1 -5 8 48", r"numAvg=48 is not a power of two"),
])
def test_cli_checks(line, match):
    with pytest.raises(ValueError, match=match):
        parse_ti_cfg(_tx13(line))


def test_process_removes_the_coupling_after_the_calibration_frames(tmp_path):
    """Tx-to-Rx leakage at -20 dBFS (a static tone 0.1 m out) and a target moving at
    0.5 m/s in range bin 5 (inside the signature's bins 0..8): without calibDcRangeSig the
    leakage is detected in every frame; with numAvg = 32 loops (two 16-loop frames) frames 0
    and 1 still show it (measured, not compensated) and frames 2-3 do not, while the moving
    target (zero mean over the chirps) stays detected in every frame."""
    text = _tx13("calibDcRangeSig -1 1 -5 8 32")
    prof = parse_ti_cfg(text)
    board = prof.radar.replace(tx_leakage_dbfs=-20.0)
    r = 5 * prof.radar.range_resolution_m
    sc = radarsim.Scatterers.from_spherical(np.array([r]), np.zeros(1), np.zeros(1),
                                            np.array([0.5]), np.array([0.05]))
    rng = np.random.default_rng(7)
    cap = tmp_path / "leak.bin"
    write_capture(cap, [radarsim.simulate_frame(board, sc, rng) for _ in range(4)],
                  cfg=prof.radar)
    out = {}
    for name, cfg_text in (("on", text), ("off", _tx13(OFF))):
        p = tmp_path / f"{name}.cfg"
        p.write_text(cfg_text)
        csv = tmp_path / f"{name}.csv"
        assert main(["process", str(cap), "--cfg", str(p), "--out", str(csv),
                     "--no-track"]) == 0
        out[name] = pd.read_csv(csv)
    for name, leak_frames in (("off", {0, 1, 2, 3}), ("on", {0, 1})):
        pc = out[name]
        leak = pc[(pc.range_bin <= 3) & (pc.doppler_bin == 0)]
        assert set(leak.frame) == leak_frames, (name, leak[["frame", "range_bin"]])
        target = pc[(pc.range_bin - 5).abs() <= 1]
        assert set(target.frame) == {0, 1, 2, 3}, name


def test_multi_obj_beamforming_disabled_keeps_one_peak_and_enabled_on_tdma_is_noted():
    """Disabled: the strongest azimuth peak only (TI's one object per cell), modelled, no
    note. Enabled on the TDMA chain (one peak per cell by construction): listed on the one
    'read but not modelled' line, with the saturation monitor."""
    from harness.cell.ti_profile import processing_from_profile
    from radarsim.ti.processing_handlers import ONE_PEAK_DB
    on = "multiObjBeamForming -1 1 0.5"
    off = parse_ti_cfg(profile_text("xwr68_tx13").replace(on, "multiObjBeamForming -1 0 0.5"))
    notes = []
    assert processing_from_profile(off, notes).angle.azimuth_sidelobe_db == ONE_PEAK_DB
    assert not any("multiObjBeamForming" in n for n in notes + list(off.notes))
    notes = []
    proc = processing_from_profile(parse_ti_cfg(profile_text("xwr68_tx13")), notes)
    assert proc.angle.azimuth_sidelobe_db == pytest.approx(20 * np.log10(2))
    lines = [n for n in notes if n.startswith("read but not modelled: ")]
    assert len(lines) == 1
    assert "multiObjBeamForming enabled (the tdma chain" in lines[0]
    assert "CQRxSatMonitor" in lines[0]
