"""Safe file input and output for every reader and writer of the project.

Input: `check_input_file` (and `read_input_text` / `read_input_bytes` on top of it) accepts
only a regular file of bounded size. A FIFO would block the reader forever, ``/dev/zero`` would
be read until memory runs out, a symlink loop raises a bare OSError; each is refused with a
`BadInputFile` (a ValueError) naming the file and what it is. The file is opened without
blocking (``O_NONBLOCK``) and checked on the open descriptor (``fstat``), so a FIFO swapped in
between a check and the read cannot block either.

Output: `atomic_write` writes a temporary file in the target folder and renames it over the
target (``os.replace`` is atomic within one filesystem, POSIX rename(2)), so a reader never sees
a half-written file and a full disk or a read-only folder leaves nothing truncated behind: it
raises `OutputError` (a ValueError) naming the path and the system's reason.
`check_output_dir` / `check_output_path` are the checks a command runs before long work.

It is standard library only and lives in `core`, so every package can use it.
"""
from __future__ import annotations

import errno
import os
import stat
import uuid
from collections.abc import Callable
from pathlib import Path

from .errors import BadInputFile, OutputError

__all__ = ["BadInputFile", "OutputError", "check_input_file", "read_input_text",
           "read_input_bytes", "atomic_write", "check_output_dir", "check_output_path",
           "MAX_TEXT_FILE_BYTES", "MAX_TABLE_FILE_BYTES"]

#: Largest text input (TOML sweep, case, gate and security files, JSON manifests, TI
#: profiles): the biggest shipped one is a few kB; 16 MiB is far beyond any real file and
#: still parsed in well under a second.
MAX_TEXT_FILE_BYTES = 16 << 20
#: Largest result table (Parquet) read back: a 10 000-cell sweep's detections stay far below.
MAX_TABLE_FILE_BYTES = 64 << 30


def _kind(mode: int) -> str:
    for test, what in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return what
    return "not a regular file"


