"""Results directories shared by several tests: a small stand-in sweep (gate and report tests)
and a small real-parts pool sweep run by the real CLI (determinism and end-to-end tests)."""
from __future__ import annotations

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
    """`radar-harness sweep <real_sweep.SWEEP_ARGS> --workers 2` run by the CLI's `main` in this
    test process: the pool path of the real parts, 2 cells (one per worker), the workers forked
    from this process as the CLI's are forked from the CLI process. Read-only for its users."""
    from harness.cli import main
    out = tmp_path_factory.mktemp("real") / "w2"
    assert main(["sweep", *real_sweep.SWEEP_ARGS, "--workers", "2", "--out", str(out)]) == 0
    return out
