"""TI mmWave SDK .cfg profiles: the shipped R79 file, exact round trips, one test per bad line."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

import radarsim
from core.errors import BadInput
from radarsim import ti
from radarsim.ti import (
    R79_CFAR,
    TiCfar,
    from_ti_cfg,
    parse_ti_cfg,
    r79_cfg_path,
    r79_cfg_text,
    to_ti_cfg,
)

R79_TI_LINES = ("profileCfg 0 77 5 5 18.81 0 0 8.883 0 384 30000 0 0 42",
                "chirpCfg 0 5 0 0 0 0 0 15", "frameCfg 0 5 128 0 384 250 1 0",
                "ddmPhaseShiftAntOrder 0 2 3 1")


# ---------------------------------------------------------------------------- shipped file
def test_shipped_cfg_is_the_r79_preset():
    prof = parse_ti_cfg(r79_cfg_path())
    assert prof.radar == radarsim.presets.r79_ddma()
    assert prof.frame_period_s == 0.25 and prof.n_frames == 0 and prof.trigger_select == 1
    assert prof.cfar == R79_CFAR
    assert prof.ddm_phase_order == (0, 2, 3, 1)
    assert prof.directives == {"phase_quantization": "floor"}
    # The R79 firmware's adcbufCfg -1 1 0 0 1: interleaved ADC buffer ([TI-DAZ] section 2).
    assert prof.adc_channel_interleaved and prof.radar.adcbuf_interleaved
    assert "adcbufCfg -1 1 0 0 1" in r79_cfg_path().read_text().splitlines()
    assert prof.profile_extras["rx_gain_code"] == 42
    # The R79 demo's processing/tracker commands are kept and reported, with line numbers.
    assert {"gtrack", "ransac", "localMaxCfg", "guiMonitor", "lowPower"} <= \
        set(prof.ignored_commands)
    text = r79_cfg_path().read_text().splitlines()
    for no, cmd in prof.ignored:
        assert text[no - 1].split()[0] == cmd
    # The TI R79 demo's own waveform lines (mmw_cli.c gHardcodedCliConfigs) are in the file.
    for line in R79_TI_LINES:
        assert line in text


def test_shipped_cfg_is_up_to_date():
    """Regenerate with REGEN_GOLDEN=1 after an intended change to to_ti_cfg or the preset."""
    path = r79_cfg_path()
    if os.environ.get("REGEN_GOLDEN"):
        path.write_text(r79_cfg_text())
    assert path.read_text() == r79_cfg_text()


def test_config_value_does_not_import_the_ti_bridge():
    """The TI bridge builds on RadarConfig; the value's module knows nothing of it (no import
    circle). `radarsim.config`, the public entry point above both, offers the bridge's two
    functions (``from radarsim.config import from_ti_cfg``)."""
    import subprocess
    import sys
    code = ("import sys, radarsim.radar_config; "
            "sys.exit('radarsim.ti' in sys.modules)")
    assert subprocess.run([sys.executable, "-c", code]).returncode == 0
    import radarsim.config
    assert radarsim.config.from_ti_cfg is from_ti_cfg
    assert radarsim.config.RadarConfig is radarsim.RadarConfig


def test_r79_units_and_reference_values():
    """TI units converted once; design.md section 8 values follow from the parsed file."""
    cfg = from_ti_cfg(Path(r79_cfg_path()))
    assert (cfg.start_freq_hz, cfg.slope_hz_per_s) == (77e9, 8.883e12)
    assert (cfg.idle_time_s, cfg.adc_start_time_s, cfg.ramp_end_time_s) == (5e-6, 5e-6, 18.81e-6)
    assert cfg.chirp_period_s == 23.81e-6 and cfg.adc_rate_sps == 30e6
    assert (cfg.n_chirps, cfg.n_subbands, cfg.tx_order) == (768, 6, (1, 3, 4, 2))
    assert cfg.range_resolution_m == pytest.approx(1.318, abs=1e-3)
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(40.9, abs=0.05)


# ---------------------------------------------------------------------------- round trips
@pytest.mark.parametrize("mimo", ["ddma", "tdma"])
def test_presets_round_trip_exactly(mimo):
    cfg = radarsim.presets.PRESETS[f"r79_{mimo}"]()
    assert from_ti_cfg(to_ti_cfg(cfg)) == cfg


@pytest.mark.parametrize("overrides", [
    dict(n_tx=3), dict(n_tx=2, n_rx=3, n_chirps=384), dict(mimo="tdma", n_tx=2, n_chirps=400),
    dict(tx_order=(1, 4, 3, 2)), dict(mimo="tdma", tx_order=(2, 1, 4, 3)),
    dict(phase_quantization="round"), dict(phase_quantization="none"),
    dict(noise_figure_db=14.5, tx_power_dbm=11.0, tx_phase_error_deg=(0.0, 3.5, -2.0, 1.25),
         phase_noise_deg_rms=2.0, antenna_pattern="isotropic"),
    dict(start_freq_hz=76.5e9, slope_hz_per_s=12.345678e12, adc_rate_sps=12.5e6,
         n_samples=128, idle_time_s=7.3e-6, ramp_end_time_s=16.2e-6, chirp_period_s=23.5e-6),
    dict(chirp_period_s=23.8100001e-6),  # within RadarConfig's tolerance: a directive keeps it
    dict(mimo="tdma", n_subbands=5),
], ids=lambda d: ",".join(d))
def test_config_variants_round_trip_exactly(overrides):
    cfg = radarsim.presets.r79_ddma(**overrides)
    assert from_ti_cfg(to_ti_cfg(cfg)) == cfg


def test_profile_round_trip_keeps_frame_and_cfar():
    cfar = {"doppler": TiCfar(direction="doppler", mode="caso", window_cells=8, guard_cells=2,
                              noise_div_shift=3, cyclic=True, threshold_db=13.5)}
    prof = parse_ti_cfg(to_ti_cfg(radarsim.presets.r79_tdma(), frame_period_s=0.05,
                                  n_frames=12, cfar=cfar))
    again = parse_ti_cfg(to_ti_cfg(prof))
    assert (again.radar, again.frame_period_s, again.n_frames, again.cfar) == \
        (prof.radar, 0.05, 12, cfar)


def test_plain_ti_file_means_sdk_rounding():
    """Without a radarsim directive the shifter codes follow TI's SDK (round to nearest)."""
    text = "\n".join(line for line in r79_cfg_text().splitlines()
                     if not line.startswith("% radarsim"))
    cfg = from_ti_cfg(text)
    assert cfg.phase_quantization == "round"
    assert cfg == radarsim.presets.r79_ddma(phase_quantization="round")


