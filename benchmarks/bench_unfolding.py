"""Velocity unfolding of every registered MIMO scheme on the same randomized point targets.

No open source publishes how often velocity unfolding fails versus SNR, speed or crowding, for
any method. Here every `radarsim.MIMO_SCHEMES` entry (and every chain variant, e.g.
``tdma_raw``) sees the same targets on the R79 frame: clusters of 1, 2 or 3 point targets
sharing one range cell (azimuths 25 deg apart, beyond the 9.6 deg array resolution), uniform
speeds over the R79 span +/-40.9 m/s, ranges 20-160 m, and a reference detection SNR uniform in
8-26 dB. The reference SNR is the TDMA baseline's coherent detection SNR (range FFT of 384 real
samples, 192-chirp Doppler FFT, 12-element azimuth FFT, two Hann losses; design.md 8): the echo
strength, the same for every scheme, whatever each scheme then makes of it.

Per target, the scheme's strongest detection within one range cell and 6 deg of the target is
its measurement (none: missed). The table gives P(correct velocity) = P(|v_meas - v| <= 2
velocity bins | detected) by reference SNR, by |v| / 10.22 m/s (the TDMA baseline's native
Vmax, lambda / (16 Tc)) and by targets per range cell; Pd by reference SNR (a detection in
the range cell but off in azimuth is a miss: TDMA without disambiguation, ``tdma_raw``,
compensates its slot phases at the aliased velocity and so mislocates fast targets); the median
detection-SNR difference to TDMA on the targets both detect; and the latency, in frames, before
the scheme reports an unfolded velocity (`MimoScheme.latency_frames`). First line: the
fast/slow chain's `process_frame` as a ratio to the FFT floor of its frame, measured in the
same run.

A second table holds the slot-coded schemes (TDMA, BPM) at fixed azimuths near boresight,
where BPM's code decides whether velocity beyond +/-Vmax can be resolved at all
(`radarsim.mimo.BpmScheme`): 20 single targets per azimuth, one per range cell, |v| up to
40 m/s, reference SNR 25 dB; wrong velocities and misses of 20, and whether the scheme
declares the direction blind (`MimoScheme.velocity_blind`: BPM's documented limit at 30 deg).

    python -m benchmarks unfolding
"""
from __future__ import annotations

import numpy as np
import pandas as pd

import pipeline
import radarsim

from .bench_schemes import timing

#: Frames simulated per scheme (6 clusters each: 480 targets).
N_FRAMES = 40
CLUSTERS_PER_FRAME = 6
SNR_RANGE_DB = (8.0, 26.0)
SPAN_MPS = 40.9
TDMA_VMAX_MPS = 10.22
AZ_SPACING_DEG = 25.0
AZ_GATE_DEG = 6.0
HANN_LOSS_DB = 1.76
SEED = 23
#: Near-boresight table: azimuths (deg), targets per azimuth, reference SNR (dB), schemes.
BORESIGHT_AZ_DEG = (0.0, 0.5, 1.0, 2.0, 30.0)
BORESIGHT_TARGETS = 20
BORESIGHT_SNR_DB = 25.0
BORESIGHT_SCHEMES = ("tdma", "bpm")


