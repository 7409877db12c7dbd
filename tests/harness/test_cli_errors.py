"""The command line tells bad input from bugs.

`core.errors.BadInput` and an `OSError` naming a path are the user's: exit 2 and one line. Any
other exception escaping a command is a bug: it keeps its traceback (exit 1 from the console
script), whatever its type, a plain `ValueError` from numpy included.
"""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from core.errors import BadInput
from harness import cli
from harness.cli import cmd_scenarios


def _numpy_value_error(args):
    return np.zeros(3).reshape(2, 2)  # ValueError: cannot reshape array of size 3


@pytest.mark.parametrize("bug", [
    _numpy_value_error,
    lambda args: 1 / 0,
    lambda args: {}["missing"],
    lambda args: (_ for _ in ()).throw(OSError("no path: the system failed, not the user")),
], ids=["numpy_value_error", "zero_division", "key_error", "oserror_without_path"])
def test_an_internal_error_escapes_with_its_traceback(monkeypatch, capsys, bug):
    monkeypatch.setattr(cmd_scenarios, "run_scenarios", bug)
    with pytest.raises(Exception) as info:
        cli.main(["scenarios"])
    assert not isinstance(info.value, BadInput)
    assert "error:" not in capsys.readouterr().err  # not disguised as a one-line bad input


def test_bad_input_is_one_line_and_exit_2(monkeypatch, capsys):
    def bad(args):
        raise BadInput("duration_s=-1 must be > 0 s")
    monkeypatch.setattr(cmd_scenarios, "run_scenarios", bad)
    assert cli.main(["scenarios"]) == cli.EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert err == "radar-harness scenarios: error: duration_s=-1 must be > 0 s\n"


def test_a_missing_file_is_bad_input(tmp_path, capsys):
    missing = tmp_path / "nope.toml"
    assert cli.main(["sweep", str(missing)]) == cli.EXIT_BAD_INPUT
    err = capsys.readouterr().err
    assert str(missing) in err and len(err.strip().splitlines()) == 1


def test_the_console_script_prints_a_bugs_traceback_and_exits_1():
    code = ("import sys; from harness import cli; from harness.cli import cmd_scenarios\n"
            "cmd_scenarios.run_scenarios = lambda args: 1 / 0\n"
            "sys.exit(cli.main(['scenarios']))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 1
    assert "Traceback (most recent call last)" in out.stderr
    assert "ZeroDivisionError" in out.stderr


def test_help_and_usage_errors_import_no_command_but_their_own():
    """``radar-harness --help``, an unknown command and ``gate --help`` build the parser from
    the light command modules: the pipeline, the scenarios, highway-env and radarsim stay
    unimported (each CLI start used to pay ~1 s CPU for them through other commands'
    options), and so do numba and scipy's linear algebra, which the process set-up
    (`prepare_process`, ~0.7 s CPU) loads only once the arguments parse; the answers are the
    usual ones."""
    code = ("import contextlib, io, sys; from harness.cli import main\n"
            "out = io.StringIO()\n"
            "with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):\n"
            "    codes = [main(['--help']), main(['bogus']), main(['gate', '--help'])]\n"
            "heavy = sorted({m.split('.')[0] for m in sys.modules} & "
            "{'pipeline', 'scenarios', 'highway_env', 'radarsim', 'pandas', 'numba'} | "
            "({'scipy.linalg', 'threadpoolctl'} & set(sys.modules)))\n"
            "print(codes, heavy, 'sweep' in out.getvalue(), '--thresholds' in out.getvalue())\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.stdout.strip() == "[0, 2, 0] [] True True", out.stderr