def test_tdma_order_comes_from_the_chirp_table():
    text = to_ti_cfg(radarsim.presets.r79_tdma())
    assert "chirpCfg 3 3 0 0 0 0 0 2" in text  # Tx2 (TI Tx1, mask 0b0010) fires last
    assert from_ti_cfg(text).tx_order == (1, 3, 4, 2)


def test_ddm_phase_order_is_tx_order():
    """TI lists Tx (0-based) by increasing phase step: 0 3 2 1 -> Tx1, Tx4, Tx3, Tx2."""
    text = r79_cfg_text().replace("ddmPhaseShiftAntOrder 0 2 3 1", "ddmPhaseShiftAntOrder 0 3 2 1")
    assert from_ti_cfg(text).tx_order == (1, 4, 3, 2)


def test_cfar_syntax_variants():
    base = [ln for ln in _lines() if not ln.startswith("cfarCfg")]
    extra = ["cfarCfg -1 0 2 8 4 3 0 15 1",                   # mmWave SDK 3.x / TDM demo
             "cfarCfg -1 1 3 16 0 0 1 12.0 0 24 0 1 0"]      # AWR2x44P DDM demo (Doppler)
    prof = parse_ti_cfg("\n".join(base[:-1] + extra + base[-1:]))
    assert prof.cfar["range"] == TiCfar(direction="range", mode="caso", window_cells=8,
                                        guard_cells=4, noise_div_shift=3, cyclic=False,
                                        threshold_db=15.0, peak_grouping=True)
    assert prof.cfar["doppler"].os_rank == 24 and prof.cfar["doppler"].variable_threshold_mode == 0


