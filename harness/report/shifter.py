"""Shifter-error sweep: per scheme, ghost rate, velocity-resolution failures, azimuth RMSE and
angle sidelobe level at a strong target, against the per-code shifter error and calibration.

`shifter_table(results)` reads a results directory of a sweep whose variants set
`shifter_phase_error_deg` (a `ShifterErrorSpec` mapping with ``rms``) and optionally
`shifter_calibration_deg` (e.g. ``harness/sweeps/shifter.toml``) and returns one row per
(variant, scheme). `html_section(results)` renders it for the report.

- ghost rate: ghosts / detections over the variant's cells (summary counts);
- velocity-resolution failures per frame: the summary column ``n_velocity_resolution_failures``
  (`metrics.velocity`: detections at a road user's range whose velocity is off by whole
  resolution steps, one DDMA sub-band or a TDMA/BPM slot span) over the frames;
- azimuth RMSE of TRUE detections against their nearest scatterer: the summary column
  ``azimuth_error_rmse_deg`` (`metrics.detection.error_stats`) pooled over the cells;
- angle sidelobe level: a strong point target (`PROBE`) simulated with the variant's radar and
  processed by the scheme's chain; the highest azimuth sidelobe outside the main lobe of its
  Doppler-azimuth cut (`pipeline.doppler_azimuth_map`) relative to the peak, median over
  `PROBE_SEEDS` noise seeds. An ideal unwindowed 12-element array gives -13.3 dB (design.md 8).
"""
from __future__ import annotations

import html
from pathlib import Path

import numpy as np
import pandas as pd

from core.errors import BadInput
from harness.report.figures import png_img, pyplot
from harness.sweep.provenance import read_manifest
from harness.sweep.store import failed_rows

__all__ = ["shifter_table", "html_section", "angle_sidelobe_db", "PROBE"]

#: Strong probe target: range m, azimuth deg, elevation deg, radial velocity m/s, RCS m^2.
PROBE = (30.0, 15.0, 0.0, -7.0, 10.0)
PROBE_SEEDS = (0, 1, 2)


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
        Result scheme (`harness.cell.spec.known_schemes`).
    """
    import pipeline
    import radarsim
    from harness.cell.spec import result_schemes
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
        best = p.max()
        for r in (rbin - 1, rbin + 1):
            _, _, q = pipeline.doppler_azimuth_map(cfg, adc, r, proc)
            if q.max() > best:
                best, p = q.max(), q
        row = p[int(np.argmax(p.max(axis=1)))]
        out.append(_psl_db(row))
    return float(np.median(out))


def _variant_info(results: Path) -> dict[str, dict]:
    from radarsim.radar_config import radar_fields
    man = read_manifest(results, required=True)
    info = {}
    for v in man["sweep"]["variants"]:
        radar = v.get("radar", {})
        fields = radar_fields({k: x for k, x in radar.items() if k != "profile"}, warn=False)
        err = fields.get("shifter_phase_error_deg")
        rms = float(err["rms"]) if isinstance(err, dict) else (0.0 if err is None else np.nan)
        info[v["name"]] = {"radar": radar, "fields": fields, "shifter_error_deg_rms": rms,
                           "calibrated": fields.get("shifter_calibration_deg") is not None}
    return info


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
    info = _variant_info(results)
    summ = summ[~failed_rows(summ)]
    grp = summ.groupby(["variant", "scheme"])
    out = grp[["n_frames", "n_ghost", "n_detections"]].sum()
    out["ghost_rate"] = out["n_ghost"] / out["n_detections"].where(out["n_detections"] > 0)
    for col in ("n_velocity_resolution_failures", "azimuth_error_rmse_deg"):
        if col not in summ:
            raise BadInput(f"{results}: summary lacks {col!r} (written by an older harness: "
                           "re-run the sweep)")
    out["velocity_resolution_failures_per_frame"] = \
        grp["n_velocity_resolution_failures"].sum() / out["n_frames"]
    # pooled over the variant's cells: sqrt of the sample-weighted mean square
    w = summ["n_error_samples"].where(np.isfinite(summ["azimuth_error_rmse_deg"]), 0)
    ms = (summ["azimuth_error_rmse_deg"].fillna(0) ** 2 * w).groupby(
        [summ["variant"], summ["scheme"]]).sum()
    n = w.groupby([summ["variant"], summ["scheme"]]).sum()
    out["azimuth_rmse_deg"] = np.sqrt(ms / n.where(n > 0))
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
               v["fields"].get("shifter_phase_error_deg") is not None for v in info.values()):
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
