"""On-disk store of sweep cells: atomic writes, code versions, verification, resume states.

A cell lives in ``<out>/cells/<cell_id>/``: one Parquet file per table and a ``cell.json`` with
its status ("ok" or "error"), its spec, the code version that computed it and the size and
SHA-256 of every table file. The rules that keep a long sweep from losing or mixing results:

- A cell directory appears in one ``rename`` of a fully written temporary directory
  (``.tmp-<cell>-<host>-<pid>-<rand>``), so a kill at any moment leaves either the old state or
  the new one, plus at worst a temporary directory that `clean_temporaries` removes later.
- A completed cell (status "ok", this code version, every table file intact) is never replaced:
  a second execution of it (a concurrent run, an orphaned Dask task) that finishes later, with a
  result or with an error, is discarded (`write_cell_dir` returns "kept").
- Every cell records `code_version()`: a hash of the source files of the harness's packages
  plus the versions of the numerical libraries. A resume only reuses cells of the same version
  (`cell_state` says "stale" otherwise) and only cells whose tables still match their recorded
  checksums ("corrupt" otherwise), so a rerun never mixes versions or reads a damaged table.
"""
from __future__ import annotations

import errno
import functools
import hashlib
import json
import os
import shutil
import socket
import subprocess
import time
import uuid
from pathlib import Path
from typing import Callable

import numpy as np

from core.fileio import read_input_text
from harness.plugins import plugins_fingerprint

__all__ = ["CELL_STATES", "code_version", "base_code_version", "code_source_files", "read_meta",
           "cell_state", "table_files", "write_cell_dir", "retire", "clean_temporaries",
           "TEMP_PREFIXES", "cell_dir", "cell_states", "completed_cells"]

#: What a cell directory can hold, as seen by a resume.
CELL_STATES = {
    "ok": "completed by this code version, every table intact: reused",
    "error": "the cell raised: retried by the next run",
    "stale": "completed by another code version: recomputed only with --force",
    "corrupt": "cell.json says ok but a table file is missing or damaged: recomputed",
    "missing": "never written (not run yet, or its worker was killed)",
}
#: Prefixes of the temporary directories of an atomic write and of a retired cell.
TEMP_PREFIXES = (".tmp-", ".old-")
#: Packages whose source defines the numbers of a cell.
_PACKAGES = ("core", "radarsim", "pipeline", "metrics", "scenarios", "harness")
_SOURCE_SUFFIXES = {".py", ".toml", ".cfg", ".json", ".npz", ".csv"}
#: Libraries whose version can change the bits of a cell.
_LIBRARIES = ("numpy", "scipy", "pandas", "pyarrow", "highway-env", "gymnasium")
_HOST = socket.gethostname().replace("-", "_") or "host"
#: A temporary directory of a process on another host is removed after this age, s.
FOREIGN_TEMP_MAX_AGE_S = 24 * 3600.0


def code_version() -> dict:
    """Version of the code that computes cells: the harness's own (`base_code_version`) and
    the plugins loaded in this process (`harness.plugins.plugins_fingerprint`).

    Returns
    -------
    dict
        ``hash``: SHA-256 (16 hex digits) of the base hash and every plugin's module and source
        hash (no plugin: the base hash itself, so results without plugins keep their version);
        ``commit`` and ``dirty``: the git state, informative only (None outside a git
        checkout); ``plugins``: ``module=sha256`` of each plugin (empty without).
    """
    base = base_code_version()
    fp = plugins_fingerprint()
    if not fp:
        return {**base, "plugins": []}
    h = hashlib.sha256(f"{base['hash']}\n{fp}".encode()).hexdigest()[:16]
    return {**base, "hash": h, "plugins": fp.splitlines()}


#: The folder holding the packages (this file is <root>/harness/sweep/store.py).
_SOURCE_ROOT = Path(__file__).resolve().parents[2]


def code_source_files() -> list[Path]:
    """Every source file whose bytes enter `base_code_version`: the files of the packages in
    `_PACKAGES` with a suffix in `_SOURCE_SUFFIXES`, sorted."""
    return [f for pkg in _PACKAGES for f in sorted((_SOURCE_ROOT / pkg).rglob("*"))
            if f.suffix in _SOURCE_SUFFIXES and f.is_file() and "__pycache__" not in f.parts]


