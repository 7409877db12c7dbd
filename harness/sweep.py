"""Scenario sweeps: a suite of cells (scenario x config variant x seed), run fault-tolerantly.

A sweep is described by a `SweepSpec`, usually read from a TOML file::

    name = "phase-noise"
    scenarios = ["r79_motorcycle_rear", "blind_spot_overtake"]   # or "all"
    seeds = [0, 1, 2]
    frame_stride = 2              # process every 2nd frame (default 1)
    duration_s = 6.0              # optional: shorten every case
    schemes = ["ddma", "tdma", "bpm"]  # optional: radarsim.MIMO_SCHEMES names (or chain
                                  # variants such as "tdma_raw"); default ddma, tdma, tdma_raw
    baseline_scheme = "tdma"      # optional: the SNR gain is each scheme minus this one
    [base.radar]                  # RadarConfig overrides for every cell (both schemes)
    tx_phase_error_deg = [0.0, 3.0, -2.0, 1.0]
    [base.processing]             # ProcessingConfig overrides; cfar_<field> for the CFAR
    cfar_threshold_db = 14.0
    [vary]                        # cartesian product -> one variant per combination
    "radar.phase_noise_deg_rms" = [0.0, 2.0, 10.0]
    "processing.cfar_mode" = ["os", "ca"]
    [association]                 # optional AssociationConfig overrides (e.g. fov_deg = 60.0)

A variant may replace the R79 preset by a TI profile: ``"radar.profile" = ["my.cfg"]`` in
[vary] or ``profile = "my.cfg"`` in a [[variants]] radar table (a path relative to the sweep
file); its other radar keys then override the profile's fields, and each scheme runs the
profile's waveform (e.g. a DDMA profile's TDMA baseline). Radar-dependent association settings
(unambiguous-velocity window, field of view, maximum range) come from each cell's configs
(`harness.runner.cell_association`) unless [association] sets them.

Execution: a local ``concurrent.futures.ProcessPoolExecutor`` (``workers``) or, given a
scheduler address, a Dask distributed cluster (workers must see the output directory). Every
cell is written by the worker that ran it, atomically (temporary directory, then
``os.replace``), to ``<out>/cells/<cell_id>/``; a rerun skips cells already written, so killing a
sweep loses no completed cell. A cell that raises is recorded (``cell.json`` with status
"error" and the traceback) and the sweep continues; errored cells are retried by the next run.
When all cells are done the per-cell tables are concatenated in cell order into
``<out>/<table>.parquet`` and a ``manifest.json`` is written.
"""
from __future__ import annotations

import concurrent.futures as cf
from concurrent.futures.process import BrokenProcessPool
import dataclasses
import hashlib
import itertools
import json
import os
import platform
import shutil
import subprocess
import sys
import time
import traceback
import uuid
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from scenarios.checks import check_keys, read_toml

from .runner import (DEFAULT_BASELINE_SCHEME, DEFAULT_SCHEMES, TABLES, CellSpec, Components,
                     result_schemes, run_cell)

__all__ = ["Variant", "SweepSpec", "SweepOutcome", "load_sweep", "default_sweep",
           "run_sweep", "cell_dir", "completed_cells", "assemble", "DEFAULT_SWEEP_PATH",
           "CI_SWEEP_PATH"]

DEFAULT_SWEEP_PATH = Path(__file__).with_name("default_sweep.toml")
CI_SWEEP_PATH = Path(__file__).with_name("ci_sweep.toml")
_SECTIONS = ("radar", "processing", "tracker")
_TOP_KEYS = {"name", "scenarios", "seeds", "frame_stride", "duration_s", "base", "vary",
             "variants", "description", "schemes", "baseline_scheme", "association"}


