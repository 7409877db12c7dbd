"""One call of an external chain: write its inputs, run it fenced in, read and check its points.

The command runs in its own scratch folder and its own process group (a new session), with
stdin closed and stdout / stderr to files. Past ``timeout_s`` the whole group is killed with
SIGKILL (a child that ignores SIGTERM dies too); after a normal exit the group is killed as
well, so no stray child outlives the call. Every failure (cannot start, non-zero exit, timeout,
no point file, a file that does not parse, missing or non-numeric columns, non-finite or
out-of-range values, frames outside the call) raises `ExternalChainError` with the command's
last stderr lines; the sweep records the cell as failed and goes on.
"""
from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

__all__ = ["ExternalChainError", "CallResult", "run_command", "read_points", "check_points",
           "REQUIRED_COLUMNS", "STDERR_TAIL_LINES"]

#: Columns a point file must have (`pipeline.process_frame`'s names and units).
REQUIRED_COLUMNS = ("range_m", "azimuth_deg", "radial_velocity_mps", "snr_db")
#: Optional columns: elevation (deg, default 0) and the frame of the call (0-based; required
#: when a call holds several frames).
OPTIONAL_COLUMNS = ("elevation_deg", "frame")
#: stderr lines quoted in a failure.
STDERR_TAIL_LINES = 5


class ExternalChainError(RuntimeError):
    """An external chain's call failed (the cell is recorded as failed, the sweep goes on)."""


class CallResult(NamedTuple):
    """Points of one call (``frame`` = index within the call) and the command's wall time, s."""

    points: pd.DataFrame
    elapsed_s: float


def _tail(path: Path) -> str:
    try:
        lines = path.read_bytes()[-8192:].decode("utf-8", "replace").splitlines()
    except OSError:
        return ""
    lines = [ln.strip() for ln in lines if ln.strip()][-STDERR_TAIL_LINES:]
    return " | ".join(lines) if lines else "(no stderr)"


def _kill_group(pid: int) -> None:
    try:
        os.killpg(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def run_command(argv: list[str], cwd: Path, timeout_s: float, what: str) -> float:
    """Run `argv` in `cwd` fenced in (module docstring); returns its wall time, s.

    Raises
    ------
    ExternalChainError
        Cannot start, exits non-zero, or runs past `timeout_s` (naming `what`, the exit status
        and the last stderr lines).
    """
    err_path = cwd / "stderr.txt"
    with open(cwd / "stdout.txt", "wb") as out, open(err_path, "wb") as err:
        t0 = time.perf_counter()
        try:
            proc = subprocess.Popen(argv, cwd=cwd, stdin=subprocess.DEVNULL, stdout=out,
                                    stderr=err, start_new_session=True)
        except OSError as exc:
            raise ExternalChainError(f"{what}: cannot start {argv[0]!r}: "
                                     f"{exc.strerror or exc}") from None
        try:
            rc = proc.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            rc = None
        finally:  # the whole group, on a timeout, an exit or an interrupt alike
            _kill_group(proc.pid)
            proc.wait()
        elapsed = time.perf_counter() - t0
    if rc is None:
        raise ExternalChainError(f"{what}: no result within timeout_s={timeout_s:g} s (its "
                                 f"process group was killed); last stderr: {_tail(err_path)}")
    if rc != 0:
        raise ExternalChainError(f"{what}: command exited with status {rc}; last stderr: "
                                 f"{_tail(err_path)}")
    return elapsed


def read_points(path: Path, what: str, stderr: Path) -> pd.DataFrame:
    """The point file a call wrote (CSV or Parquet by suffix).

    Raises
    ------
    ExternalChainError
        No file, or a file that does not parse.
    """
    if not path.is_file() or path.stat().st_size == 0:
        raise ExternalChainError(f"{what}: the command wrote no point file {path.name!r}; "
                                 f"last stderr: {_tail(stderr)}")
    try:
        if path.suffix.lower() == ".parquet":
            return pd.read_parquet(path)
        return pd.read_csv(path)
    except Exception as exc:  # noqa: BLE001 - any parser error is the command's garbage
        text = " ".join(str(exc).split())[:200]
        raise ExternalChainError(f"{what}: point file {path.name!r} does not parse "
                                 f"({type(exc).__name__}: {text}); last stderr: "
                                 f"{_tail(stderr)}") from None


def check_points(points: pd.DataFrame, radar, n_frames: int, what: str) -> pd.DataFrame:
    """Validated points with the chain's columns: the required ones, elevation (0 when
    absent), ``frame`` (0 when a call holds one frame), float64.

    Limits: 0 <= range_m <= the radar's maximum range, |azimuth_deg| and |elevation_deg|
    <= 90, |radial_velocity_mps| <= n_tx x the radar's unambiguous velocity (the widest a
    velocity-extension chain reports), snr_db finite; frame an integer in 0..n_frames - 1.

    Raises
    ------
    ExternalChainError
        Naming the column and the first offending value.
    """
    missing = [c for c in REQUIRED_COLUMNS if c not in points.columns]
    if "frame" not in points.columns and n_frames > 1:
        missing.append("frame")
    if missing:
        raise ExternalChainError(f"{what}: point file lacks column(s) {missing}; it has "
                                 f"{list(map(str, points.columns))[:12]}")
    cols = [c for c in (*REQUIRED_COLUMNS, *OPTIONAL_COLUMNS) if c in points.columns]
    out = {}
    for c in cols:
        s = points[c]
        if len(s) and (not pd.api.types.is_numeric_dtype(s) or pd.api.types.is_bool_dtype(s)):
            # (a header-only CSV has untyped columns: no points is a valid answer)
            raise ExternalChainError(f"{what}: column {c!r} is not numeric ({s.dtype})")
        v = s.to_numpy(dtype=np.float64)
        bad = ~np.isfinite(v)
        if bad.any():
            raise ExternalChainError(f"{what}: column {c!r} holds non-finite value "
                                     f"{float(v[bad][0])!r} (row {int(np.flatnonzero(bad)[0])})")
        out[c] = v
    v_lim = radar.n_tx * radar.max_unambiguous_velocity_mps
    limits = {"range_m": (0.0, radar.max_range_m), "azimuth_deg": (-90.0, 90.0),
              "elevation_deg": (-90.0, 90.0), "radial_velocity_mps": (-v_lim, v_lim),
              "frame": (0, n_frames - 1)}
    for c, (lo, hi) in limits.items():
        if c in out:
            bad = (out[c] < lo) | (out[c] > hi)
            if c == "frame":
                bad |= out[c] != np.round(out[c])
            if bad.any():
                raise ExternalChainError(f"{what}: column {c!r} value {out[c][bad][0]:g} (row "
                                         f"{int(np.flatnonzero(bad)[0])}) is outside "
                                         f"[{lo:g}, {hi:g}]")
    n = len(points)
    return pd.DataFrame({
        "frame": out["frame"].astype(np.int64) if "frame" in out else np.zeros(n, np.int64),
        "range_m": out["range_m"], "azimuth_deg": out["azimuth_deg"],
        "elevation_deg": out.get("elevation_deg", np.zeros(n)),
        "radial_velocity_mps": out["radial_velocity_mps"], "snr_db": out["snr_db"]})
