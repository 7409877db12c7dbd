"""Results directories shared by several tests: a small stand-in sweep (gate and report tests)
and a small real-parts pool sweep run by the real CLI (determinism and end-to-end tests)."""
from __future__ import annotations

import pytest

from harness.schedule import run_sweep
from harness.sweepspec import SweepSpec
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
    """`radar-harness sweep <real_sweep.SWEEP_ARGS> --workers 2` in a fresh process: the pool
    path of the real parts, 2 cells (one per worker). Read-only for its users."""
    out = tmp_path_factory.mktemp("real") / "w2"
    real_sweep.cli("sweep", *real_sweep.SWEEP_ARGS, "--workers", "2", "--out", str(out))
    return out