@dataclass(frozen=True)
class Variant:
    """A named set of config overrides (one column of the sweep)."""

    name: str = "baseline"
    radar: dict = field(default_factory=dict)
    processing: dict = field(default_factory=dict)
    tracker: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SweepSpec:
    """A suite: scenarios x variants x seeds, with frame stride and optional duration.

    Raises
    ------
    ValueError
        Empty scenario or seed list, negative seed, stride < 1, duplicate variant names.
    """

    name: str
    scenarios: tuple[str, ...]
    seeds: tuple[int, ...] = (0,)
    variants: tuple[Variant, ...] = (Variant(),)
    frame_stride: int = 1
    duration_s: float | None = None
    description: str = ""
    schemes: tuple[str, ...] = DEFAULT_SCHEMES
    baseline_scheme: str = DEFAULT_BASELINE_SCHEME
    association: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "schemes", tuple(self.schemes))
        from metrics.association import AssociationConfig
        AssociationConfig(**self.association)  # unknown keys / bad values fail here
        result_schemes(self.schemes)
        # CellSpec checks the baseline name; check it here too, before any cell is built.
        CellSpec(scenario="-", schemes=self.schemes, baseline_scheme=self.baseline_scheme)
        if not self.scenarios:
            raise ValueError("scenarios: the sweep has no scenario")
        if not self.seeds or any(not isinstance(s, int) or s < 0 for s in self.seeds):
            raise ValueError(f"seeds={list(self.seeds)!r} must be a non-empty list of "
                             "integers >= 0")
        if not isinstance(self.frame_stride, int) or self.frame_stride < 1:
            raise ValueError(f"frame_stride={self.frame_stride!r} must be an integer >= 1")
        if self.duration_s is not None and not (isinstance(self.duration_s, (int, float))
                                                and self.duration_s > 0):
            raise ValueError(f"duration_s={self.duration_s!r} must be > 0")
        names = [v.name for v in self.variants]
        if len(set(names)) != len(names):
            raise ValueError(f"variants: duplicate names {names}")

    def cells(self) -> list[CellSpec]:
        """Cells in a fixed order: scenario, then variant, then seed."""
        return [CellSpec(scenario=sc, seed=seed, variant=v.name, radar=dict(v.radar),
                         processing=dict(v.processing), tracker=dict(v.tracker),
                         frame_stride=self.frame_stride, duration_s=self.duration_s,
                         schemes=self.schemes, baseline_scheme=self.baseline_scheme,
                         association=dict(self.association))
                for sc in self.scenarios for v in self.variants for seed in self.seeds]

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @property
    def run_id(self) -> str:
        """Deterministic id, so rerunning the same command resumes the same directory (the
        scheme keys enter it only when they differ from the defaults)."""
        d = self.to_dict()
        if tuple(d["schemes"]) == DEFAULT_SCHEMES:
            del d["schemes"]
        if d["baseline_scheme"] == DEFAULT_BASELINE_SCHEME:
            del d["baseline_scheme"]
        if not d["association"]:
            del d["association"]
        blob = json.dumps(d, sort_keys=True, default=str)
        return f"{self.name}-{hashlib.sha1(blob.encode()).hexdigest()[:8]}"

    def with_overrides(self, *, seeds=None, frame_stride=None, duration_s=None,
                       scenarios=None, schemes=None) -> "SweepSpec":
        """Copy with command-line overrides (None keeps the file's value)."""
        ch: dict[str, Any] = {}
        if schemes is not None:
            ch["schemes"] = tuple(schemes)
        if seeds is not None:
            ch["seeds"] = tuple(int(s) for s in seeds)
        if frame_stride is not None:
            ch["frame_stride"] = int(frame_stride)
        if duration_s is not None:
            ch["duration_s"] = float(duration_s)
        if scenarios is not None:
            ch["scenarios"] = tuple(_resolve_scenarios(list(scenarios)))
        return dataclasses.replace(self, **ch) if ch else self


def _catalogue() -> list[str]:
    import scenarios
    return list(scenarios.SCENARIOS)


def _resolve_scenarios(value, check: bool = True) -> list[str]:
    if value == "all" or value == ["all"]:
        return _catalogue()
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ValueError(f"scenarios={value!r} must be \"all\" or a list of case names")
    if check:
        known = set(_catalogue())
        bad = [v for v in value if v not in known]
        if bad:
            raise ValueError(f"scenarios: unknown case(s) {bad}; known: {sorted(known)}")
    return value


