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

Validation: the file and every variant's configs (both radar presets, the processing config of
every scheme, the tracker config; chip limits, RF budget, CFAR window against the Doppler axis)
are built before any worker starts; a bad value raises ValueError naming the file, the variant,
the key and the value. Durations, seeds, strides and the cell count are bounded; the sweep
``name`` is a single folder name, so ``results/<run-id>`` never leaves the results folder.

Execution: a local ``concurrent.futures.ProcessPoolExecutor`` (``workers``) or, given a
scheduler address, a Dask distributed cluster (``tls://`` with `dask_security`; workers must see
the output directory, which is made absolute first). Every cell is written by the worker that
ran it through `harness.cellstore`: atomically (temporary directory, then one rename) to
``<out>/cells/<cell_id>/``, never over a completed cell, with the code version and the checksum
of every table. A rerun reuses cells of the same code version whose tables are intact
(damaged ones are recomputed, temporaries of killed writers removed) and refuses to resume over
cells of another version unless ``force`` (then they are recomputed). A cell that raises is
recorded (``cell.json`` with status "error" and the traceback) and the sweep continues; errored
cells are retried by the next run. Every path runs with one BLAS thread, so the same seeds give
the same bits whatever the worker count or scheduler. When all cells are done the per-cell
tables are concatenated in cell order into ``<out>/<table>.parquet`` and a ``manifest.json``
lists every cell as resumed, computed, error or missing; a sweep with missing cells is
incomplete (`SweepOutcome.complete`).
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
import re
import sys
import time
import traceback
import uuid
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from scenarios.checks import check_keys, read_toml

from . import cellstore as store
from .args import MAX_DURATION_S, MAX_SEED
from .runner import (DEFAULT_BASELINE_SCHEME, DEFAULT_SCHEMES, SEED_STREAMS, TABLES, CellSpec,
                     Components, result_schemes, run_cell)

__all__ = ["Variant", "SweepSpec", "SweepOutcome", "load_sweep", "default_sweep",
           "run_sweep", "cell_dir", "completed_cells", "cell_states", "assemble",
           "validate_cells", "prepare_out", "dask_security", "DEFAULT_SWEEP_PATH",
           "CI_SWEEP_PATH", "SCHEMES_SWEEP_PATH", "MAX_DURATION_S", "MAX_CELLS", "MAX_WORKERS",
           "MAX_FRAME_STRIDE", "MAX_SEED"]

DEFAULT_SWEEP_PATH = Path(__file__).with_name("default_sweep.toml")
CI_SWEEP_PATH = Path(__file__).with_name("ci_sweep.toml")
SCHEMES_SWEEP_PATH = Path(__file__).with_name("schemes_sweep.toml")
_SECTIONS = ("radar", "processing", "tracker", "scene")
#: Most cells in one sweep (scenarios x variants x seeds): beyond it a typo in [vary] is likelier
#: than a plan (10 000 R79 cells are days of CPU).
MAX_CELLS = 10_000
#: Most local worker processes.
MAX_WORKERS = 256
#: Largest frame stride (a stride beyond the frame count keeps only frame 0).
MAX_FRAME_STRIDE = 10_000
#: Default wait for a Dask scheduler to answer, s.
DEFAULT_SCHEDULER_TIMEOUT_S = 20.0
#: A sweep name becomes a folder under results/: letters, digits, "_", "-", "." (not first).
_NAME_RE = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,99}")
_TOP_KEYS = {"name", "scenarios", "seeds", "frame_stride", "duration_s", "base", "vary",
             "variants", "description", "schemes", "baseline_scheme", "association"}


