"""`radar-harness report RESULTS [--out FILE] [--no-maps] [--max-cases N]`: HTML report."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from core.errors import BadInput
from harness.cli.args import MAX_CASES, add_plugin_option, check_output_file


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("results", help="results directory written by `radar-harness sweep`")
    parser.add_argument("--out", default=None, help="output HTML (default RESULTS/report.html)")
    parser.add_argument("--maps", action=argparse.BooleanOptionalAction, default=True,
                        help="re-simulate one frame per case for range-Doppler and "
                             "Doppler-azimuth maps (default on)")
    parser.add_argument("--max-cases", type=MAX_CASES, default=None,
                        help="limit the per-case sections")
    add_plugin_option(parser)


def run(args: argparse.Namespace) -> int:
    from harness.report.page import build_report
    res = Path(args.results)
    if not res.is_dir():
        raise BadInput(f"results {args.results!r}: not a results directory (run `radar-harness "
                       "sweep` first)")
    check_output_file(args.out if args.out is not None else res / "report.html", "--out")
    from harness.sweep.provenance import plugins_line, read_manifest, version_line
    manifest = read_manifest(res)
    line, warning = version_line(manifest)
    print(line)
    if plugins_line(manifest):
        print(plugins_line(manifest))
    if warning:  # the maps are re-simulated with today's code
        print(f"radar-harness report: {warning}", file=sys.stderr)
    path = build_report(args.results, args.out, maps=args.maps, max_cases=args.max_cases,
                        notify=lambda gap: print(f"radar-harness report: warning: {gap}",
                                                 file=sys.stderr))
    print(f"report written to {path}")
    return 0