def _check_section(where: str, section: str, overrides: dict) -> None:
    """Reject unknown config fields early (before any worker starts)."""
    if section not in _SECTIONS:
        raise ValueError(f"{where}: unknown section {section!r}; use one of {list(_SECTIONS)}")
    if not isinstance(overrides, dict):
        raise ValueError(f"{where}: [{section}] must be a table of field = value")
    if section == "radar" and overrides:
        from radarsim.config import RadarConfig
        names = {f.name for f in dataclasses.fields(RadarConfig)} | {"profile"}
        bad = sorted(set(overrides) - names)
        if bad:
            raise ValueError(f"{where}: unknown radar field(s) {bad}")
        if "profile" in overrides:
            from radarsim.config import from_ti_cfg
            prof = overrides["profile"]
            if not isinstance(prof, str) or not Path(prof).is_file():
                raise ValueError(f"{where}: radar.profile={prof!r} is not a TI .cfg file")
            try:
                from_ti_cfg(Path(prof))
            except ValueError as exc:
                raise ValueError(f"{where}: radar.profile={prof!r}: {exc}") from None
    if section == "processing" and overrides:
        import pipeline
        pipeline.ProcessingConfig().replace(**overrides)


def _init_worker() -> None:
    """Pool-worker initializer: one BLAS thread per worker process (with one worker per core,
    BLAS's own threads only oversubscribe the cores: the front end's GEMM slows 8x under load
    with two threads per worker) and the allocator tuning of `harness.runtime`."""
    from threadpoolctl import threadpool_limits

    from .runtime import tune_allocator
    threadpool_limits(limits=1, user_api="blas")
    tune_allocator()


def _fmt(v) -> str:
    return "-".join(map(str, v)) if isinstance(v, (list, tuple)) else str(v)


def _resolve_profiles(p: Path, data: dict) -> None:
    """``radar.profile`` paths relative to the sweep file become absolute (in place)."""
    def fix(v):
        return str((p.parent / v).resolve()) if isinstance(v, str) and \
            not Path(v).is_absolute() else v
    radar = data.get("base", {}).get("radar")
    if isinstance(radar, dict) and "profile" in radar:
        radar["profile"] = fix(radar["profile"])
    vary = data.get("vary", {})
    if isinstance(vary, dict) and isinstance(vary.get("radar.profile"), list):
        vary["radar.profile"] = [fix(v) for v in vary["radar.profile"]]
    for extra in data.get("variants", []) or []:
        if isinstance(extra, dict) and isinstance(extra.get("radar"), dict) and \
                "profile" in extra["radar"]:
            extra["radar"]["profile"] = fix(extra["radar"]["profile"])


