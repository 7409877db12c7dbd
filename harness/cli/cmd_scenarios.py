"""`radar-harness scenarios` lists the catalogue; `radar-harness show CASE` draws one case.

`show` writes `<CASE>.png` (bird's-eye view with the actors' tracks and the radar FOV) and
`<CASE>.gif` (animation) into the current directory or `--out DIR`. CASE is a catalogue name or
the path of a case file (a TOML case, or an OpenSCENARIO .xosc).
"""
from __future__ import annotations

import argparse
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
    parser.add_argument("case", help="catalogue case name or case file (.toml, .xosc)")
    parser.add_argument("--out", default=".", help="output directory (default: current)")
    parser.add_argument("--seed", type=SEED, default=0)


def resolve_case(case: str):
    """The case a command line names: a catalogue name or a case file (.toml, .xosc), its
    criteria checked against the metrics (a broken file is named, not taken for a case)."""
    from harness.sweep.file import check_case_criteria
    from scenarios import get_case
    from scenarios.files import is_case_path
    if is_case_path(case):
        c = get_case(case)
        check_case_criteria(case, c)
        return c
    return get_case(case)  # ValueError naming the known cases


def run_show(args: argparse.Namespace) -> int:
    from core.fileio import check_output_dir
    from scenarios import run_scenario
    from scenarios.plot import write_views
    if Path(args.out).exists() and not Path(args.out).is_dir():
        raise BadInput(f"--out {args.out!r} is a file; give a folder for the PNG and GIF")
    check_output_dir(args.out, "--out")  # before the scenario runs
    run = run_scenario(resolve_case(args.case), seed=args.seed)
    png, gif = write_views(run, args.out)
    print(f"wrote {png}")
    print(f"wrote {gif}")
    return 0
