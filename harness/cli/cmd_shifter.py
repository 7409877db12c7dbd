"""`radar-harness shifter`: [TI-DDMA] figures 7-8, one Tx stepped by a fixed phase per chirp
against a corner reflector, before and after `calibrate_shifters`.

Prints the lines of the range-Doppler cut at the reflector's range (target, mirror ghost,
other spurs) measured on the simulated frame and predicted by the DFT of the code period, in
dBc, and optionally writes the plot. The uncalibrated table is either a documented random
table (`--distribution`, `--error-deg-rms`, `--seed`) or a vector-modulator shifter with a
quadrature skew (`--quadrature-skew-deg`).
"""
from __future__ import annotations

import argparse
import re

import numpy as np

from core.errors import BadInput
from harness.cli.args import SEED, check_output_file, float_in, int_in

#: Most chirps of the experiment: a (n_chirps, 4, 384) frame is 6 kB per chirp as int16 and
#: the chain's complex cubes 8 times that; 16384 chirps stay under 1 GB (the R79 frame has 768).
MAX_SHIFTER_CHIRPS = 16384
#: Largest per-code phase error rms, deg: 6 sigma of a Gaussian table stays inside the
#: +/-180 deg a phase error can mean.
MAX_ERROR_DEG_RMS = 30.0
#: Internal names in the messages of the experiment and the calibration -> option names.
_OPTION_OF = {"step_deg": "--step-deg", "tx": "--tx", "n_chirps": "--n-chirps",
              "range_m": "--range-m"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from radarsim.shifter import SHIFTER_ERROR_DISTRIBUTIONS
    parser.add_argument("--distribution", choices=sorted(SHIFTER_ERROR_DISTRIBUTIONS),
                        default="inl_dnl", help="random per-code table (default inl_dnl)")
    parser.add_argument("--error-deg-rms", type=float_in(0.0, MAX_ERROR_DEG_RMS, " deg",
                                                         lo_open=False), default=6.0,
                        help="phase error per code, deg rms (default 6: about +/-10 deg; at "
                             f"most {MAX_ERROR_DEG_RMS:g})")
    parser.add_argument("--gain-error-db-rms", type=float_in(0.0, 6.0, " dB", lo_open=False),
                        default=0.0, help="gain error per code, dB rms (default 0, at most 6)")
    parser.add_argument("--quadrature-skew-deg", type=float_in(-45.0, 45.0, " deg"),
                        default=None,
                        help="instead of a random table: vector-modulator quadrature skew, deg")
    parser.add_argument("--seed", type=SEED, default=0, help="table and noise seed")
    parser.add_argument("--step-deg", type=float_in(0.0, 180.0, " deg"), default=90.0,
                        help="phase step per chirp (360 / step an integer >= 2)")
    parser.add_argument("--tx", type=int_in(1, 4), default=1, help="stepped transmitter (1..4)")
    parser.add_argument("--range-m", type=float_in(0.0, 250.0, " m"), default=4.5,
                        help="corner-reflector range (the calibration needs its SNR)")
    parser.add_argument("--n-chirps", type=int_in(2, MAX_SHIFTER_CHIRPS), default=1024)
    parser.add_argument("--plot", default=None, help="write the range-Doppler cut to this PNG")


def _in_option_names(exc: ValueError) -> BadInput:
    """The experiment's and calibration's message with internal names as option names."""
    text = str(exc)
    for name, opt in _OPTION_OF.items():
        text = re.sub(rf"(?<![\w-]){name}=", f"{opt} ", text)
    return BadInput(text)


def run(args: argparse.Namespace) -> int:
    import radarsim
    from harness.shifter_experiment import (
        check_phase_step,
        format_lines,
        phase_step_experiment,
        plot_phase_step,
    )
    from radarsim import shifter as sh

    if args.plot:  # before the experiment, not after it
        check_output_file(args.plot, "--plot")
    if args.quadrature_skew_deg is not None:
        e, _ = sh.vector_modulator_tables(64, args.quadrature_skew_deg)
        phase = np.tile(e, (4, 1))
    else:
        phase = {"distribution": args.distribution, "rms": args.error_deg_rms,
                 "seed": args.seed}
    gain = {"distribution": args.distribution, "rms": args.gain_error_db_rms,
            "seed": args.seed + 1}
    try:
        cfg = radarsim.presets.r79_ddma(shifter={"phase_quantization": "round",
                                                 "shifter_phase_error_deg": phase,
                                                 "shifter_gain_error_db": gain})
    except BadInput as exc:
        raise BadInput(f"--error-deg-rms {args.error_deg_rms:g} / --gain-error-db-rms "
                       f"{args.gain_error_db_rms:g} (--distribution {args.distribution}, "
                       f"--seed {args.seed}) draws an impossible table: {exc}") from None
    try:
        check_phase_step(cfg, args.step_deg, args.tx, args.n_chirps)  # before the calibration
        cal = radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(args.seed),
                                          range_m=args.range_m, full_output=True)
    except BadInput as exc:
        raise _in_option_names(exc) from None
    kw = dict(step_deg=args.step_deg, tx=args.tx, range_m=args.range_m,
              n_chirps=args.n_chirps)
    before = phase_step_experiment(cfg, rng=np.random.default_rng(args.seed + 1), **kw)
    after = phase_step_experiment(cal.config, rng=np.random.default_rng(args.seed + 1), **kw)
    print(f"calibration SNR {cal.snr_db:.1f} dB per chirp; R79 code residual before rms "
          f"{cal.residual_before_rms_deg:.2f} / max {cal.residual_before_max_deg:.2f} deg, "
          f"after rms {cal.residual_rms_deg:.2f} / max {cal.residual_max_deg:.2f} deg")
    for res, title in ((before, "before calibration"), (after, "after calibration")):
        print("\n".join(format_lines(res, title)))
    if args.plot:
        plot_phase_step(before, after, args.plot)
        print(f"wrote {args.plot}")
    return 0
