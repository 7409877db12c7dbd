"""`radar-harness run CASE` and `radar-harness sweep [SWEEP.toml]`.

``run`` evaluates one case (a catalogue name or a case file: .toml, .xosc) with the given
schemes (``--schemes``: names of
``radarsim.MIMO_SCHEMES`` or chain variants such as ``tdma_raw``; default DDMA, TDMA and
TDMA-without-disambiguation) and prints the summary table (``--out DIR`` also writes its
tables). ``sweep`` runs a suite (default: the
shipped ``harness/sweeps/default.toml``: whole catalogue, one seed) on a local process pool or a
Dask cluster and writes ``results/<run-id>/`` (``--out DIR``): ``detections.parquet`` (long),
``frames.parquet`` (per frame), ``actors.parquet`` (per actor and frame),
``actor_summary.parquet`` (per actor: detection probability, first-detection range),
``summary.parquet``,
``truth.parquet``, ``tracks.parquet`` and ``manifest.json``. Rerunning the same command resumes.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import pandas as pd

from core.errors import BadInput
from core.fileio import check_output_dir
from harness.cli.args import (
    DURATION_S,
    FRAME_STRIDE,
    SEED,
    TIMEOUT_S,
    WORKERS,
    add_plugin_option,
)
from harness.sweep.store import failed_rows

#: Columns printed by `run` and `sweep` (all are in summary.parquet, with many more).
SUMMARY_COLUMNS = [
    "scenario", "variant", "seed", "scheme", "n_frames", "detections_per_frame", "ghost_rate",
    "velocity_unambiguity_rate", "n_velocity_resolution_failures", "range_error_rmse_m",
    "range_error_median_m", "radial_velocity_error_rmse_mps",
    "detection_probability_mean", "target_first_detection_range_m", "snr_gain_median_db",
    "case_pass",
]


def format_summary(summary: pd.DataFrame, columns=None) -> str:
    """Fixed-width text of the main summary columns (those present)."""
    cols = [c for c in (columns or SUMMARY_COLUMNS) if c in summary.columns]
    if summary.empty:
        return "(no rows)"
    text = summary[cols].to_string(index=False, float_format=lambda v: f"{v:.3g}",
                                   na_rep="-")
    for _, r in summary[failed_rows(summary)].iterrows():
        text += f"\nERROR {r['scenario']} {r['variant']} seed {r['seed']}: {r['error']}"
    return text


def add_arguments_run(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("case", help="catalogue case name (see `radar-harness scenarios`) or "
                        "case file (.toml, .xosc)")
    parser.add_argument("--seed", type=SEED, default=0)
    parser.add_argument("--duration-s", type=DURATION_S, default=None,
                        help="shorten the case (default: its own duration; at most 120 s)")
    parser.add_argument("--frame-stride", type=FRAME_STRIDE, default=1,
                        help="process every k-th frame")
    parser.add_argument("--out", default=None, help="also write the tables to this directory")
    _add_scheme_arguments(parser)


def _add_scheme_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--schemes", nargs="+", default=None, metavar="SCHEME",
                        help="result schemes: radarsim.MIMO_SCHEMES names or chain variants "
                             "(default ddma tdma tdma_raw)")
    parser.add_argument("--baseline-scheme", default=None,
                        help="scheme the SNR gain is taken over (default tdma)")
    add_plugin_option(parser)


def _check_baseline(schemes, baseline: str | None, explicit: bool) -> None:
    """An explicit (or non-default) baseline must be one of the schemes run: otherwise every
    SNR-gain column would be NaN, silently."""
    from harness.cell.spec import DEFAULT_BASELINE_SCHEME, DEFAULT_SCHEMES
    schemes = list(schemes if schemes is not None else DEFAULT_SCHEMES)
    baseline = baseline if baseline is not None else DEFAULT_BASELINE_SCHEME
    if (explicit or baseline != DEFAULT_BASELINE_SCHEME) and baseline not in schemes:
        raise BadInput(f"--baseline-scheme {baseline} is not among the schemes run "
                       f"{schemes}: the SNR gain of every scheme would be NaN; add it to "
                       "--schemes or pick one of them")


def _scheme_kwargs(args: argparse.Namespace) -> dict:
    _check_baseline(args.schemes, args.baseline_scheme, args.baseline_scheme is not None)
    kw = {}
    if args.schemes is not None:
        kw["schemes"] = tuple(args.schemes)
    if args.baseline_scheme is not None:
        kw["baseline_scheme"] = args.baseline_scheme
    return kw


def run_run(args: argparse.Namespace) -> int:
    from harness.cell.run import run_cell
    from harness.cell.spec import CellSpec
    from harness.cli.cmd_scenarios import resolve_case
    from harness.sweep.assemble import write_atomic
    from harness.sweep.schedule import prepare_out
    from harness.sweep.spec import resolve_scenarios
    ref = resolve_scenarios([args.case])[0]  # a case file: its absolute path, loaded
    resolve_case(ref)  # and its criteria checked, before any work
    out = prepare_out(args.out) if args.out else None  # fail before the (long) run
    spec = CellSpec(scenario=ref, seed=args.seed, duration_s=args.duration_s,
                    frame_stride=args.frame_stride, **_scheme_kwargs(args))
    res = run_cell(spec)
    print(format_summary(res.tables["summary"]))
    print(f"({res.elapsed_s:.1f} s)")
    if out is not None:
        for name, df in res.tables.items():
            write_atomic(out / f"{name}.parquet",
                          lambda tmp, df=df: df.to_parquet(tmp, index=False))
        print(f"tables written to {out}/")
    return 0


def add_arguments_sweep(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("sweep_file", nargs="?", default=None,
                        help="sweep TOML (default: harness/sweeps/default.toml)")
    parser.add_argument("--out", default=None,
                        help="results directory (default results/<run-id>)")
    parser.add_argument("--workers", type=WORKERS, default=None,
                        help="local worker processes (default: CPU count)")
    parser.add_argument("--scheduler", default=None,
                        help="Dask scheduler address, tls://host:8786 with --security (plain "
                             "tcp:// only on a trusted network: the workers run pickled "
                             "code); workers must see --out")
    parser.add_argument("--security", default=None,
                        help="TOML with ca_file, cert, key (PEM) for a tls:// scheduler "
                             "(default: Dask's distributed.comm.tls configuration)")
    parser.add_argument("--scheduler-timeout-s", type=TIMEOUT_S, default=20.0,
                        help="give up if the scheduler does not answer within this time")
    parser.add_argument("--force", action="store_true",
                        help="recompute cells that another code version completed in --out "
                             "(without it such a resume is refused)")
    parser.add_argument("--frame-stride", type=FRAME_STRIDE, default=None,
                        help="process every k-th frame (overrides the sweep file)")
    parser.add_argument("--duration-s", type=DURATION_S, default=None,
                        help="shorten every case, at most 120 s (overrides the sweep file)")
    parser.add_argument("--seeds", type=SEED, nargs="+", default=None,
                        help="seeds (override the sweep file)")
    parser.add_argument("--scenarios", nargs="+", default=None,
                        help="only these cases: names or case files (override the sweep "
                             "file)")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                        help="progress bar (default: only on a terminal)")
    parser.add_argument("--export-xosc", default=None, metavar="DIR",
                        help="also write every case the sweep ran (its duration, each seed) "
                             "as OpenSCENARIO .xosc + .xodr into DIR")
    _add_scheme_arguments(parser)


def _print_profile_notes(spec) -> None:
    """One stderr line per note of each TI profile the sweep's variants name: what the cells
    read but do not run (nothing a profile asks for is dropped silently)."""
    from harness.cell.ti_profile import load_profile, sweep_profile_notes
    paths = sorted({v.radar["profile"] for v in spec.variants if "profile" in v.radar})
    for path in paths:
        for note in sweep_profile_notes(load_profile(Path(path))):
            print(f"note: radar.profile={path}: {note}", file=sys.stderr)


def _export_cases(spec, folder: str) -> None:
    """Write every case of a sweep as OpenSCENARIO (one file per case and seed; the seed is in
    the name when the sweep has several)."""
    from scenarios import get_case, run_scenario
    from scenarios.openscenario.export import export_run
    for ref in spec.scenarios:
        case = get_case(ref)
        for seed in spec.seeds:
            run = run_scenario(case, seed=seed, duration_s=spec.duration_s)
            name = case.name if len(spec.seeds) == 1 else f"{case.name}_s{seed}"
            xosc, _ = export_run(run, folder, name)
            print(f"wrote {xosc}", file=sys.stderr)


def run_sweep(args: argparse.Namespace) -> int:
    from harness.sweep import dask_cluster, schedule
    from harness.sweep import file as sweepfile
    spec = sweepfile.load_sweep(args.sweep_file).with_overrides(
        seeds=args.seeds, frame_stride=args.frame_stride, duration_s=args.duration_s,
        scenarios=args.scenarios, schemes=args.schemes)
    if args.baseline_scheme is not None:
        import dataclasses
        spec = dataclasses.replace(spec, baseline_scheme=args.baseline_scheme)
    _check_baseline(spec.schemes, spec.baseline_scheme, args.baseline_scheme is not None)
    out = Path(args.out) if args.out else Path("results") / spec.run_id
    workers = args.workers if args.workers is not None else (os.cpu_count() or 1)
    security = dask_cluster.dask_security(args.security) if args.security else None
    out = schedule.prepare_out(out)
    if args.export_xosc is not None:
        check_output_dir(args.export_xosc, "--export-xosc")  # before the sweep
    _print_profile_notes(spec)
    n = len(spec.cells())
    print(f"sweep {spec.name}: {n} cells ({len(spec.scenarios)} scenarios x "
          f"{len(spec.variants)} variants x {len(spec.seeds)} seeds) -> {out}/",
          file=sys.stderr)
    outcome = schedule.run_sweep(spec, out, workers=workers, scheduler=args.scheduler,
                                 progress=args.progress, force=args.force,
                                 security=security,
                                 scheduler_timeout_s=args.scheduler_timeout_s)
    summary = pd.read_parquet(out / "summary.parquet")
    print(format_summary(summary))
    if args.export_xosc is not None:
        _export_cases(spec, args.export_xosc)
    print(f"{outcome.n_ok} cells computed, {outcome.n_skipped} resumed, "
          f"{outcome.n_recomputed} recomputed (other code version or damaged), "
          f"{outcome.n_error} failed, {outcome.n_missing} missing -> {out}/")
    if outcome.n_missing:
        print(f"{outcome.n_missing} of {outcome.n_cells} cells are missing (a worker died or "
              f"wrote elsewhere): rerun the same command to resume them; first: "
              f"{outcome.missing[0]}", file=sys.stderr)
    return 0 if outcome.n_error == 0 and outcome.complete else 1
