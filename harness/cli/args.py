"""Bounded argument types of the `radar-harness` commands, checked at parse time.

Every number a user types is bounded by what a case and the machine can do, so a typo fails in
milliseconds with exit code 2 and one line naming the option, the value and the limit, instead
of hanging (``--duration-s 1e9``) or failing deep inside (``--duration-s inf``).
"""
from __future__ import annotations

import argparse
import math

__all__ = ["int_in", "float_in", "DURATION_S", "SEED", "FRAMES", "FRAME_STRIDE", "WORKERS",
           "MAX_CASES", "TIMEOUT_S", "check_output_file", "MAX_DURATION_S", "MAX_SEED",
           "MAX_FRAMES", "LAYOUTS", "add_capture_reading", "add_plugin_option"]

#: Longest scenario, s (the catalogue's limit on a case duration).
MAX_DURATION_S = 120.0
#: Largest seed (numpy's legacy 32-bit seed range; the tables store it as int64).
MAX_SEED = 2**32 - 1
#: Most frames a command reads or writes (120 s at 20 frames/s is 2400).
MAX_FRAMES = 100_000


def int_in(lo: int, hi: int, unit: str = ""):
    """argparse type: an integer in lo..hi."""
    def parse(text: str) -> int:
        try:
            v = int(text, 10)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError(f"{v} is outside {lo}..{hi}{unit}")
        return v
    parse.__name__ = "integer"
    return parse


def float_in(lo: float, hi: float, unit: str = "", lo_open: bool = True):
    """argparse type: a finite number in (lo, hi] (or [lo, hi] with ``lo_open=False``)."""
    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
        ok = math.isfinite(v) and (lo < v if lo_open else lo <= v) and v <= hi
        if not ok:
            bracket = "(" if lo_open else "["
            raise argparse.ArgumentTypeError(f"{text} is outside {bracket}{lo:g}, {hi:g}]{unit}")
        return v
    parse.__name__ = "number"
    return parse


DURATION_S = float_in(0.0, MAX_DURATION_S, " s")
SEED = int_in(0, MAX_SEED)
FRAMES = int_in(1, MAX_FRAMES)
FRAME_STRIDE = int_in(1, 10_000)
WORKERS = int_in(1, 256)
MAX_CASES = int_in(1, 10_000)
TIMEOUT_S = float_in(0.0, 3600.0, " s")


def check_output_file(path, option: str):
    """An output file path that can be written: not a directory, in an existing folder that
    takes new files (a probe file is created: a read-only mount is caught even for root),
    an existing file writable. Checked before a long computation, so it never fails at the
    end (`core.fileio.check_output_path`).

    Raises
    ------
    ValueError
        Naming the option, the path and what is wrong.
    """
    from core.fileio import check_output_path
    return check_output_path(path, option)


#: ``--layout`` choices -> the ADC buffer order they force (None: the profile's ``adcbufCfg``
#: ChanInterleave decides).
LAYOUTS: dict[str, bool | None] = {"auto": None, "non-interleaved": False, "interleaved": True}


def add_capture_reading(parser: argparse.ArgumentParser, verb: str) -> None:
    """The ``--frames`` and ``--layout`` options of every command that reads a DCA1000
    capture (``process``, ``calibrate``); ``verb`` says what the frames are for."""
    parser.add_argument("--frames", type=FRAMES, default=None, help=f"{verb} at most N frames")
    parser.add_argument("--layout", choices=list(LAYOUTS), default="auto",
                        help="sample order; auto follows the profile's adcbufCfg")


def add_plugin_option(parser: argparse.ArgumentParser) -> None:
    """``--plugin MODULE_OR_FILE`` (repeatable): a plugin that is not installed, loaded before
    the command builds a config (`harness.plugins`; installed ones load by themselves)."""
    parser.add_argument("--plugin", action="append", default=[], metavar="MODULE_OR_FILE",
                        help="import this plugin module or .py file first (repeatable); "
                             "installed plugins (entry points radar_harness.plugins) load "
                             "by themselves")
