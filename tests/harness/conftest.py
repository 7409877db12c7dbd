"""A small results directory produced by a stand-in sweep, shared by gate and report tests."""
from __future__ import annotations

import pytest

from harness.schedule import run_sweep
from harness.sweepspec import SweepSpec
from tests.harness.fakes import FAKE


@pytest.fixture(scope="session")
def fake_results(tmp_path_factory):
    out = tmp_path_factory.mktemp("results")
    spec = SweepSpec(name="fake", scenarios=("fast", "slow"), seeds=(0,), duration_s=1.0)
    run_sweep(spec, out, components=FAKE, progress=False)
    return out
