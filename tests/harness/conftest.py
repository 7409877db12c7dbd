"""Results directories shared by several tests: a small stand-in sweep (gate and report tests)
and a small real-parts pool sweep run by the real CLI (determinism and end-to-end tests)."""
from __future__ import annotations

import fcntl
import os

import pytest

from harness.sweep.schedule import run_sweep
from harness.sweep.spec import SweepSpec
from tests.harness import real_sweep
from tests.harness.fakes import FAKE


@pytest.fixture(scope="session")
def fake_results(tmp_path_factory):
    out = tmp_path_factory.mktemp("results")
    spec = SweepSpec(name="fake", scenarios=("fast", "slow"), seeds=(0,), duration_s=1.0)
    run_sweep(spec, out, components=FAKE, progress=False)
    return out


@pytest.fixture(scope="session")
def real_pool_sweep(tmp_path_factory):
    """`radar-harness sweep <real_sweep.SWEEP_ARGS> --workers 2` run by the CLI's `main` in a
    test process: the pool path of the real parts, 2 cells (one per worker), the workers forked
    from that process as the CLI's are forked from the CLI process. Read-only for its users.

    Run once per test run: its users (determinism and end-to-end tests) may land on different
    xdist workers, and the first to need it computes it under a file lock in the folder all
    workers' temporary folders share; the others wait and read it (~2 s CPU each saved)."""
    from harness.cli import main
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent  # pytest-of-<user>/pytest-<n>: shared by the run's workers
    out, done = root / "real_pool_sweep" / "w2", root / "real_pool_sweep.done"
    with open(root / "real_pool_sweep.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            assert main(["sweep", *real_sweep.SWEEP_ARGS, "--workers", "2",
                         "--out", str(out)]) == 0
            done.touch()
    return out
