"""DCA1000 word layouts pinned by hand-made files, every chip family's round trip, and the
public readers' ordering (TI's readDCA1000.m, OpenRadar's DCA1000.organize) re-implemented
independently from their documented logic.

Word order of the hand-made files (sample value v = 100 chirp + 10 rx + n, 2 chirps, 2 Rx,
4 samples; complex Q = -v - 1):

real, non-interleaved (adcbufCfg ChanInterleave 1; SWRA581 real format):
    0 1 2 3 | 10 11 12 13 | 100 101 102 103 | 110 111 112 113
real, interleaved (ChanInterleave 0; AWR2944 R79 firmware):
    0 10 1 11 2 12 3 13 | 100 110 101 111 102 112 103 113
complex, non-interleaved, 2 lanes (SWRA581 complex format; xWR16/18/68):
    0 1 -1 -2 2 3 -3 -4 | 10 11 -11 -12 12 13 -13 -14 | 100 101 -101 -102 ... (I I Q Q)
"""
from __future__ import annotations

import numpy as np
import pytest

import radarsim
from radarsim.capture import CAPTURE_LAYOUTS, layout_of, read_capture, write_capture
from radarsim.ti import parse_ti_cfg, to_ti_cfg
from tests.radarsim.profiles import profile_text

# A small xWR18xx-style complex profile (TI Visualizer 3.5 syntax, our own numbers).
XWR18_SMALL = profile_text("xwr18_small")


def _tiny(chip: str, adc_mode: str, interleaved: bool | None = None) -> radarsim.RadarConfig:
    return radarsim.RadarConfig.from_fields(
        chip=chip, adc_mode=adc_mode, mimo="tdma", n_tx=1, n_rx=2, n_samples=4, n_chirps=2,
        adc_rate_sps=10e6, adcbuf_interleaved=interleaved)


def _values() -> np.ndarray:
    c, r, n = np.meshgrid(np.arange(2), np.arange(2), np.arange(4), indexing="ij")
    return (100 * c + 10 * r + n)[None]  # (1, 2, 2, 4)


HAND_MADE = {
    "real_noninterleaved": (("AWR1843", "real", None), False,
                            [0, 1, 2, 3, 10, 11, 12, 13, 100, 101, 102, 103, 110, 111, 112, 113]),
    "real_interleaved": (("AWR2944", "real", None), False,
                         [0, 10, 1, 11, 2, 12, 3, 13, 100, 110, 101, 111, 102, 112, 103, 113]),
    "complex_noninterleaved": (("AWR1843", "complex1x", None), True,
                               [0, 1, -1, -2, 2, 3, -3, -4, 10, 11, -11, -12, 12, 13, -13, -14,
                                100, 101, -101, -102, 102, 103, -103, -104,
                                110, 111, -111, -112, 112, 113, -113, -114]),
}


@pytest.mark.parametrize("name", sorted(HAND_MADE))
def test_hand_made_layouts(tmp_path, name):
    (chip, mode, il), cplx, words = HAND_MADE[name]
    cfg = _tiny(chip, mode, il)
    assert layout_of(cfg).name == name
    v = _values()
    frames = (v - 1j * (v + 1)).astype(np.complex64) if cplx else v.astype(np.int16)
    path = tmp_path / "hand.bin"
    path.write_bytes(np.asarray(words, dtype="<i2").tobytes())
    back = read_capture(path, cfg)
    assert back.dtype == (np.complex64 if cplx else np.int16)
    np.testing.assert_array_equal(back, frames)
    out = tmp_path / "written.bin"
    write_capture(out, frames, cfg=cfg)
    assert out.read_bytes() == path.read_bytes()


