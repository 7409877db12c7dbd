"""`radar-harness gate RESULTS [--thresholds gates.toml] [--junit FILE] [--markdown FILE]`.

Compares the summary table of a results directory with thresholds, prints a pass/fail table
and the verdict table (case x scheme: pass/fail with the deciding numbers), optionally writes
JUnit XML and a Markdown summary (default ``RESULTS/gates.md``), each atomically. Exit code 0
if every gate passes, 1 if any fails, 2 on bad input (missing results, malformed gates file, a
metric not in `metrics.METRICS` or one that cannot be gated, an unknown case class). The exit
code is the verdict even when a report file cannot be written (a read-only results folder: a
warning on stderr). The code version of the results is printed, with a warning when it is not
today's (`harness.sweep.provenance`).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from harness.cli.args import add_plugin_option, check_output_file


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("results", help="results directory (or its summary.parquet)")
    parser.add_argument("--thresholds", default=None,
                        help="gates TOML (default: the shipped harness/gates/gates.toml)")
    parser.add_argument("--junit", default=None, help="write JUnit XML here")
    parser.add_argument("--markdown", default=None,
                        help="write the Markdown summary here (default RESULTS/gates.md)")
    add_plugin_option(parser)


def run(args: argparse.Namespace) -> int:
    import pandas as pd

    from core.fileio import OutputError, atomic_write
    from harness.gates import check as g
    from harness.sweep.provenance import plugins_line, version_line
    for opt, val in (("--junit", args.junit), ("--markdown", args.markdown)):
        if val is not None:
            if opt == "--junit":
                Path(val).parent.mkdir(parents=True, exist_ok=True)
            check_output_file(val, opt)
    gates = g.load_gates(args.thresholds)
    summary, manifest = g.load_summary(args.results)
    results = g.evaluate_gates(summary, gates, manifest)
    line, warning = version_line(manifest)
    print(line)
    if plugins_line(manifest):
        print(plugins_line(manifest))
    if warning:
        print(f"radar-harness gate: {warning}", file=sys.stderr)
    table = g.results_table(results)
    with pd.option_context("display.max_colwidth", 60, "display.width", 200):
        print(table[["status", "gate", "where", "value", "bound"]].to_string(
            index=False, float_format=lambda v: f"{v:.4g}"))
    n_fail = int((table["status"] == "fail").sum())
    verdicts = g.verdict_table(results)
    if len(verdicts):
        with pd.option_context("display.max_colwidth", 70, "display.width", 250,
                               "display.max_columns", None):
            print("\nVerdicts (case x scheme; pass: first deciding gate's value, FAIL: the "
                  "failing metrics):")
            print(verdicts.to_string())
    print(f"{len(table) - n_fail} of {len(table)} gate checks passed or skipped, "
          f"{n_fail} failed")
    verdict = 1 if n_fail else 0
    md = Path(args.markdown) if args.markdown else \
        (Path(args.results) if Path(args.results).is_dir() else Path(args.results).parent) \
        / "gates.md"
    outputs = ([(Path(args.junit), g.junit_xml(results))] if args.junit else []) + \
        [(md, g.markdown(results))]
    for path, text in outputs:
        # The verdict is the exit code even when a report file cannot be written (a
        # read-only results folder in CI): say so on stderr, never turn a pass into a fail.
        try:
            atomic_write(path, lambda tmp, text=text: tmp.write_text(text, encoding="utf-8"))
        except OutputError as exc:
            word = "fail" if verdict else "pass"
            print(f"radar-harness gate: warning: {exc}; the verdict ({word}) stands as the exit "
                  "code", file=sys.stderr)
    return verdict
