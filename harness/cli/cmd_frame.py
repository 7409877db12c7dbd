"""`radar-harness frame`: simulate one R79 frame of a fixed two-car scene and summarise it."""
from __future__ import annotations

import argparse

import numpy as np

from core.errors import BadInput
from harness.cli.args import SEED, add_plugin_option


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--mimo", default="ddma",
                        help="MIMO scheme (radarsim.MIMO_SCHEMES, a plugin's included)")
    parser.add_argument("--seed", type=SEED, default=0)
    add_plugin_option(parser)


def run(args: argparse.Namespace) -> int:
    import radarsim

    if args.mimo not in radarsim.MIMO_SCHEMES:  # checked after the plugins have loaded
        raise BadInput(f"--mimo: invalid choice: {args.mimo!r} (choose from "
                       f"{sorted(radarsim.MIMO_SCHEMES)})")
    cfg = radarsim.presets.r79(args.mimo)
    sc = radarsim.Scatterers(position_m=[[50.0, 5.0, 0.0], [120.0, -20.0, 0.3]],
                             velocity_mps=[[-20.0, 0.0, 0.0], [8.0, 0.0, 0.0]],
                             rcs_m2=[10.0, 10.0], actor_id=np.array([0, 1]))
    adc = radarsim.simulate_frame(cfg, sc, rng=np.random.default_rng(args.seed))
    print(f"{args.mimo.upper()} frame: adc {adc.shape} {adc.dtype}, rms {adc.std():.1f} LSB, "
          f"peak {np.abs(adc).max()} LSB, noise {cfg.noise_rms_lsb:.1f} LSB rms")
    print(f"range res {cfg.range_resolution_m:.3f} m, max range {cfg.max_range_m:.1f} m, "
          f"v res {cfg.velocity_resolution_mps:.4f} m/s, "
          f"Vmax +/-{cfg.max_unambiguous_velocity_mps:.2f} m/s")
    for r, snr in zip(sc.range_m, radarsim.expected_sample_snr_db(cfg, sc)):
        print(f"  scatterer at {r:6.1f} m: per-sample SNR {snr:6.1f} dB")
    return 0
