"""`radar-harness export CASE --format xosc --out DIR`: a case in the industry's format.

Runs CASE (a catalogue name or a case file) with ``--seed`` in highway-env and writes
``DIR/<CASE>.xosc`` (OpenSCENARIO 1.2: entities, Init, one timed trajectory per entity, the
harness fields as parameters) and ``DIR/<CASE>.xodr`` (its road, OpenDRIVE), with
`scenarios.openscenario.export`. ``radar-harness run DIR/<CASE>.xosc`` plays it back.
"""
from __future__ import annotations

import argparse

from harness.cli.args import SEED

#: Export formats: name -> what it writes.
FORMATS = {"xosc": "OpenSCENARIO 1.2 (.xosc) and its OpenDRIVE road (.xodr)"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("case", help="catalogue case name or case file (.toml, .xosc)")
    parser.add_argument("--format", choices=sorted(FORMATS), required=True,
                        help="; ".join(f"{k}: {v}" for k, v in FORMATS.items()))
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--seed", type=SEED, default=0,
                        help="seed of the random traffic (scripted cases do not use it)")


def run(args: argparse.Namespace) -> int:
    from core.fileio import check_output_dir
    from harness.cli.cmd_scenarios import resolve_case
    from scenarios.openscenario.export import export_case
    case = resolve_case(args.case)
    check_output_dir(args.out, "--out")  # before the case runs
    xosc_path, xodr_path = export_case(case, args.out, seed=args.seed)
    print(f"wrote {xosc_path}")
    print(f"wrote {xodr_path}")
    return 0
