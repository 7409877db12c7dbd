"""Shifter-error sweep: per scheme, ghost rate, velocity-resolution failures, azimuth RMSE and
angle sidelobe level at a strong target, against the per-code shifter error and calibration.

`shifter_table(results)` reads a results directory of a sweep whose variants set
`shifter_phase_error_deg` (a `ShifterErrorSpec` mapping with ``rms``) and optionally
`shifter_calibration_deg` (e.g. ``harness/shifter_sweep.toml``) and returns one row per
(variant, scheme). `html_section(results)` renders it for the report.

- ghost rate: ghosts / detections over the variant's cells (summary counts);
- velocity-resolution failures per frame: VELOCITY_AMBIGUOUS detections plus GHOST detections
  inside an actor's footprint (grown by `FOOTPRINT_GATE_M`) whose radial velocity is off the
  actor's by a non-zero multiple of the scheme's failure step (one DDMA sub-band, or the
  unambiguous span of a TDMA/BPM slot sequence, `MimoScheme.velocity_failure_step_mps`)
  within `VELOCITY_GATE_MPS` (fallback for results written before the runner counted them);
  the summary column ``n_velocity_resolution_failures`` (`metrics.detection`) when present;
- azimuth RMSE of TRUE detections against their nearest scatterer (``azimuth_error_deg``);
- angle sidelobe level: a strong point target (`PROBE`) simulated with the variant's radar and
  processed by the scheme's chain; the highest azimuth sidelobe outside the main lobe of its
  Doppler-azimuth cut (`pipeline.doppler_azimuth_map`) relative to the peak, median over
  `PROBE_SEEDS` noise seeds. An ideal unwindowed 12-element array gives -13.3 dB (DESIGN 8).
"""
from __future__ import annotations

import html
from pathlib import Path

import numpy as np
import pandas as pd

from .cellstore import failed_rows
from .figures import png_img, pyplot
from .provenance import read_manifest

__all__ = ["shifter_table", "html_section", "angle_sidelobe_db", "PROBE",
           "FOOTPRINT_GATE_M", "VELOCITY_GATE_MPS"]

#: Strong probe target: range m, azimuth deg, elevation deg, radial velocity m/s, RCS m^2.
PROBE = (30.0, 15.0, 0.0, -7.0, 10.0)
PROBE_SEEDS = (0, 1, 2)
FOOTPRINT_GATE_M = 1.5
VELOCITY_GATE_MPS = 1.0


def _psl_db(row_db: np.ndarray) -> float:
    """Peak sidelobe of a cyclic azimuth cut: highest value outside the main lobe (walk down
    from the peak to the first local minimum on each side) minus the peak, dB."""
    n = row_db.size
    a = int(np.argmax(row_db))
    lobe = {a}
    for step in (1, -1):
        i = a
        while True:
            j = (i + step) % n
            if row_db[j] > row_db[i] or j == a:
                break
            lobe.add(j)
            i = j
    outside = np.array([k for k in range(n) if k not in lobe])
    return float(row_db[outside].max() - row_db[a]) if outside.size else float("nan")


def angle_sidelobe_db(radar_overrides: dict, scheme: str) -> float:
    """Angle sidelobe level of the `PROBE` target for one radar variant and result scheme, dB.

    Parameters
    ----------
    radar_overrides : dict
        `RadarConfig` overrides of the variant (as in the sweep file).
    scheme : str
        Result scheme (`harness.cellspec.known_schemes`).
    """
    import pipeline
    import radarsim
    from harness.cellspec import result_schemes
    rs = result_schemes([scheme])[0]
    cfg = radarsim.presets.r79(rs.mimo, **radar_overrides)
    proc = pipeline.ProcessingConfig()
    sc = radarsim.Scatterers.from_spherical(*np.array(PROBE, dtype=float)[:, None])
    out = []
    for seed in PROBE_SEEDS:
        adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(seed))
        rbin = int(round(PROBE[0] / cfg.range_resolution_m))
        rbin = max(0, min(cfg.n_range_bins - 1, rbin))
        # The probe's range bin is the strongest of its neighbourhood.
        _, _, p = pipeline.doppler_azimuth_map(cfg, adc, rbin, proc)
        best, best_bin = p.max(), rbin
        for r in (rbin - 1, rbin + 1):
            _, _, q = pipeline.doppler_azimuth_map(cfg, adc, r, proc)
            if q.max() > best:
                best, best_bin, p = q.max(), r, q
        row = p[int(np.argmax(p.max(axis=1)))]
        out.append(_psl_db(row))
    return float(np.median(out))


def _variant_info(results: Path) -> dict[str, dict]:
    man = read_manifest(results, required=True)
    info = {}
    for v in man["sweep"]["variants"]:
        radar = v.get("radar", {})
        err = radar.get("shifter_phase_error_deg")
        rms = float(err["rms"]) if isinstance(err, dict) else (0.0 if err is None else np.nan)
        info[v["name"]] = {"radar": radar, "shifter_error_deg_rms": rms,
                           "calibrated": radar.get("shifter_calibration_deg") is not None}
    return info


def _failure_steps(schemes) -> dict[str, float]:
    import radarsim
    from harness.cellspec import result_schemes
    out = {}
    for s in schemes:
        rs = result_schemes([s])[0]
        cfg = radarsim.presets.r79(rs.mimo)
        out[s] = cfg.scheme.velocity_failure_step_mps(cfg)
    return out