def test_flush_cfg_discards_earlier_commands():
    lines = _lines()
    text = "\n".join(["dfeDataOutputMode 1", "profileCfg 1 78 5 5 18.81 0 0 8.883 0 384 30000 0 "
                      "0 42", "flushCfg"] + lines)
    assert from_ti_cfg(text) == from_ti_cfg("\n".join(lines))


def test_path_and_text_inputs(tmp_path):
    path = tmp_path / "p.cfg"
    path.write_text(r79_cfg_text())
    assert from_ti_cfg(str(path)) == from_ti_cfg(path) == from_ti_cfg(r79_cfg_text())
    with pytest.raises(BadInput, match="missing.cfg"):
        from_ti_cfg(str(tmp_path / "missing.cfg"))


def test_to_ti_cfg_rejects_what_the_chip_cannot_run():
    cfg = radarsim.presets.r79_ddma(n_chirps=6 * 300)
    with pytest.raises(ValueError, match="300 loops .* 255"):
        to_ti_cfg(cfg)
    with pytest.raises(ValueError, match="framePeriodicity=10 ms is shorter than the chirp burst"):
        to_ti_cfg(radarsim.presets.r79_ddma(), frame_period_s=0.01)


# ---------------------------------------------------------------------------- bad lines
def _lines() -> list[str]:
    """The R79 file's commands (no comments but TI's ``% Platform:`` header), ending with
    sensorStart."""
    return [line for line in r79_cfg_text().splitlines()
            if not line.startswith("%") or line.startswith("% Platform:")]


def _edit(prefix: str, new: str | None, lines: list[str] | None = None) -> tuple[str, int]:
    """Replace (or, new=None, delete) the first line starting with `prefix`; return the text
    and the 1-based number of the edited line."""
    lines = list(_lines() if lines is None else lines)
    i = next(k for k, line in enumerate(lines) if line.startswith(prefix))
    if new is None:
        del lines[i]
    else:
        lines[i] = new
    return "\n".join(lines) + "\n", i + 1