def _open_checked(path: str | os.PathLike, what: str, max_bytes: int) -> tuple[int, int]:
    """Open `path` read-only without blocking; return (fd, size). The caller closes fd."""
    p = os.fspath(path)
    try:
        fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise FileNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT), p) from None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise BadInputFile(f"{what} {p!r}: symbolic link loop") from None
        if exc.errno == errno.EISDIR:
            raise BadInputFile(f"{what} {p!r}: is a directory, not a file") from None
        if exc.errno in (errno.EACCES, errno.EPERM):
            raise BadInputFile(f"{what} {p!r}: permission denied") from None
        if exc.errno == errno.ENXIO:  # a socket or a device without a driver
            raise BadInputFile(f"{what} {p!r}: is not a regular file") from None
        raise BadInputFile(f"{what} {p!r}: cannot open ({exc.strerror or exc})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise BadInputFile(f"{what} {p!r}: is {_kind(st.st_mode)}, not a regular file")
        if st.st_size > max_bytes:
            raise BadInputFile(f"{what} {p!r} is {st.st_size} bytes, more than the "
                               f"{max_bytes}-byte limit for this kind of file")
        os.set_blocking(fd, True)
    except BaseException:
        os.close(fd)
        raise
    return fd, st.st_size


def check_input_file(path: str | os.PathLike, what: str = "input file", *,
                     max_bytes: int = MAX_TEXT_FILE_BYTES) -> Path:
    """Check that `path` is a regular file of at most `max_bytes` bytes that can be opened.

    Parameters
    ----------
    path : path-like
    what : str
        What the file is, for the message (``"sweep file"``, ``"--thresholds"``).
    max_bytes : int
        Size limit, bytes.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    FileNotFoundError
        The path does not exist.
    BadInputFile
        ``{what} '{path}': is a FIFO (named pipe), not a regular file`` (or a directory, a
        character or block device, a socket), a symbolic link loop, no permission, or more than
        `max_bytes` bytes.
    """
    fd, _ = _open_checked(path, what, max_bytes)
    os.close(fd)
    return Path(path)


def read_input_bytes(path: str | os.PathLike, what: str = "input file", *,
                     max_bytes: int = MAX_TEXT_FILE_BYTES) -> bytes:
    """The bytes of a checked input file (`check_input_file`), read from the checked
    descriptor; at most `max_bytes` are read even if the file grows meanwhile."""
    fd, size = _open_checked(path, what, max_bytes)
    with os.fdopen(fd, "rb") as fh:
        data = fh.read(max_bytes + 1)
    if len(data) > max_bytes:
        raise BadInputFile(f"{what} {os.fspath(path)!r}: grew beyond the limit {max_bytes} "
                           "bytes while being read")
    return data


def read_input_text(path: str | os.PathLike, what: str = "input file", *,
                    max_bytes: int = MAX_TEXT_FILE_BYTES, encoding: str = "utf-8") -> str:
    """The text of a checked input file (`read_input_bytes`).

    Raises
    ------
    BadInputFile
        As `check_input_file`, or ``{what} '{path}': not {encoding} text (byte {i}: ...)``.
    """
    data = read_input_bytes(path, what, max_bytes=max_bytes)
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise BadInputFile(f"{what} {os.fspath(path)!r}: not {encoding.upper()} text (byte "
                           f"{exc.start}: {data[exc.start:exc.start + 1]!r})") from None


def _output_error(path, exc: OSError) -> OutputError:
    why = {errno.ENOSPC: "no space left on the device", errno.EDQUOT: "disk quota exceeded",
           errno.EROFS: "read-only file system", errno.EACCES: "permission denied",
           errno.EPERM: "permission denied"}.get(exc.errno, exc.strerror or str(exc))
    return OutputError(f"cannot write {os.fspath(path)!r}: {why}")


def atomic_write(path: str | os.PathLike, write: Callable[[Path], object]) -> Path:
    """Write `path` through a temporary file in its folder, then rename it over `path`.

    Parameters
    ----------
    path : path-like
        The output file (its folder must exist).
    write : callable
        ``write(tmp_path)`` writes the whole content to `tmp_path` (e.g.
        ``lambda tmp: df.to_parquet(tmp)``; the temporary name ends with the target's name,
        so a writer that picks the format from the suffix picks the right one).

    Returns
    -------
    pathlib.Path
        `path`.

    Raises
    ------
    OutputError
        ``cannot write '{path}': no space left on the device`` (or read-only file system,
        permission denied, ...): the temporary file is removed and `path` is left as it was.
    """
    p = Path(path)
    # The target's name stays last, so writers that pick the format from the suffix (savefig,
    # PillowWriter, pandas) see the right one.
    tmp = p.with_name(f".tmp-{os.getpid()}-{uuid.uuid4().hex[:8]}-{p.name}")
    try:
        write(tmp)
        if tmp.exists():  # flush to the disk before the rename makes it visible
            fd = os.open(tmp, os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
        os.replace(tmp, p)
    except OSError as exc:
        raise _output_error(p, exc) from None
    finally:
        try:
            tmp.unlink()
        except FileNotFoundError:
            pass
        except OSError:  # a read-only folder: nothing could have been created there
            pass
    return p


def check_output_dir(folder: str | os.PathLike, what: str = "output folder", *,
                     create: bool = True) -> Path:
    """Check (before long work) that files can be created in `folder`.

    A probe file is created and removed, which catches read-only mounts that ``os.access``
    does not see.

    Raises
    ------
    OutputError
        `folder` is a file, cannot be created, or cannot be written.
    """
    p = Path(folder) if str(folder) else Path(".")
    if p.exists() and not p.is_dir():
        raise OutputError(f"{what} {os.fspath(folder)!r}: exists and is not a folder")
    try:
        if create:
            p.mkdir(parents=True, exist_ok=True)
        probe = p / f".tmp-probe-{os.getpid()}-{uuid.uuid4().hex[:8]}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise OutputError(f"{what} {os.fspath(folder)!r}: cannot create or write there "
                          f"({_output_error(folder, exc).args[0].split(': ', 1)[-1]})") from None
    return p


def check_output_path(path: str | os.PathLike, what: str = "output file") -> Path:
    """Check (before long work) that the output file `path` can be written: not a folder,
    its folder exists and takes new files (`check_output_dir`), an existing file is writable.

    Raises
    ------
    OutputError
    """
    p = Path(path)
    if p.is_dir():
        raise OutputError(f"{what} {os.fspath(path)!r} is a directory; give a file to write")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"{what} {os.fspath(path)!r}: folder {os.fspath(parent)!r} does not "
                          "exist")
    check_output_dir(parent, f"{what} {os.fspath(path)!r}: folder", create=False)
    if p.exists() and not os.access(p, os.W_OK):
        raise OutputError(f"{what} {os.fspath(path)!r}: not writable")
    return p
