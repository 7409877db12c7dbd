"""Same seed, same bits on every execution path.

`run`, a serial sweep (`--workers 1`), a pool sweep (`--workers 2`) and a Dask cluster give
bit-identical tables for the same cell, and `simulate` writes exactly the ADC frames a pool
worker simulates. The serial sweep, `run` and `simulate` run in fresh processes, so a BLAS
thread setting left behind by another test cannot hide a difference: one BLAS thread must come
from the path itself (`harness.runtime.single_thread_blas`). The dense highway is used because
its front-end GEMM is large enough for a two-thread OpenBLAS to split the sums differently:
before the fix, 2 ADC samples of its frame 3 flipped by 1 LSB and `--workers 1` and
`--workers 2` gave different range errors (with today's front end a serial sweep with two
OpenBLAS threads gives the same bits as the pool's one: the check stays for the next BLAS).
The pool sweep is `real_pool_sweep` (tests/harness/conftest.py): the CLI's `main` in the test
process, whose state left by earlier tests its forked workers inherit, a harder reference than
a fresh process for state leaking between cells; its two cases (`tests/harness/real_sweep.py`)
make the fresh serial process run two cells one after the other while each pool worker runs
one, so state one cell leaves behind for the next shows as a difference too.
"""
from __future__ import annotations

import concurrent.futures as cf
import os
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from harness.cell import components
from harness.sweep import file as sweepfile
from harness.sweep import schedule, worker
from harness.sweep import spec as sweepspec
from radarsim.capture import read_capture
from radarsim.ti import parse_ti_cfg, r79_cfg_path
from tests.harness import real_sweep
from tests.harness.real_sweep import ROOT

CASE = "dense_highway"
TABLES = ("summary", "detections", "frames", "actors", "actor_summary", "truth", "tracks")
_cli = real_sweep.cli


def _tables(out, case: str | None = None) -> dict[str, pd.DataFrame]:
    """The result tables under `out`; with `case`, only that scenario's rows."""
    tabs = {t: pd.read_parquet(out / f"{t}.parquet") for t in TABLES}
    if case is None:
        return tabs
    return {t: df[df["scenario"] == case].reset_index(drop=True) for t, df in tabs.items()}


def _assert_same(a: dict, b: dict) -> None:
    for t in TABLES:
        pd.testing.assert_frame_equal(a[t], b[t], check_exact=True, obj=t)


def test_workers_1_and_2_give_the_same_bits(tmp_path, real_pool_sweep):
    _cli("sweep", *real_sweep.SWEEP_ARGS, "--workers", "1", "--out", str(tmp_path / "w1"))
    _assert_same(_tables(tmp_path / "w1"), _tables(real_pool_sweep))


def test_one_frame_thread_gives_the_bits_of_two(tmp_path, real_pool_sweep):
    """A pool sweep runs a cell on one frame thread while cells queue behind it, on two at the
    end (`harness.cell.run.cell_frame_threads`): the real parts give the same bits either way
    (the pool's two cells ran on two frame threads: they were its last)."""
    spec = sweepfile.load_sweep(sweepspec.DEFAULT_SWEEP_PATH).with_overrides(
        scenarios=[CASE], duration_s=real_sweep.DURATION_S,
        frame_stride=real_sweep.FRAME_STRIDE, seeds=[real_sweep.SEED])
    (cell,) = spec.cells()
    assert worker.execute_cell(cell, str(tmp_path), frame_threads=1)["status"] == "ok"
    for t in TABLES:
        pd.testing.assert_frame_equal(
            pd.read_parquet(tmp_path / "cells" / cell.cell_id / f"{t}.parquet"),
            pd.read_parquet(real_pool_sweep / "cells" / cell.cell_id / f"{t}.parquet"),
            check_exact=True, obj=t)