PROFILE = "profileCfg 0 77 5 5 18.81 0 0 8.883 0 384 30000 0 0 42"
BAD_LINES = {
    # kind: (line prefix to replace, replacement, message pattern[, prefix of the line the
    # error must name when it is not the edited one])
    "misspelled_command": ("lowPower", "profileCfgg 0", r"did you mean 'profileCfg'"),
    "wrong_arg_count": ("profileCfg", PROFILE.rsplit(" ", 1)[0], r"expects 14 arguments, got 13"),
    "wrong_arg_count_ignored_cmd": ("lowPower", "lowPower 0", r"expects 2 arguments, got 1"),
    "not_a_number": ("profileCfg", PROFILE.replace("18.81", "18.8x1"),
                     r"rampEndTime='18.8x1' is not a number"),
    "not_an_integer": ("profileCfg", PROFILE.replace(" 384 ", " 384.5 "),
                       r"numAdcSamples='384.5' is not an integer"),
    "start_freq_outside_band": ("profileCfg", PROFILE.replace(" 77 ", " 82 "),
                                r"startFreq=82 GHz is outside the AWR2944 band"),
    "adc_rate_over_chip_limit": ("profileCfg", PROFILE.replace("30000", "40000"),
                                 r"adc_rate_sps=4e\+07 exceeds the AWR2944 limit"),
    "adc_window_after_ramp_end": ("profileCfg", PROFILE.replace("5 5 18.81", "5 10 18.81"),
                                  r"n_samples=384: ADC window ends"),
    "ramp_beyond_band": ("profileCfg", PROFILE.replace(" 77 ", " 80.9 "),
                         r"ramp end frequency .* exceeds the AWR2944 band limit"),
    "tx_backoff_not_modelled": ("profileCfg", PROFILE.replace("18.81 0 0", "18.81 3 0"),
                                r"txOutPower=3: Tx back-off is not modelled"),
    "too_many_loops": ("frameCfg", "frameCfg 0 5 300 0 384 250 1 0",
                       r"numLoops=300 is outside 1..255"),
    "frame_period_shorter_than_burst": ("frameCfg", "frameCfg 0 5 128 0 384 10 1 0",
                                        r"shorter than the chirp burst"),
    "frame_samples_mismatch": ("frameCfg", "frameCfg 0 5 128 0 256 250 1 0",
                               r"numAdcSamples=256 differs from profileCfg's"),
    "undefined_chirp_in_frame": ("frameCfg", "frameCfg 0 7 128 0 384 250 1 0",
                                 r"chirp 6 of the frame is not defined"),
    "bad_trigger": ("frameCfg", "frameCfg 0 5 128 0 384 250 3 0",
                    r"triggerSelect=3 is outside 1..2"),
    "too_few_subbands": ("frameCfg", "frameCfg 0 2 192 0 384 250 1 0",
                         r"matches no MIMO scheme"),
    "rx_mask_over_chip": ("channelCfg", "channelCfg 31 15 0", r"rxChannelEn=31 is outside 1..15"),
    "drive_strength_over_limit": ("channelCfg", "channelCfg 15 15 0 0 16",
                                  r"driveStrength=16 is outside 0..15"),
    "cascading": ("channelCfg", "channelCfg 15 15 1", r"cascading=1 is outside 0..0"),
    "complex_adc": ("adcCfg", "adcCfg 2 1", r"adcOutputFmt=1 \(complex1x\): the AWR2944 "
                    r"supports \['real'\] \(real-only"),
    "adcbuf_contradicts_adc": ("adcbufCfg", "adcbufCfg -1 0 0 0 1",
                               r"adcOutputFmt=0 \(complex\) contradicts adcCfg's real"),
    "twelve_bit_adc": ("adcCfg", "adcCfg 0 0", r"numADCBits=0: .* int16"),
    "chirp_threshold": ("adcbufCfg", "adcbufCfg -1 1 0 0 9", r"ChirpThreshold=9 is outside 0..8"),
    "per_chirp_variation": ("chirpCfg", "chirpCfg 0 5 0 0 0 0.5 0 15",
                            r"per-chirp variations are not modelled"),
    "chirp_unknown_profile": ("chirpCfg", "chirpCfg 0 5 1 0 0 0 0 15",
                              r"profileId=1 is not defined"),
    "mixed_tx_pattern": ("chirpCfg", "chirpCfg 0 4 0 0 0 0 0 15\nchirpCfg 5 5 0 0 0 0 0 3",
                         r"matches no MIMO scheme", "frameCfg"),
    "bpm_on_a_ddma_loop": ("lowPower", "bpmCfg -1 1 0 1", r"BPM needs a loop of exactly"),
    "sub_frame_without_advanced_frame": ("lowPower", "subFrameCfg 0 0 0 1 1 1 0 1 1 1",
                                         r"sub-frame command without advFrameCfg"),
    "ddm_order_not_permutation": ("ddmPhaseShiftAntOrder", "ddmPhaseShiftAntOrder 0 2 2 1",
                                  r"must list each of the AWR2944's Tx 0..3 once"),
    "ant_geometry_not_tx_plus_rx": ("antGeometryCfg",
                                    "antGeometryCfg 1 0 1 1 1 2 1 3 0 2 0 3 0 4 0 5 1 4 1 5 1 6 "
                                    "1 8 1 8 1 9 1 10 1 11 0.5 0.8",
                                    r"Tx2Rx3 .* is not Tx2 \+ Rx3"),
    "cfar_threshold_over_limit": ("cfarCfg", "cfarCfg -1 1 3 16 0 0 1 120 0 24 0",
                                  r"threshold_db=120 must be within 0..100 dB"),
    "cfar_os_rank_too_large": ("cfarCfg", "cfarCfg -1 1 3 16 0 0 1 12 0 40 0",
                               r"os_rank=40: OS-CFAR needs 1 <= k <= 2 x window_cells = 32"),
    "cfar_os_without_k": ("cfarCfg", "cfarCfg -1 1 3 16 0 0 1 12 0",
                          r"averageMode=3 \(OS\) needs the osKvalue argument"),
    "advanced_frame_with_frame_cfg": ("lowPower", "advFrameCfg 1 0 0 1 0 1",
                                      r"frameCfg in an advanced-frame profile", "frameCfg"),
    "advanced_mode_without_adv_frame": ("dfeDataOutputMode", "dfeDataOutputMode 3",
                                        r"modeType=3 \(advanced frame\) needs an advFrameCfg"),
    "continuous_mode": ("dfeDataOutputMode", "dfeDataOutputMode 2",
                        r"modeType=2: only 1 \(frame\) and 3 \(advanced frame\)"),
    "subframe_index_in_frame_mode": ("cfarCfg -1 1", "cfarCfg 1 1 3 16 0 0 1 12.0 0 24 0",
                                     r"subFrameIdx=1 is outside -1..0 \(a frame-mode profile"),
    "duplicated_channel_cfg": ("lowPower", "channelCfg 15 3 0",
                               r"duplicate of line \d+ \(channelCfg 15 15 0\)"),
    "directive_unknown_field": ("lowPower", "% radarsim: noise_figure = 3",
                                r"unknown RadarConfig field 'noise_figure'"),
    "directive_on_ti_field": ("lowPower", "% radarsim: n_samples = 256",
                              r"n_samples is set by TI commands"),
    "directive_bad_value": ("lowPower", "% radarsim: noise_figure_db = -2.0",
                            r"noise_figure_db=-2.0 must be >= 0"),
}


