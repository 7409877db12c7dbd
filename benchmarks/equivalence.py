"""Statistical equivalence of two versions of the receive chains: the evidence a speed change
that moves bits must bring.

A faster method (an FFT azimuth map for a matrix product, a cheaper order statistic, float32
tails, another summation order) changes the last bits of a frame's numbers, so the CI sweep's
tables are no longer identical. It is as good when the statistics of what the chain reports
are the same. Three measurements, each on the same draws for both versions (a paired design:
the same seeds give the same frames, so what differs is the method, not the noise):

* **ROC, per scheme** (every `radarsim.MIMO_SCHEMES` entry, R79 preset, isotropic elements):
  the false-alarm rate over the cells of the scheme's detection map on noise-only frames (at
  least `MIN_NOISE_CELLS`), and the detection probability of `TARGETS_PER_LEVEL` point targets
  at each detection SNR of `SNR_LEVELS_DB` (2 016 targets): a target is detected when a point
  lies within 1.5 range resolutions of it. Both with 95 % Clopper-Pearson intervals; two
  versions agree when the intervals overlap.
* **Accuracy at 15, 20, 25 dB**: the RMSE of range, radial velocity and azimuth of the
  detected targets (the strongest point near each; a velocity more than 0.5 m/s off is a
  resolution failure, counted and left out) and its ratio to the Cramer-Rao bound (design.md 8,
  as `python -m benchmarks crb`; azimuth's bound grows as 1 / cos(az)). Two versions agree
  when every RMSE is within `RMSE_TOLERANCE` (5 %) of the other's.
* **The CI sweep over three seeds** (`--sweep BASE NEW`, two results folders of
  ``radar-harness sweep harness/sweeps/ci.toml --seeds 0 1 2``): every numeric metric of the
  summary table, per (case, variant, scheme), has its mean over the seeds within the base
  version's seed-to-seed spread (max - min) of the base mean (a metric defined on one seed
  only has no spread: its difference is printed, not judged). Any sweep over the same >= 3
  seeds compares alike (an interference sweep for a change to the repair).

Usage::

    python -m benchmarks equivalence --out base.json           # on the old code
    python -m benchmarks equivalence --out new.json            # on the new code
    python -m benchmarks equivalence --compare base.json new.json
    python -m benchmarks equivalence --sweep results/base_s3 results/new_s3

``--compare`` and ``--sweep`` print one verdict line per check and exit 1 when any fails.

References
----------
.. [1] [Clopper1934] C. J. Clopper and E. S. Pearson, "The use of confidence or fiducial limits
       illustrated in the case of the binomial", Biometrika 26(4), 1934.
.. [2] [Kay1993] S. M. Kay, Fundamentals of Statistical Signal Processing: Estimation Theory,
       1993, section 3.11 (the bound of a sinusoid's frequency).
"""
from __future__ import annotations

import argparse
import json
import sys
import zlib
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.stats import beta

import pipeline
import radarsim

from .bench_crb import DOPPLER_BINS, RANGE_BINS, TARGETS_PER_FRAME
from .bench_schemes import crb, scene_at_detection_snr

#: Detection SNRs of the targets, dB: the ROC's knee (10-17 dB for every scheme's CFAR at its
#: design false-alarm rate) and the accuracy levels.
SNR_LEVELS_DB = (10.0, 12.0, 13.0, 14.0, 15.0, 16.0, 17.0, 20.0, 25.0)
#: Targets per SNR level (28 frames of 8): 2 016 in all.
TARGETS_PER_LEVEL = 224
#: SNR levels whose RMSE is compared.
ACCURACY_LEVELS_DB = (15.0, 20.0, 25.0)
#: Least noise-only cells of the detection map per scheme.
MIN_NOISE_CELLS = 1_000_000
#: Accepted relative RMSE difference between two versions.
RMSE_TOLERANCE = 0.05
#: Confidence of the Clopper-Pearson intervals.
CONFIDENCE = 0.95
SEED = 38
#: A point within this many range resolutions of a target detects it.
MATCH_RANGE_RES = 1.5
#: A velocity off by more than this is a resolution failure, not an accuracy sample, m/s.
VELOCITY_FAILURE_MPS = 0.5