@dataclass(frozen=True)
class Variant:
    """A named set of config overrides (one column of the sweep)."""

    name: str = "baseline"
    radar: dict = field(default_factory=dict)
    processing: dict = field(default_factory=dict)
    tracker: dict = field(default_factory=dict)
    scene: dict = field(default_factory=dict)


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
        if not isinstance(self.name, str) or not _NAME_RE.fullmatch(self.name):
            raise ValueError(f"name={self.name!r} must be 1-100 letters, digits, '_', '-' or "
                             "'.' (not first): it names a folder under the results directory")
        object.__setattr__(self, "schemes", tuple(self.schemes))
        from metrics.association import AssociationConfig
        AssociationConfig(**self.association)  # unknown keys / bad values fail here
        result_schemes(self.schemes)
        # CellSpec checks the baseline name; check it here too, before any cell is built.
        CellSpec(scenario="-", schemes=self.schemes, baseline_scheme=self.baseline_scheme)
        if not self.scenarios:
            raise ValueError("scenarios: the sweep has no scenario")
        dup = sorted({sc for sc in self.scenarios if list(self.scenarios).count(sc) > 1})
        if dup:
            raise ValueError(f"scenarios: duplicate case(s) {dup}")
        if not self.seeds or any(isinstance(s, bool) or not isinstance(s, int)
                                 or not 0 <= s <= MAX_SEED for s in self.seeds):
            raise ValueError(f"seeds={list(self.seeds)!r} must be a non-empty list of "
                             f"integers in 0..{MAX_SEED}")
        if len(set(self.seeds)) != len(self.seeds):
            raise ValueError(f"seeds={list(self.seeds)!r}: duplicate seed")
        if isinstance(self.frame_stride, bool) or not isinstance(self.frame_stride, int) or \
                not 1 <= self.frame_stride <= MAX_FRAME_STRIDE:
            raise ValueError(f"frame_stride={self.frame_stride!r} must be an integer in "
                             f"1..{MAX_FRAME_STRIDE}")
        if self.duration_s is not None and (
                isinstance(self.duration_s, bool)
                or not isinstance(self.duration_s, (int, float))
                or not 0 < self.duration_s <= MAX_DURATION_S):
            raise ValueError(f"duration_s={self.duration_s!r} must be a number in "
                             f"(0, {MAX_DURATION_S:g}] s")
        names = [v.name for v in self.variants]
        if len(set(names)) != len(names):
            raise ValueError(f"variants: duplicate names {names}")
        n = len(self.scenarios) * len(self.variants) * len(self.seeds)
        if n > MAX_CELLS:
            raise ValueError(f"the sweep has {n} cells ({len(self.scenarios)} scenarios x "
                             f"{len(self.variants)} variants x {len(self.seeds)} seeds), more "
                             f"than the limit {MAX_CELLS}")

    def cells(self) -> list[CellSpec]:
        """Cells in a fixed order: scenario, then variant, then seed."""
        return [CellSpec(scenario=sc, seed=seed, variant=v.name, radar=dict(v.radar),
                         processing=dict(v.processing), tracker=dict(v.tracker),
                         scene=dict(v.scene),
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
        for v in d["variants"]:  # the scene section enters the id only when used
            if not v.get("scene"):
                v.pop("scene", None)
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
            ch["seeds"] = tuple(seeds)
        if frame_stride is not None:
            ch["frame_stride"] = frame_stride
        if duration_s is not None:
            ch["duration_s"] = duration_s
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
            from radarsim.ti import from_ti_cfg
            prof = overrides["profile"]
            if not isinstance(prof, str) or not Path(prof).is_file():
                raise ValueError(f"{where}: radar.profile={prof!r} is not a TI .cfg file")
            try:
                from_ti_cfg(Path(prof))
            except ValueError as exc:
                raise ValueError(f"{where}: radar.profile={prof!r}: {exc}") from None
    if section == "processing" and overrides:
        import pipeline
        try:
            pipeline.ProcessingConfig().replace(**overrides)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"{where}: processing {overrides!r}: {exc}") from None
    if section == "scene" and overrides:
        from .runner import check_scene
        check_scene(overrides)


def _init_worker() -> None:
    """Pool-worker initializer: one BLAS thread per worker process (bit-identical to every
    other path; with one worker per core, BLAS's own threads only oversubscribe the cores: the
    front end's GEMM slows 8x under load with two threads per worker), the allocator tuning of
    `harness.runtime`, and SIGINT left to the parent (a Ctrl-C lets running cells finish and
    write, the parent cancels the rest)."""
    import signal

    from .runtime import prepare_process
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    prepare_process()


def _culprit(v: Variant, build) -> str:
    """Which override of a variant breaks its configs: the first that fails on its own, else
    the whole set. ``build(section, overrides)`` raises for bad overrides."""
    for sec in _SECTIONS:
        for key, value in getattr(v, sec).items():
            try:
                build(sec, {key: value})
            except (ValueError, TypeError, KeyError) as exc:
                return f"{sec}.{key} = {value!r}: {exc}"
    for sec in _SECTIONS:
        try:
            build(sec, dict(getattr(v, sec)))
        except (ValueError, TypeError, KeyError) as exc:
            return f"[{sec}] {getattr(v, sec)!r}: {exc}"
    return ""


def validate_cells(spec: SweepSpec, source: str | Path | None = None) -> None:
    """Build every variant's configs (both radar presets, the processing configs of every
    scheme, the tracker config) before any worker starts.

    Raises
    ------
    ValueError
        Naming the sweep file, the variant, the key, the value and the config's own message
        (which names the limit).
    """
    from pipeline.tracking import TrackerConfig

    from .runner import build_configs, default_components
    comps = default_components()
    where = f"{source}: " if source is not None else ""

    def check(cell: CellSpec) -> None:
        radar, procs = build_configs(cell, comps)
        for proc in procs.values():  # CFAR window and EGE blocks must fit every radar
            for r in radar.values():
                proc.check_radar(r)

    schemes = {"schemes": spec.schemes, "baseline_scheme": spec.baseline_scheme}

    def build(section: str, overrides: dict) -> None:
        if section == "tracker":
            TrackerConfig(**overrides)
        else:
            check(CellSpec(scenario=spec.scenarios[0], **{section: overrides}, **schemes))

    for v in spec.variants:
        try:
            check(CellSpec(scenario=spec.scenarios[0], seed=spec.seeds[0], variant=v.name,
                           radar=dict(v.radar), processing=dict(v.processing),
                           tracker=dict(v.tracker), scene=dict(v.scene), **schemes))
            TrackerConfig(**v.tracker)
        except (ValueError, TypeError, KeyError) as exc:
            why = _culprit(v, build) or f"{type(exc).__name__}: {exc}"
            raise ValueError(f"{where}variant {v.name!r}: {why}") from None


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
    if p.is_dir():
        raise ValueError(f"sweep file {str(p)!r} is a directory, not a TOML file")
    data = read_toml(p)
    try:
        check_keys(data, _TOP_KEYS)
    except ValueError as exc:
        raise ValueError(f"{p}: {exc}") from None
    for key, kind, what in (("base", dict, "a table [base.<section>]"),
                            ("vary", dict, 'a table of "section.field" = [values]'),
                            ("variants", list, "an array of [[variants]] tables"),
                            ("name", str, "a string"), ("description", str, "a string")):
        if key in data and not isinstance(data[key], kind):
            raise ValueError(f"{p}: {key} = {data[key]!r} must be {what}")
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
        try:
            check_keys(extra, {"name", *_SECTIONS}, f"variants[{i}].")
            if "name" not in extra:
                raise ValueError(f"variants[{i}].name: required key missing")
        except ValueError as exc:
            raise ValueError(f"{p}: {exc}") from None
        for s in _SECTIONS:
            if not isinstance(extra.get(s, {}), dict):
                raise ValueError(f"{p}: [[variants]] {extra['name']!r}: {s} = {extra[s]!r} must "
                                 "be a table of field = value")
        ov = {s: {**base.get(s, {}), **extra.get(s, {})} for s in _SECTIONS}
        for s in _SECTIONS:
            _check_section(f"{p} [[variants]] {extra['name']}", s, ov[s])
        variants.append(Variant(name=str(extra["name"]), **ov))
    if data.get("variants") and not keys:
        variants = variants[1:]  # explicit variants replace the implicit baseline
    seeds = data.get("seeds", [0])
    try:
        spec = SweepSpec(name=data.get("name", p.stem),
                         scenarios=tuple(_resolve_scenarios(data.get("scenarios", "all"),
                                                            check_scenarios)),
                         seeds=tuple(seeds) if isinstance(seeds, list) else (seeds,),
                         variants=tuple(variants), frame_stride=data.get("frame_stride", 1),
                         duration_s=data.get("duration_s"),
                         description=data.get("description", ""),
                         schemes=_schemes_key(p, data.get("schemes", list(DEFAULT_SCHEMES))),
                         baseline_scheme=data.get("baseline_scheme", DEFAULT_BASELINE_SCHEME),
                         association=_association_key(p, data.get("association", {})))
    except ValueError as exc:
        msg = str(exc)
        raise ValueError(msg if msg.startswith(f"{p}:") else f"{p}: {msg}") from None
    validate_cells(spec, p)
    return spec


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
    if value == "all":  # every registered scheme and chain variant (harness.runner)
        from .runner import known_schemes
        return tuple(known_schemes())
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
    return store.read_meta(d)


def cell_states(out: Path, cells: list[CellSpec]) -> dict[str, str]:
    """`harness.cellstore.cell_state` of every cell under ``out`` (cell id -> state)."""
    version = store.code_version()["hash"]
    return {c.cell_id: store.cell_state(cell_dir(out, c), version) for c in cells}


def completed_cells(out: Path, cells: list[CellSpec]) -> set[str]:
    """Ids of cells completed under ``out`` by this code version with intact tables."""
    return {i for i, st in cell_states(out, cells).items() if st == "ok"}


def prepare_out(out: str | Path) -> Path:
    """Absolute, existing, writable results directory (a relative path is resolved here, in
    the client, so Dask workers with another working directory write to the same place).

    Raises
    ------
    ValueError
        ``out`` is a file, lies under a file, or cannot be created or written.
    """
    p = Path(out).expanduser().resolve()
    if p.exists() and not p.is_dir():
        raise ValueError(f"--out {str(out)!r}: exists and is not a directory")
    try:
        p.mkdir(parents=True, exist_ok=True)
        probe = p / f".tmp-probe-{os.getpid()}-{uuid.uuid4().hex[:6]}"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        raise ValueError(f"--out {str(out)!r}: cannot create or write the results directory "
                         f"({exc.strerror or exc})") from None
    return p


def _cell_record(spec: CellSpec, status: str, **extra) -> dict:
    return {"status": status, "cell_id": spec.cell_id, "spec": spec.to_dict(),
            "code_version": store.code_version(), **extra}


def execute_cell(spec: CellSpec, out: str, comps: Components | None = None) -> dict:
    """Run one cell in a worker and write it atomically; never raises for a cell error.

    Runs with one BLAS thread (`harness.runtime.single_thread_blas`) on every path. A cell
    already completed under ``out`` (by a duplicate execution) is never replaced: the result
    says ``"written": "kept"``.
    """
    from .runtime import single_thread_blas
    single_thread_blas()
    out_p = Path(out)
    t0 = time.perf_counter()
    try:
        res = run_cell(spec, comps)

        def write(tmp: Path) -> None:
            for name, df in res.tables.items():
                df.to_parquet(tmp / f"{name}.parquet", index=False)
            (tmp / "cell.json").write_text(json.dumps(_cell_record(
                spec, "ok", elapsed_s=res.elapsed_s, files=store.table_files(tmp)),
                indent=1, default=str))
        how = store.write_cell_dir(cell_dir(out_p, spec), write)
        return {"cell_id": spec.cell_id, "status": "ok", "elapsed_s": res.elapsed_s,
                "written": how}
    except Exception as exc:  # noqa: BLE001 - a failing cell is recorded, the sweep goes on
        meta = _cell_record(spec, "error", error=f"{type(exc).__name__}: {exc}",
                            traceback=traceback.format_exc(),
                            elapsed_s=time.perf_counter() - t0)
        how = store.write_cell_dir(cell_dir(out_p, spec), lambda tmp: (
            tmp / "cell.json").write_text(json.dumps(meta, indent=1, default=str)))
        if how == "kept":  # a duplicate failed after the cell was completed: keep the result
            return {"cell_id": spec.cell_id, "status": "ok", "elapsed_s": meta["elapsed_s"],
                    "written": how}
        return {k: meta[k] for k in ("cell_id", "status", "error", "elapsed_s")} | \
            {"written": how}


@dataclass
class SweepOutcome:
    """What a sweep did: counts of cells and where the tables are.

    ``n_skipped`` cells were resumed (completed earlier by the same code version),
    ``n_ok`` computed now, ``n_error`` raised, ``n_interrupted`` lost their worker,
    ``n_missing`` are not on disk at the end for any reason (interrupted, a Dask worker that
    wrote elsewhere, a cell of another code version written by a foreign worker).
    """

    out_dir: Path
    n_cells: int
    n_skipped: int
    n_ok: int
    n_error: int
    n_interrupted: int
    errors: dict[str, str]
    n_missing: int = 0
    n_recomputed: int = 0
    missing: list[str] = field(default_factory=list)

    @property
    def complete(self) -> bool:
        return self.n_interrupted == 0 and self.n_missing == 0


def _progress(total: int, show: bool | None):
    from tqdm.auto import tqdm
    if show is None:
        show = sys.stderr.isatty()
    return tqdm(total=total, disable=not show, unit="cell", desc="sweep")


def run_sweep(spec: SweepSpec, out: str | Path, *, workers: int = 1,
              scheduler: Any = None, components: Components | None = None,
              progress: bool | None = None, force: bool = False, security: Any = None,
              scheduler_timeout_s: float = DEFAULT_SCHEDULER_TIMEOUT_S) -> SweepOutcome:
    """Run every pending cell of ``spec`` and assemble the tables under ``out``.

    Parameters
    ----------
    spec : SweepSpec
    out : path
        Results directory (created; a relative path is resolved here, before any worker gets
        it). Cells completed there by the same code version are resumed.
    workers : int
        Local worker processes (1: run in this process, no pool).
    scheduler : str or distributed.Client, optional
        Dask scheduler address (``tls://host:8786``, ``tcp://...`` only on a trusted network)
        or a Client: run the cells on that cluster instead of the local pool.
    components : Components, optional
        Substitute parts (tests); default the real ones, whose configs are then built and
        validated for every cell before any worker starts.
    progress : bool, optional
        Show a tqdm bar; default only when stderr is a terminal.
    force : bool
        Recompute cells completed by another code version instead of refusing to resume.
    security : distributed.Security, optional
        TLS settings for ``scheduler`` (see `dask_security`).
    scheduler_timeout_s : float
        How long to wait for the scheduler to answer.

    Raises
    ------
    ValueError
        Bad ``out``/``workers``, a cell config that cannot be built (file, key, value, limit),
        cells of another code version under ``out`` without ``force``, an unreachable
        scheduler.
    """
    if isinstance(workers, bool) or not isinstance(workers, int) or \
            not 1 <= workers <= MAX_WORKERS:
        raise ValueError(f"workers={workers!r} must be an integer in 1..{MAX_WORKERS}")
    cells = spec.cells()
    ids = [c.cell_id for c in cells]
    if len(set(ids)) != len(ids):
        raise ValueError("two sweep cells share an id (duplicate scenario or seed?)")
    if components is None:
        validate_cells(spec)
    out = prepare_out(out)
    store.clean_temporaries(out / "cells")
    states = cell_states(out, cells)
    stale = [i for i, st in states.items() if st == "stale"]
    if stale and not force:
        old = sorted({str((store.read_meta(out / "cells" / i) or {}).get("code_version", {})
                          .get("hash")) for i in stale})
        raise ValueError(f"--out {str(out)!r}: {len(stale)} completed cell(s) were computed by "
                         f"code version {', '.join(old)}, this is "
                         f"{store.code_version()['hash']}: rerun with --force to recompute "
                         "them, or use a new --out")
    recompute = [i for i, st in states.items() if st in ("stale", "corrupt")]
    for i in recompute:
        store.retire(out / "cells" / i)
    done = {i for i, st in states.items() if st == "ok"}
    pending = [c for c in cells if c.cell_id not in done]
    results: dict[str, dict] = {}
    interrupted: list[str] = []
    bar = _progress(len(pending), progress)
    try:
        if not pending:
            pass
        elif scheduler is not None:
            res, lost = _run_dask(pending, out, scheduler, components, bar, security,
                                  scheduler_timeout_s)
            results.update(res)
            interrupted.extend(lost)
        elif workers == 1:
            from .runtime import single_thread_blas
            single_thread_blas()
            for c in pending:
                results[c.cell_id] = execute_cell(c, str(out), components)
                bar.update(1)
        else:
            ex = cf.ProcessPoolExecutor(max_workers=workers, initializer=_init_worker)
            try:
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
            except BaseException:
                # Ctrl-C (or any escape): stop now. Running cells are lost whole (their
                # temporary directories are cleaned by the next run), written ones stay.
                for proc in list(getattr(ex, "_processes", {}).values()):
                    proc.terminate()
                ex.shutdown(wait=False, cancel_futures=True)
                raise
            ex.shutdown(wait=True)
    finally:
        bar.close()
    final = cell_states(out, cells)
    missing = [i for i in ids if final[i] not in ("ok", "error")]
    interrupted = [i for i in interrupted if final[i] != "ok"]
    errors = {i: r.get("error", "") for i, r in results.items()
              if r.get("status") == "error" and final[i] == "error"}
    origin = {i: ("resumed" if i in done else "computed") if final[i] == "ok" else final[i]
              for i in ids}
    outcome = SweepOutcome(out_dir=out, n_cells=len(cells), n_skipped=len(done),
                           n_ok=sum(o == "computed" for o in origin.values()),
                           n_error=len(errors), n_interrupted=len(interrupted), errors=errors,
                           n_missing=len(missing), n_recomputed=len(recompute),
                           missing=missing)
    assemble(spec, out, origin=origin, states=final)
    return outcome


def dask_security(path: str | Path | None):
    """`distributed.Security` for TLS from a TOML file (None: Dask's own configuration,
    ``distributed.comm.tls.*``).

    The file holds ``ca_file``, ``cert`` and ``key`` (PEM paths, relative to the file)::

        ca_file = "ca.pem"      # the CA that signed the scheduler's and workers' certificates
        cert = "client.pem"     # this client's certificate
        key = "client-key.pem"  # and its private key

    Raises
    ------
    ValueError
        Unreadable file, unknown or missing keys, a PEM file that does not exist.
    """
    from distributed.security import Security
    if path is None:
        return Security()
    p = Path(path)
    try:
        data = read_toml(p)
    except (OSError, ValueError) as exc:
        raise ValueError(f"--security {str(path)!r}: cannot read the file ({exc})") from None
    keys = {"ca_file", "cert", "key"}
    bad, miss = sorted(set(data) - keys), sorted(keys - set(data))
    if bad or miss:
        raise ValueError(f"--security {str(path)!r}: unknown key(s) {bad}, missing key(s) "
                         f"{miss}; needs {sorted(keys)}")
    files = {}
    for k in sorted(keys):
        v = data[k]
        f = (p.parent / v) if isinstance(v, str) else None
        if f is None or not f.is_file():
            raise ValueError(f"--security {str(path)!r}: {k} = {v!r} is not a readable file")
        files[k] = str(f.resolve())
    return Security(tls_ca_file=files["ca_file"], tls_client_cert=files["cert"],
                    tls_client_key=files["key"], require_encryption=True)


def _connect(scheduler, security, timeout_s: float):
    from distributed import Client
    if isinstance(scheduler, Client):
        return scheduler
    addr = str(scheduler)
    if "://" not in addr:
        raise ValueError(f"--scheduler {addr!r}: give a protocol, tls://host:port (or tcp:// "
                         "on a trusted network)")
    proto = addr.split("://", 1)[0]
    if proto not in ("tls", "tcp", "inproc", "ws", "wss", "ucx"):
        raise ValueError(f"--scheduler {addr!r}: unknown protocol {proto!r}")
    if proto == "tls":
        security = security if security is not None else dask_security(None)
        if not getattr(security, "tls_ca_file", None):
            raise ValueError(f"--scheduler {addr!r}: tls:// needs --security FILE (ca_file, "
                             "cert, key) or Dask's distributed.comm.tls configuration")
    try:
        return Client(addr, timeout=f"{timeout_s}s", security=security)
    except (OSError, TimeoutError) as exc:
        raise ValueError(f"--scheduler {addr!r}: no Dask scheduler answered within "
                         f"{timeout_s:g} s ({type(exc).__name__}: {exc})") from None


def _run_dask(pending, out, scheduler, components, bar, security=None,
              timeout_s: float = DEFAULT_SCHEDULER_TIMEOUT_S):
    """Run cells on a Dask cluster; returns (results by cell id, ids whose task failed)."""
    from distributed import as_completed
    client = _connect(scheduler, security, timeout_s)
    try:
        try:  # a scheduler without workers would leave every task waiting forever
            client.wait_for_workers(1, timeout=timeout_s)
        except (TimeoutError, OSError):
            raise ValueError(f"--scheduler {client.scheduler.address!r}: no Dask worker joined "
                             f"the scheduler within {timeout_s:g} s") from None
        futs = {client.submit(execute_cell, c, str(out), components, key=f"cell-{c.cell_id}",
                              pure=False): c for c in pending}
        res, lost = {}, []
        for fut in as_completed(list(futs)):
            try:
                r = fut.result()
                res[r["cell_id"]] = r
            except Exception:  # noqa: BLE001 - a killed worker (KilledWorker) loses the task
                lost.append(futs[fut].cell_id)
            bar.update(1)
        return res, lost
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


def _write_atomic(path: Path, write) -> None:
    tmp = path.with_name(f".tmp-{path.name}-{uuid.uuid4().hex[:6]}")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def assemble(spec: SweepSpec, out: str | Path, origin: dict[str, str] | None = None,
             states: dict[str, str] | None = None) -> dict[str, pd.DataFrame]:
    """Concatenate completed cells (in cell order) into ``out/<table>.parquet`` + manifest.

    Only cells completed by this code version with intact tables enter the tables
    (`harness.cellstore.cell_state` "ok"). The summary table gets an ``error`` column ("" for
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
        d = cell_dir(out, c)
        state = (states or {}).get(c.cell_id) or store.cell_state(d, version["hash"])
        meta = (_read_cell_meta(d) or {}) if state in ("ok", "error") else {}
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
        "seed_streams": "SeedSequence([seed, frame, stream]); " + ", ".join(
            f"stream {i} {name}" for name, i in SEED_STREAMS.items())
        + " (the tracker's RANSAC: frame 0 of that stream); other schemes' ADC "
          "harness.runner.stream_id(name)",
        "cells": cell_meta,
        "n_cells": len(cells),
        "n_ok": sum(m["status"] == "ok" for m in cell_meta),
        "n_error": sum(m["status"] == "error" for m in cell_meta),
        "n_missing": sum(m["status"] not in ("ok", "error") for m in cell_meta),
        "n_resumed": sum(m["origin"] == "resumed" for m in cell_meta),
        "n_computed": sum(m["origin"] == "computed" for m in cell_meta),
        "code_version": version["hash"],
        "versions": _versions(), "git": {"commit": version["commit"],
                                         "dirty": version["dirty"]},
        "written_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "tables": {t: f"{t}.parquet" for t in TABLES},
    }
    import radarsim
    try:
        manifest["radar_presets"] = {
            m: radarsim.presets.r79(m).to_dict()
            for m in dict.fromkeys(rs.mimo for rs in result_schemes(spec.schemes))}
    except ValueError:  # a scheme with no R79 preset: the manifest just lacks the presets
        pass
    _write_atomic(out / "manifest.json", lambda tmp: tmp.write_text(
        json.dumps(manifest, indent=1, default=str)))
    return tables
