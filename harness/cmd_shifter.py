"""`radar-harness shifter`: seed 000 figures 7-8, one Tx stepped by a fixed phase per chirp
against a corner reflector, before and after `calibrate_shifters`.

Prints the lines of the range-Doppler cut at the reflector's range (target, mirror ghost,
other spurs) measured on the simulated frame and predicted by the DFT of the code period, in
dBc, and optionally writes the plot. The uncalibrated table is either a documented random
table (`--distribution`, `--error-deg-rms`, `--seed`) or a vector-modulator shifter with a
quadrature skew (`--quadrature-skew-deg`).
"""
from __future__ import annotations

import argparse
import math

import numpy as np


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from radarsim.shifter import SHIFTER_ERROR_DISTRIBUTIONS
    parser.add_argument("--distribution", choices=sorted(SHIFTER_ERROR_DISTRIBUTIONS),
                        default="inl_dnl", help="random per-code table (default inl_dnl)")
    parser.add_argument("--error-deg-rms", type=float, default=6.0,
                        help="phase error per code, deg rms (default 6: about +/-10 deg)")
    parser.add_argument("--gain-error-db-rms", type=float, default=0.0,
                        help="gain error per code, dB rms (default 0)")
    parser.add_argument("--quadrature-skew-deg", type=float, default=None,
                        help="instead of a random table: vector-modulator quadrature skew, deg")
    parser.add_argument("--seed", type=int, default=0, help="table and noise seed")
    parser.add_argument("--step-deg", type=float, default=90.0, help="phase step per chirp")
    parser.add_argument("--tx", type=int, default=1, help="stepped transmitter (1..4)")
    parser.add_argument("--range-m", type=float, default=4.5, help="corner-reflector range")
    parser.add_argument("--n-chirps", type=int, default=1024)
    parser.add_argument("--plot", default=None, help="write the range-Doppler cut to this PNG")


def run(args: argparse.Namespace) -> int:
    import radarsim
    from harness.shifter_experiment import (check_phase_step, format_lines, phase_step_experiment,
                                            plot_phase_step)
    from radarsim import shifter as sh

    if not (math.isfinite(args.error_deg_rms) and args.error_deg_rms >= 0):
        raise ValueError(f"--error-deg-rms={args.error_deg_rms!r} must be >= 0")
    if args.seed < 0:
        raise ValueError(f"--seed={args.seed!r} must be >= 0")
    if args.quadrature_skew_deg is not None:
        e, _ = sh.vector_modulator_tables(64, args.quadrature_skew_deg)
        phase = np.tile(e, (4, 1))
    else:
        phase = {"distribution": args.distribution, "rms": args.error_deg_rms,
                 "seed": args.seed}
    gain = {"distribution": args.distribution, "rms": args.gain_error_db_rms,
            "seed": args.seed + 1}
    cfg = radarsim.presets.r79_ddma(phase_quantization="round", shifter_phase_error_deg=phase,
                                    shifter_gain_error_db=gain)
    check_phase_step(cfg, args.step_deg, args.tx, args.n_chirps)  # before the calibration
    cal = radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(args.seed),
                                      range_m=args.range_m, full_output=True)
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
