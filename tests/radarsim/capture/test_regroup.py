"""One chirp per frame (vital signs, vibration): N frames regrouped into one frame of N chirps
at the frame period (`radarsim.capture.regroup`, ``process --regroup-frames``)."""
import re

import numpy as np
import pytest

import radarsim
from harness.cli import main
from radarsim.capture import write_capture
from radarsim.capture.regroup import chirps_per_frame, regroup_profile
from tests.radarsim.profiles import profile_text

#: A vital-signs style profile: the AWR1843 Visualizer profile with one Tx and one chirp per
#: frame every 50 ms.
ONE_CHIRP = re.sub(r"(?m)^chirpCfg [12] .*\n", "", profile_text("xwr18_visualizer"))
ONE_CHIRP = re.sub(r"(?m)^frameCfg .*$", "frameCfg 0 0 1 0 50 1 0", ONE_CHIRP)
ONE_CHIRP = re.sub(r"(?m)^channelCfg 15 7 0$", "channelCfg 15 1 0", ONE_CHIRP)


def test_chirps_per_frame():
    assert chirps_per_frame(ONE_CHIRP) == 1
    assert chirps_per_frame(profile_text("xwr18_visualizer")) == 3 * 16


def test_regrouped_radar_samples_slow_time_at_the_frame_period():
    """N = 64 frames of 50 ms: 64 chirps at T = 50 ms, Vmax = lambda / (4 T), resolution
    lambda / (2 N T) (77 GHz: 1.947 cm/s and 0.61 mm/s), frame period 3.2 s."""
    prof = regroup_profile(ONE_CHIRP, 64)
    cfg = prof.radar
    lam = radarsim.config.C_MPS / cfg.start_freq_hz
    assert cfg.n_chirps == 64 and cfg.n_tx == 1
    assert cfg.chirp_period_s == pytest.approx(0.05)
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(lam / (4 * 0.05))
    assert cfg.velocity_resolution_mps == pytest.approx(lam / (2 * 64 * 0.05))
    assert prof.frame_period_s == pytest.approx(3.2)


_TOO_MANY = radarsim.chips.CHIPS["AWR1843"].max_chirps + 1


@pytest.mark.parametrize("n, match", [
    (1, r"--regroup-frames=1 must be an integer >= 2"),
    (_TOO_MANY, rf"--regroup-frames {_TOO_MANY}: n_chirps={_TOO_MANY} exceeds the AWR1843 "
                "limit")])
def test_bad_regroup_counts(n, match):
    with pytest.raises(ValueError, match=match):
        regroup_profile(ONE_CHIRP, n)


def test_multi_chirp_profiles_are_not_regrouped():
    with pytest.raises(ValueError, match="frames hold 48 chirps; regrouping builds slow time "
                                         "from one-chirp frames only"):
        regroup_profile(profile_text("xwr18_visualizer"), 8)


@pytest.fixture(scope="module")
def vital(tmp_path_factory):
    """192 one-chirp frames of a reflector at 1 m, 10 deg, moving 1 cm/s."""
    d = tmp_path_factory.mktemp("vital")
    cfg_path = d / "vital.cfg"
    cfg_path.write_text(ONE_CHIRP)
    cfg = regroup_profile(ONE_CHIRP, 64).radar
    sc = radarsim.Scatterers.from_spherical(np.array([1.0]), np.array([10.0]), np.zeros(1),
                                            np.array([0.01]), np.array([0.01]))
    cap = d / "vital.bin"
    write_capture(cap, [radarsim.simulate_frame(cfg, sc, np.random.default_rng(i))
                        for i in range(3)], cfg=cfg)
    return cap, cfg_path, cfg


def test_process_regroups_and_reports_the_slow_motion(vital, tmp_path):
    """The reflector at its range (half a bin), azimuth (1 deg) and 1 cm/s (one velocity bin
    of the regrouped frame, 0.6 mm/s), one regrouped frame every 3.2 s."""
    import pandas as pd
    cap, cfg_path, cfg = vital
    out = tmp_path / "p.csv"
    assert main(["process", str(cap), "--cfg", str(cfg_path), "--out", str(out), "--no-track",
                 "--regroup-frames", "64"]) == 0
    pc = pd.read_csv(out)
    best = pc.loc[pc.groupby("frame").snr_db.idxmax()]
    assert list(best.frame) == [0, 1, 2]
    np.testing.assert_allclose(best.time_s, [0.0, 3.2, 6.4])
    assert np.all(np.abs(best.range_m - 1.0) <= cfg.range_resolution_m / 2)
    assert np.all(np.abs(best.azimuth_deg - 10.0) <= 1.0)
    assert np.all(np.abs(best.radial_velocity_mps - 0.01) <= cfg.velocity_resolution_mps)


def test_one_chirp_profile_without_the_option_exits_2(vital, tmp_path, capsys):
    cap, cfg_path, _ = vital
    assert main(["process", str(cap), "--cfg", str(cfg_path), "--out",
                 str(tmp_path / "p.csv"), "--no-track"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "has one chirp per frame: give --regroup-frames N" in err[0]


def test_count_that_does_not_divide_exits_2(vital, tmp_path, capsys):
    cap, cfg_path, _ = vital
    assert main(["process", str(cap), "--cfg", str(cfg_path), "--out",
                 str(tmp_path / "p.csv"), "--no-track", "--regroup-frames", "50"]) == 2
    err = [ln for ln in capsys.readouterr().err.strip().splitlines()
           if not ln.startswith("note:")]
    assert err == ["radar-harness process: error: --regroup-frames 50 does not divide the "
                   "capture's 192 frames (3 x 50 + 42)"]


def test_regrouping_reads_a_commented_profile_as_a_cfg_and_refuses_a_logfile():
    """The kind decision is `radarsim.ti.setup_kind`'s, here as in `parse_setup`: LogFile lines
    quoted in comments change nothing; a LogFile is refused by name."""
    from tests.radarsim.profiles import PROFILE_DIR
    quoted = "% API:ChannelConfig,3,15,0 -> Tx mask 3\n% frameCfg 0 0 64 0 50 1 0\n" + ONE_CHIRP
    got, want = regroup_profile(quoted, 8), regroup_profile(ONE_CHIRP, 8)
    assert (got.radar, got.frame_period_s) == (want.radar, want.frame_period_s)
    log = (PROFILE_DIR / "awr2243_studio_LogFile.txt").read_text()
    with pytest.raises(ValueError, match="--regroup-frames 8: the profile is an mmWave Studio "
                                         "LogFile; regrouping reads TI CLI profiles"):
        regroup_profile(log, 8)
