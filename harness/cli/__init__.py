"""`radar-harness` command line: one sub-command per module, registered in `COMMANDS`.

Each command module exposes `add_arguments(parser)` and `run(args) -> int`. Exit codes: 0 ok,
1 a gate or check failed (or a sweep ended with missing cells), 2 bad input
(`core.errors.BadInput`: one line naming the field, the value and the limit) or a file the system
refuses (an `OSError` naming its path: missing, unreadable, full disk, read-only folder: one line
naming the path). Any other exception is a bug in this code or a library: it keeps its
traceback and exits 1, never disguised as bad input. 130 interrupted (Ctrl-C: "rerun the same
command to resume"), 143 / 129 stopped by SIGTERM / SIGHUP (handled like Ctrl-C: pool workers
stopped,
cells written so far kept, the same resume hint; `harness.runtime.terminate_on_signals`).
Every process runs with one BLAS thread (`harness.runtime.prepare_process`), so every path gives
the same bits.
"""
from __future__ import annotations

import argparse
import importlib
import sys

from core.errors import BadInput
from harness.plugins import load_plugins
from harness.runtime import Terminated, prepare_process, terminate_on_signals

#: name -> (module implementing it, one-line help). Modules are imported lazily so that
#: `radar-harness scenarios` does not pay for Dask or matplotlib imports.
COMMANDS: dict[str, tuple[str, str]] = {
    "frame": ("harness.cli.cmd_frame", "simulate one R79 frame and print its summary"),
    "scenarios": ("harness.cli.cmd_scenarios", "list the scenario catalogue"),
    "show": ("harness.cli.cmd_scenarios", "bird's-eye PNG/GIF of a scenario"),
    "run": ("harness.cli.cmd_sweep", "run one scenario with the chosen MIMO schemes"),
    "sweep": ("harness.cli.cmd_sweep", "run a scenario sweep and write result tables"),
    "gate": ("harness.cli.cmd_gate", "check result tables against thresholds"),
    "report": ("harness.cli.cmd_report", "write an HTML report of a results directory"),
    "process": ("harness.cli.cmd_ti", "run the pipeline on a DCA1000 capture"),
    "simulate": ("harness.cli.cmd_ti", "write a scenario's ADC frames as a DCA1000 capture"),
    "rcs": ("harness.cli.cmd_rcs", "a class's RCS aspect pattern against published values"),
    "calibrate": ("harness.cli.cmd_calibrate",
                  "measure range bias and channel phases on a capture"),
    "export": ("harness.cli.cmd_export", "write a case as OpenSCENARIO (.xosc + .xodr)"),
    "shifter": ("harness.cli.cmd_shifter", "[TI-DDMA] figs 7-8: shifter spurs before/after "
                "calibration"),
    "plugins": ("harness.cli.cmd_plugins", "list every registry's entries and who added them"),
}


#: Exit codes.
EXIT_OK, EXIT_FAIL, EXIT_BAD_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130


def _is_bad_input(exc: BaseException) -> bool:
    """Bad input: a validation's `BadInput`, or an `OSError` on a path the user named (missing,
    unreadable, a directory, full disk, read-only folder). An `OSError` without a path is the
    system failing us, not the user: a bug report, with its traceback."""
    return isinstance(exc, BadInput) or (isinstance(exc, OSError) and exc.filename is not None)


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``radar-harness CMD: error: ...`` and exit code 2."""

    def error(self, message: str):  # noqa: D102 - argparse API
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The ``radar-harness`` parser. With `only` a command's name, only that command's module
    is imported and only its sub-parser gets its options: the others keep their name and help
    (all that ``radar-harness --help`` and an unknown command's error show), so a run pays for
    the imports of its own command alone (``gate`` or ``scenarios`` used to import the
    pipeline, the scenarios and highway-env through ``sweep``'s and ``process``' options, ~1.5 s
    CPU per start). ``only=None`` builds every command's options; ``only=""`` (no command
    named: ``--help``, an unknown word) none."""
    parser = _Parser(prog="radar-harness", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, (module, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text)
        p.set_defaults(_module=module)
        if only is None or name == only:
            mod = importlib.import_module(module)
            getattr(mod, f"add_arguments_{name}", getattr(mod, "add_arguments", None))(p)
    return parser


def _command_named(argv: list[str]) -> str | None:
    """The command `argv` names: its first word not an option (the top-level parser has no
    option taking a value), or None (``--help``, nothing, an unknown word)."""
    word = next((a for a in argv if not a.startswith("-")), None)
    return word if word in COMMANDS else None


def _one_line(exc: BaseException) -> str:
    text = str(exc) or type(exc).__name__
    if isinstance(exc, OSError) and exc.filename is not None and exc.strerror:
        text = f"{exc.filename}: {exc.strerror}"
    return " | ".join(line.strip() for line in text.splitlines() if line.strip())


def main(argv: list[str] | None = None) -> int:
    try:
        with terminate_on_signals():
            return _main(argv)
    except KeyboardInterrupt as exc:  # during start-up: the commands' modules (pandas, scipy,
        return _stopped("", exc)      # the pipeline) take most of a second to import


def _stopped(command: str, exc: KeyboardInterrupt) -> int:
    why = f"stopped by {exc.args[0]}" if isinstance(exc, Terminated) else "interrupted"
    print(f"radar-harness{' ' + command if command else ''}: {why}: rerun the same command to "
          "resume", file=sys.stderr)
    return 128 + exc.signum if isinstance(exc, Terminated) else EXIT_INTERRUPTED


def _main(argv: list[str] | None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    command = _command_named(argv)
    parser = build_parser(command or "")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help (0) or a one-line usage error (2)
        return int(exc.code or 0) if not isinstance(exc.code, str) else EXIT_BAD_INPUT
    # Once the arguments parse, before the command computes anything (its module's import
    # included): one BLAS thread, the allocator, numba's cache lock. Not earlier: loading
    # scipy.linalg and numba is ~0.7 s of CPU that `--help` and a usage error do not need.
    prepare_process()
    mod = importlib.import_module(args._module)
    runner = getattr(mod, f"run_{args.command}", getattr(mod, "run", None))
    try:
        # Installed plugins (entry points) and --plugin ones, before any config is built; a
        # plugin that fails to import is named with its error (exit 2), never half-loaded.
        load_plugins(getattr(args, "plugin", None) or ())
        return int(runner(args) or 0)
    except (BadInput, OSError) as exc:
        if not _is_bad_input(exc):
            raise  # a bug: Python prints the traceback, exit 1
        print(f"radar-harness {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as exc:
        return _stopped(args.command, exc)


if __name__ == "__main__":
    sys.exit(main())