# One small profile per chip family and ADC mode: round trip of simulated frames.
FAMILY_CFGS = {
    "AWR2944_real_interleaved": dict(chip="AWR2944", mimo="ddma"),
    "AWR2944P_real": dict(chip="AWR2944P", mimo="ddma", adcbuf_interleaved=False),
    "AWR2544_real": dict(chip="AWR2544", mimo="ddma"),
    "AWR1843_complex": dict(chip="AWR1843", mimo="tdma", n_tx=3, adc_mode="complex1x",
                            adc_rate_sps=10e6),
    "AWR1843_complex2x": dict(chip="AWR1843", mimo="tdma", n_tx=3, adc_mode="complex2x",
                              adc_rate_sps=20e6),
    "AWR1642_complex": dict(chip="AWR1642", mimo="tdma", n_tx=2, adc_mode="complex1x",
                            adc_rate_sps=5e6),
    "IWR6843_complex": dict(chip="IWR6843", mimo="tdma", n_tx=3, adc_mode="complex1x",
                            adc_rate_sps=10e6, start_freq_hz=60e9),
    "IWR6843_real": dict(chip="IWR6843", mimo="tdma", n_tx=3, adc_rate_sps=10e6,
                         start_freq_hz=60e9),
}


@pytest.mark.parametrize("name", sorted(FAMILY_CFGS))
def test_every_family_round_trips(tmp_path, name):
    kw = dict(n_samples=32, n_chirps=24, **FAMILY_CFGS[name])
    cfg = radarsim.RadarConfig.from_fields(**kw)
    sc = radarsim.Scatterers(position_m=[[10.0, 1.0, 0.0]], velocity_mps=[[-2.0, 0, 0]],
                             rcs_m2=[1.0])
    frames = np.stack([radarsim.simulate_frame(cfg, sc, np.random.default_rng(i))
                       for i in range(2)])
    assert frames.dtype == cfg.adc_dtype
    path = tmp_path / "c.bin"
    write_capture(path, frames, cfg=cfg)
    assert path.stat().st_size == frames.size * 2 * (2 if cfg.is_complex else 1)
    np.testing.assert_array_equal(read_capture(path, cfg), frames)
    # Through the profile text too: the writer's .cfg makes the reader pick the same layout.
    prof = parse_ti_cfg(to_ti_cfg(cfg))
    np.testing.assert_array_equal(read_capture(path, prof), frames)


