"""Fast/slow chirp frames as TI profiles (`radarsim.ti.fast_slow`): an advanced frame of two
TDMA sub-frames whose chirp profiles differ only in idle time, read and written."""
import numpy as np
import pytest

import radarsim
from harness.cli import main
from radarsim.mimo import MIMO_SCHEMES, register_scheme
from radarsim.mimo.fast_slow import FastSlowScheme
from radarsim.ti import from_ti_cfg, parse_ti_cfg, to_ti_cfg
from tests.radarsim.profiles import profile_text

LAMBDA_M = 299_792_458.0 / 77e9


def test_srr_style_profile_reads_as_one_fast_slow_radar():
    """Hand-computed from the file: T_f = 3 + 56 = 59 us, T_s = 14.8 + 56 = 70.8 us (ratio
    1.2, the registered fast_slow's); the mean chirp 64.9 us (idle 8.9 us); 2 x 64 loops x 2
    chirps = 256 chirps; V_f = lambda / (4 x 2 x 59 us) = 8.249 m/s, unfolded 4 V_f =
    32.99 m/s. parse_ti_cfg still sees the two sub-frames (each a 2-Tx TDMA loop)."""
    text = profile_text("xwr18_fast_slow_srr")
    cfg = from_ti_cfg(text)
    assert (cfg.chip, cfg.mimo, cfg.n_tx, cfg.tx_channels, cfg.n_chirps) == \
        ("AWR1843", "fast_slow", 2, (1, 3), 256)
    assert cfg.idle_time_s == pytest.approx(8.9e-6, rel=1e-12)
    assert cfg.chirp_period_s == pytest.approx(64.9e-6, rel=1e-12)
    sets = cfg.scheme.chirp_sets(cfg)
    assert sets.fast_period_s == pytest.approx(59e-6, rel=1e-12)
    assert sets.slow_period_s == pytest.approx(70.8e-6, rel=1e-12)
    assert sets.n_doppler_bins == 64
    assert cfg.scheme.native_max_velocity_mps(cfg) == pytest.approx(LAMBDA_M / (8 * 59e-6))
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(32.99, abs=0.01)
    subs = parse_ti_cfg(text).subframes
    assert [p.radar.mimo for p in subs] == ["tdma", "tdma"]
    assert [p.radar.idle_time_s for p in subs] == [3e-6, 14.8e-6]


def test_r79_fast_slow_round_trip():
    """The R79 preset writes as two sub-frames (idle 2.84 / 7.16 us on TI's 10 ns grid,
    96 loops of 4 TDMA chirps each, sub-frame 0's periodicity = its 8.3136 ms burst) and
    reads back equal."""
    cfg = radarsim.presets.r79("fast_slow")
    text = to_ti_cfg(cfg)
    assert "profileCfg 0 77 2.84 5 18.81" in text and "profileCfg 1 77 7.16 5 18.81" in text
    assert "subFrameCfg 0 0 0 4 96 8.3136 0 1 1 8.3136" in text
    assert "subFrameCfg 1 0 4 4 96 9.97248 " in text
    assert from_ti_cfg(text) == cfg


@pytest.fixture
def slow_first():
    register_scheme(FastSlowScheme("fs_slow_first", "", slow_first=True))
    yield "fs_slow_first"
    del MIMO_SCHEMES["fs_slow_first"]


def test_slow_first_round_trip_names_its_scheme(slow_first):
    """The set order is part of the match: sub-frame 0 slow reads as the slow-first scheme."""
    cfg = radarsim.presets.r79(slow_first)
    text = to_ti_cfg(cfg)
    assert "profileCfg 0 77 7.16" in text
    assert from_ti_cfg(text) == cfg


def test_other_advanced_frames_are_untouched():
    """Sub-frames that differ in more than idle time (near / far profiles) are separate
    radars: from_ti_cfg gives sub-frame 0's, as before."""
    text = profile_text("xwr68_advanced_subframes")
    assert from_ti_cfg(text) == parse_ti_cfg(text).radar


def _edited(**replace) -> str:
    text = profile_text("xwr18_fast_slow_srr")
    for old, new in replace.items():
        assert old in text
        text = text.replace(old, new)
    return text


UNEQUAL = {"subFrameCfg 1 0 2 2 64 9.0624": "subFrameCfg 1 0 2 2 32 9.0624"}
UNKNOWN_RATIO = {"profileCfg 1 77 14.8": "profileCfg 1 77 20",
                 "subFrameCfg 1 0 2 2 64 9.0624": "subFrameCfg 1 0 2 2 64 9.728"}