def clopper_pearson(k: int, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """Exact two-sided binomial interval of k successes in n trials."""
    a = (1 - confidence) / 2
    lo = 0.0 if k == 0 else float(beta.ppf(a, k, n - k + 1))
    hi = 1.0 if k == n else float(beta.ppf(1 - a, k + 1, n - k))
    return lo, hi


@dataclass
class Level:
    """Detection and accuracy of the targets at one detection SNR."""

    snr_db: float
    n_targets: int
    n_detected: int
    n_velocity_failures: int
    rmse: list[float]        # range m, velocity m/s, azimuth deg
    rmse_over_crb: list[float]


@dataclass
class SchemeStats:
    """ROC and accuracy of one scheme."""

    n_noise_cells: int
    n_false_alarms: int
    levels: list[Level]


def _rng(scheme: str, part: str) -> np.random.Generator:
    """A generator per scheme and part, stable when schemes are added or removed."""
    return np.random.default_rng([SEED, zlib.crc32(scheme.encode()), zlib.crc32(part.encode())])


def false_alarms(cfg, scheme: str) -> tuple[int, int]:
    """(cells, points) of noise-only frames: every point is a false alarm."""
    rng = _rng(scheme, "noise")
    empty = radarsim.Scatterers.empty()
    adc = radarsim.simulate_frame(cfg, empty, rng)
    cells_per_frame = pipeline.detection_map(cfg, adc).power.size
    n_frames = -(-MIN_NOISE_CELLS // cells_per_frame)
    points = len(pipeline.process_frame(cfg, adc))
    for _ in range(n_frames - 1):
        points += len(pipeline.process_frame(cfg, radarsim.simulate_frame(cfg, empty, rng)))
    return n_frames * cells_per_frame, points


def draw_targets(cfg, rng: np.random.Generator, snr_db: float) -> np.ndarray:
    """(8, 5) targets of a frame: range_m, az_deg, el_deg, v_mps, snr_db, 20 range bins and 12
    Doppler bins apart (as `python -m benchmarks crb`), sub-bin offsets, azimuth +/-20 deg."""
    n = TARGETS_PER_FRAME
    r = (RANGE_BINS + rng.uniform(-0.5, 0.5, n)) * cfg.range_resolution_m
    v = (rng.permutation(DOPPLER_BINS) + rng.uniform(-0.5, 0.5, n)) * cfg.velocity_resolution_mps
    return np.column_stack([r, rng.uniform(-20, 20, n), np.zeros(n), v, np.full(n, snr_db)])


def match(cfg, targets: np.ndarray, cloud: pd.DataFrame) -> tuple[int, int, np.ndarray]:
    """(detected, velocity failures, (m, 4) range, velocity, azimuth errors and the target's
    azimuth, deg) of a frame's targets against its point cloud (the strongest point within
    `MATCH_RANGE_RES`)."""
    rng_m, v, az, snr = (cloud[c].to_numpy() for c in ("range_m", "radial_velocity_mps",
                                                        "azimuth_deg", "snr_db"))
    detected = failures = 0
    errs = []
    for r0, az0, _, v0, _ in targets:  # 8 targets per frame
        near = np.flatnonzero(np.abs(rng_m - r0) < MATCH_RANGE_RES * cfg.range_resolution_m)
        if near.size == 0:
            continue
        detected += 1
        b = near[np.argmax(snr[near])]
        if abs(v[b] - v0) > VELOCITY_FAILURE_MPS:
            failures += 1
            continue
        errs.append((rng_m[b] - r0, v[b] - v0, az[b] - az0, az0))
    return detected, failures, np.array(errs).reshape(-1, 4)


def level(cfg, scheme: str, snr_db: float) -> Level:
    """Detection and accuracy of `TARGETS_PER_LEVEL` targets at `snr_db`."""
    rng = _rng(scheme, f"targets {snr_db:g}")
    detected = failures = 0
    errs = []
    for _ in range(TARGETS_PER_LEVEL // TARGETS_PER_FRAME):
        t = draw_targets(cfg, rng, snr_db)
        adc = radarsim.simulate_frame(cfg, scene_at_detection_snr(cfg, t), rng)
        d, f, e = match(cfg, t, pipeline.process_frame(cfg, adc))
        detected, failures = detected + d, failures + f
        errs.append(e)
    e = np.concatenate(errs)
    bound_r, bound_v, bound_az0 = crb(cfg, snr_db)
    # Normalised errors: the azimuth bound at each target's angle is the boresight one over
    # cos(az) (the row's sin(az) bound mapped to degrees).
    z = e[:, :3] / np.column_stack([np.full(len(e), bound_r), np.full(len(e), bound_v),
                                    bound_az0 / np.cos(np.radians(e[:, 3]))])
    rmse = np.sqrt(np.mean(e[:, :3] ** 2, axis=0)) if len(e) else np.full(3, np.nan)
    ratio = np.sqrt(np.mean(z ** 2, axis=0)) if len(e) else np.full(3, np.nan)
    return Level(snr_db, TARGETS_PER_LEVEL, detected, failures, rmse.tolist(), ratio.tolist())


def measure(schemes: list[str]) -> dict[str, SchemeStats]:
    """ROC and accuracy of every scheme in `schemes`."""
    out = {}
    for name in schemes:
        cfg = radarsim.presets.r79(name, array={"antenna_pattern": "isotropic"})
        cells, fa = false_alarms(cfg, name)
        out[name] = SchemeStats(cells, fa, [level(cfg, name, s) for s in SNR_LEVELS_DB])
        print(f"{name}: {fa} false alarms in {cells} cells; Pd "
              + " ".join(f"{lv.snr_db:g}dB {lv.n_detected / lv.n_targets:.3f}"
                         for lv in out[name].levels), flush=True)
    return out


def _overlap(a: tuple[float, float], b: tuple[float, float]) -> bool:
    return a[0] <= b[1] and b[0] <= a[1]


def compare(base: dict, new: dict) -> list[tuple[bool, str]]:
    """Verdicts (ok, line) of every check between two `measure` results (as loaded JSON)."""
    out = []
    for name in sorted(set(base) & set(new)):
        b, n = base[name], new[name]
        ci_b = clopper_pearson(b["n_false_alarms"], b["n_noise_cells"])
        ci_n = clopper_pearson(n["n_false_alarms"], n["n_noise_cells"])
        out.append((_overlap(ci_b, ci_n),
                    f"{name} Pfa: {b['n_false_alarms']}/{b['n_noise_cells']} "
                    f"[{ci_b[0]:.2e}, {ci_b[1]:.2e}] vs {n['n_false_alarms']}/"
                    f"{n['n_noise_cells']} [{ci_n[0]:.2e}, {ci_n[1]:.2e}]"))
        for lb, ln in zip(b["levels"], n["levels"]):
            s = lb["snr_db"]
            for what, key in (("Pd", "n_detected"), ("velocity failures", "n_velocity_failures")):
                kb, kn = lb[key], ln[key]
                nb, nn = (lb["n_targets"], ln["n_targets"]) if key == "n_detected" else \
                    (lb["n_detected"], ln["n_detected"])
                cb, cn = clopper_pearson(kb, nb), clopper_pearson(kn, nn)
                out.append((_overlap(cb, cn), f"{name} {what} at {s:g} dB: {kb}/{nb} "
                            f"[{cb[0]:.3f}, {cb[1]:.3f}] vs {kn}/{nn} [{cn[0]:.3f}, {cn[1]:.3f}]"))
            if s in ACCURACY_LEVELS_DB:
                for i, q in enumerate(("range", "velocity", "azimuth")):
                    rb, rn = lb["rmse"][i], ln["rmse"][i]
                    rel = rn / rb - 1
                    qb, qn = lb["rmse_over_crb"][i], ln["rmse_over_crb"][i]
                    out.append((bool(abs(rel) <= RMSE_TOLERANCE),
                                f"{name} {q} RMSE at {s:g} dB: {rb:.4g} ({qb:.3f} x CRB) vs "
                                f"{rn:.4g} ({qn:.3f} x CRB), {100 * rel:+.2f} %"))
    return out


#: Summary columns that describe a cell rather than measure it.
_KEYS = ("scenario", "variant", "scheme")
_NOT_METRICS = ("seed", "n_frames", "duration_s", "track_n_frames", "n_actors", "s_critical_m",
                "r79_required_range_m", "case_criteria_n")


def compare_sweeps(base_dir: Path, new_dir: Path) -> list[tuple[bool, str]]:
    """Per (case, variant, scheme) and numeric summary metric: the new mean over seeds within
    the base's seed-to-seed spread (max - min) of the base mean; a metric constant over the
    base's seeds must be equal (to 1e-9 relative)."""
    b = pd.read_parquet(base_dir / "summary.parquet")
    n = pd.read_parquet(new_dir / "summary.parquet")
    if sorted(b["seed"].unique()) != sorted(n["seed"].unique()) or b["seed"].nunique() < 3:
        raise SystemExit(f"the two sweeps need the same >= 3 seeds, got "
                         f"{sorted(b['seed'].unique())} and {sorted(n['seed'].unique())}")
    metrics = [c for c in b.columns if c not in _KEYS and c not in _NOT_METRICS
               and pd.api.types.is_numeric_dtype(b[c]) and not pd.api.types.is_bool_dtype(b[c])]
    gb, gn = b.groupby(list(_KEYS))[metrics], n.groupby(list(_KEYS))[metrics]
    mean_b, mean_n = gb.mean(), gn.mean()
    spread = gb.max() - gb.min()
    diff = (mean_n - mean_b).abs()
    both_nan = mean_b.isna() & mean_n.isna()
    # A metric defined on one seed only (a track's RMSE where one seed has the track) has no
    # seed-to-seed spread: its difference is reported, not judged against a spread of 0.
    single = (gb.count() < 2) & (gn.count() == gb.count()) & ~both_nan
    tol = np.maximum(spread, 1e-9 * mean_b.abs())
    ok = both_nan | single | (diff <= tol)
    out = []
    for key, row in ok.iterrows():
        for m in metrics:
            if not row[m]:
                out.append((False, f"{'/'.join(map(str, key))} {m}: base mean "
                            f"{mean_b.loc[key, m]:.4g} (spread {spread.loc[key, m]:.3g}) vs "
                            f"new {mean_n.loc[key, m]:.4g}"))
    for key, row in single.iterrows():
        for m in metrics:
            if row[m] and diff.loc[key, m] > 0:
                out.append((True, f"{'/'.join(map(str, key))} {m}: one seed only, no spread: "
                            f"base {mean_b.loc[key, m]:.7g} vs new {mean_n.loc[key, m]:.7g} "
                            f"({diff.loc[key, m] / abs(mean_b.loc[key, m]):.1e} relative)"))
    moved = int(((diff > 0) & ~both_nan).to_numpy().sum())
    outside = ok.size - int(ok.to_numpy().sum())
    seeds = sorted(int(s) for s in b["seed"].unique())
    out.append((outside == 0, f"sweep, {len(ok)} cells x {len(metrics)} metrics over seeds "
                f"{seeds}: {moved} moved, {outside} outside the base's seed-to-seed spread, "
                f"{int(single.to_numpy().sum())} defined on one seed only (reported above)"))
    return out


def _report(verdicts: list[tuple[bool, str]]) -> int:
    for ok, line in verdicts:
        print(f"{'ok  ' if ok else 'FAIL'} {line}")
    bad = sum(not ok for ok, _ in verdicts)
    print(f"{len(verdicts) - bad}/{len(verdicts)} checks agree")
    return 1 if bad else 0


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks equivalence", description=__doc__
                                .split("\n\n")[0])
    p.add_argument("--out", type=Path, help="measure this code's chains, write JSON here")
    p.add_argument("--schemes", nargs="+", help="schemes to measure (default: every one)")
    p.add_argument("--compare", nargs=2, type=Path, metavar=("BASE", "NEW"))
    p.add_argument("--sweep", nargs=2, type=Path, metavar=("BASE_DIR", "NEW_DIR"))
    a = p.parse_args(argv)
    if a.out:
        stats = measure(a.schemes or sorted(radarsim.MIMO_SCHEMES))
        a.out.write_text(json.dumps({k: asdict(v) for k, v in stats.items()}, indent=1))
    status = 0
    if a.compare:
        base, new = (json.loads(f.read_text()) for f in a.compare)
        status |= _report(compare(base, new))
    if a.sweep:
        status |= _report(compare_sweeps(*a.sweep))
    if not (a.out or a.compare or a.sweep):
        p.error("give --out, --compare or --sweep")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
