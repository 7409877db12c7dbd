"""DCA1000 capture I/O: documented byte layouts, bit-exact round trips, clean failures.

The small fixture config is the R79 preset (AWR2944, real ADC, interleaved ADC buffer as the
R79 firmware's ``adcbufCfg -1 1 0 0 1``); hand-made files with their word order written out and
the public readers' ordering are in test_capture_layouts.py."""
from __future__ import annotations

import numpy as np
import pytest

from radarsim.capture import (
    capture_n_frames,
    frame_nbytes,
    iter_capture,
    open_capture,
    read_capture,
    write_capture,
)


@pytest.fixture
def small_cfg(make_config):
    # 12 chirps (2 DDMA code periods) x 4 Rx x 16 samples: 1536 bytes a frame; the
    # non-interleaved buffer (profile_LVDS.cfg's adcbufCfg -1 1 1 1 1) unless a test says.
    return make_config(n_chirps=12, n_samples=16, adcbuf_interleaved=False)


@pytest.fixture
def frames(small_cfg, rng):
    f = rng.integers(-32768, 32768, size=(3, 12, 4, 16), dtype=np.int16)
    f[0, 0, 0, :2] = (-32768, 32767)  # both int16 extremes survive
    return f


def _tmp_files(directory):
    return sorted(p.name for p in directory.iterdir() if p.name.startswith("."))


def test_round_trip_is_bit_exact(tmp_path, small_cfg, frames):
    path = tmp_path / "adc_data.bin"
    assert write_capture(path, frames, cfg=small_cfg) == 3
    back = read_capture(path, small_cfg)
    assert back.dtype == np.int16 and back.shape == (3, 12, 4, 16)
    assert type(back) is np.ndarray and back.flags.c_contiguous and back.flags.writeable
    np.testing.assert_array_equal(back, frames)
    assert path.stat().st_size == 3 * frame_nbytes(small_cfg) == 3 * 12 * 4 * 16 * 2


def test_byte_layout_is_chirp_rx_sample_little_endian(tmp_path, small_cfg):
    """TI SWRA581 readDCA1000 (real data): per chirp, Rx0 samples 0..N-1, then Rx1, ..."""
    f = np.arange(12 * 4 * 16, dtype=np.int16).reshape(1, 12, 4, 16)
    f[0, 0, 0, 0] = 0x0102
    path = tmp_path / "c.bin"
    write_capture(path, f)
    raw = path.read_bytes()
    assert raw[:2] == b"\x02\x01"                               # little-endian int16
    flat = np.frombuffer(raw, dtype="<i2")
    assert flat[16] == f[0, 0, 1, 0]                            # Rx1 follows Rx0's 16 samples
    assert flat[4 * 16] == f[0, 1, 0, 0]                        # chirp 1 follows all Rx
    np.testing.assert_array_equal(flat, f.ravel())


def test_interleaved_layout(tmp_path, small_cfg, frames):
    """Interleaved ADC buffer (adcbufCfg ChanInterleave 0): the Rx alternate per sample."""
    path = tmp_path / "c.bin"
    write_capture(path, frames, interleaved=True)
    flat = np.fromfile(path, dtype="<i2")
    np.testing.assert_array_equal(flat, frames.transpose(0, 1, 3, 2).ravel())
    np.testing.assert_array_equal(read_capture(path, small_cfg, interleaved=True), frames)
    # The reader follows the profile: the R79 config's own buffer is interleaved.
    r79 = small_cfg.replace(adcbuf_interleaved=True)
    np.testing.assert_array_equal(read_capture(path, r79), frames)
    path2 = tmp_path / "d.bin"
    write_capture(path2, frames, cfg=r79)
    assert path2.read_bytes() == path.read_bytes()


def test_streamed_frames_equal_array(tmp_path, small_cfg, frames):
    a, b = tmp_path / "a.bin", tmp_path / "b.bin"
    write_capture(a, frames)
    assert write_capture(b, (f for f in frames), cfg=small_cfg) == 3
    assert a.read_bytes() == b.read_bytes()
    got = list(iter_capture(b, small_cfg))
    assert len(got) == 3 and all(np.array_equal(g, f) for g, f in zip(got, frames))
    assert len(list(iter_capture(b, small_cfg, max_frames=2))) == 2


def test_memory_map_is_read_only_view(tmp_path, small_cfg, frames):
    path = tmp_path / "c.bin"
    write_capture(path, frames)
    mm = open_capture(path, small_cfg)   # (frames, words) in file order
    np.testing.assert_array_equal(mm[2], frames[2].ravel())
    with pytest.raises(ValueError):
        mm[0, 0] = 1


@pytest.mark.parametrize("cut", [2, 1, 1536 + 2])
def test_truncated_capture_is_rejected(tmp_path, small_cfg, frames, cut):
    path = tmp_path / "c.bin"
    write_capture(path, frames)
    size = path.stat().st_size
    with open(path, "r+b") as fh:
        fh.truncate(size - cut)
    with pytest.raises(ValueError, match=rf"has {size - cut} bytes, not a whole number of "
                                         r"frames of 1536 bytes .* truncated"):
        read_capture(path, small_cfg)
    with pytest.raises(ValueError, match="not a whole number of frames"):
        next(iter_capture(path, small_cfg))   # no partial frame is ever yielded


def test_capture_of_another_profile_is_rejected(tmp_path, small_cfg, frames, make_config):
    path = tmp_path / "c.bin"
    write_capture(path, frames)          # 3 x 1536 bytes
    other = make_config(n_chirps=12, n_samples=20, adcbuf_interleaved=False)  # 4608 % 1920
    with pytest.raises(ValueError, match=r"12 chirps x 4 Rx x 20 samples x 2 bytes"):
        read_capture(path, other)
    assert capture_n_frames(path, small_cfg) == 3


def test_empty_capture_is_rejected(tmp_path, small_cfg):
    path = tmp_path / "c.bin"
    path.write_bytes(b"")
    with pytest.raises(ValueError, match="is empty"):
        read_capture(path, small_cfg)


@pytest.mark.parametrize("bad, pattern", [
    (lambda f: f.astype(np.float32), r"frame 0: dtype float32 is not int16"),
    (lambda f: f[:, :, :3], r"frame 0: shape \(12, 3, 16\) differs"),
    (lambda f: f[:0], r"no frames to write"),
    (lambda f: f[0, 0], r"frames shape \(4, 16\) is not"),
])
def test_failed_write_leaves_target_untouched(tmp_path, small_cfg, frames, bad, pattern):
    path = tmp_path / "c.bin"
    path.write_bytes(b"previous capture")
    with pytest.raises(ValueError, match=pattern):
        write_capture(path, bad(frames), cfg=small_cfg)
    assert path.read_bytes() == b"previous capture"
    assert _tmp_files(tmp_path) == []


def test_frames_of_differing_shapes_are_rejected(tmp_path, frames):
    path = tmp_path / "c.bin"
    with pytest.raises(ValueError, match=r"frame 1: shape \(12, 4, 8\) differs from the expected"):
        write_capture(path, [frames[0], frames[1][:, :, :8]])
    assert not path.exists() and _tmp_files(tmp_path) == []
