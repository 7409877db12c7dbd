"""`radar-harness scenarios` lists the catalogue; `radar-harness show CASE` draws one case.

`show` writes `<CASE>.png` (bird's-eye view with the actors' tracks and the radar FOV) and
`<CASE>.gif` (animation) into the current directory or `--out DIR`. CASE is a catalogue name or
the path of a TOML scenario file.
"""
from __future__ import annotations

import argparse
import os
from pathlib import Path

from core.errors import BadInput
from harness.cli.args import SEED


def add_arguments_scenarios(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--verbose", action="store_true",
                        help="also print each case's pass criteria")


def run_scenarios(args: argparse.Namespace) -> int:
    from scenarios import SCENARIOS

    for case in SCENARIOS.values():
        print(case.summary())
        if getattr(args, "verbose", False):
            for c in case.criteria:
                who = f"actor {c.actor_id}" if c.actor_id is not None else "scenario"
                print(f"{'':28s}   pass: {c.metric} {c.op} {c.value:g} ({who}) {c.note}")
    return 0


def add_arguments_show(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("case", help="catalogue case name or TOML scenario file")
    parser.add_argument("--out", default=".", help="output directory (default: current)")
    parser.add_argument("--seed", type=SEED, default=0)


def _resolve(case: str):
    from metrics.registry import check_criterion
    from scenarios import get_case, load_scenario_file

    if case.endswith(".toml") or os.sep in case:  # a file (a broken one is named, not a case)
        c = load_scenario_file(case)
        for i, crit in enumerate(c.criteria):  # the metrics downstream define the names
            try:
                check_criterion(crit.metric, crit.actor_id)
            except BadInput as exc:
                raise BadInput(f"{case}: criteria[{i}].metric: {exc}") from None
        return c
    return get_case(case)  # ValueError naming the known cases


def run_show(args: argparse.Namespace) -> int:
    from core.fileio import check_output_dir
    from scenarios import run_scenario
    from scenarios.plot import write_views
    if Path(args.out).exists() and not Path(args.out).is_dir():
        raise BadInput(f"--out {args.out!r} is a file; give a folder for the PNG and GIF")
    check_output_dir(args.out, "--out")  # before the scenario runs
    run = run_scenario(_resolve(args.case), seed=args.seed)
    png, gif = write_views(run, args.out)
    print(f"wrote {png}")
    print(f"wrote {gif}")
    return 0
