"""A profile means what its chip family's TI demo means (radarsim.ti.families): every processing
command maps to a ProcessingConfig field, a command left out takes that demo's default (off),
a command of another family's demo is ignored with a note, and what is read but not modelled
is listed in one note line. Expected values by hand from the lines each test edits."""
from __future__ import annotations

import math

import pytest

from radarsim.ti import parse_ti_cfg, r79_cfg_text
from tests.radarsim.profiles import profile_text

X68 = profile_text("xwr68_tx13")          # SDK 3.5 demo profile: extendedMaxVelocity -1 0
R79 = r79_cfg_text()                      # DDM demo: compressionCfg -1 1 0 0.5 8, intfMitigCfg


def _without(text: str, command: str) -> str:
    return "\n".join(s for s in text.splitlines() if not s.startswith(command + " "))


def _with(text: str, line: str) -> str:
    lines = text.splitlines()
    return "\n".join(lines[:-1] + [line] + lines[-1:]) + "\n"


def test_sdk3_profile_without_the_ddm_commands_is_neither_compressed_nor_mitigated():
    prof = parse_ti_cfg(X68)
    assert prof.demo_family == "sdk3"
    assert prof.processing["compression"] is False
    assert prof.processing["interference_mitigation"] is False
    assert prof.processing["tdma_disambiguation"] is False      # extendedMaxVelocity -1 0


@pytest.mark.parametrize("line, expected", [("extendedMaxVelocity -1 1", True),
                                            (None, False)])      # absent: the demo's off
def test_extended_max_velocity_switches_tdma_disambiguation(line, expected):
    text = _without(X68, "extendedMaxVelocity")
    if line:
        text = _with(text, line)
    assert parse_ti_cfg(text).processing["tdma_disambiguation"] is expected


def test_ddm_profile_compression_and_mitigation_follow_their_commands():
    prof = parse_ti_cfg(R79)
    assert prof.demo_family == "mcu_plus_ddm"
    assert (prof.processing["compression"], prof.processing["compression_ratio"],
            prof.processing["compression_range_bins_per_block"]) == (True, 0.5, 8)
    assert (prof.processing["interference_mitigation"], prof.processing["intf_mag_snr_db"],
            prof.processing["intf_magdiff_snr_db"]) == (True, 15.0, 18.0)
    bare = parse_ti_cfg(_without(_without(R79, "compressionCfg"), "intfMitigCfg"))
    assert bare.processing["compression"] is False
    assert bare.processing["interference_mitigation"] is False


def test_a_command_of_another_family_is_ignored_with_a_note():
    prof = parse_ti_cfg(_with(X68, "compressionCfg -1 1 0 0.5 8"))
    assert prof.processing["compression"] is False
    assert "compressionCfg" in prof.ignored_commands
    assert any("compressionCfg is not a command of the mmWave SDK 2.x/3.x demo" in n
               for n in prof.notes)
    ddm = parse_ti_cfg(_with(R79, "extendedMaxVelocity -1 1"))
    assert "tdma_disambiguation" not in ddm.processing
    assert any("extendedMaxVelocity is not a command of the mmWave MCU+ SDK DDM demo" in n
               for n in ddm.notes)


def test_multi_object_beamforming_threshold_is_a_magnitude_ratio():
    """threshold 0.5 of the first peak's magnitude = 20 log10 2 = 6.02 dB in power."""
    prof = parse_ti_cfg(X68)          # multiObjBeamForming -1 1 0.5
    assert prof.processing["azimuth_sidelobe_db"] == pytest.approx(20 * math.log10(2))


def test_fields_of_view_are_read():
    text = _without(_without(X68, "cfarFovCfg"), "aoaFovCfg")
    text = _with(_with(_with(text, "cfarFovCfg -1 0 0.5 7.5"), "cfarFovCfg -1 1 -3 3"),
                 "aoaFovCfg -1 -60 60 -10 10")
    p = parse_ti_cfg(text).processing
    assert (p["range_fov_m"], p["velocity_fov_mps"]) == ((0.5, 7.5), (-3.0, 3.0))
    assert (p["azimuth_fov_deg"], p["elevation_fov_deg"]) == ((-60.0, 60.0), (-10.0, 10.0))
    absent = parse_ti_cfg(_without(_without(X68, "cfarFovCfg"), "aoaFovCfg")).processing
    assert absent["range_fov_m"] is absent["azimuth_fov_deg"] is None


def test_read_but_not_modelled_commands_are_listed_in_one_note():
    text = _without(_without(X68, "clutterRemoval"), "calibDcRangeSig")
    text = _with(_with(text, "clutterRemoval -1 1"), "calibDcRangeSig -1 1 -5 8 256")
    notes = [n for n in parse_ti_cfg(text).notes if n.startswith("read but not modelled: ")]
    assert len(notes) == 1
    assert "CQRxSatMonitor" in notes[0]
    assert "calibDcRangeSig" not in notes[0]           # modelled: TiProfile.dc_range_signature
    assert parse_ti_cfg(text).dc_range_signature[:3] == (-5, 8, 256)
    assert "clutterRemoval" not in notes[0]            # modelled: ProcessingConfig field
    assert parse_ti_cfg(text).processing["clutter_removal"] is True
    assert parse_ti_cfg(X68).processing["clutter_removal"] is False     # clutterRemoval -1 0


@pytest.mark.parametrize("line, pattern", [
    ("multiObjBeamForming -1 1 1.5", r"threshold=1.5 is outside 0..1"),
    ("cfarFovCfg -1 0 9 2", r"min=9 is above max=2"),
    ("aoaFovCfg -1 -100 60 -10 10", r"azimuth field of view -100..60 deg"),
    ("measureRangeBiasAndRxChanPhase 1 -1 0.2", r"targetDistance=-1 m .* must be > 0"),
])
def test_bad_processing_command_names_line_and_limit(line, pattern):
    cmd = line.split()[0]
    text = _with(_without(X68, cmd), line)
    no = len(text.splitlines()) - 1
    with pytest.raises(ValueError, match=rf"line {no} \({cmd}\): {pattern}"):
        parse_ti_cfg(text)
