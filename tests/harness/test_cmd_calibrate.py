"""`radar-harness calibrate` end to end on a simulated IWR6843 capture with a known board."""
import re

import numpy as np
import pytest

import radarsim
from harness.cli import main
from harness.cli.cmd_calibrate import with_comp_line
from radarsim.capture import write_capture
from tests.pipeline.test_channel_calibration import BIAS_M, imbalanced_board, reflector_frames
from tests.radarsim.profiles import PROFILE_DIR

PROFILE = PROFILE_DIR / "xwr68_aop.cfg"


@pytest.fixture(scope="module")
def capture(tmp_path_factory):
    from radarsim.ti import parse_ti_cfg
    cfg = parse_ti_cfg(PROFILE).radar
    r = 40 * cfg.range_resolution_m - BIAS_M
    path = tmp_path_factory.mktemp("cal") / "reflector.bin"
    write_capture(path, reflector_frames(imbalanced_board(cfg), r, 0.0, 1e-4, 3, 7), cfg=cfg)
    return path, r


def test_prints_the_line_and_writes_the_profile(capture, tmp_path, capsys):
    path, r = capture
    out = tmp_path / "calibrated.cfg"
    assert main(["calibrate", str(path), "--cfg", str(PROFILE), "--target-range-m", f"{r}",
                 "--write", str(out)]) == 0
    line = capsys.readouterr().out.splitlines()[0]
    assert line.startswith("compRangeBiasAndRxChanPhase ")
    values = [float(v) for v in line.split()[1:]]
    assert len(values) == 1 + 2 * 12 and abs(values[0] - BIAS_M) < 2e-3
    text = out.read_text().splitlines()
    assert line in text
    assert sum(ln.startswith("compRangeBiasAndRxChanPhase") for ln in text) == 1
    assert len(text) == len(PROFILE.read_text().splitlines())