def test_unequal_sets_refused():
    with pytest.raises(ValueError, match=r"subFrameCfg: sub-frames 0 and 1 are a fast/slow chirp "
                                         r"pair .* n_chirps=128 and 64: .* must be equal"):
        from_ti_cfg(_edited(**UNEQUAL))


def test_ratio_of_no_registered_scheme_refused():
    """Idle 20 us: T_s / T_f = 76 / 59 = 1.28814, no registered scheme's."""
    with pytest.raises(ValueError, match=r"T_s / T_f = 76 / 59 us = 1\.28814, which no registered "
                                         r"fast/slow scheme \(fast_slow: 1\.2\) matches .* "
                                         r"slow_period_ratio=1\.28814"):
        from_ti_cfg(_edited(**UNKNOWN_RATIO))


@pytest.mark.parametrize("edit", [UNEQUAL, UNKNOWN_RATIO], ids=["unequal", "ratio"])
def test_bad_fast_slow_profile_in_a_sweep_exits_2(tmp_path, capsys, edit):
    (tmp_path / "fs.cfg").write_text(_edited(**edit))
    f = tmp_path / "s.toml"
    f.write_text('name = "p"\nscenarios = ["slow"]\nschemes = ["fast_slow"]\n'
                 'baseline_scheme = "fast_slow"\n[[variants]]\nname = "fs"\n'
                 'radar = {profile = "fs.cfg"}\n')
    assert main(["sweep", str(f), "--out", str(tmp_path / "r"), "--workers", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "radar.profile=" in err[0] and "fast/slow chirp pair" in err[0]


def test_fast_slow_profile_runs_in_a_sweep_cell(tmp_path):
    """The SRR-style profile as a sweep variant builds the fast/slow radar of the file."""
    from harness.cell.config import radar_config
    path = tmp_path / "fs.cfg"
    path.write_text(profile_text("xwr18_fast_slow_srr"))
    cfg = radar_config({"profile": str(path)}, "fast_slow")
    assert (cfg.mimo, cfg.n_chirps) == ("fast_slow", 256)
    sc = radarsim.Scatterers.from_spherical(np.array([30.0]), np.array([10.0]), np.zeros(1),
                                            np.array([-25.0]), np.array([10.0]))
    import pipeline
    pc = pipeline.process_frame(cfg, radarsim.simulate_frame(cfg, sc, np.random.default_rng(0)))
    best = pc.loc[pc.snr_db.idxmax()]
    assert best.radial_velocity_mps == pytest.approx(-25.0, abs=cfg.velocity_resolution_mps)


def test_process_unfolds_a_fast_slow_capture(tmp_path, capsys):
    """`radar-harness process` on a DCA1000 capture recorded with the SRR-style profile: each
    frame's two sub-frame blocks are one fast/slow frame, so a -25 m/s target (three native
    spans of 8.25 m/s out) comes back at -25 m/s, tracked as one radar."""
    import pandas as pd

    from radarsim.capture.subframes import encode_frame
    text = profile_text("xwr18_fast_slow_srr")
    (tmp_path / "fs.cfg").write_text(text)
    profile = parse_ti_cfg(text)
    cfg = profile.radar
    sc = radarsim.Scatterers.from_spherical(np.array([30.0]), np.array([10.0]), np.zeros(1),
                                            np.array([-25.0]), np.array([10.0]))
    rng = np.random.default_rng(4)
    words = []
    for _ in range(2):
        adc = radarsim.simulate_frame(cfg, sc, rng)
        words.append(encode_frame(profile, [adc[:128], adc[128:]]))
    np.concatenate(words).tofile(tmp_path / "cap.bin")
    out = tmp_path / "pc.csv"
    assert main(["process", str(tmp_path / "cap.bin"), "--cfg", str(tmp_path / "fs.cfg"),
                 "--out", str(out)]) == 0
    pc = pd.read_csv(out)
    assert "subframe" not in pc.columns and sorted(pc.frame.unique()) == [0, 1]
    for _, f in pc.groupby("frame"):
        best = f.loc[f.snr_db.idxmax()]
        assert best.radial_velocity_mps == pytest.approx(-25.0, abs=cfg.velocity_resolution_mps)
        assert best.range_m == pytest.approx(30.0, abs=cfg.range_resolution_m)