def load_sweep(path: str | Path | None = None, *, check_scenarios: bool = True) -> SweepSpec:
    """Read a sweep TOML (None: the shipped default sweep).

    ``check_scenarios`` validates case names against ``scenarios.SCENARIOS``.

    Raises
    ------
    ValueError
        Malformed TOML, unknown keys or config fields, bad values; FileNotFoundError if the
        file does not exist.
    """
    p = Path(path) if path is not None else DEFAULT_SWEEP_PATH
    data = read_toml(p)
    try:
        check_keys(data, _TOP_KEYS)
    except ValueError as exc:
        raise ValueError(f"{p}: {exc}") from None
    base = data.get("base", {})
    _resolve_profiles(p, data)
    for sec, ov in base.items():
        _check_section(f"{p} [base]", sec, ov)
    variants: list[Variant] = []
    vary = data.get("vary", {})
    if not isinstance(vary, dict):
        raise ValueError(f"{p}: [vary] must be a table of \"section.field\" = [values]")
    keys = list(vary)
    for k in keys:
        if "." not in k or not isinstance(vary[k], list) or not vary[k]:
            raise ValueError(f"{p}: vary key {k!r} must look like \"radar.field\" and map to "
                             "a non-empty list")
    combos = list(itertools.product(*(vary[k] for k in keys))) if keys else [()]
    for combo in combos:
        ov = {s: dict(base.get(s, {})) for s in _SECTIONS}
        parts = []
        for k, v in zip(keys, combo):
            sec, fld = k.split(".", 1)
            _check_section(f"{p} [vary]", sec, {fld: v})
            ov[sec][fld] = v
            parts.append(f"{fld}={_fmt(v)}")
        variants.append(Variant(name=",".join(parts) or "baseline", **ov))
    for i, extra in enumerate(data.get("variants", [])):
        bad = sorted(set(extra) - {"name", *_SECTIONS})
        if bad or "name" not in extra:
            raise ValueError(f"{p}: [[variants]] #{i}: needs a name, unknown key(s) {bad}")
        ov = {s: {**base.get(s, {}), **extra.get(s, {})} for s in _SECTIONS}
        for s in _SECTIONS:
            _check_section(f"{p} [[variants]] {extra['name']}", s, ov[s])
        variants.append(Variant(name=str(extra["name"]), **ov))
    if data.get("variants") and not keys:
        variants = variants[1:]  # explicit variants replace the implicit baseline
    seeds = data.get("seeds", [0])
    return SweepSpec(name=str(data.get("name", p.stem)),
                     scenarios=tuple(_resolve_scenarios(data.get("scenarios", "all"),
                                                        check_scenarios)),
                     seeds=tuple(seeds) if isinstance(seeds, list) else (seeds,),
                     variants=tuple(variants), frame_stride=data.get("frame_stride", 1),
                     duration_s=data.get("duration_s"),
                     description=str(data.get("description", "")),
                     schemes=_schemes_key(p, data.get("schemes", list(DEFAULT_SCHEMES))),
                     baseline_scheme=data.get("baseline_scheme", DEFAULT_BASELINE_SCHEME),
                     association=_association_key(p, data.get("association", {})))


def _association_key(p: Path, value) -> dict:
    if not isinstance(value, dict):
        raise ValueError(f"{p}: [association] must be a table of AssociationConfig fields")
    from metrics.association import AssociationConfig
    try:
        AssociationConfig(**value)
    except TypeError as exc:
        raise ValueError(f"{p}: [association]: {exc}") from None
    return dict(value)


def _schemes_key(p: Path, value) -> tuple[str, ...]:
    if not isinstance(value, list):
        raise ValueError(f"{p}: schemes={value!r} must be a list of scheme names")
    return tuple(value)


def default_sweep() -> SweepSpec:
    """The shipped default: the whole catalogue, both schemes, one seed."""
    return load_sweep(DEFAULT_SWEEP_PATH)


# ----------------------------------------------------------------------------- execution
def cell_dir(out: Path, spec: CellSpec) -> Path:
    return Path(out) / "cells" / spec.cell_id


def _read_cell_meta(d: Path) -> dict | None:
    try:
        return json.loads((d / "cell.json").read_text())
    except (FileNotFoundError, json.JSONDecodeError):
        return None


def completed_cells(out: Path, cells: list[CellSpec]) -> set[str]:
    """Ids of cells already written successfully under ``out``."""
    done = set()
    for c in cells:
        meta = _read_cell_meta(cell_dir(out, c))
        if meta and meta.get("status") == "ok":
            done.add(c.cell_id)
    return done


def _atomic_dir(final: Path, write) -> None:
    """Write a directory under a temporary name, then move it into place in one rename."""
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = final.parent / f".tmp-{final.name}-{os.getpid()}-{uuid.uuid4().hex[:6]}"
    tmp.mkdir()
    try:
        write(tmp)
        if final.exists():  # an earlier errored attempt: replace it
            trash = final.parent / f".old-{final.name}-{uuid.uuid4().hex[:6]}"
            os.replace(final, trash)
            shutil.rmtree(trash, ignore_errors=True)
        os.replace(tmp, final)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)


