"""Real DCA1000 captures: `radar-harness process` and `calibrate` report what the capture's
source says was in front of the radar.

The captures cannot ship (their licences forbid redistribution, ``tests/data/README.md``): each
test skips when its capture is not installed (``python -m tests.data.public_captures``).

TI mmWave Industrial Toolbox, memory-compression model capture (IWR6843 ES2.0, DCA1000): TI
states a strong corner reflector in an anechoic chamber, "a distinct peak in the range-Doppler
heat-map plot at range Bin of 38 and zero Doppler bin". The chirp slope and timing are not
stated (our profile's are nominal), so the checks are in bins, in the static share and in what
calibration must achieve by construction (reflector at the range it was told, on boresight).
"""
import pandas as pd
import pytest

from harness.cli import main
from radarsim.ti import parse_ti_cfg
from tests.data.public_captures import PUBLIC_CAPTURES, find_capture

TI_REFLECTOR = PUBLIC_CAPTURES["ti_iwr6843_anechoic_reflector"]
#: Range bin and Doppler bin (0 = static) of the reflector, as TI states them.
STATED_RANGE_BIN, STATED_DOPPLER_BIN = 38, 0
#: Bins next to the radar (Tx-to-Rx leakage, DC residue) are not the reflector.
LEAKAGE_BINS = 3


@pytest.fixture(scope="module")
def ti_capture():
    path = find_capture(TI_REFLECTOR.name)
    if path is None:
        pytest.skip(f"{TI_REFLECTOR.name} not installed (python -m tests.data.public_captures "
                    "install ...; it may not be redistributed)")
    return path


def _process(capture, profile, out) -> pd.DataFrame:
    assert main(["process", str(capture), "--cfg", str(profile), "--out", str(out),
                 "--no-track"]) == 0
    return pd.read_csv(out)


def _reflector(pc: pd.DataFrame) -> pd.Series:
    """The strongest detection beyond the leakage bins."""
    far = pc[pc.range_bin >= LEAKAGE_BINS]
    return far.loc[far.snr_db.idxmax()]


def test_reflector_at_the_stated_range_and_doppler_bin(ti_capture, tmp_path):
    prof = parse_ti_cfg(TI_REFLECTOR.profile_path)
    pc = _process(ti_capture, TI_REFLECTOR.profile_path, tmp_path / "pc.csv")
    best = _reflector(pc)
    assert best.range_bin == STATED_RANGE_BIN
    assert best.doppler_bin == STATED_DOPPLER_BIN
    # Interpolated range within the stated bin (+/- half a bin around its centre).
    assert abs(best.range_m / prof.radar.range_resolution_m - STATED_RANGE_BIN) <= 0.5
    # "Strong", "distinct": far above the CFAR threshold (15 dB in the profile).
    assert best.snr_db > 40.0
    # Static, and reported so: without extendedMaxVelocity nothing moves it to +/-2 Vmax.
    assert abs(best.radial_velocity_mps) < prof.radar.velocity_resolution_mps
    # The source states only the reflector; two weak returns beyond 9 m move at Doppler bin
    # 5 on this capture (something in the chamber, not the reflector): not asserted.


def test_calibration_puts_the_reflector_at_r_and_on_boresight(ti_capture, tmp_path, capsys):
    """TI's procedure places the reflector on boresight at a known range R; the source states
    bin 38, so R is that bin's centre. After calibration the reflector is reported at R (the
    written bias has 4 decimals: 0.1 mm) and at 0 deg (the coefficients are fitted to it, so
    only the interpolation of a 12-element array over the azimuth grid is left: < 0.5 deg),
    and it stays static with velocity extension on."""
    radar = parse_ti_cfg(TI_REFLECTOR.profile_path).radar
    r = STATED_RANGE_BIN * radar.range_resolution_m
    cal = tmp_path / "calibrated.cfg"
    assert main(["calibrate", str(ti_capture), "--cfg", str(TI_REFLECTOR.profile_path),
                 "--target-range-m", f"{r}", "--search-window-m",
                 f"{2 * radar.range_resolution_m}", "--write", str(cal)]) == 0
    line = capsys.readouterr().out.splitlines()[0]
    assert line.startswith("compRangeBiasAndRxChanPhase ")
    bias = float(line.split()[1])
    assert abs(bias) < radar.range_resolution_m / 2  # the peak is in bin 38
    best = _reflector(_process(ti_capture, cal, tmp_path / "cal.csv"))
    assert best.range_bin == STATED_RANGE_BIN
    assert abs(best.range_m - r) < 1e-4
    assert abs(best.azimuth_deg) < 0.5 and abs(best.elevation_deg) < 0.5
    static = set(_process(ti_capture, cal, tmp_path / "cal2.csv").query("doppler_bin == 0")
                 .range_bin)
    ext = tmp_path / "calibrated_ext.cfg"
    ext.write_text(cal.read_text().replace("extendedMaxVelocity -1 0", "extendedMaxVelocity -1 1"))
    pc = _process(ti_capture, ext, tmp_path / "ext.csv")
    best = _reflector(pc)
    assert best.range_bin == STATED_RANGE_BIN
    assert abs(best.radial_velocity_mps) < radar.velocity_resolution_mps
    # Calibrated, extension on: the static scene stays static (a calibrated board's promise): every
    # return in Doppler bin 0 without extension is still reported there with it.
    moved = static - set(pc.query("doppler_bin == 0").range_bin)
    assert not moved, sorted(moved)


def test_installer_refuses_a_file_that_is_not_the_capture(tmp_path):
    from tests.data.public_captures import install
    fake = tmp_path / "adc_data_Raw_0.bin"
    fake.write_bytes(b"\0" * TI_REFLECTOR.size_bytes)
    with pytest.raises(ValueError, match="not the published capture"):
        install(TI_REFLECTOR.name, fake, tmp_path / "out")
    with pytest.raises(ValueError, match="not found"):
        install(TI_REFLECTOR.name, tmp_path / "nowhere", tmp_path / "out")
    with pytest.raises(ValueError, match="unknown capture"):
        install("no_such_capture", fake, tmp_path / "out")
