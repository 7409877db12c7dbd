"""Bad DCA1000 captures and profiles: exit code 2 / ValueError naming the file and the problem."""
from __future__ import annotations

import numpy as np
import pytest

import radarsim
from harness.cli import main
from radarsim.capture import capture_n_frames, write_capture
from radarsim.ti import r79_cfg_path

CFG = radarsim.presets.r79("ddma")


def _capture_cases(tmp_path):
    torn = tmp_path / "torn.bin"
    torn.write_bytes(b"\0" * 1000)
    empty = tmp_path / "empty.bin"
    empty.write_bytes(b"")
    folder = tmp_path / "folder.bin"
    folder.mkdir()
    return {
        "torn": (torn, r"capture '.*torn\.bin' has 1000 bytes, not a whole number of frames"),
        "empty": (empty, r"capture '.*empty\.bin' is empty"),
        "missing": (tmp_path / "nope.bin", r"nope\.bin: No such file or directory"),
        "directory": (folder, r"capture '.*folder\.bin' is a directory"),
    }


@pytest.mark.parametrize("kind", ["torn", "empty", "missing", "directory"])
def test_process_rejects_a_bad_capture_with_exit_2(tmp_path, capsys, kind):
    path, match = _capture_cases(tmp_path)[kind]
    assert main(["process", str(path), "--cfg", str(r79_cfg_path()), "--out",
                 str(tmp_path / "p.parquet")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert __import__("re").search(match, err[0]), err[0]


def test_capture_length_checked_against_the_profile(tmp_path):
    path = tmp_path / "one.bin"
    write_capture(path, np.zeros((1, CFG.n_chirps, CFG.n_rx, CFG.n_samples), np.int16), cfg=CFG)
    assert capture_n_frames(path, CFG) == 1
    other = radarsim.presets.r79("ddma", n_samples=256)  # 1.5 of its frames
    with pytest.raises(ValueError, match=r"not a whole number of frames"):
        capture_n_frames(path, other)


@pytest.mark.parametrize("frame, match", [
    (np.zeros((CFG.n_chirps, CFG.n_rx, CFG.n_samples), np.float32), r"frame 0: dtype float32"),
    (np.zeros((2, CFG.n_rx, CFG.n_samples), np.int16), r"frame 0: shape"),
])
def test_write_capture_rejects_bad_frames_and_writes_nothing(tmp_path, frame, match):
    path = tmp_path / "x.bin"
    with pytest.raises(ValueError, match=match):
        write_capture(path, [frame], cfg=CFG)
    assert not path.exists() and not list(tmp_path.iterdir())


@pytest.mark.parametrize("content, match", [
    (b"\xff\xfe\x00\x01binary",
     r"profile '.*bad\.cfg' is not UTF-8 text: byte 0xff at offset 0 \(line 1\)"),
    (None, r"--cfg '.*bad\.cfg' is a directory"),
])
def test_bad_profile_is_exit_2(tmp_path, capsys, content, match):
    bad = tmp_path / "bad.cfg"
    if content is None:
        bad.mkdir()
    else:
        bad.write_bytes(content)
    cap = tmp_path / "c.bin"
    write_capture(cap, np.zeros((1, CFG.n_chirps, CFG.n_rx, CFG.n_samples), np.int16), cfg=CFG)
    assert main(["process", str(cap), "--cfg", str(bad), "--out",
                 str(tmp_path / "p.parquet")]) == 2
    assert __import__("re").search(match, capsys.readouterr().err)


N_KINDS = 4 + 1 + 2 + 2