def _velocity_failures(det: pd.DataFrame, truth: pd.DataFrame, steps: dict) -> pd.Series:
    """Per (variant, scheme): velocity-resolution failures (see module docstring)."""
    keys = ["scenario", "variant", "seed", "frame"]
    amb = det[det["label"] == "VELOCITY_AMBIGUOUS"].groupby(["variant", "scheme"]).size()
    g = det[det["label"] == "GHOST"][keys + ["scheme", "x_m", "y_m", "radial_velocity_mps"]]
    g = g.reset_index(names="det")
    t = truth[keys + ["x_radar_m", "y_radar_m", "length_m", "width_m", "radial_velocity_mps"]]
    m = g.merge(t, on=keys, suffixes=("", "_truth"))
    if len(m):
        d = np.hypot(m["x_m"] - m["x_radar_m"], m["y_m"] - m["y_radar_m"])
        inside = d <= 0.5 * np.hypot(m["length_m"], m["width_m"]) + FOOTPRINT_GATE_M
        step = m["scheme"].map(steps).to_numpy(dtype=float)
        dv = (m["radial_velocity_mps"] - m["radial_velocity_mps_truth"]).to_numpy()
        k = np.round(dv / step)
        fail = inside.to_numpy() & (k != 0) & (np.abs(dv - k * step) <= VELOCITY_GATE_MPS)
        ghost_fail = m[fail].drop_duplicates("det").groupby(["variant", "scheme"]).size()
    else:
        ghost_fail = pd.Series(dtype=float)
    return amb.add(ghost_fail, fill_value=0)


def shifter_table(results: str | Path, *, probe: bool = True) -> pd.DataFrame:
    """One row per (variant, scheme) of a shifter sweep.

    Returns
    -------
    DataFrame
        variant, scheme, shifter_error_deg_rms, calibrated, n_frames, ghost_rate,
        velocity_resolution_failures_per_frame, azimuth_rmse_deg, angle_psl_db (NaN without
        `probe`), sorted by scheme, calibration, error.
    """
    results = Path(results)
    summ = pd.read_parquet(results / "summary.parquet")
    det = pd.read_parquet(results / "detections.parquet")
    truth = pd.read_parquet(results / "truth.parquet")
    info = _variant_info(results)
    summ = summ[~failed_rows(summ)]
    grp = summ.groupby(["variant", "scheme"])
    out = grp[["n_frames", "n_ghost", "n_detections"]].sum()
    out["ghost_rate"] = out["n_ghost"] / out["n_detections"].where(out["n_detections"] > 0)
    if "n_velocity_resolution_failures" in summ:  # the runner's own count (metrics.detection)
        fails = grp["n_velocity_resolution_failures"].sum()
    else:
        fails = _velocity_failures(det, truth, _failure_steps(summ["scheme"].unique()))
    out["velocity_resolution_failures_per_frame"] = \
        fails.reindex(out.index).fillna(0) / out["n_frames"]
    if "azimuth_error_deg" in det:
        tr = det[det["label"] == "TRUE"]
        out["azimuth_rmse_deg"] = tr.groupby(["variant", "scheme"])["azimuth_error_deg"].apply(
            lambda x: float(np.sqrt(np.nanmean(np.square(x)))) if x.notna().any() else np.nan)
    else:
        out["azimuth_rmse_deg"] = np.nan
    out = out.reset_index()
    out["shifter_error_deg_rms"] = out["variant"].map(
        lambda v: info.get(v, {}).get("shifter_error_deg_rms", np.nan))
    out["calibrated"] = out["variant"].map(lambda v: info.get(v, {}).get("calibrated", False))
    out["angle_psl_db"] = [angle_sidelobe_db(info[v]["radar"], s) if probe and v in info
                           else np.nan for v, s in zip(out["variant"], out["scheme"])]
    cols = ["variant", "scheme", "shifter_error_deg_rms", "calibrated", "n_frames",
            "ghost_rate", "velocity_resolution_failures_per_frame", "azimuth_rmse_deg",
            "angle_psl_db"]
    return out[cols].sort_values(["scheme", "calibrated", "shifter_error_deg_rms"],
                                 kind="stable").reset_index(drop=True)


def html_section(results: str | Path, *, probe: bool = True) -> str:
    """HTML section (table and one plot per metric) of a shifter sweep, or "" when the results
    hold no shifter variants."""
    results = Path(results)
    try:
        info = _variant_info(results)
    except (OSError, KeyError, ValueError):
        return ""
    if not any(np.isfinite(v["shifter_error_deg_rms"]) and
               v["radar"].get("shifter_phase_error_deg") is not None for v in info.values()):
        return ""
    tab = shifter_table(results, probe=probe)
    plt = pyplot()
    metrics = [("ghost_rate", "ghost rate"),
               ("velocity_resolution_failures_per_frame", "velocity-resolution failures / frame"),
               ("azimuth_rmse_deg", "azimuth RMSE, deg"),
               ("angle_psl_db", "angle sidelobe level (strong target), dB")]
    fig, axes = plt.subplots(1, len(metrics), figsize=(4.2 * len(metrics), 3.4))
    for ax, (col, label) in zip(axes, metrics):
        for (scheme, cal), d in tab.groupby(["scheme", "calibrated"]):
            ax.plot(d["shifter_error_deg_rms"], d[col], "o-" if cal else "s--",
                    label=f"{scheme}{' cal' if cal else ''}")
        ax.set_xlabel("shifter error, deg rms per code")
        ax.set_title(label, fontsize=9)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    body = tab.to_html(index=False, float_format=lambda x: f"{x:.3g}", border=0)
    return ("<h2>Phase-shifter error and calibration</h2>"
            f"<p>{html.escape(__doc__.splitlines()[0])}</p>{png_img(fig)}{body}")
