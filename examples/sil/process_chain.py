#!/usr/bin/env python3
"""An external receive chain for a sweep's ``[[external_chains]]``: it stands in for a team's
own program (an embedded DSP built for the host, a MATLAB script, a C program), taking the
profile and the capture the harness writes and writing a point file.

This one runs ``radar-harness process`` on the files it is given, so its points must be the
built-in chain's: the sweep beside it (``sweep.toml``) runs both and its gates
(``gates.toml``) check that the external chain reproduces the built-in one.

    process_chain.py --cfg PROFILE.cfg --adc CAPTURE.bin --out POINTS.parquet

Any program with this interface works: read the TI profile (the chip's CLI syntax) and the
DCA1000 capture (int16 words in the layout the profile implies), write the points with the
columns range_m, azimuth_deg, radial_velocity_mps, snr_db (optional elevation_deg; frame,
0-based within the call, when the call holds several frames), exit 0.
"""
import argparse
import subprocess
import sys

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--cfg", required=True, help="TI profile the harness wrote")
parser.add_argument("--adc", required=True, help="DCA1000 capture the harness wrote")
parser.add_argument("--out", required=True, help="point file to write (.csv or .parquet)")
args = parser.parse_args()
# The interpreter that runs this script is the harness's ({python} in the sweep file).
sys.exit(subprocess.call([sys.executable, "-m", "harness.cli", "process", args.adc,
                          "--cfg", args.cfg, "--out", args.out, "--no-track"]))