def execute_cell(spec: CellSpec, out: str, comps: Components | None = None) -> dict:
    """Run one cell in a worker and write it atomically; never raises for a cell error."""
    out_p = Path(out)
    t0 = time.perf_counter()
    try:
        res = run_cell(spec, comps)

        def write(tmp: Path) -> None:
            for name, df in res.tables.items():
                df.to_parquet(tmp / f"{name}.parquet", index=False)
            (tmp / "cell.json").write_text(json.dumps(
                {"status": "ok", "cell_id": spec.cell_id, "spec": spec.to_dict(),
                 "elapsed_s": res.elapsed_s}, indent=1, default=str))
        _atomic_dir(cell_dir(out_p, spec), write)
        return {"cell_id": spec.cell_id, "status": "ok", "elapsed_s": res.elapsed_s}
    except Exception as exc:  # noqa: BLE001 - a failing cell is recorded, the sweep goes on
        meta = {"status": "error", "cell_id": spec.cell_id, "spec": spec.to_dict(),
                "error": f"{type(exc).__name__}: {exc}", "traceback": traceback.format_exc(),
                "elapsed_s": time.perf_counter() - t0}
        _atomic_dir(cell_dir(out_p, spec), lambda tmp: (tmp / "cell.json").write_text(
            json.dumps(meta, indent=1, default=str)))
        return {k: meta[k] for k in ("cell_id", "status", "error", "elapsed_s")}


@dataclass
class SweepOutcome:
    """What a sweep did: counts of cells and where the tables are."""

    out_dir: Path
    n_cells: int
    n_skipped: int
    n_ok: int
    n_error: int
    n_interrupted: int
    errors: dict[str, str]

    @property
    def complete(self) -> bool:
        return self.n_interrupted == 0


def _progress(total: int, show: bool | None):
    from tqdm.auto import tqdm
    if show is None:
        show = sys.stderr.isatty()
    return tqdm(total=total, disable=not show, unit="cell", desc="sweep")


