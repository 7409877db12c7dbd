"""`radar-harness` command line: one sub-command per module, registered in `COMMANDS`.

Each command module exposes `add_arguments(parser)` and `run(args) -> int`. Exit codes: 0 ok,
1 a gate or check failed, 2 bad input (the message names the field, the value and the limit).
"""
from __future__ import annotations

import argparse
import importlib
import sys

#: name -> (module implementing it, one-line help). Modules are imported lazily so that
#: `radar-harness scenarios` does not pay for Dask or matplotlib imports.
COMMANDS: dict[str, tuple[str, str]] = {
    "frame": ("harness.cmd_frame", "simulate one R79 frame and print its summary"),
    "scenarios": ("harness.cmd_scenarios", "list the scenario catalogue"),
    "show": ("harness.cmd_scenarios", "bird's-eye PNG/GIF of a scenario"),
    "run": ("harness.cmd_sweep", "run one scenario with the chosen MIMO schemes"),
    "sweep": ("harness.cmd_sweep", "run a scenario sweep and write result tables"),
    "gate": ("harness.cmd_gate", "check result tables against thresholds"),
    "report": ("harness.cmd_report", "write an HTML report of a results directory"),
    "process": ("harness.cmd_ti", "run the pipeline on a DCA1000 capture"),
    "simulate": ("harness.cmd_ti", "write a scenario's ADC frames as a DCA1000 capture"),
}


class UsageError(ValueError):
    """Bad command-line input: reported with exit code 2."""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="radar-harness", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    for name, (module, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text)
        mod = importlib.import_module(module)
        getattr(mod, f"add_arguments_{name}", getattr(mod, "add_arguments", None))(p)
        p.set_defaults(_module=module)
    return parser


def main(argv: list[str] | None = None) -> int:
    from .runtime import tune_allocator
    tune_allocator()
    parser = build_parser()
    args = parser.parse_args(argv)
    mod = importlib.import_module(args._module)
    runner = getattr(mod, f"run_{args.command}", getattr(mod, "run", None))
    try:
        return int(runner(args) or 0)
    except (UsageError, ValueError, FileNotFoundError) as exc:
        print(f"radar-harness {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