@pytest.mark.parametrize("kind", sorted(BAD_LINES))
def test_bad_line_names_its_line(kind):
    prefix, new, pattern, *at = BAD_LINES[kind]
    text, no = _edit(prefix, new)
    if at:
        no = next(k for k, line in enumerate(text.splitlines(), 1) if line.startswith(at[0]))
    with pytest.raises(ValueError, match=pattern) as err:
        parse_ti_cfg(text)
    assert f"line {no}" in str(err.value)


@pytest.mark.parametrize("command", ["channelCfg", "adcCfg", "chirpCfg", "frameCfg"])
def test_missing_required_command(command):
    """(A missing dfeDataOutputMode or profileCfg is caught earlier, at the first command
    that needs it: see test_profile_before_output_mode_is_rejected.)"""
    text, _ = _edit(command + " ", None)
    n_lines = len(text.splitlines())
    with pytest.raises(ValueError, match=rf"line {n_lines} \(end of input\): missing required "
                                         rf"command '{command}'"):
        parse_ti_cfg(text)


def test_r79_firmware_list_defaults_to_the_r79_order():
    """TI's R79 firmware hard-codes its command list without ddmPhaseShiftAntOrder or
    antGeometryCfg: the DDM order is the demo's Tx1, Tx3, Tx4, Tx2 (horizontal first, the raised
    Tx2 last) and the array the AWR2944 EVM's; its ADC buffer is interleaved."""
    prof = parse_ti_cfg("\n".join(ti.R79_FIRMWARE_LINES) + "\n")
    assert prof.radar == radarsim.presets.r79_ddma(phase_quantization="round")
    assert prof.radar.tx_order == (1, 3, 4, 2) and prof.radar.adcbuf_interleaved
    assert any("ddmPhaseShiftAntOrder" in n for n in prof.notes)
    assert "rangeCfar" in prof.ignored_commands