# ---------------------------------------------------------------------------- public readers
def _openradar_organize(raw_frame, num_chirps, num_rx, num_samples):
    """OpenRadar ``DCA1000.organize`` ordering, written from its documented rule: words
    4k and 4k+1 are the real parts of samples 2k and 2k+1, words 4k+2 and 4k+3 their imaginary
    parts; the result is (chirps, rx, samples)."""
    raw = np.asarray(raw_frame, dtype=np.float64)
    out = np.empty(raw.size // 2, dtype=complex)
    for k in range(raw.size // 4):  # explicit loop: an independent re-statement of the rule
        out[2 * k] = raw[4 * k] + 1j * raw[4 * k + 2]
        out[2 * k + 1] = raw[4 * k + 1] + 1j * raw[4 * k + 3]
    return out.reshape(num_chirps, num_rx, num_samples)


def _ti_read_dca1000_complex(adc_data, num_adc_samples, num_rx):
    """TI SWRA581 ``readDCA1000.m`` complex branch, MATLAB indices emulated: pairs of I then
    pairs of Q into LVDS(1, :); LVDS = reshape(LVDS, N*numRX, numChirps).' (column-major);
    retVal(row, (i-1)*N+1 : i*N) = LVDS(i, (row-1)*N+1 : row*N). Returns (numRX, chirps*N)."""
    file_size = len(adc_data)
    num_chirps = file_size // 2 // num_adc_samples // num_rx
    lvds = np.zeros(file_size // 2, dtype=complex)
    counter = 1
    for i in range(1, file_size, 4):  # MATLAB: for i = 1:4:fileSize-1
        lvds[counter - 1] = adc_data[i - 1] + 1j * adc_data[i + 1]
        lvds[counter] = adc_data[i] + 1j * adc_data[i + 2]
        counter += 2
    lvds = lvds.reshape(num_adc_samples * num_rx, num_chirps, order="F").T
    ret = np.zeros((num_rx, num_chirps * num_adc_samples), dtype=complex)
    for row in range(1, num_rx + 1):
        for i in range(1, num_chirps + 1):
            ret[row - 1, (i - 1) * num_adc_samples: i * num_adc_samples] = \
                lvds[i - 1, (row - 1) * num_adc_samples: row * num_adc_samples]
    return ret


def test_complex_xwr18xx_capture_reads_identically_in_the_public_readers(tmp_path):
    prof = parse_ti_cfg(XWR18_SMALL)
    cfg = prof.radar
    assert (cfg.chip, cfg.adc_mode, cfg.n_chirps, cfg.n_rx, cfg.n_samples) == \
        ("AWR1843", "complex1x", 24, 4, 64)
    sc = radarsim.Scatterers(position_m=[[3.0, 0.5, 0.0]], velocity_mps=[[1.0, 0, 0]],
                             rcs_m2=[1.0])
    frames = np.stack([radarsim.simulate_frame(cfg, sc, np.random.default_rng(i))
                       for i in range(2)])
    path = tmp_path / "adc_data.bin"
    write_capture(path, frames, cfg=prof)
    ours = read_capture(path, prof)
    np.testing.assert_array_equal(ours, frames)
    words = np.fromfile(path, dtype="<i2")
    per_frame = words.size // 2
    for f in range(2):
        raw = words[f * per_frame:(f + 1) * per_frame]
        np.testing.assert_array_equal(_openradar_organize(raw, 24, 4, 64), ours[f])
    # TI's reader works on the whole file: Rx-major rows of all chirps' samples.
    ti = _ti_read_dca1000_complex(words.astype(np.float64), 64, 4)
    np.testing.assert_array_equal(
        ti, ours.transpose(2, 0, 1, 3).reshape(4, 2 * 24 * 64))


def test_layout_registry_and_refusals():
    # complex_4lane (4 Rx only): test_four_lane_complex_layout_is_ti_readers_order.
    assert set(CAPTURE_LAYOUTS) == set(HAND_MADE) | {"complex_4lane"}
    with pytest.raises(ValueError, match="n_samples=5: the 2-lane complex layout"):
        layout_of(radarsim.RadarConfig.from_fields(
            chip="AWR1843", adc_mode="complex1x", mimo="tdma", n_tx=1, n_samples=5, n_chirps=2,
            adc_rate_sps=10e6))
    with pytest.raises(ValueError, match="interleaved complex captures are not modelled"):
        layout_of(_tiny("AWR1843", "complex1x"), interleaved=True)


def test_four_lane_complex_layout_is_ti_readers_order(tmp_path):
    """xWR1243/1443/2243 captures (4 LVDS lanes, mmWave Studio): TI's readDCA1000.m reshapes the
    words to (8, -1) and takes rows 1-4 + j rows 5-8, lane k = Rx k, each lane's samples chirp
    after chirp. A hand-built frame: sample s of chirp c on Rx r = v - j v,
    v = (100 c + 10 r + s) mod 16000."""
    from radarsim.ti import parse_setup
    from tests.radarsim.profiles import PROFILE_DIR

    prof = parse_setup(PROFILE_DIR / "awr2243_studio_LogFile.txt")
    cfg = prof.radar
    assert layout_of(cfg).name == "complex_4lane"
    c, r, n = cfg.n_chirps, cfg.n_rx, cfg.n_samples
    ci, ri, si = np.meshgrid(np.arange(c), np.arange(r), np.arange(n), indexing="ij")
    v = (100 * ci + 10 * ri + si) % 16000
    frame = (v - 1j * v).astype(np.complex64)
    path = tmp_path / "adc_data_Raw_0.bin"
    write_capture(path, frame[None], cfg=cfg)
    words = np.fromfile(path, dtype="<i2").astype(np.int64)
    lanes = words.reshape(-1, 8).T                       # MATLAB reshape(adcData, 8, []) order
    rx = lanes[0:4] + 1j * lanes[4:8]                    # (Rx, chirp x sample)
    np.testing.assert_array_equal(rx.reshape(r, c, n).transpose(1, 0, 2), frame)
    np.testing.assert_array_equal(read_capture(path, cfg)[0], frame)