@functools.lru_cache(maxsize=1)
def base_code_version() -> dict:
    """Version of the harness's own code (cached per process).

    Returns
    -------
    dict
        ``hash``: SHA-256 (16 hex digits) over the relative path and bytes of every source file
        of the packages in `_PACKAGES` and the versions of the numerical libraries (a numpy
        upgrade can flip bits); ``commit`` and ``dirty``: the git state.
    """
    from importlib import metadata
    root = _SOURCE_ROOT
    h = hashlib.sha256()
    for f in code_source_files():
        h.update(str(f.relative_to(root)).encode())
        h.update(b"\0")
        h.update(f.read_bytes())
        h.update(b"\0")
    for lib in _LIBRARIES:
        try:
            h.update(f"{lib}=={metadata.version(lib)}\n".encode())
        except metadata.PackageNotFoundError:
            h.update(f"{lib} missing\n".encode())
    return {"hash": h.hexdigest()[:16], **_git_state(root)}


def _git_state(root: Path) -> dict:
    try:
        sha = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True,
                             text=True, timeout=10, check=True).stdout.strip()
        dirty = bool(subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                                    cwd=root, capture_output=True, text=True,
                                    timeout=10).stdout.strip())
        return {"commit": sha, "dirty": dirty}
    except (OSError, subprocess.SubprocessError):
        return {"commit": None, "dirty": None}


def read_meta(d: Path) -> dict | None:
    """``cell.json`` of a cell directory, or None if absent or unreadable."""
    try:  # a FIFO or device in place of cell.json is damage too, never a blocking read
        meta = json.loads(read_input_text(Path(d) / "cell.json", "cell.json"))
    except (OSError, ValueError):
        return None
    return meta if isinstance(meta, dict) else None


def _sha256(path: Path) -> str:
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def table_files(d: Path) -> dict[str, dict]:
    """Size and SHA-256 of every ``*.parquet`` in a (temporary) cell directory."""
    return {f.name: {"bytes": f.stat().st_size, "sha256": _sha256(f)}
            for f in sorted(Path(d).glob("*.parquet"))}


def cell_state(d: Path, version: str | None = None) -> str:
    """State of one cell directory for a resume (one of `CELL_STATES`).

    Parameters
    ----------
    d : path
        The cell directory.
    version : str, optional
        Code-version hash to compare with (default: this process's `code_version()`).
    """
    meta = read_meta(d)
    if meta is None:
        return "corrupt" if Path(d).exists() else "missing"
    if meta.get("status") == "error":
        return "error"
    if meta.get("status") != "ok":
        return "corrupt"
    version = code_version()["hash"] if version is None else version
    if (meta.get("code_version") or {}).get("hash") != version:
        return "stale"
    files = meta.get("files")
    if not isinstance(files, dict) or not files:
        return "corrupt"
    for name, rec in files.items():
        f = Path(d) / name
        try:
            if f.stat().st_size != rec.get("bytes") or _sha256(f) != rec.get("sha256"):
                return "corrupt"
        except (OSError, AttributeError):
            return "corrupt"
    return "ok"


def cell_dir(out: Path, spec) -> Path:
    """Directory of a cell (``spec.cell_id``, a `harness.cell.spec.CellSpec`) under ``out``."""
    return Path(out) / "cells" / spec.cell_id


def cell_states(out: Path, cells: list) -> dict[str, str]:
    """`cell_state` of every cell under ``out`` (cell id -> state)."""
    version = code_version()["hash"]
    return {c.cell_id: cell_state(cell_dir(out, c), version) for c in cells}


def completed_cells(out: Path, cells: list) -> set[str]:
    """Ids of cells completed under ``out`` by this code version with intact tables."""
    return {i for i, st in cell_states(out, cells).items() if st == "ok"}


