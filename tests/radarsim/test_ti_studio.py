"""mmWave Studio setups read as profiles (radarsim.ti.studio): a LogFile's API: calls in
mmWaveLink units and a setup JSON, converted to CLI commands and read by the one reader.

Hand computations (mmWaveLink units, rl_sensor.h / Radar Interface Control Document):
LogFile (AWR2243): startFreqConst 1435384036 x 3.6e9 / 2^26 Hz = 77.0000000238 GHz;
freqSlopeConst 1243 x 3.6e9 x 900 / 2^26 Hz/us = 60.01174 MHz/us; idle 700 + ramp 5800 x 10 ns
= 65 us; framePeriodicity 8000000 x 5 ns = 40 ms; chirps 0..1 (Tx1, Tx3) x 128 loops = 256;
256 complex samples at 10 Msps: dR = c / (2 S N / fs).
JSON (AWR1243): 77 GHz, 29.982 MHz/us, 100 + 60 us, 3 chirps (Tx1, Tx3, Tx2) x 128 = 384,
100 ms, 8 frames.
"""
from __future__ import annotations

import pytest

from radarsim.ti import parse_setup, parse_studio_json, parse_studio_log
from tests.radarsim.profiles import PROFILE_DIR

C = 299_792_458.0
LOG = PROFILE_DIR / "awr2243_studio_LogFile.txt"
JSON = PROFILE_DIR / "awr1243_studio_setup.mmwave.json"


def test_logfile_is_read_in_mmwavelink_units():
    prof = parse_setup(LOG)
    r = prof.radar
    assert (r.chip, r.mimo, r.n_tx, r.n_rx, r.tx_order) == ("AWR2243", "tdma", 2, 4, (1, 2))
    assert r.tx_channels == (1, 3)
    assert r.start_freq_hz == pytest.approx(1435384036 * 3.6e9 / 2 ** 26, rel=1e-12)
    slope = 1243 * 3.6e9 * 900 / 2 ** 26 * 1e6
    assert r.slope_hz_per_s == pytest.approx(slope, rel=1e-12)
    assert r.chirp_period_s == pytest.approx(65e-6)
    assert (r.n_chirps, r.n_samples, r.adc_mode) == (256, 256, "complex1x")
    assert r.range_resolution_m == pytest.approx(C / (2 * slope * 256 / 10e6), rel=1e-9)
    assert prof.frame_period_s == pytest.approx(0.04) and prof.n_frames == 100
    assert not r.adcbuf_interleaved            # DataFmtConfig chInterleave 1
    assert any("mmWave Studio LogFile" in n for n in prof.notes)


def test_the_last_configuration_of_a_logfile_wins(tmp_path):
    """A session log holds every configuration sent; the one before the capture counts."""
    text = LOG.read_text()
    first = text.replace("API:ChannelConfig,15,5,0,0,", "API:ChannelConfig,3,1,0,0,")
    path = tmp_path / "LogFile.txt"
    path.write_text(first + text)
    assert parse_studio_log(path).radar == parse_setup(LOG).radar


def test_setup_json_is_read_with_the_chip_given():
    prof = parse_studio_json(JSON, chip="AWR1243")
    r = prof.radar
    assert (r.chip, r.board, r.n_tx, r.tx_order, r.n_chirps) == ("AWR1243", "AWR1243BOOST", 3,
                                                                 (1, 3, 2), 384)
    assert r.slope_hz_per_s == pytest.approx(29.982e12) and r.chirp_period_s == \
        pytest.approx(160e-6)
    assert (prof.frame_period_s, prof.n_frames) == (pytest.approx(0.1), 8)
    # Without a chip the commands decide (complex, 3 Tx: the AWR1843 family limits).
    assert parse_setup(JSON).radar.chip == "AWR1843"


@pytest.mark.parametrize("old, new, pattern", [
    ("API:ProfileConfig,0,1435384036,700,600,5800,0,0,1243,0,256,10000,",
     "API:ProfileConfig,0,1435384036,700,600,5800,0,0,1243,0,256,60000,",
     r"LogFile line 10 \(API:ProfileConfig\): .*adc_rate_sps=6e\+07 exceeds the AWR2243 limit"),
    ("API:ChirpConfig,1,1,0,0,0,0,0,4,0,", "API:ChirpConfig,1,1,0,0,0,5,0,4,0,",
     r"LogFile line 12 \(API:ChirpConfig\): per-chirp variations"),
    ("API:FrameConfig,0,1,100,128,8000000,", "API:FrameConfig,0,1,100,128,800,",
     r"LogFile line 13 \(API:FrameConfig\): framePeriodicity=0.004 ms is shorter"),
    ("API:AdcOutConfig,2,1,0,", "API:AdcOutConfig,2,x,0,",
     r"LogFile line 5 \(API:AdcOutConfig\): '2,x,0,' is not a list of integers"),
])
def test_bad_logfile_value_names_the_logfile_line(tmp_path, old, new, pattern):
    text = LOG.read_text()
    assert old in text
    path = tmp_path / "LogFile.txt"
    path.write_text(text.replace(old, new))
    with pytest.raises(ValueError, match=pattern):
        parse_setup(path)