def run_sweep(spec: SweepSpec, out: str | Path, *, workers: int = 1,
              scheduler: Any = None, components: Components | None = None,
              progress: bool | None = None) -> SweepOutcome:
    """Run every pending cell of ``spec`` and assemble the tables under ``out``.

    Parameters
    ----------
    spec : SweepSpec
    out : path
        Results directory (created); cells already completed there are skipped.
    workers : int
        Local worker processes (1: run in this process, no pool).
    scheduler : str or distributed.Client, optional
        Dask scheduler address (``tcp://host:8786``) or a Client: run the cells on that
        cluster instead of the local pool.
    components : Components, optional
        Substitute parts (tests); default the real ones.
    progress : bool, optional
        Show a tqdm bar; default only when stderr is a terminal.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers={workers!r} must be an integer >= 1")
    cells = spec.cells()
    ids = [c.cell_id for c in cells]
    if len(set(ids)) != len(ids):
        raise ValueError("two sweep cells share an id (duplicate scenario or seed?)")
    done = completed_cells(out, cells)
    pending = [c for c in cells if c.cell_id not in done]
    results: dict[str, dict] = {}
    interrupted: list[str] = []
    bar = _progress(len(pending), progress)
    try:
        if not pending:
            pass
        elif scheduler is not None:
            results.update(_run_dask(pending, out, scheduler, components, bar))
        elif workers == 1:
            for c in pending:
                results[c.cell_id] = execute_cell(c, str(out), components)
                bar.update(1)
        else:
            with cf.ProcessPoolExecutor(max_workers=workers,
                                        initializer=_init_worker) as ex:
                futs = {ex.submit(execute_cell, c, str(out), components): c for c in pending}
                for fut in cf.as_completed(futs):
                    c = futs[fut]
                    try:
                        results[c.cell_id] = fut.result()
                    except BrokenProcessPool:
                        # A worker died (killed, OOM): its cells are not recorded as errors;
                        # the next run of the same command resumes them.
                        interrupted.append(c.cell_id)
                    bar.update(1)
    finally:
        bar.close()
    # A cell whose worker died may still have been written before the pool broke.
    finished = completed_cells(out, cells)
    interrupted = [i for i in interrupted if i not in finished]
    errors = {i: r.get("error", "") for i, r in results.items() if r.get("status") == "error"}
    outcome = SweepOutcome(out_dir=out, n_cells=len(cells), n_skipped=len(done),
                           n_ok=sum(r.get("status") == "ok" for r in results.values()),
                           n_error=len(errors), n_interrupted=len(interrupted), errors=errors)
    assemble(spec, out)
    return outcome


def _run_dask(pending, out, scheduler, components, bar) -> dict[str, dict]:
    from distributed import Client, as_completed
    client = scheduler if isinstance(scheduler, Client) else Client(scheduler)
    try:
        futs = [client.submit(execute_cell, c, str(out), components, key=f"cell-{c.cell_id}",
                              pure=False) for c in pending]
        res = {}
        for fut in as_completed(futs):
            r = fut.result()
            res[r["cell_id"]] = r
            bar.update(1)
        return res
    finally:
        if client is not scheduler:
            client.close()


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


def _git_commit() -> dict[str, Any]:
    root = Path(__file__).resolve().parent.parent
    try:
        sha = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True,
                             text=True, timeout=10, check=True).stdout.strip()
        dirty = bool(subprocess.run(["git", "status", "--porcelain"], cwd=root,
                                    capture_output=True, text=True, timeout=10).stdout.strip())
        return {"commit": sha, "dirty": dirty}
    except (OSError, subprocess.SubprocessError):
        return {"commit": None, "dirty": None}


def _write_atomic(path: Path, write) -> None:
    tmp = path.with_name(f".tmp-{path.name}-{uuid.uuid4().hex[:6]}")
    write(tmp)
    os.replace(tmp, path)


def assemble(spec: SweepSpec, out: str | Path) -> dict[str, pd.DataFrame]:
    """Concatenate completed cells (in cell order) into ``out/<table>.parquet`` + manifest.

    The summary table gets an ``error`` column ("" for completed cells) and one row per
    errored cell, so gates see failures. Returns the tables.
    """
    out = Path(out)
    cells = spec.cells()
    parts: dict[str, list[pd.DataFrame]] = {t: [] for t in TABLES}
    cell_meta = []
    for c in cells:
        d = cell_dir(out, c)
        meta = _read_cell_meta(d) or {"status": "missing", "cell_id": c.cell_id}
        cell_meta.append({k: meta.get(k) for k in ("cell_id", "status", "elapsed_s", "error")}
                         | {"scenario": c.scenario, "variant": c.variant, "seed": c.seed})
        if meta.get("status") == "ok":
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
        _write_atomic(out / f"{t}.parquet", lambda tmp, df=df: df.to_parquet(tmp, index=False))
    from metrics.association import AssociationConfig
    manifest = {
        "run_id": spec.run_id, "sweep": spec.to_dict(), "seeds": list(spec.seeds),
        # Radar-dependent settings (window, FOV, max range) are each cell's
        # (harness.runner.cell_association); the rest are these, with [association] applied.
        "association": {**AssociationConfig().to_dict(), **spec.association,
                        "radar_dependent": "per cell from its radar configs unless "
                                           "[association] sets them"},
        "schemes": list(spec.schemes),
        "baseline_scheme": spec.baseline_scheme,
        "seed_streams": "SeedSequence([seed, frame, stream]); stream 0 RCS, 1 DDMA ADC, "
                        "2 TDMA ADC, other schemes harness.runner.stream_id(name)",
        "cells": cell_meta,
        "n_cells": len(cells),
        "n_ok": sum(m["status"] == "ok" for m in cell_meta),
        "n_error": sum(m["status"] == "error" for m in cell_meta),
        "n_missing": sum(m["status"] == "missing" for m in cell_meta),
        "versions": _versions(), "git": _git_commit(),
        "written_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "tables": {t: f"{t}.parquet" for t in TABLES},
    }
    try:
        import radarsim
        manifest["radar_presets"] = {
            m: radarsim.presets.r79(m).to_dict()
            for m in dict.fromkeys(rs.mimo for rs in result_schemes(spec.schemes))}
    except Exception:  # noqa: BLE001 - the manifest is informative, never fatal
        pass
    _write_atomic(out / "manifest.json", lambda tmp: tmp.write_text(
        json.dumps(manifest, indent=1, default=str)))
    return tables
