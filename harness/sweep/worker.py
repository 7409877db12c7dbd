"""What a worker does with one cell: run it and write it atomically (`harness.sweep.store`).

Shared by the local process pool, the in-process path and Dask workers, so every path runs
with one BLAS thread and writes the same files.
"""
from __future__ import annotations

import errno
import json
import time
import traceback
from pathlib import Path

from core.fileio import OutputError
from core.numba_cache import install_cache_lock
from harness.cell.components import Components
from harness.cell.run import FRAME_THREADS, run_cell
from harness.cell.spec import CellSpec
from harness.plugins import PluginInfo, ensure_plugins
from harness.runtime import prepare_worker, single_thread_blas
from harness.sweep import store

__all__ = ["execute_cell", "init_worker"]


def init_worker(parent_pid: int) -> None:
    """Pool-worker initializer (`harness.runtime.prepare_worker`): one BLAS thread per worker
    process (bit-identical to every other path; with one worker per core, BLAS's own threads
    only oversubscribe the cores: the front end's GEMM slows 8x under load with two threads per
    worker), the allocator tuning of `harness.runtime`, SIGINT left to the parent (a Ctrl-C or
    SIGTERM lets the parent stop the pool; written cells stay), SIGTERM at its default, and
    death with the parent `parent_pid`."""
    prepare_worker(parent_pid)


#: A disk that cannot take the cell: the sweep stops (every later cell would fail the same
#: way), instead of recording the cell as an error it is not.
_DISK_ERRNOS = (errno.ENOSPC, errno.EDQUOT, errno.EROFS)


def _cell_record(spec: CellSpec, status: str, **extra) -> dict:
    return {"status": status, "cell_id": spec.cell_id, "spec": spec.to_dict(),
            "code_version": store.code_version(), **extra}


def execute_cell(spec: CellSpec, out: str, comps: Components | None = None,
                 plugins: tuple[PluginInfo, ...] = (),
                 frame_threads: int = FRAME_THREADS) -> dict:
    """Run one cell in a worker and write it atomically; never raises for a cell error (a full
    disk or read-only folder is no cell error: `OutputError`, which stops the sweep).

    The client's `plugins` are loaded first (`harness.plugins.ensure_plugins`: a no-op where
    they are loaded already); a worker that cannot load one records the cell as failed with
    one line naming the plugin.

    Runs with one BLAS thread (`harness.runtime.single_thread_blas`) on every path, and
    `frame_threads` frames at a time (`harness.cell.run.cell_frame_threads`). A cell
    already completed under ``out`` (by a duplicate execution) is never replaced: the result
    says ``"written": "kept"``.
    """
    single_thread_blas()
    install_cache_lock()  # a Dask worker runs no `prepare_process`: its kernels compile here
    out_p = Path(out)
    t0 = time.perf_counter()
    try:
        ensure_plugins(plugins)
        res = run_cell(spec, comps, frame_threads=frame_threads)

        def write(tmp: Path) -> None:
            for name, df in res.tables.items():
                df.to_parquet(tmp / f"{name}.parquet", index=False)
            (tmp / "cell.json").write_text(json.dumps(_cell_record(
                spec, "ok", elapsed_s=res.elapsed_s, files=store.table_files(tmp)),
                indent=1, default=str))
        how = store.write_cell_dir(store.cell_dir(out_p, spec), write)
        return {"cell_id": spec.cell_id, "status": "ok", "elapsed_s": res.elapsed_s,
                "written": how}
    except Exception as exc:  # noqa: BLE001 - a failing cell is recorded, the sweep goes on
        if isinstance(exc, OSError) and exc.errno in _DISK_ERRNOS:
            raise OutputError(f"cannot write {exc.filename or store.cell_dir(out_p, spec)!s}: "
                              f"{exc.strerror or exc} (the sweep stops; cells written so far "
                              "are kept, rerun to resume)") from None
        meta = _cell_record(spec, "error", error=f"{type(exc).__name__}: {exc}",
                            traceback=traceback.format_exc(),
                            elapsed_s=time.perf_counter() - t0)
        how = store.write_cell_dir(store.cell_dir(out_p, spec), lambda tmp: (
            tmp / "cell.json").write_text(json.dumps(meta, indent=1, default=str)))
        if how == "kept":  # a duplicate failed after the cell was completed: keep the result
            return {"cell_id": spec.cell_id, "status": "ok", "elapsed_s": meta["elapsed_s"],
                    "written": how}
        return {k: meta[k] for k in ("cell_id", "status", "error", "elapsed_s")} | \
            {"written": how}