def test_second_profile_unused_by_the_frame_is_ignored():
    lines = _lines()
    i = next(k for k, line in enumerate(lines) if line.startswith("profileCfg"))
    lines.insert(i + 1, PROFILE.replace("profileCfg 0", "profileCfg 1"))
    prof = parse_ti_cfg("\n".join(lines))
    assert prof.radar == radarsim.presets.r79_ddma(phase_quantization="round")
    assert any("profiles [1]" in n for n in prof.notes)


def test_duplicate_profile_id_is_rejected():
    lines = _lines()
    i = next(k for k, line in enumerate(lines) if line.startswith("profileCfg"))
    lines.insert(i + 1, lines[i])
    with pytest.raises(ValueError, match=rf"line {i + 2} .*profileId=0 was already defined on "
                                         rf"line {i + 1}"):
        parse_ti_cfg("\n".join(lines))


def test_frame_using_two_profiles_is_rejected():
    lines = _lines()
    i = next(k for k, line in enumerate(lines) if line.startswith("profileCfg"))
    lines.insert(i + 1, PROFILE.replace("profileCfg 0", "profileCfg 1"))
    j = next(k for k, line in enumerate(lines) if line.startswith("chirpCfg"))
    lines[j] = "chirpCfg 0 4 0 0 0 0 0 15\nchirpCfg 5 5 1 0 0 0 0 15"
    text = "\n".join(lines)
    no = next(k for k, line in enumerate(text.splitlines(), 1) if line.startswith("frameCfg"))
    with pytest.raises(ValueError, match=rf"line {no} .*profiles \[0, 1\]"):
        parse_ti_cfg(text)


def test_unknown_commands_are_kept_and_reported():
    """A lab firmware's own command is ignored with a note, never answered with an unrelated
    command name; only near-misspellings of modelled commands are refused."""
    text, no = _edit("lowPower", "fooCfg 1 2")
    prof = parse_ti_cfg(text)
    assert (no, "fooCfg") in prof.ignored
    text, _ = _edit("lowPower", "sensorPosition 1 0 0")
    assert "sensorPosition" in parse_ti_cfg(text).ignored_commands


def test_chirp_without_profile_is_rejected():
    text, _ = _edit("profileCfg", None)
    no = next(k for k, line in enumerate(text.splitlines(), 1) if line.startswith("chirpCfg"))
    with pytest.raises(ValueError, match=rf"line {no} \(chirpCfg\): profileId=0 is not defined"):
        parse_ti_cfg(text)


def test_profile_without_output_mode_is_read_in_frame_mode():
    # Hand-trimmed profiles often drop dfeDataOutputMode; frame mode is the only mode modelled.
    lines = [line for line in _lines() if not line.startswith("dfeDataOutputMode")]
    assert parse_ti_cfg("\n".join(lines)).radar == parse_ti_cfg("\n".join(_lines())).radar


def test_chirp_tx_outside_channel_mask():
    lines = _lines()
    text, no = _edit("chirpCfg", "chirpCfg 0 5 0 0 0 0 0 15",
                     [line.replace("channelCfg 15 15 0", "channelCfg 15 7 0") for line in lines])
    with pytest.raises(ValueError, match=rf"line {no} .*txEnable=15 .* txChannelEn=7"):
        parse_ti_cfg(text)


def test_non_utf8_profile_names_file_offset_and_line(tmp_path):
    path = tmp_path / "latin1.cfg"
    path.write_bytes(r79_cfg_text().replace("% TI R79", "% T\xe9 R79").encode("latin-1"))
    line = next(k for k, s in enumerate(r79_cfg_text().splitlines(), 1) if "% TI R79" in s)
    with pytest.raises(ValueError, match=rf"profile '.*latin1\.cfg' is not UTF-8 text: byte "
                                         rf"0xe9 at offset \d+ \(line {line}\)"):
        parse_ti_cfg(path)


