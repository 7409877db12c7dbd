"""Count the probe set's outcomes per class and surface (the closing notes' figures).

    python -m tests.harness.probe_survey [--time-limit-s 60] [--memory-gib 4] [--only SURFACE]
        [--json FILE]

Each probe runs in a fresh temporary folder, in this process, under a time limit (longer:
"hang") and an address-space limit (a runaway allocation ends as MemoryError: "crash" instead
of taking the machine down). Prints one line per probe that is not clear and the counts per
class, overall and per surface.
"""
from __future__ import annotations

import argparse
import collections
import json
import resource
import sys
import tempfile
import time
from pathlib import Path

from tests.harness.probes import CLASSES, all_probes, classify
from tests.harness.probes_surfaces import surface_probes


def _warm_up() -> None:
    """Import every package and compile what compiles on first use, outside the time limits,
    so a slow first import on a loaded machine is not counted as a hang (an import cut by the
    time limit would also leave a half-initialised module behind for every later probe)."""
    import tempfile

    import matplotlib.pyplot  # noqa: F401
    import numpy as np

    import harness.cli  # noqa: F401
    import pipeline
    import radarsim
    import scenarios
    from tests.harness.probes import fake_results
    scenarios.run_scenario(scenarios.get_case("head_on_aliasing"), seed=0)
    cfg = radarsim.presets.r79_ddma()
    pipeline.process_frame(cfg, np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), np.int16))
    with tempfile.TemporaryDirectory() as d:
        fake_results(Path(d))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time-limit-s", type=float, default=45.0)
    ap.add_argument("--memory-gib", type=float, default=4.0)
    ap.add_argument("--only", nargs="*", default=None, help="surfaces to run")
    ap.add_argument("--json", default=None, help="write every outcome here")
    ap.add_argument("--ids", nargs="*", default=None, help="only these probe ids")
    ap.add_argument("--skip-ids", nargs="*", default=(), help="leave these probe ids out")
    args = ap.parse_args(argv)
    lim = int(args.memory_gib * (1 << 30))
    resource.setrlimit(resource.RLIMIT_AS, (lim, resource.getrlimit(resource.RLIMIT_AS)[1]))
    probes = [p for p in all_probes() + surface_probes()
              if (args.only is None or p.surface in args.only)
              and (args.ids is None or p.id in args.ids) and p.id not in args.skip_ids]
    _warm_up()
    rows = []
    for p in probes:
        t0 = time.monotonic()
        with tempfile.TemporaryDirectory(prefix="probe-") as d:
            try:
                cls, detail = classify(p, Path(d), args.time_limit_s * p.time_factor)
            except BaseException as exc:  # noqa: BLE001 - a probe that escaped classification
                if isinstance(exc, KeyboardInterrupt):
                    raise
                cls, detail = "crash", f"{type(exc).__name__}: {exc}"
        rows.append({"probe": p.id, "surface": p.surface, "owner": p.owner, "class": cls,
                     "detail": detail[:300], "elapsed_s": round(time.monotonic() - t0, 2)})
        print(f"{cls:8s} {p.id} [{p.owner}] {rows[-1]['elapsed_s']:.1f} s"
              + (f": {detail[:200]}" if cls != "clear" else ""), flush=True)
    for owner in sorted({r["owner"] for r in rows}):
        mine = [r for r in rows if r["owner"] == owner]
        c = collections.Counter(r["class"] for r in mine)
        print(f"\n{owner}: {len(mine)} probes: " + ", ".join(f"{k} {c.get(k, 0)}"
                                                           for k in CLASSES))
        for surface in dict.fromkeys(r["surface"] for r in mine):
            cs = collections.Counter(r["class"] for r in mine if r["surface"] == surface)
            print(f"  {surface:15s} " + " ".join(f"{k} {cs.get(k, 0):3d}" for k in CLASSES))
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
