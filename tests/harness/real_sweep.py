"""One small real-parts sweep, shared by the determinism and end-to-end tests (its pool run is
the `real_pool_sweep` fixture in conftest.py; `cli` runs the serial one in a fresh process):
the default sweep cut to two cases of two processed frames each (0.2 s at frame stride 2).
The dense highway is one of them: its front-end GEMM is the largest of the catalogue
(`tests/harness/test_determinism.py`)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CASES = ("dense_highway", "head_on_aliasing")
DURATION_S, FRAME_STRIDE, SEED = 0.2, 2, 0
#: `radar-harness sweep` arguments of the shared sweep (without --workers / --out).
SWEEP_ARGS = ("--scenarios", *CASES, "--duration-s", str(DURATION_S),
              "--frame-stride", str(FRAME_STRIDE), "--seeds", str(SEED))


def cli(*argv: str) -> None:
    """Run ``python -m harness.cli *argv`` in a fresh process; assert exit 0."""
    r = subprocess.run([sys.executable, "-m", "harness.cli", *argv], cwd=ROOT,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