@pytest.mark.slow
def test_dask_gives_the_same_bits_as_the_pool(tmp_path, real_pool_sweep):
    import distributed
    spec = sweepfile.load_sweep(sweepspec.DEFAULT_SWEEP_PATH).with_overrides(
        scenarios=list(real_sweep.CASES), duration_s=real_sweep.DURATION_S,
        frame_stride=real_sweep.FRAME_STRIDE, seeds=[real_sweep.SEED])
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        o = schedule.run_sweep(spec, tmp_path / "dask", scheduler=cluster.scheduler_address,
                               progress=False)
    assert o.complete
    _assert_same(_tables(tmp_path / "dask"), _tables(real_pool_sweep))


@pytest.mark.slow
def test_run_gives_the_same_bits_as_the_sweep(tmp_path, real_pool_sweep):
    _cli("run", CASE, "--seed", str(real_sweep.SEED), "--duration-s", str(real_sweep.DURATION_S),
         "--frame-stride", str(real_sweep.FRAME_STRIDE), "--out", str(tmp_path / "run"))
    run = _tables(tmp_path / "run")
    sweep = _tables(real_pool_sweep, CASE)
    for t in TABLES:
        # `run` has no error column (it raises instead of recording a failed cell), nor the
        # columns only the sweep's other case fills (empty in this case's rows).
        other = [c for c in sweep[t].columns if c not in run[t].columns and c != "error"]
        assert sweep[t][other].isna().all().all(), (t, other)
        pd.testing.assert_frame_equal(run[t].drop(columns=["variant"], errors="ignore"),
                                      sweep[t].drop(columns=["variant", "error", *other],
                                                    errors="ignore"),
                                      check_exact=True, obj=t)


def _pool_frames(case: str, seed: int, duration_s: float, n: int) -> np.ndarray:
    """ADC frames of the R79 profile simulated inside a sweep pool worker, the scene sampled at
    the profile's frame period as `simulate` does."""
    from harness.cli.cmd_ti import simulate_frames
    comps = components.default_components()
    profile = parse_ti_cfg(r79_cfg_path())
    cfg = profile.radar
    run = comps.run_scenario(case, seed, duration_s, frame_rate_hz=1.0 / profile.frame_period_s)
    frames = np.unique(run.ego["frame"].to_numpy())[:n]
    return np.stack(list(simulate_frames(cfg, run, seed, frames, comps)))


@pytest.mark.slow
def test_simulate_writes_the_bits_a_pool_worker_simulates(tmp_path):
    out = tmp_path / "sim.bin"
    duration_s = "0.5"  # two frames of the R79 profile's 250 ms period
    _cli("simulate", CASE, "--cfg", str(r79_cfg_path()), "--out", str(out), "--seed", "1",
         "--frames", "2", "--duration-s", duration_s)
    with cf.ProcessPoolExecutor(1, initializer=worker.init_worker,
                               initargs=(os.getpid(),)) as ex:
        ref = ex.submit(_pool_frames, CASE, 1, float(duration_s), 2).result(timeout=300)
    got = read_capture(out, parse_ti_cfg(r79_cfg_path()).radar,
                       interleaved=parse_ti_cfg(r79_cfg_path()).adc_channel_interleaved)
    np.testing.assert_array_equal(got, ref)


def test_one_blas_thread_reaches_every_blas_library():
    """`prepare_process` runs before the chain is imported (the CLI's first step): afterwards
    every loaded BLAS, scipy's own OpenBLAS included, runs one thread. It did not reach scipy's
    OpenBLAS, loaded later with `scipy.linalg`, so `run` differed from a sweep cell in the last
    bits of every range (the slow test above)."""
    code = ("from harness.runtime import prepare_process; prepare_process(); "
            "import scipy.linalg, pipeline, radarsim; from threadpoolctl import threadpool_info; "
            "print(sorted({i['num_threads'] for i in threadpool_info() "
            "if i['user_api'] == 'blas'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT, env={**os.environ,
                                                    "OPENBLAS_NUM_THREADS": "",
                                                    "OMP_NUM_THREADS": ""})
    assert out.stdout.strip() == "[1]"