def test_no_target_in_window_exits_2_with_one_line(capture, capsys):
    path, r = capture
    assert main(["calibrate", str(path), "--cfg", str(PROFILE), "--target-range-m", "4.0",
                 "--search-window-m", "0.2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("radar-harness calibrate: error: --target-range-m 4 "
                             "--search-window-m 0.2: target too weak or absent")
    assert "below the limit 20 dB" in err[0]


def test_comp_line_goes_before_sensor_start_when_absent():
    text = "flushCfg\nchannelCfg 15 7 0\nsensorStart\n"
    assert with_comp_line(text, "compRangeBiasAndRxChanPhase 0.0 1 0") == \
        "flushCfg\nchannelCfg 15 7 0\ncompRangeBiasAndRxChanPhase 0.0 1 0\nsensorStart\n"


def test_processing_with_the_written_profile_puts_the_reflector_at_r(capture, tmp_path):
    """The loop a lab runs: calibrate, then process the same capture with the written
    profile: the static reflector at R (CRB of 3 frames at about 33 dB: 0.2 mm; 1 mm allowed),
    on boresight within a quarter of the 48-point azimuth grid, and static (extension on)."""
    import pandas as pd
    path, r = capture
    prof = tmp_path / "calibrated.cfg"
    assert main(["calibrate", str(path), "--cfg", str(PROFILE), "--target-range-m", f"{r}",
                 "--write", str(prof)]) == 0
    out = tmp_path / "points.csv"
    assert main(["process", str(path), "--cfg", str(prof), "--out", str(out), "--no-track"]) == 0
    pc = pd.read_csv(out)
    best = pc.loc[pc.groupby("frame").snr_db.idxmax()]
    assert np.all(np.abs(best.range_m - r) < 1e-3)
    assert np.all(np.abs(best.azimuth_deg) < np.degrees(np.arcsin(2 / 48)) / 4)
    assert np.all(np.abs(best.radial_velocity_mps) < 0.1)  # Vmax 1.62 m/s: never 2 Vmax


def test_wrong_coefficient_count_exits_2(capture, tmp_path, capsys):
    path, _ = capture
    text = PROFILE.read_text().replace(
        "compRangeBiasAndRxChanPhase 0.0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0",
        "compRangeBiasAndRxChanPhase 0.0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0")
    bad = tmp_path / "bad.cfg"
    bad.write_text(text)
    assert main(["process", str(path), "--cfg", str(bad), "--out", str(tmp_path / "p.csv"),
                 "--no-track"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "compRangeBiasAndRxChanPhase" in err[0]
    assert "17 values; the IWR6843 needs 25" in err[0]


def test_advanced_frame_profile_exits_2(capture, capsys):
    path, _ = capture
    prof = PROFILE_DIR / "xwr68_advanced_subframes.cfg"
    assert main(["calibrate", str(path), "--cfg", str(prof), "--target-range-m", "1.7"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is an advanced-frame profile" in err[0]


def test_target_and_window_from_the_profiles_measure_line(capture, tmp_path, capsys):
    """Without --target-range-m the profile's enabled ``measureRangeBiasAndRxChanPhase 1 X D``
    gives X and the window X +/- D/2 (TI's searchWin spans D); without either, exit 2."""
    path, r = capture
    text = PROFILE.read_text() + f"measureRangeBiasAndRxChanPhase 1 {r:.4f} 0.2\n"
    prof = tmp_path / "measure.cfg"
    prof.write_text(text)
    assert main(["calibrate", str(path), "--cfg", str(prof)]) == 0
    out = capsys.readouterr()
    assert out.out.startswith("compRangeBiasAndRxChanPhase 0.07")
    assert main(["calibrate", str(path), "--cfg", str(PROFILE)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["radar-harness calibrate: error: --target-range-m is required: the profile "
                   "has no enabled measureRangeBiasAndRxChanPhase line to take it from"]


def test_ddm_profile_gets_the_antenna_calib_form_and_one_correction(tmp_path, capsys):
    """A DDM demo profile (AWR2944P) whose antennaCalibParams already corrects: calibrate
    prints the antennaCalibParams form of the measurement too (Im, Re per chip virtual
    antenna) and --write resets the profile's own to the identity, so the written profile
    reads (one correction) and carries the measured coefficients."""
    from radarsim.ti import parse_ti_cfg
    from tests.radarsim.profiles import profile_text
    ident = "antennaCalibParams " + " ".join(["0 1"] * 16)
    text = profile_text("awr2944p_ddm").replace(ident, "antennaCalibParams " + " ".join(
        ["0.1 0.9"] * 16))
    prof_path = tmp_path / "ddm.cfg"
    prof_path.write_text(text)
    cfg = parse_ti_cfg(text).radar
    r = 12 * cfg.range_resolution_m
    cap = tmp_path / "ddm.bin"
    write_capture(cap, reflector_frames(imbalanced_board(cfg), r, 0.0, 1.0, 2, 3), cfg=cfg)
    out = tmp_path / "cal.cfg"
    assert main(["calibrate", str(cap), "--cfg", str(prof_path), "--target-range-m", f"{r}",
                 "--write", str(out)]) == 0
    comp, calib = capsys.readouterr().out.splitlines()[:2]
    assert comp.startswith("compRangeBiasAndRxChanPhase ")
    assert calib.startswith("antennaCalibParams ") and len(calib.split()) == 1 + 32
    re_im = [float(v) for v in comp.split()[2:]]
    im_re = [float(v) for v in calib.split()[1:]]
    assert re_im[0::2] == im_re[1::2] and re_im[1::2] == im_re[0::2]
    written = parse_ti_cfg(out)
    np.testing.assert_allclose(written.processing["channel_comp"],
                               np.reshape(re_im, (-1, 2)), atol=1e-12)
    assert ident in out.read_text()


def test_calibrate_then_process_a_board_with_leakage_and_a_positive_bias(tmp_path, capsys):
    """The lab loop on a board whose range bias (+0.3735 m) exceeds its Tx-to-Rx leakage path
    (0.1 m): calibrate measures the bias, and process -- tracker included -- runs with the
    written line on the same capture: the leakage at 0 m (TI's clamp), the reflector at R."""
    import pandas as pd

    from radarsim.ti import parse_ti_cfg
    cfg = parse_ti_cfg(PROFILE).radar
    board = imbalanced_board(cfg).replace(range_bias_m=0.3735, tx_leakage_dbfs=-20.0)
    r = 40 * cfg.range_resolution_m - 0.3735
    path = tmp_path / "leaky.bin"
    write_capture(path, reflector_frames(board, r, 0.0, 1e-4, 3, 11), cfg=cfg)
    prof = tmp_path / "calibrated.cfg"
    assert main(["calibrate", str(path), "--cfg", str(PROFILE), "--target-range-m", f"{r}",
                 "--search-window-m", "1.0", "--write", str(prof)]) == 0
    bias = float(capsys.readouterr().out.split()[1])
    assert abs(bias - 0.3735) < 2e-3
    out = tmp_path / "points.csv"
    assert main(["process", str(path), "--cfg", str(prof), "--out", str(out)]) == 0
    pc = pd.read_csv(out)
    assert (pc.range_m >= 0).all() and (pc.range_m == 0).any()
    # The reflector's cell (the leakage's window sidelobes wrap to the last range bins).
    cell = pc[np.abs(pc.range_bin - 40) <= 1]
    best = cell.loc[cell.groupby("frame").snr_db.idxmax()]
    assert len(best) == 3
    assert np.all(np.abs(best.range_m - r) < 1e-3)
    assert (tmp_path / "points_tracks.csv").exists()


def test_clipped_capture_exits_2(tmp_path, capsys):
    """A reflector strong enough to clip half the samples (the old code printed a line with
    'SNR 130 dB' and Rx gains of 0.0x dB where the unclipped capture gives the board's)."""
    from radarsim.ti import parse_ti_cfg
    cfg = parse_ti_cfg(PROFILE).radar
    r = 40 * cfg.range_resolution_m - BIAS_M
    path = tmp_path / "clipped.bin"
    with pytest.warns(radarsim.ADCSaturationWarning):
        write_capture(path, reflector_frames(imbalanced_board(cfg), r, 0.0, 1e4, 2, 7), cfg=cfg)
    assert main(["calibrate", str(path), "--cfg", str(PROFILE), "--target-range-m", f"{r}"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    want = (r"the capture is clipped: 2 of 2 frame\(s\) have samples at the ADC rails "
            r"\(up to 25 % of a frame.s values")
    assert len(err) == 1 and re.search(want, err[0]), err


def test_two_equal_reflectors_in_the_window_exit_2(tmp_path, capsys):
    """Two equal reflectors 1.5 bins apart merge into one peak (the old code measured the bias
    0.034 m off, half a bin)."""
    from radarsim.ti import parse_ti_cfg
    cfg = parse_ti_cfg(PROFILE).radar
    dr = cfg.range_resolution_m
    r = 40 * dr - BIAS_M
    sc = radarsim.Scatterers.from_spherical(np.array([r, r + 1.5 * dr]), np.zeros(2),
                                            np.zeros(2), np.zeros(2), np.array([1e-4, 1e-4]))
    rng = np.random.default_rng(7)
    path = tmp_path / "two.bin"
    board = imbalanced_board(cfg)
    write_capture(path, [radarsim.simulate_frame(board, sc, rng) for _ in range(3)], cfg=cfg)
    assert main(["calibrate", str(path), "--cfg", str(PROFILE), "--target-range-m", f"{r}"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and re.search(r"ambiguous reflector: a second return at 1\.\d+ m "
                                       r"\(-\d+\.\d dB from the strongest", err[0]), err


@pytest.mark.parametrize("which", ["capture", "profile", "capture_via_link"])
def test_write_never_replaces_an_input(capture, tmp_path, capsys, which):
    path, r = capture
    prof = tmp_path / "p.cfg"
    prof.write_text(PROFILE.read_text())
    target = {"capture": path, "profile": prof, "capture_via_link": tmp_path / "link.bin"}[which]
    if which == "capture_via_link":
        target.symlink_to(path)
    before = path.read_bytes(), prof.read_text()
    assert main(["calibrate", str(path), "--cfg", str(prof), "--target-range-m", f"{r}",
                 "--write", str(target)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    what = "--cfg" if which == "profile" else "CAPTURE"
    assert len(err) == 1 and re.search(rf"--write .* is the {what} file being read", err[0]), err
    assert (path.read_bytes(), prof.read_text()) == before
