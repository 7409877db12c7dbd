"""Running a sweep fault-tolerantly: scheduling, resume and the outcome.

Execution: a local ``concurrent.futures.ProcessPoolExecutor`` (``workers``) or, given a
scheduler address, a Dask distributed cluster (`harness.sweep.dask_cluster`). Every cell is written
by
the worker that ran it through `harness.sweep.store`: atomically (temporary directory, then one
rename) to ``<out>/cells/<cell_id>/``, never over a completed cell, with the code version and the
checksum of every table. A rerun reuses cells of the same code version whose tables are intact
(damaged ones are recomputed, temporaries of killed writers removed) and refuses to resume over
cells of another version unless ``force`` (then they are recomputed). A cell that raises is
recorded (``cell.json`` with status "error" and the traceback) and the sweep continues; errored
cells are retried by the next run. A stop signal (Ctrl-C, SIGTERM, SIGHUP) at any moment of a
pool sweep stops it and its workers (`harness.runtime.stoppable_pool`). Every path runs
with one BLAS thread, so the same seeds give the same bits whatever the worker count or
scheduler. When all cells are done the tables are assembled (`harness.sweep.assemble`); a sweep with
missing cells is incomplete (`SweepOutcome.complete`).
"""
from __future__ import annotations

import os
import sys
import uuid
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from core.errors import BadInput
from harness.cell.components import Components
from harness.cell.run import cell_frame_threads
from harness.plugins import loaded_plugins
from harness.runtime import single_thread_blas, stoppable_pool
from harness.sweep import store
from harness.sweep.assemble import assemble
from harness.sweep.dask_cluster import DEFAULT_SCHEDULER_TIMEOUT_S, run_dask
from harness.sweep.file import validate_cells
from harness.sweep.spec import SweepSpec
from harness.sweep.worker import execute_cell, init_worker

__all__ = ["run_sweep", "SweepOutcome", "prepare_out", "MAX_WORKERS"]


#: Most local worker processes.
MAX_WORKERS = 256


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
        raise BadInput(f"--out {str(out)!r}: exists and is not a directory")
    try:
        p.mkdir(parents=True, exist_ok=True)
        probe = p / f".tmp-probe-{os.getpid()}-{uuid.uuid4().hex[:6]}"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        raise BadInput(f"--out {str(out)!r}: cannot create or write the results directory "
                       f"({exc.strerror or exc})") from None
    return p


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
        raise BadInput(f"workers={workers!r} must be an integer in 1..{MAX_WORKERS}")
    cells = spec.cells()
    ids = [c.cell_id for c in cells]
    if len(set(ids)) != len(ids):
        raise BadInput("two sweep cells share an id (duplicate scenario or seed?)")
    if components is None:
        validate_cells(spec)
    out = prepare_out(out)
    done, recompute = _resume(out, cells, force)
    pending = [c for c in cells if c.cell_id not in done]
    bar = _progress(len(pending), progress)
    plugins = tuple(loaded_plugins())  # every worker loads what this process loaded
    try:
        if not pending:
            results, interrupted = {}, []
        elif scheduler is not None:
            results, interrupted = run_dask(pending, out, scheduler, components, bar, security,
                                            scheduler_timeout_s, plugins)
        else:
            results, interrupted = _run_local(pending, out, workers, components, bar, plugins)
    finally:
        bar.close()
    final = store.cell_states(out, cells)
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


def _resume(out: Path, cells: list, force: bool) -> tuple[set[str], list[str]]:
    """Clean temporaries, refuse (or, with ``force``, retire) cells of another code version,
    retire damaged ones. Returns (ids of cells to reuse, ids retired for recomputation)."""
    store.clean_temporaries(out / "cells")
    states = store.cell_states(out, cells)
    stale = [i for i, st in states.items() if st == "stale"]
    if stale and not force:
        old = sorted({str((store.read_meta(out / "cells" / i) or {}).get("code_version", {})
                          .get("hash")) for i in stale})
        raise BadInput(f"--out {str(out)!r}: {len(stale)} completed cell(s) were computed by "
                       f"code version {', '.join(old)}, this is "
                       f"{store.code_version()['hash']}: rerun with --force to recompute "
                       "them, or use a new --out")
    recompute = [i for i, st in states.items() if st in ("stale", "corrupt")]
    for i in recompute:
        store.retire(out / "cells" / i)
    return {i for i, st in states.items() if st == "ok"}, recompute


def _run_local(pending: list, out: Path, workers: int, components, bar, plugins=()
               ) -> tuple[dict[str, dict], list[str]]:
    """Run cells in this process (``workers`` 1) or on a local process pool. Returns (results
    by cell id, ids whose worker died).

    The pool starts the cells in order; each runs its frames on one thread while the cells
    submitted after it keep the other workers busy, and on `harness.cell.run.FRAME_THREADS`
    where a core would otherwise idle (`harness.cell.run.cell_frame_threads`: the last
    ``workers`` cells, or every cell when the workers are fewer than the cores)."""
    results: dict[str, dict] = {}
    interrupted: list[str] = []
    threads = [cell_frame_threads(len(pending) - 1 - i, workers) for i in range(len(pending))]
    if workers == 1:
        single_thread_blas()
        for c, n in zip(pending, threads):
            results[c.cell_id] = execute_cell(c, str(out), components, plugins, n)
            bar.update(1)
        return results, interrupted
    # Ctrl-C, SIGTERM, SIGHUP at any moment, the pool's start included, stop it now
    # (`stoppable_pool`): running cells are lost whole (their temporary directories are
    # cleaned by the next run), written ones stay; no worker outlives this process.
    with stoppable_pool(workers, init_worker, (os.getpid(),)) as pool:
        futs = {pool.executor.submit(execute_cell, c, str(out), components, plugins, n): c
                for c, n in zip(pending, threads)}
        for fut in pool.completed(futs):
            c = futs[fut]
            try:
                results[c.cell_id] = fut.result()
            except BrokenProcessPool:
                # A worker died (killed, OOM): its cells are not recorded as errors; the next
                # run of the same command resumes them.
                interrupted.append(c.cell_id)
            bar.update(1)
    return results, interrupted