def test_utf8_bom_is_skipped(tmp_path):
    path = tmp_path / "bom.cfg"
    path.write_bytes(b"\xef\xbb\xbf" + r79_cfg_text().encode())
    assert from_ti_cfg(path) == from_ti_cfg(r79_cfg_text())


def test_profile_larger_than_the_limit_is_refused_before_reading(tmp_path, monkeypatch):
    from radarsim.ti import reader

    path = tmp_path / "big.cfg"
    path.write_text(r79_cfg_text())
    monkeypatch.setattr(reader, "MAX_PROFILE_BYTES", 1000)
    with pytest.raises(ValueError, match=r"big\.cfg' is \d+ bytes, more than the 1000-byte "
                                         r"limit"):
        parse_ti_cfg(path)


def test_close_match_search_is_bounded_for_many_unknown_commands(monkeypatch):
    """Suggestions are sought once per distinct name and for at most MAX_SUGGESTIONS names;
    the notes list MAX_UNKNOWN_NOTES lines and count the rest."""
    from radarsim.ti import reader

    calls = []
    real = reader.difflib.get_close_matches

    def counting(word, *args, **kwargs):
        calls.append(word)
        return real(word, *args, **kwargs)

    monkeypatch.setattr(reader.difflib, "get_close_matches", counting)
    junk = [f"vendorCmd{k % 500} 1 2 3" for k in range(5000)]
    lines = _lines()
    prof = parse_ti_cfg("\n".join(lines[:-1] + junk + lines[-1:]))
    assert len(calls) == reader.MAX_SUGGESTIONS
    assert len(prof.ignored_commands) >= 5000
    assert sum("not a command of the SDK demos" in n for n in prof.notes) == \
        reader.MAX_UNKNOWN_NOTES
    assert any(n.startswith(f"{5000 - reader.MAX_UNKNOWN_NOTES} more unknown commands")
               for n in prof.notes)


@pytest.mark.parametrize("command", ["channelCfg 15 3 0", "frameCfg 0 5 64 0 384 250 1 0",
                                     "adcCfg 2 0", "cfarCfg -1 1 3 16 0 0 1 10.0 0 24 0",
                                     "compressionCfg -1 0 0 0.5 8"])
def test_duplicated_command_is_refused_with_both_lines(command):
    """A 4-Rx capture must not be read as 2-Rx because a second channelCfg silently won."""
    lines = _lines()
    cmd, *args = command.split()
    key = 2 if cmd == "cfarCfg" else 0  # cfarCfg: one per (sub-frame, direction)
    first = next(k for k, s in enumerate(lines, 1)
                 if s.split()[0] == cmd and s.split()[1:1 + key] == args[:key])
    text = "\n".join(lines[:-1] + [command] + lines[-1:])
    with pytest.raises(ValueError, match=rf"line {len(lines)} \({cmd}\): "
                                         rf"duplicate of line {first} "):
        parse_ti_cfg(text)


def test_a_command_repeated_after_flush_cfg_is_no_duplicate():
    lines = _lines()
    assert from_ti_cfg("\n".join(lines[:-1] + ["flushCfg"] + lines)) == from_ti_cfg(
        "\n".join(lines))


@pytest.mark.parametrize("special", ["fifo", "/dev/zero"])
def test_special_file_as_profile_is_refused_without_reading(tmp_path, special):
    """A FIFO would block the read, /dev/zero never end (special files)."""
    if special == "fifo":
        path = tmp_path / "p.cfg"
        os.mkfifo(path)
    else:
        path = Path(special)
        if not path.exists():
            pytest.skip("no /dev/zero")
    with pytest.raises(ValueError, match=rf"profile '{path}': is .*, not a regular file"):
        parse_ti_cfg(path)
    with pytest.raises(ValueError, match=r", not a regular file"):
        parse_ti_cfg(str(path))
