"""Concatenating the completed cells of a sweep into ``<out>/<table>.parquet`` + manifest.

When all cells are done the per-cell tables are concatenated in cell order and a
``manifest.json`` lists every cell as resumed, computed, error or missing.
"""
from __future__ import annotations

import json
import platform
import time
from pathlib import Path

import pandas as pd

from core.fileio import atomic_write
from harness.cell.spec import TABLES, result_schemes
from harness.plugins import loaded_plugins, plugin_entries
from harness.sweep import store
from harness.sweep.spec import SweepSpec
from harness.sweep.streams import SEED_STREAMS
from metrics.association import AssociationConfig

__all__ = ["assemble", "write_atomic"]


# ----------------------------------------------------------------------------- assembly
def _versions() -> dict[str, str]:
    from importlib import metadata
    out = {"python": platform.python_version()}
    for pkg in ("corner-radar-harness", "numpy", "scipy", "pandas", "pyarrow", "highway-env",
                "gymnasium", "dask", "distributed", "matplotlib"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def write_atomic(path: Path, write) -> None:
    """`core.fileio.atomic_write`: temporary file, then rename; a full disk or read-only
    folder raises `OutputError` naming the path and leaves nothing behind."""
    atomic_write(path, write)


def assemble(spec: SweepSpec, out: str | Path, origin: dict[str, str] | None = None,
             states: dict[str, str] | None = None) -> dict[str, pd.DataFrame]:
    """Concatenate completed cells (in cell order) into ``out/<table>.parquet`` + manifest.

    Only cells completed by this code version with intact tables enter the tables
    (`harness.sweep.store.cell_state` "ok"). The summary table gets an ``error`` column ("" for
    completed cells) and one row per errored cell, so gates see failures. The manifest lists
    every cell with its state and origin ("resumed": reused from an earlier run, "computed":
    by this run, or "error" / "missing" / "stale" / "corrupt"). ``states`` (cell id ->
    `cell_state`) saves re-verifying cells the caller has just checked. Returns the tables.
    """
    out = Path(out)
    cells = spec.cells()
    version = store.code_version()
    parts: dict[str, list[pd.DataFrame]] = {t: [] for t in TABLES}
    cell_meta = []
    for c in cells:
        d = store.cell_dir(out, c)
        state = (states or {}).get(c.cell_id) or store.cell_state(d, version["hash"])
        meta = (store.read_meta(d) or {}) if state in ("ok", "error") else {}
        meta = {**meta, "status": state, "cell_id": c.cell_id}
        cell_meta.append({k: meta.get(k) for k in ("cell_id", "status", "elapsed_s", "error")}
                         | {"origin": (origin or {}).get(c.cell_id, "resumed" if state == "ok"
                                                         else state),
                            "code_version": (meta.get("code_version") or {}).get("hash"),
                            "scenario": c.scenario, "variant": c.variant, "seed": c.seed})
        if state == "ok":
            for t in TABLES:
                f = d / f"{t}.parquet"
                if f.exists():
                    parts[t].append(pd.read_parquet(f))
        elif meta.get("status") == "error":
            parts["summary"].append(pd.DataFrame([{
                "scenario": c.scenario, "variant": c.variant, "seed": c.seed, "scheme": "",
                "error": meta.get("error", "error")}]))
    tables = {}
    for t in TABLES:
        non_empty = [p for p in parts[t] if len(p)]
        df = pd.concat(non_empty, ignore_index=True) if non_empty else \
            (parts[t][0] if parts[t] else pd.DataFrame())
        if t == "summary":
            if "error" not in df.columns:
                df["error"] = ""
            df["error"] = df["error"].fillna("").astype(str)
        tables[t] = df
        write_atomic(out / f"{t}.parquet", lambda tmp, df=df: df.to_parquet(tmp, index=False))
    manifest = {
        "run_id": spec.run_id, "sweep": spec.to_dict(), "seeds": list(spec.seeds),
        # Radar-dependent settings (window, FOV, max range) are each cell's
        # (harness.cell.config.cell_association); the rest are these, with [association] applied.
        "association": {**AssociationConfig().to_dict(), **spec.association,
                        "radar_dependent": "per cell from its radar configs unless "
                                           "[association] sets them"},
        "schemes": list(spec.schemes),
        "baseline_scheme": spec.baseline_scheme,
        "seed_streams": "SeedSequence([seed, frame, stream]); " + ", ".join(
            f"stream {i} {name}" for name, i in SEED_STREAMS.items())
        + " (the tracker's RANSAC: frame 0 of that stream); other schemes' ADC "
          "harness.sweep.streams.stream_id(name)",
        "cells": cell_meta,
        "n_cells": len(cells),
        "n_ok": sum(m["status"] == "ok" for m in cell_meta),
        "n_error": sum(m["status"] == "error" for m in cell_meta),
        "n_missing": sum(m["status"] not in ("ok", "error") for m in cell_meta),
        "n_resumed": sum(m["origin"] == "resumed" for m in cell_meta),
        "n_computed": sum(m["origin"] == "computed" for m in cell_meta),
        "code_version": version["hash"],
        # Which plugin made what: each plugin's module, distribution, version and source hash
        # (part of the code version) and the registry entries it added.
        "plugins": [{**p.record(), "entries": plugin_entries(p)} for p in loaded_plugins()],
        "versions": _versions(), "git": {"commit": version["commit"],
                                         "dirty": version["dirty"]},
        "written_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "tables": {t: f"{t}.parquet" for t in TABLES},
    }
    import radarsim
    try:
        manifest["radar_presets"] = {
            m: radarsim.presets.r79(m).to_dict()
            for m in dict.fromkeys(rs.mimo for rs in result_schemes(spec.schemes,
                                                                  spec.external_chains))}
    except ValueError:  # a scheme with no R79 preset: the manifest just lacks the presets
        pass
    write_atomic(out / "manifest.json", lambda tmp: tmp.write_text(
        json.dumps(manifest, indent=1, default=str)))
    return tables
