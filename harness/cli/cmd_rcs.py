"""`radar-harness rcs CLASS [--plot]`: a class's RCS aspect pattern against the published values.

The model's pattern is `radarsim.rcs.single_actor` (one actor alone on boresight, exactly as the
scene model makes it) summed over its scatterers (the incoherent sum: the expected value of the
coherent sum over random phases), averaged over `--draws` frames with the aspect jittered by
+/-1 deg; the references are `radarsim.scene.rcs_patterns.REFERENCES` with their citations. `--plot`
writes a PNG of the pattern (model mean, its 10-90 % fluctuation band, references).
"""
from __future__ import annotations

import argparse
from typing import NamedTuple

import numpy as np

from core.errors import BadInput
from core.fileio import atomic_write
from harness.cli.args import SEED, check_output_file, float_in, int_in

#: Aspects of the printed table, deg (0 front, 90 left side, 180 rear).
TABLE_ASPECTS_DEG = (0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0)


class AspectPattern(NamedTuple):
    """Model RCS statistics per aspect (N aspects)."""

    aspect_deg: np.ndarray     # (N,) deg
    mean_dbsm: np.ndarray      # (N,) 10 lg of the mean linear RCS
    p10_dbsm: np.ndarray       # (N,) 10th percentile of the per-frame RCS
    p90_dbsm: np.ndarray       # (N,) 90th percentile
    spread_db: np.ndarray      # (N,) std of the per-frame RCS in dB


def model_pattern(actor_class: str, aspects_deg, *, range_m: float, draws: int,
                  seed: int) -> AspectPattern:
    """Per-aspect statistics of `single_actor`'s total RCS over `draws` frames."""
    from radarsim.rcs import single_actor
    rng = np.random.default_rng(seed)
    aspects = np.asarray(aspects_deg, dtype=float)
    tot = np.array([[single_actor(actor_class, a + rng.uniform(-1.0, 1.0), range_m=range_m,
                                  rng=rng).rcs_m2.sum() for _ in range(draws)]
                    for a in aspects])
    db = 10 * np.log10(np.maximum(tot, 1e-12))
    return AspectPattern(aspects, 10 * np.log10(np.maximum(tot.mean(axis=1), 1e-12)),
                         np.percentile(db, 10, axis=1), np.percentile(db, 90, axis=1),
                         db.std(axis=1, ddof=1) if draws > 1 else np.zeros(aspects.size))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("actor_class", metavar="CLASS",
                        help="actor class (car, truck, motorcycle, bicycle, pedestrian, "
                             "guard_rail)")
    parser.add_argument("--range-m", type=float_in(0.0, 250.0, " m"), default=30.0,
                        help="distance of the actor's centre, m (default 30)")
    parser.add_argument("--draws", type=int_in(1, 1000), default=32,
                        help="frames per aspect (default 32)")
    parser.add_argument("--seed", type=SEED, default=0)
    parser.add_argument("--plot", action="store_true", help="write a PNG of the pattern")
    parser.add_argument("--out", default=None,
                        help="PNG path for --plot (default rcs_<CLASS>.png)")


def _fmt(v) -> str:
    return "   -  " if v is None or not np.isfinite(v) else f"{v:6.1f}"


def run(args: argparse.Namespace) -> int:
    from radarsim.rcs import CLASS_RCS
    from radarsim.scene.rcs_patterns import REFERENCES
    if args.actor_class not in CLASS_RCS:
        raise BadInput(f"CLASS={args.actor_class!r} unknown; known: {sorted(CLASS_RCS)}")
    out = None
    if args.plot:
        out = check_output_file(args.out or f"rcs_{args.actor_class}.png", "--out")
    refs = REFERENCES.get(args.actor_class, ())
    pat = model_pattern(args.actor_class, TABLE_ASPECTS_DEG, range_m=args.range_m,
                        draws=args.draws, seed=args.seed)
    print(f"{args.actor_class}: RCS at {args.range_m:g} m, {args.draws} frames per aspect "
          f"(+/-1 deg jitter), dBsm")
    head = "aspect  model  p10    p90   spread" + "".join(f"  ref{i + 1}" for i in range(len(refs)))
    print(head)
    for i, a in enumerate(pat.aspect_deg):
        # References list 0..180 deg; the right side mirrors the left.
        key = float(a) if a <= 180 else float(360 - a)
        ref = "".join(f" {_fmt(r.values_dbsm.get(key))}" for r in refs)
        print(f"{a:6.0f} {_fmt(pat.mean_dbsm[i])} {_fmt(pat.p10_dbsm[i])} "
              f"{_fmt(pat.p90_dbsm[i])} {_fmt(pat.spread_db[i])}{ref}")
    cls = CLASS_RCS[args.actor_class]
    print(f"model fluctuation: log-normal, {cls.fluctuation_db:g} dB per actor and frame")
    for i, r in enumerate(refs):
        spread = f", spread {r.spread_db:g} dB" if r.spread_db is not None else ""
        mean = r.values_dbsm.get("mean")
        print(f"ref{i + 1}: {r.source}{spread}"
              + (f", mean {mean:g} dBsm" if mean is not None else "") + f" ({r.note})")
    if not refs:
        print("no published pattern could be sourced for this class (docs/rcs.md)")
    if out is not None:
        _plot(args, refs, out)
        print(f"wrote {out}")
    return 0


def _plot(args, refs, out) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from radarsim.rcs import CLASS_RCS

    aspects = np.arange(0.0, 360.0, 5.0)
    pat = model_pattern(args.actor_class, aspects, range_m=args.range_m,
                        draws=max(4, args.draws // 4), seed=args.seed)
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.fill_between(aspects, pat.p10_dbsm, pat.p90_dbsm, alpha=0.25, label="model 10-90 %")
    ax.plot(aspects, pat.mean_dbsm, "C0", label="model mean")
    pattern = CLASS_RCS[args.actor_class].pattern
    if pattern is not None:
        fine = np.arange(0.0, 360.5, 0.5)
        ax.plot(fine, pattern.rcs_dbsm(fine), "k--", lw=1, label=pattern.source)
    for i, r in enumerate(refs):
        pts = [(a, v) for a, v in r.values_dbsm.items() if a != "mean"]
        if pts:
            ax.plot(*zip(*pts), "o", ms=5, label=f"ref{i + 1}")
        if "mean" in r.values_dbsm:
            ax.axhline(r.values_dbsm["mean"], color=f"C{i + 2}", lw=0.8,
                       label=f"ref{i + 1} mean")
    ax.set_xlabel("aspect, deg (0 front, 90 left side, 180 rear)")
    ax.set_ylabel("RCS, dBsm")
    ax.set_xlim(0, 360)
    ax.set_title(f"{args.actor_class} at {args.range_m:g} m")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    try:
        atomic_write(out, lambda tmp: fig.savefig(tmp, dpi=110))
    finally:
        plt.close(fig)