def retire(d: Path) -> None:
    """Remove a cell directory (stale, corrupt): renamed aside first, so a kill mid-delete
    leaves an ``.old-*`` directory for `clean_temporaries`, never half a cell."""
    d = Path(d)
    trash = d.parent / f"{TEMP_PREFIXES[1]}{d.name}-{_HOST}-{os.getpid()}-{uuid.uuid4().hex[:6]}"
    try:
        os.rename(d, trash)
    except FileNotFoundError:
        return
    shutil.rmtree(trash, ignore_errors=True)


def write_cell_dir(final: Path, write: Callable[[Path], None]) -> str:
    """Write a cell directory atomically; never replace a completed cell.

    ``write(tmp)`` fills a temporary directory, which is then renamed onto ``final``. An
    existing error record, stale or corrupt cell is moved aside first; a completed cell
    (`cell_state` "ok") is kept and the new result discarded.

    Returns
    -------
    str
        "written" or "kept".
    """
    final = Path(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = final.parent / (f"{TEMP_PREFIXES[0]}{final.name}-{_HOST}-{os.getpid()}-"
                          f"{uuid.uuid4().hex[:6]}")
    tmp.mkdir()
    try:
        write(tmp)
        for _ in range(8):
            try:
                os.rename(tmp, final)  # fails on an existing non-empty directory
                return "written"
            except OSError as exc:
                if exc.errno not in (errno.ENOTEMPTY, errno.EEXIST):
                    raise
            if cell_state(final) == "ok":
                return "kept"
            trash = final.parent / (f"{TEMP_PREFIXES[1]}{final.name}-{_HOST}-{os.getpid()}-"
                                    f"{uuid.uuid4().hex[:6]}")
            try:
                os.rename(final, trash)
            except FileNotFoundError:
                continue
            if cell_state(trash) == "ok":
                # Completed by another execution between the check and the move: put it back.
                try:
                    os.rename(trash, final)
                except OSError:
                    pass
                else:
                    return "kept"
            shutil.rmtree(trash, ignore_errors=True)
        raise RuntimeError(f"{final}: could not place the cell after 8 attempts "
                           "(another process keeps writing it)")
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


def _pid_alive(pid: int) -> bool:
    """Whether process `pid` of this host still runs. A zombie (exited, not yet reaped) does
    not: a killed sweep's orphaned pool workers stay zombies until the host's init reaps them,
    which a container's PID 1 may never do, and their temporaries would then be kept for good
    (Linux: the state letter of /proc/<pid>/stat, proc(5))."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:  # no procfs (not Linux), or the process just went
        return True
    return stat[stat.rfind(")") + 2:][:1] != "Z"  # after "pid (comm) ", comm may hold ")"


def clean_temporaries(cells_root: Path) -> list[Path]:
    """Remove leftovers of killed writes under ``<out>/cells``; returns what was removed.

    A temporary directory of a process on this host is removed when that process no longer
    exists; one of another host (a Dask worker) when older than `FOREIGN_TEMP_MAX_AGE_S`.
    """
    root = Path(cells_root)
    removed = []
    if not root.is_dir():
        return removed
    now = time.time()
    for d in root.iterdir():
        if not d.name.startswith(TEMP_PREFIXES) or not d.is_dir():
            continue
        parts = d.name.rsplit("-", 3)
        host, pid = (parts[1], parts[2]) if len(parts) == 4 else ("", "")
        if host == _HOST and pid.isdigit():
            stale = not _pid_alive(int(pid)) or int(pid) == os.getpid()
        else:
            try:
                stale = now - d.stat().st_mtime > FOREIGN_TEMP_MAX_AGE_S
            except FileNotFoundError:
                continue
        if stale:
            shutil.rmtree(d, ignore_errors=True)
            removed.append(d)
    return removed


def failed_rows(summary) -> "np.ndarray":
    """(n_rows,) bool: the rows of a sweep summary table that record an errored cell, i.e. a
    non-empty ``error``. A missing value, or a table without the column, counts as completed
    (`harness.sweep.assemble.assemble` writes "" for completed cells). The one rule every reader of
    sweep results applies."""
    if "error" not in summary.columns:
        return np.zeros(len(summary), dtype=bool)
    return (summary["error"].fillna("").astype(str) != "").to_numpy()
