"""The schema of a results folder, checked once where `gate` and `report` read it.

A results folder is days old, copied between machines and sometimes edited by hand. Its
``manifest.json`` and tables are validated here against what `harness.assemble` writes and
what the readers use, so damage is refused as bad input (exit 2) naming the file and the field,
never met later as a ``KeyError`` or an ``AttributeError`` deep inside a plot. What may
legitimately be absent (a count not recorded, a metric the run could not compute) is not
refused: `results_gaps` lists it so the report can say so.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from core.errors import BadInput
from core.fileio import MAX_TABLE_FILE_BYTES, check_input_file, read_input_text

__all__ = ["MANIFEST_COUNTS", "TABLE_COLUMNS", "HEADLINE_INPUTS", "REPORTED_METRICS",
           "read_manifest",
           "check_manifest", "read_table", "results_gaps"]

#: Cell counts of a manifest: a non-negative integer, or null / NaN for "not recorded".
MANIFEST_COUNTS = ("n_cells", "n_ok", "n_error", "n_missing", "n_resumed", "n_computed")
#: Text fields of a manifest (null allowed: not recorded).
_MANIFEST_TEXT = ("run_id", "baseline_scheme", "code_version", "written_utc")

#: Columns every reader of a table relies on (the rows' identity and what is drawn); a table
#: without one is damaged. `harness.assemble` writes all of them.
TABLE_COLUMNS = {
    "summary": ("scenario", "variant", "seed", "scheme"),
    "detections": ("scenario", "variant", "seed", "scheme", "frame", "label", "range_m",
                   "snr_db", "x_m", "y_m"),
    "actors": ("scenario", "variant", "seed", "scheme", "frame", "actor_id", "actor_class",
               "range_m", "visible", "detected", "max_snr_db"),
    "actor_summary": ("scheme", "actor_class", "n_visible_frames", "n_detected_frames",
                      "first_detection_range_m"),
    "truth": ("scenario", "variant", "seed", "frame", "actor_id", "actor_class", "length_m",
              "width_m", "x_radar_m", "y_radar_m", "yaw_radar_deg"),
}

#: Summary columns the report's headline is computed from (`metrics.suite.headline_table`):
#: absent or all-NaN, the headline shows a blank that `results_gaps` explains.
HEADLINE_INPUTS = ("n_detections", "n_ghost", "range_error_rmse_m",
                   "radial_velocity_error_rmse_mps", "n_error_samples", "n_velocity_right",
                   "n_velocity_resolution_failures")
#: Summary columns whose absence or lack of any finite value the report states: the headline's
#: inputs and the metrics every case section shows.
REPORTED_METRICS = HEADLINE_INPUTS + ("ghost_rate", "detections_per_frame",
                                      "velocity_unambiguity_rate", "detection_probability_mean")


def read_manifest(folder: str | Path, *, required: bool = False) -> dict:
    """``manifest.json`` of a results folder, checked by `check_manifest` ({} when absent and
    not `required`).

    Raises
    ------
    core.errors.BadInput
        ``{path}: damaged manifest (...)`` naming the field; the file is a FIFO, a device, too
        large (`core.fileio.read_input_text`); absent and `required`.
    """
    mf = Path(folder) / "manifest.json"
    if not mf.exists() and not mf.is_symlink():
        if required:
            raise BadInput(f"no manifest.json in {folder}")
        return {}
    text = read_input_text(mf, "manifest")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise BadInput(f"{mf}: damaged manifest (not JSON: {exc})") from None
    except RecursionError:
        # json's decoder recurses per nesting level; assemble writes four levels.
        raise BadInput(f"{mf}: damaged manifest (nested deeper than a manifest can be)") \
            from None
    if not isinstance(data, dict):
        raise BadInput(f"{mf}: damaged manifest (not a JSON object)")
    check_manifest(data, mf)
    return data


def _damaged(path, field: str, value, want: str) -> BadInput:
    return BadInput(f"{path}: damaged manifest ({field}={_short(value)} must be {want})")


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _is_count(v) -> bool:
    """A non-negative integer, or null / NaN (not recorded)."""
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return True
    return isinstance(v, int) and not isinstance(v, bool) and v >= 0


def check_manifest(m: dict, path) -> None:
    """Raise `core.errors.BadInput` ``{path}: damaged manifest (field=value must be ...)`` for
    a field of the wrong type: every field a reader uses (`MANIFEST_COUNTS`, the text fields,
    ``git``, ``schemes``, ``tables``, ``sweep.variants`` and each of ``cells``). Absent fields
    are allowed (older runs)."""
    for f in _MANIFEST_TEXT:
        if m.get(f) is not None and not isinstance(m[f], str):
            raise _damaged(path, f, m[f], "a string")
    for f in MANIFEST_COUNTS:
        if f in m and not _is_count(m[f]):
            raise _damaged(path, f, m[f], "a non-negative integer")
    git = m.get("git")
    if git is not None:
        if not isinstance(git, dict):
            raise _damaged(path, "git", git, "an object {commit, dirty}")
        if git.get("commit") is not None and not isinstance(git["commit"], str):
            raise _damaged(path, "git.commit", git["commit"], "a string")
    schemes = m.get("schemes")
    if schemes is not None and not (isinstance(schemes, list)
                                    and all(isinstance(s, str) for s in schemes)):
        raise _damaged(path, "schemes", schemes, "a list of scheme names")
    tables = m.get("tables")
    if tables is not None and not (isinstance(tables, dict)
                                   and all(isinstance(v, str) for v in tables.values())):
        raise _damaged(path, "tables", tables, "an object of table file names")
    sweep = m.get("sweep")
    if sweep is not None and not isinstance(sweep, dict):
        raise _damaged(path, "sweep", sweep, "an object (the sweep file)")
    _check_records((sweep or {}).get("variants"), path, "sweep.variants",
                   {"name": (str, True), "processing": (dict, False)})
    _check_records(m.get("cells"), path, "cells",
                   {"cell_id": (str, True), "status": (str, True)})


def _check_records(records, path, field: str, keys: dict) -> None:
    """A list (None: absent) of objects whose `keys` (name -> (type, required)) have those
    types; an optional key may be absent."""
    if records is None:
        return
    if not isinstance(records, list):
        raise _damaged(path, field, records, "a list of records")
    for i, r in enumerate(records):
        if not isinstance(r, dict):
            raise _damaged(path, f"{field}[{i}]", r, "an object {" + ", ".join(keys) + ", ...}")
        for key, (kind, required) in keys.items():
            if (required or key in r) and not isinstance(r.get(key), kind):
                raise _damaged(path, f"{field}[{i}].{key}", r.get(key),
                               "a string" if kind is str else "an object")


def read_table(results: str | Path, name: str, manifest: dict) -> pd.DataFrame:
    """Table `name` of a results folder with the columns of `TABLE_COLUMNS` checked.

    An absent table the manifest does not list reads as an empty frame with those columns
    (an older or partial run); one the manifest lists is damage.

    Raises
    ------
    core.errors.BadInput
        ``{file}: ...`` an absent listed table, an unreadable file, a missing column.
    """
    f = Path(results) / f"{name}.parquet"
    need = list(TABLE_COLUMNS.get(name, ()))
    if not f.exists() and not f.is_symlink():
        if name in (manifest.get("tables") or {}):
            raise BadInput(f"{f}: missing (manifest.json lists the {name} table): the "
                             "results folder is incomplete; rerun the sweep")
        return pd.DataFrame({c: pd.Series(dtype=object) for c in need})
    check_input_file(f, f"{name} table", max_bytes=MAX_TABLE_FILE_BYTES)
    try:
        df = pd.read_parquet(f)
    except Exception as exc:  # noqa: BLE001 - pyarrow raises several types
        raise BadInput(f"{f}: not a readable Parquet {name} table: {exc}") from None
    missing = [c for c in need if c not in df.columns]
    if missing:
        raise BadInput(f"{f}: the {name} table lacks column(s) {missing}")
    return df


def results_gaps(summary: pd.DataFrame, manifest: dict, baseline: str) -> list[str]:
    """What a results folder does not hold that the report would otherwise show as a blank:
    counts not recorded, a baseline scheme that was not run, metric columns
    (`REPORTED_METRICS`) absent or without a finite value. Empty for a complete run."""
    out = []
    for f in ("n_ok", "n_cells"):
        v = manifest.get(f)
        if manifest and (v is None or isinstance(v, float)):
            out.append(f"manifest.json records no {f} ({v!r}): the cell count is unknown")
    ok = summary[summary["error"].fillna("").astype(str) == ""] if "error" in summary \
        else summary
    schemes = [s for s in dict.fromkeys(ok["scheme"]) if s]
    if schemes and baseline not in schemes:
        out.append(f"baseline scheme {baseline!r} was not run (schemes {schemes}): no SNR "
                   "gain over it")
    absent = [c for c in REPORTED_METRICS if c not in ok.columns]
    if absent:
        out.append(f"summary.parquet has no column(s) {absent}: what they give is blank")
    empty = [c for c in REPORTED_METRICS if c in ok.columns and len(ok)
             and not np.isfinite(pd.to_numeric(ok[c], errors="coerce")).any()]
    if empty:
        out.append(f"summary.parquet column(s) {empty} hold no finite value in any completed "
                   "cell: what they give is blank")
    return out