def _reference_gain_db(tdma: radarsim.RadarConfig) -> float:
    """TDMA's coherent detection gain: 384-sample real range FFT, 192-chirp Doppler FFT,
    12-element azimuth FFT, minus two Hann losses, dB."""
    return (10 * np.log10(tdma.n_samples / 2) + 10 * np.log10(tdma.n_chirps // tdma.n_tx)
            + 10 * np.log10(12) - 2 * HANN_LOSS_DB)


def draw_targets(rng: np.random.Generator, n_frames: int) -> pd.DataFrame:
    """Targets of every frame: frame, cluster, n_in_cell, range_m, az_deg, v_mps, snr_db.

    Cluster c of a frame holds 1 + (c mod 3) targets at one range (20 + 23 c m plus up to
    8 m), azimuths 25 deg apart at a random offset, speeds and SNRs independent."""
    rows = []
    for f in range(n_frames):
        for c in range(CLUSTERS_PER_FRAME):
            n = 1 + c % 3
            r = 20.0 + 23.0 * c + rng.uniform(0, 8)
            az0 = rng.uniform(-50, 50 - AZ_SPACING_DEG * (n - 1))
            for i in range(n):
                rows.append((f, c, n, r, az0 + AZ_SPACING_DEG * i,
                             rng.uniform(-SPAN_MPS, SPAN_MPS), rng.uniform(*SNR_RANGE_DB)))
    return pd.DataFrame(rows, columns=["frame", "cluster", "n_in_cell", "range_m", "az_deg",
                                       "v_mps", "snr_db"])


def _scene(tdma: radarsim.RadarConfig, t: pd.DataFrame) -> radarsim.Scatterers:
    """Scatterers of one frame's targets at their reference SNR (elevation 0)."""
    geo = (t.range_m.to_numpy(), t.az_deg.to_numpy(), np.zeros(len(t)), t.v_mps.to_numpy())
    s1 = radarsim.expected_sample_snr_db(tdma, radarsim.Scatterers.from_spherical(
        *geo, np.ones(len(t))))
    rcs = 10 ** ((t.snr_db.to_numpy() - s1 - _reference_gain_db(tdma)) / 10)
    return radarsim.Scatterers.from_spherical(*geo, rcs)


def measure(cfg: radarsim.RadarConfig, pc: pd.DataFrame, t: pd.DataFrame) -> pd.DataFrame:
    """Per target: detected, measured velocity and SNR of its strongest gated detection."""
    out = []
    for r, az in zip(t.range_m, t.az_deg):
        near = pc[((pc.range_m - r).abs() <= cfg.range_resolution_m)
                  & ((pc.azimuth_deg - az).abs() <= AZ_GATE_DEG)]
        if near.empty:
            out.append((False, np.nan, np.nan))
        else:
            b = near.loc[near.snr_db.idxmax()]
            out.append((True, b.radial_velocity_mps, b.snr_db))
    return pd.DataFrame(out, columns=["detected", "v_meas_mps", "snr_meas_db"], index=t.index)


def run_schemes(n_frames: int = N_FRAMES, seed: int = SEED) -> pd.DataFrame:
    """Every registered scheme and chain variant on the same targets: one row per (result
    scheme, target), with the target's truth and the scheme's measurement."""
    targets = draw_targets(np.random.default_rng(seed), n_frames)
    tdma = radarsim.presets.r79("tdma", array={"antenna_pattern": "isotropic"})
    scenes = [_scene(tdma, t) for _, t in targets.groupby("frame")]
    results = []
    for s_id, name in enumerate(sorted(radarsim.MIMO_SCHEMES)):
        cfg = radarsim.presets.r79(name, array={"antenna_pattern": "isotropic"})
        chain = pipeline.MIMO_CHAINS[name]
        procs = {name: pipeline.ProcessingConfig(),
                 **{v: pipeline.ProcessingConfig().replace(**kw)
                    for v, kw in chain.variants.items()}}
        for f, (_, t) in enumerate(targets.groupby("frame")):
            adc = radarsim.simulate_frame(cfg, scenes[f],
                                          np.random.default_rng([seed, f, s_id]))
            for result, proc in procs.items():
                m = measure(cfg, pipeline.process_frame(cfg, adc, proc), t)
                tol = 2 * cfg.velocity_resolution_mps
                m["correct"] = m.detected & ((m.v_meas_mps - t.v_mps).abs() <= tol)
                results.append(pd.concat([t, m], axis=1).assign(
                    scheme=result, latency_frames=cfg.scheme.latency_frames,
                    vmax_mps=cfg.max_unambiguous_velocity_mps))
    return pd.concat(results, ignore_index=True)


def near_boresight(seed: int = SEED) -> pd.DataFrame:
    """Wrong velocities and misses of `BORESIGHT_TARGETS` single targets per azimuth of
    `BORESIGHT_AZ_DEG`, per scheme of `BORESIGHT_SCHEMES` (the same targets for each), with
    the scheme's `velocity_blind` flag for the direction."""
    tdma = radarsim.presets.r79("tdma", array={"antenna_pattern": "isotropic"})
    n = BORESIGHT_TARGETS
    rows = []
    for a_id, az in enumerate(BORESIGHT_AZ_DEG):
        rng = np.random.default_rng([seed, a_id])
        t = pd.DataFrame({"range_m": 20.0 + 7.0 * np.arange(n) + rng.uniform(0, 2, n),
                          "az_deg": np.full(n, az), "v_mps": rng.uniform(-40.0, 40.0, n),
                          "snr_db": np.full(n, BORESIGHT_SNR_DB)})
        scene = _scene(tdma, t)
        for s_id, name in enumerate(BORESIGHT_SCHEMES):
            cfg = radarsim.presets.r79(name, array={"antenna_pattern": "isotropic"})
            adc = radarsim.simulate_frame(cfg, scene, np.random.default_rng([seed, a_id, s_id]))
            m = measure(cfg, pipeline.process_frame(cfg, adc), t)
            wrong = m.detected & ((m.v_meas_mps - t.v_mps).abs() > 2 * cfg.velocity_resolution_mps)
            rows.append({"scheme": name, "azimuth (deg)": az, "wrong": int(wrong.sum()),
                         "missed": int((~m.detected).sum()),
                         "blind": bool(cfg.scheme.velocity_blind(cfg, az))})
    return pd.DataFrame(rows)


def boresight_markdown(table: pd.DataFrame) -> list[str]:
    """The near-boresight table as markdown: one row per scheme, "wrong/missed" per azimuth,
    a blind direction marked "(blind)"."""
    azs = list(dict.fromkeys(table["azimuth (deg)"]))
    lines = ["| scheme | " + " | ".join(f"{a:g} deg" for a in azs) + " |",
             "|" + "---|" * (len(azs) + 1)]
    for name, g in table.groupby("scheme", sort=False):
        cells = [f"{r.wrong}/{r.missed}" + (" (blind)" if r.blind else "")
                 for r in g.itertuples()]
        lines.append(f"| `{name}` | " + " | ".join(cells) + " |")
    return lines


def summary_table(res: pd.DataFrame) -> pd.DataFrame:
    """One row per result scheme: P(correct velocity | detected) by reference SNR, speed and
    crowding; Pd by reference SNR; detection-SNR difference to TDMA; latency."""
    res = res.assign(speed=(res.v_mps.abs() / TDMA_VMAX_MPS).astype(int).clip(upper=3),
                     snr_band=pd.cut(res.snr_db, [8, 14, 20, 26], right=False))
    det = res[res.detected]
    tdma_snr = res[res.scheme == "tdma"].set_index(["frame", "cluster", "az_deg"]).snr_meas_db
    rows = []
    for name, g in det.groupby("scheme", sort=False):
        row = {"scheme": name, "Vmax (m/s)": g.vmax_mps.iloc[0]}
        for band, gb in g.groupby("snr_band", observed=False):
            row[f"SNR {band.left:g}-{band.right:g}"] = gb.correct.mean()
        for k, gk in g.groupby("speed"):
            row[f"|v|/V_T {k}-{k + 1}" if k < 3 else "|v|/V_T 3-4"] = gk.correct.mean()
        for n, gn in g.groupby("n_in_cell"):
            row[f"{n} per cell"] = gn.correct.mean()
        all_t = res[res.scheme == name]
        for band, gb in all_t.groupby("snr_band", observed=False):
            row[f"Pd {band.left:g}-{band.right:g}"] = gb.detected.mean()
        both = g.set_index(["frame", "cluster", "az_deg"]).snr_meas_db - tdma_snr
        row["SNR - TDMA (dB)"] = float(np.nanmedian(both)) if name != "tdma" else 0.0
        row["latency (frames)"] = int(g.latency_frames.iloc[0])
        rows.append(row)
    return pd.DataFrame(rows)


def markdown(table: pd.DataFrame) -> list[str]:
    """The table as markdown lines (probabilities to 2 decimals)."""
    cols = list(table.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, r in table.iterrows():
        cells = []
        for c in cols:
            v = r[c]
            if isinstance(v, str):
                cells.append(f"`{v}`")
            elif c in ("Vmax (m/s)", "SNR - TDMA (dB)"):
                cells.append(f"{v:+.1f}" if c.startswith("SNR") else f"{v:.1f}")
            elif c == "latency (frames)":
                cells.append(f"{v:d}")
            else:
                cells.append("-" if pd.isna(v) else f"{v:.2f}")
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def speed_line(name: str = "fast_slow") -> str:
    """process_frame of `name` against its FFT floor (range rFFT + Doppler FFTs of its frame),
    best of alternating rounds in one run (`bench_schemes.timing`)."""
    t = timing(name)
    return (f"{name} process_frame cpu {1e3 * t.chain.cpu_s:.1f} ms, one-core FFT floor "
            f"{1e3 * t.floor_cpu_s:.1f} ms: {t.cpu_ratio:.2f}x CPU (target <= 2.5x), "
            f"{t.wall_ratio:.2f}x wall")


def run():
    yield speed_line()
    res = run_schemes()
    n_t = res.groupby("scheme").size().iloc[0]
    yield (f"{n_t} targets per scheme ({N_FRAMES} frames x {CLUSTERS_PER_FRAME} range cells of "
           f"1-3 targets), reference SNR {SNR_RANGE_DB[0]:g}-{SNR_RANGE_DB[1]:g} dB, speeds "
           f"+/-{SPAN_MPS} m/s; P(correct velocity | detected) and Pd (machine shared: "
           "figures, not times)")
    yield from markdown(summary_table(res))
    yield (f"Near boresight: wrong velocities / misses of {BORESIGHT_TARGETS} single targets "
           f"per azimuth, reference SNR {BORESIGHT_SNR_DB:g} dB, |v| up to 40 m/s")
    yield from boresight_markdown(near_boresight())