def test_cascade_json_is_refused(tmp_path):
    import json
    data = json.loads(JSON.read_text())
    data["mmWaveDevices"] *= 4
    path = tmp_path / "cascade.mmwave.json"
    path.write_text(json.dumps(data, indent=1))
    with pytest.raises(ValueError, match=r"mmWaveDevices has 4 devices \(a cascade\)"):
        parse_setup(path)


def test_setup_json_advanced_frame_gives_one_profile_per_subframe(tmp_path):
    """rlAdvFrameCfg_t.frameSeq (the key names TI's JSON readers use): two sub-frames of the
    JSON's chirps 0..1 (Tx1, Tx3) x 64 loops (128 x 160 us = 20.48 ms in a 25 ms burst and
    sub-frame) and chirp 2 (Tx2) x 32 loops in 30 ms: frame 55 ms, sub-frame 1 at 25 ms."""
    import json
    data = json.loads(JSON.read_text())
    rf = data["mmWaveDevices"][0]["rfConfig"]
    del rf["rlFrameCfg_t"]
    sub = {"forceProfileIdx": 0, "chirpStartIdxOffset": 0, "numOfBurst": 1,
           "numOfBurstLoops": 1}
    rf["rlAdvFrameCfg_t"] = {"frameSeq": {
        "numOfSubFrames": 2, "forceProfile": 0, "numFrames": 4, "triggerSelect": 1,
        "frameTrigDelay_usec": 0,
        "subFrameCfg": [
            {"rlSubFrameCfg_t": {**sub, "chirpStartIdx": 0, "numOfChirps": 2, "numLoops": 64,
                                 "burstPeriodicity_msec": 25.0,
                                 "subFramePeriodicity_msec": 25.0}},
            {"rlSubFrameCfg_t": {**sub, "chirpStartIdx": 2, "numOfChirps": 1, "numLoops": 32,
                                 "burstPeriodicity_msec": 30.0,
                                 "subFramePeriodicity_msec": 30.0}}]}}
    path = tmp_path / "adv.mmwave.json"
    path.write_text(json.dumps(data, indent=1))
    prof = parse_studio_json(path, chip="AWR1243")
    assert prof.is_advanced and prof.frame_period_s == pytest.approx(0.055)
    s0, s1 = prof.subframes
    assert (s0.radar.n_tx, s0.radar.n_chirps, s1.radar.n_tx, s1.radar.n_chirps) == (2, 128, 1, 32)
    assert s1.radar.tx_channels == (2,) and s1.subframe_start_s == pytest.approx(0.025)


#: `%` comments quoting the mmWave Studio LogFile a CLI profile was written from.
QUOTED_LOG = ("% Written from the lab's mmWave Studio session:\n"
              "% API:ChannelConfig,3,15,0 -> Tx mask 3\n"
              "% 10:00:00:003: API:ProfileConfig,0,1435384036,700,600,5800 (start 77 GHz)\n")


def test_a_cfg_quoting_logfile_lines_in_comments_is_a_cfg():
    """A file's kind comes from the lines that are read: comment lines quoting LogFile calls
    leave an SDK profile an SDK profile, read exactly as without them."""
    from radarsim.ti import parse_ti_cfg, setup_kind
    from tests.radarsim.profiles import profile_text
    plain = profile_text("xwr68_aop")
    quoted = QUOTED_LOG + plain + "sensorStart % API:ProfileConfig,0,1 trailing note\n"
    assert setup_kind(quoted) == "cli_profile"
    assert parse_setup(quoted).radar == parse_ti_cfg(plain).radar


def test_a_commented_call_in_a_logfile_is_not_read():
    """The LogFile stays a LogFile, and a commented-out call is not a call: the commented
    ChannelConfig (1 Tx) after the real one does not become the last configuration."""
    from radarsim.ti import setup_kind
    text = LOG.read_text()
    commented = text + "% 10:09:00:000: API:ChannelConfig,3,1,0,0,\n"
    assert setup_kind(commented) == "studio_log"
    assert parse_setup(commented).radar == parse_setup(LOG).radar
    only_comments = "".join(f"% {ln}\n" for ln in text.splitlines())
    assert setup_kind(only_comments) == "cli_profile"


def _json_with(tmp_path, path: tuple, value):
    """The setup JSON with the value at `path` (keys and indices from the file's root)."""
    import json
    data = json.loads(JSON.read_text())
    obj = data
    for key in path[:-1]:
        obj = obj[key]
    obj[path[-1]] = value
    out = tmp_path / "setup.mmwave.json"
    out.write_text(json.dumps(data))
    return out


_RF = ("mmWaveDevices", 0, "rfConfig")
_PROFILE = _RF + ("rlProfiles", 0, "rlProfileCfg_t")
_FRAME = _RF + ("rlFrameCfg_t",)
_INT = r'must be an integer \(or a "0x\.\.\." hex string\)'


