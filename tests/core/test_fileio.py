"""The shared input check and atomic write (`core.fileio`): one rule per test."""
from __future__ import annotations

import errno
import os
import socket
import subprocess
import sys

import pytest

from core import fileio as fio


def _fifo(p):
    os.mkfifo(p)
    return p


def _loop(p):
    os.symlink(p.with_name("b"), p)
    os.symlink(p, p.with_name("b"))
    return p


@pytest.mark.parametrize("make, match", [
    (_fifo, r"'.*x': is a FIFO \(named pipe\), not a regular file"),
    (lambda p: (os.symlink("/dev/zero", p), p)[1], r"is a character device, not a regular"),
    (_loop, r"symbolic link loop"),
    (lambda p: (p.mkdir(), p)[1], r"is a directory"),
], ids=["fifo", "dev_zero", "symlink_loop", "directory"])
def test_special_files_are_named_without_blocking(tmp_path, make, match):
    p = make(tmp_path / "x")
    with pytest.raises(fio.BadInputFile, match=match):
        fio.read_input_text(p, "sweep file")


def test_socket_is_not_a_regular_file(tmp_path):
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(tmp_path / "s"))
    try:
        with pytest.raises(fio.BadInputFile, match=r"socket|not a regular file"):
            fio.check_input_file(tmp_path / "s", "case file")
    finally:
        s.close()


def test_size_limit(tmp_path):
    p = tmp_path / "big.toml"
    p.write_bytes(b"x" * 101)
    with pytest.raises(fio.BadInputFile,
                       match=r"big\.toml' is 101 bytes, more than the 100-byte limit"):
        fio.read_input_text(p, "gates file", max_bytes=100)
    assert fio.read_input_text(p, max_bytes=101) == "x" * 101


def test_not_utf8_names_the_byte(tmp_path):
    p = tmp_path / "b.toml"
    p.write_bytes(b"ok\n\xff")
    with pytest.raises(fio.BadInputFile, match=r"not UTF-8 text \(byte 3: b'\\xff'\)"):
        fio.read_input_text(p, "sweep file")


def test_missing_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        fio.check_input_file(tmp_path / "nope")


def test_fifo_with_a_writer_is_still_refused(tmp_path):
    """The check is made on the opened descriptor: a FIFO that has a writer is not read."""
    p = _fifo(tmp_path / "f")
    w = subprocess.Popen([sys.executable, "-c", f"open({str(p)!r}, 'w').write('x = 1')"])
    try:
        with pytest.raises(fio.BadInputFile, match="FIFO"):
            fio.read_input_bytes(p)
    finally:
        w.kill()
        w.wait()


def _enospc(tmp):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(tmp))


@pytest.mark.parametrize("err, why", [(errno.ENOSPC, "no space left on the device"),
                                      (errno.EROFS, "read-only file system"),
                                      (errno.EACCES, "permission denied")])
def test_atomic_write_failure_names_the_path_and_leaves_nothing(tmp_path, err, why):
    target = tmp_path / "report.html"
    target.write_text("old")

    def write(tmp):
        tmp.write_text("half")
        raise OSError(err, os.strerror(err), str(tmp))
    with pytest.raises(fio.OutputError, match=rf"cannot write '.*report\.html': {why}"):
        fio.atomic_write(target, write)
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report.html"]


def test_atomic_write_keeps_the_suffix_last_and_replaces(tmp_path):
    seen = []
    fio.atomic_write(tmp_path / "a.png", lambda tmp: (seen.append(tmp.name),
                                                       tmp.write_bytes(b"png")))
    assert seen[0].startswith(".tmp-") and seen[0].endswith("-a.png")
    assert (tmp_path / "a.png").read_bytes() == b"png"


def test_check_output_dir_probes_the_folder(tmp_path, monkeypatch):
    monkeypatch.setattr(type(tmp_path), "write_bytes", lambda self, data: _enospc(self))
    with pytest.raises(fio.OutputError, match=r"--plot .*: cannot create or write there "
                                              r"\(no space left on the device\)"):
        fio.check_output_dir(tmp_path, "--plot")


def test_check_output_path_refuses_a_directory_and_a_missing_folder(tmp_path):
    with pytest.raises(fio.OutputError, match=r"is a directory; give a file"):
        fio.check_output_path(tmp_path, "--out")
    with pytest.raises(fio.OutputError, match=r"folder .*nope' does not exist"):
        fio.check_output_path(tmp_path / "nope" / "x.csv", "--out")
