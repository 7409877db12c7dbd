"""Results directories shared by several tests: a small stand-in sweep (gate and report tests)
and a small real-parts pool sweep run by the real CLI (determinism and end-to-end tests)."""
from __future__ import annotations

import fcntl
import os
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest

from harness.cli import main
from harness.sweep.schedule import run_sweep
from harness.sweep.spec import SweepSpec
from tests.harness import real_sweep
from tests.harness.fakes import FAKE


def _once_per_run(tmp_path_factory, name: str, make: Callable[[Path], object]) -> Path:
    """``make(folder)`` run once per test run, not once per xdist worker: the first worker to
    need `name` runs it under a file lock in the folder the workers' temporary folders share
    (pytest-of-<user>/pytest-<n>); the others wait for it and get the same folder."""
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent
    out, done = root / name, root / f"{name}.done"
    with open(root / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            make(out)
            done.touch()
    return out


def _fake_sweep(out: Path) -> None:
    spec = SweepSpec(name="fake", scenarios=("fast", "slow"), seeds=(0,), duration_s=1.0)
    run_sweep(spec, out, components=FAKE, progress=False)


@pytest.fixture(scope="session")
def fake_report(tmp_path_factory) -> Path:
    """The report.html of ``radar-harness report --no-maps`` on a copy of the stand-in sweep's
    results, drawn once per run, not once per xdist worker (~1.5-3 s CPU each). Read-only."""
    def make(out: Path) -> None:
        shutil.copytree(_once_per_run(tmp_path_factory, "fake_results", _fake_sweep), out)
        assert main(["report", str(out), "--no-maps"]) == 0
    return _once_per_run(tmp_path_factory, "fake_report", make) / "report.html"


@pytest.fixture(scope="session")
def fake_results(tmp_path_factory):
    """The stand-in sweep's results, computed once per run (~1 s CPU) and copied into this
    worker's own folder: its users write into it (report.html, gates.md)."""
    out = tmp_path_factory.mktemp("results")
    shutil.copytree(_once_per_run(tmp_path_factory, "fake_results", _fake_sweep), out,
                    dirs_exist_ok=True)
    return out


def _real_pool_sweep(out: Path) -> None:
    from harness.cli import main
    assert main(["sweep", *real_sweep.SWEEP_ARGS, "--workers", "2", "--out",
                 str(out / "w2")]) == 0


@pytest.fixture(scope="session")
def real_pool_sweep(tmp_path_factory):
    """`radar-harness sweep <real_sweep.SWEEP_ARGS> --workers 2` run by the CLI's `main` in a
    test process: the pool path of the real parts, 2 cells (one per worker), the workers forked
    from that process as the CLI's are forked from the CLI process. Read-only for its users.

    Run once per test run (`_once_per_run`): its users (determinism and end-to-end tests) may
    land on different xdist workers (~2 s CPU each saved)."""
    return _once_per_run(tmp_path_factory, "real_pool_sweep", _real_pool_sweep) / "w2"
