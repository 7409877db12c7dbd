"""`radar-harness calibrate`: the SDK's ``measureRangeBiasAndRxChanPhase``, offline.

    radar-harness calibrate CAPTURE --cfg PROFILE --target-range-m R [--search-window-m W]
                            [--azimuth-deg A] [--frames N] [--write OUT.cfg]

R and W default to the profile's enabled ``measureRangeBiasAndRxChanPhase 1 X D`` (X, D / 2:
TI searches X +/- D / 2); W otherwise to four range bins.

Reads a DCA1000 capture of a static reflector (a corner reflector on boresight, TI's
procedure) recorded with PROFILE, measures the range bias and the virtual-channel coefficients
(`pipeline.channel_calibration`) and prints the ``compRangeBiasAndRxChanPhase`` line on stdout
(the measured range, SNR and Cramer-Rao bounds go to stderr). ``--write`` writes PROFILE with
that line (replacing the profile's own, or added before ``sensorStart``). Processing the same
capture with the written profile reports the reflector at R and at azimuth A.

A profile of the MCU+ SDK DDM demo corrects its channels with ``antennaCalibParams`` (no range
bias; `radarsim.ti.board_calibration`): a second stdout line gives the coefficients in that
form, and ``--write`` sets the profile's own ``antennaCalibParams`` to the identity, since the
written ``compRangeBiasAndRxChanPhase`` now carries them (one correction per board).

Bad input (exit 2, one line): no peak within R +/- W, a measurement below
`pipeline.channel_calibration.MIN_CALIBRATION_SNR_DB`, a window outside the radar's range, a
clipped capture (samples at the ADC rails), a second return near the reflector (ambiguous),
``--write`` naming the capture or the profile (an input is never written over).
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from core.errors import BadInput
from core.fileio import atomic_write
from harness.cli.args import LAYOUTS, add_capture_reading, check_output_file, float_in

__all__ = ["add_arguments", "run", "with_comp_line", "antenna_calib_line",
           "with_identity_antenna_calib"]

#: How many range bins the default search window spans on each side of R (TI: "at least the
#: distance equivalent of a few range bins").
DEFAULT_WINDOW_BINS = 4


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("capture", type=Path, help="DCA1000 capture of a static reflector")
    parser.add_argument("--cfg", type=Path, required=True,
                        help="TI .cfg profile it was recorded with")
    parser.add_argument("--target-range-m", type=float_in(0.0, 1000.0, " m"), default=None,
                        help="true range of the reflector, m (default: the targetDistance of "
                             "the profile's enabled measureRangeBiasAndRxChanPhase)")
    parser.add_argument("--search-window-m", type=float_in(0.0, 100.0, " m"), default=None,
                        help="search the peak within R +/- W, m (default: half the profile's "
                             "measureRangeBiasAndRxChanPhase searchWin when it measures, else "
                             f"{DEFAULT_WINDOW_BINS} range bins)")
    parser.add_argument("--azimuth-deg", type=float_in(-90.0, 90.0, " deg"), default=0.0,
                        help="azimuth the reflector stands at (TI's procedure: 0, boresight)")
    add_capture_reading(parser, "use")
    parser.add_argument("--write", type=Path, default=None,
                        help="write the profile with the measured line to this file")


def with_comp_line(text: str, line: str) -> str:
    """Profile text with its ``compRangeBiasAndRxChanPhase`` line(s) replaced by `line` (at
    the first one's place), or `line` inserted before the first ``sensorStart`` (at the end
    when there is none). Every other line is kept as it was."""
    from pipeline.compensation import COMP_COMMAND
    lines = text.splitlines()
    is_comp = [ln.split()[:1] == [COMP_COMMAND] for ln in lines]
    if any(is_comp):
        at = is_comp.index(True)
        lines = [ln for ln, c in zip(lines, is_comp) if not c]
    else:
        starts = [i for i, ln in enumerate(lines) if ln.split()[:1] == ["sensorStart"]]
        at = starts[0] if starts else len(lines)
    lines.insert(at, line)
    return "\n".join(lines) + "\n"


def antenna_calib_line(chip_coefficients) -> str:
    """The DDM demo's ``antennaCalibParams`` line of chip-ordered coefficients: Im, Re of each
    (5 decimals, as `pipeline.compensation.comp_line`)."""
    import numpy as np
    parts = []
    for c in np.asarray(chip_coefficients, dtype=complex):
        parts += [f"{round(c.imag, 5) + 0.0:.5f}", f"{round(c.real, 5) + 0.0:.5f}"]
    return " ".join(["antennaCalibParams", *parts])


def with_identity_antenna_calib(text: str, n_pairs: int) -> str:
    """Profile text with every ``antennaCalibParams`` line replaced by the identity
    (``0 1`` per virtual antenna); other lines kept as they were."""
    ident = "antennaCalibParams " + " ".join(["0 1"] * n_pairs)
    lines = [ident if ln.split()[:1] == ["antennaCalibParams"] else ln
             for ln in text.splitlines()]
    return "\n".join(lines) + "\n"


def _write_text(path: Path, text: str) -> None:
    """Atomically, a full disk named (`core.fileio.atomic_write`)."""
    atomic_write(path, lambda tmp: tmp.write_text(text))


def _refuse_writing_over_an_input(args: argparse.Namespace) -> None:
    """``--write`` naming the capture or the profile (itself, a link to it, another spelling)
    would replace an input with the written profile: refused."""
    for opt, path in (("CAPTURE", args.capture), ("--cfg", args.cfg)):
        try:
            same = os.path.samefile(args.write, path)
        except OSError:  # one of them does not exist (yet): not the same file
            same = False
        if same:
            raise BadInput(f"--write {str(args.write)!r} is the {opt} file being read; "
                           "write the profile to another path")


def _target_and_window(args: argparse.Namespace, profile) -> tuple[float, float]:
    """Target range and search half-window: the options, else the profile's enabled
    ``measureRangeBiasAndRxChanPhase <1> <targetDistance> <searchWin>`` (TI searches
    targetDistance +/- searchWin / 2), else (window only) `DEFAULT_WINDOW_BINS` range bins."""
    measure = profile.measure_range_bias
    on = measure is not None and bool(measure[0])
    target = args.target_range_m
    if target is None:
        if not on:
            raise BadInput("--target-range-m is required: the profile has no enabled "
                           "measureRangeBiasAndRxChanPhase line to take it from")
        target = float(measure[1])
    if args.search_window_m is not None:
        return target, args.search_window_m
    if on and float(measure[2]) > 0:
        return target, float(measure[2]) / 2
    return target, DEFAULT_WINDOW_BINS * profile.radar.range_resolution_m


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from harness.cell.ti_profile import load_profile, processing_from_profile
    from pipeline.channel_calibration import measure_channel_calibration
    from radarsim.capture import capture_n_frames, iter_capture

    if args.capture.is_dir():
        raise BadInput(f"capture {str(args.capture)!r} is a directory, not a capture file")
    if args.write is not None:
        _refuse_writing_over_an_input(args)
        check_output_file(args.write, "--write")
    profile = load_profile(args.cfg)
    if profile.is_advanced:
        raise BadInput(f"--cfg {str(args.cfg)!r} is an advanced-frame profile "
                       f"({len(profile.subframes)} sub-frames): calibrate on a capture "
                       "recorded with a one-frame profile (TI's procedure uses one)")
    cfg = profile.radar
    proc = processing_from_profile(profile).replace(
        **{"calibration.range_bias_m": 0.0, "calibration.channel_comp": None})
    target, window = _target_and_window(args, profile)
    n_frames = capture_n_frames(args.capture, cfg)
    if args.frames is not None:
        n_frames = min(n_frames, args.frames)
    frames = iter_capture(args.capture, cfg, interleaved=LAYOUTS[args.layout],
                          max_frames=n_frames)
    try:
        cal = measure_channel_calibration(cfg, frames, target, window, proc,
                                          azimuth_deg=args.azimuth_deg)
    except BadInput as exc:
        raise BadInput(f"--target-range-m {target:g} --search-window-m {window:g}: "
                       f"{exc}") from None
    print(cal.line)
    from radarsim.ti.families import DEMO_FAMILIES
    ddm = bool(profile.demo_family) and \
        DEMO_FAMILIES[profile.demo_family].has("antennaCalibParams")
    if ddm:
        print(antenna_calib_line(cal.chip_coefficients))
    crb_deg = np.degrees(cal.phase_crb_rad())
    print(f"note: reflector at {cal.measured_range_m:.4f} m (bin {cal.range_bin}), range bias "
          f"{cal.range_bias_m:+.4f} m (CRB {cal.range_crb_m(cfg.range_resolution_m):.2g} m), "
          f"{cal.n_frames} frame(s), SNR per channel and frame {cal.snr_db.min():.1f}.."
          f"{cal.snr_db.max():.1f} dB, phase CRB <= {crb_deg.max():.2g} deg", file=sys.stderr)
    if args.write is not None:
        text = with_comp_line(Path(args.cfg).read_text(), cal.line)
        if ddm:
            text = with_identity_antenna_calib(text, len(cal.chip_coefficients))
        _write_text(args.write, text)
        print(f"note: profile with the measured line -> {args.write}", file=sys.stderr)
    return 0