@pytest.mark.parametrize("path, value, pattern", [
    (_FRAME + ("numLoops",), None, r"rfConfig\.rlFrameCfg_t\.numLoops=None " + _INT),
    (_FRAME + ("numLoops",), [128], r"rfConfig\.rlFrameCfg_t\.numLoops=\[128\] " + _INT),
    (_FRAME + ("numLoops",), 64.7, r"numLoops=64\.7 " + _INT),
    (_FRAME + ("numLoops",), True, r"numLoops=True " + _INT),
    (_FRAME + ("numLoops",), "abc", r"numLoops='abc' " + _INT),
    (_PROFILE + ("startFreqConst_GHz",), "abc",
     r"rlProfiles\[0\]\.rlProfileCfg_t\.startFreqConst_GHz='abc' must be a finite number"),
    (_PROFILE + ("startFreqConst_GHz",), None, r"startFreqConst_GHz=None must be a finite"),
    (_PROFILE + ("startFreqConst_GHz",), True, r"startFreqConst_GHz=True must be a finite"),
    (_PROFILE + ("digOutSampleRate",), 9999.9, r"digOutSampleRate=9999\.9 " + _INT),
    (_FRAME + ("framePeriodicity_msec",), float("inf"),
     r"framePeriodicity_msec=inf must be a finite number"),
    (_RF + ("rlChanCfg_t", "rxChannelEn"), True, r"rlChanCfg_t\.rxChannelEn=True " + _INT),
    (_RF + ("rlChanCfg_t", "rxChannelEn"), "0xZZ", r"rxChannelEn='0xZZ' " + _INT),
    (_RF + ("rlProfiles",), None, r"rfConfig\.rlProfiles=None must be a list"),
    (_RF + ("rlChirps",), "abc", r"rfConfig\.rlChirps='abc' must be a list"),
    (_RF + ("rlChirps", 0, "rlChirpCfg_t", "startFreqVar_MHz"), "abc",
     r"rlChirps\[0\]\.rlChirpCfg_t\.startFreqVar_MHz='abc' must be a finite number"),
    (("mmWaveDevices", 0, "mmWaveDevice"), "AWR9999",
     r"mmWaveDevices\[0\]\.mmWaveDevice: chip 'AWR9999' is not one the harness knows "
     r"\(known: AWR1243, "),
])
def test_setup_json_type_errors_name_the_key(tmp_path, path, value, pattern):
    """Each was a TypeError / decimal.InvalidOperation traceback, a silent truncation (64.7
    loops ran 64, 9999.9 ksps ran at 9999, true read as 1) or, for the chip, another chip
    inferred without a word."""
    with pytest.raises(ValueError, match=r"setup JSON: (\S*\.)?" + pattern):
        parse_setup(_json_with(tmp_path, path, value))


def test_integral_json_numbers_are_integers(tmp_path):
    """Studio writes digOutSampleRate as 10000.0: an integral number is the integer."""
    r = parse_setup(_json_with(tmp_path, _FRAME + ("numLoops",), 128.0)).radar
    assert r.n_chirps == parse_setup(JSON).radar.n_chirps == 384


def test_unknown_chip_argument_is_refused():
    with pytest.raises(ValueError, match=r"chip: chip 'AWR9999' is not one the harness knows"):
        parse_studio_json(JSON, chip="AWR9999")


def test_logfile_select_chip_version_unknown_is_refused(tmp_path):
    """It was replaced by a chip inferred from the commands without a word."""
    text = LOG.read_text()
    assert "select_chip_version,AWR2243" in text
    path = tmp_path / "LogFile.txt"
    path.write_text(text.replace("select_chip_version,AWR2243", "select_chip_version,AWR9999"))
    with pytest.raises(ValueError, match=r"LogFile line \d+ \(API:select_chip_version\): chip "
                                         r"'AWR9999' is not one the harness knows"):
        parse_setup(path)


def test_logfile_select_chip_version_studio_spelling(tmp_path):
    text = LOG.read_text()
    path = tmp_path / "LogFile.txt"
    path.write_text(text.replace("select_chip_version,AWR2243", "select_chip_version,AR1243"))
    assert parse_setup(path).radar.chip == "AWR1243"


def test_logfile_without_profile_config_names_it(tmp_path):
    """It was read as a CLI profile and blamed on a missing channelCfg."""
    lines = [ln for ln in LOG.read_text().splitlines() if "API:ProfileConfig" not in ln]
    path = tmp_path / "LogFile.txt"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"LogFile: its last configuration \(from line \d+, "
                                         r"API:ChannelConfig\) has no API:ProfileConfig call"):
        parse_setup(path)


@pytest.mark.parametrize("text", ["", "\n\n  \n"], ids=["empty", "blank"])
def test_empty_setup_file_says_it_is_empty(tmp_path, text):
    """It said "TI .cfg file '' not found"."""
    path = tmp_path / "LogFile.txt"
    path.write_text(text)
    with pytest.raises(ValueError, match=r"setup '.*LogFile\.txt' is empty: no TI CLI commands"):
        parse_setup(path)
