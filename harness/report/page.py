"""Self-contained HTML report of a results directory (images embedded as base64 PNG).

The page leads with the answer: one headline table (per scheme, suite-wide: detection
probability and first-detection range per actor class, range and radial-velocity RMSE,
velocity-unambiguity rate, ghost rate, SNR gain over the baseline scheme and the gate verdict,
`metrics.suite.headline_table`) and two figures (detection probability versus range per
class; the SNR-gain histogram of each scheme minus the baseline on the same actor and frame).
Then one section per case: its summary rows, a bird's-eye view (ground truth and the
detections of each MIMO scheme) and the range-Doppler and Doppler-azimuth maps of one frame,
re-simulated bit-exactly from the cell's seeds. Then the ghost map and the full summary table,
and last, collapsed, the gate table. Panels follow the schemes present in the tables (their
``scheme`` column, in run order), never a fixed list.
"""
from __future__ import annotations

import fnmatch
import html
import os
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

from core.errors import BadInput
from core.fileio import atomic_write
from harness.report.figures import png_img as _img
from harness.report.figures import pyplot as _plt
from harness.report.figures import scheme_order, table_html
from harness.report.sections import REPORT_SECTIONS, ReportInputs
from harness.runtime import prepare_worker, stoppable_pool
from harness.sweep.provenance import plugins_line, version_line
from harness.sweep.results_schema import HEADLINE_INPUTS, read_manifest, read_table, results_gaps
from harness.sweep.store import failed_rows, read_meta

__all__ = ["build_report", "doppler_azimuth_map", "choose_frame"]

_LABEL_COLOURS = {"TRUE": "tab:green", "VELOCITY_AMBIGUOUS": "tab:orange", "GHOST": "tab:red",
                  "CLUTTER": "0.6"}
_SUMMARY_COLUMNS = [
    "scenario", "variant", "seed", "scheme", "case_class", "n_frames", "detections_per_frame",
    "ghost_rate", "ghosts_per_frame", "velocity_unambiguity_rate",
    "velocity_unambiguity_rate_in_span", "range_error_rmse_m",
    "radial_velocity_error_rmse_mps", "azimuth_error_rmse_deg", "detection_probability_mean",
    "target_first_detection_range_m", "case_pass", "s_critical_m", "r79_margin_m", "r79_pass",
    "snr_gain_median_db", "track_confirm_range_m_max", "gospa_mean_m", "noise_floor_rise_db",
    "mitigation_floor_recovery_db", "mitigation_ghost_rate_added", "interference_to_noise_db",
    "error",
]


def _legend(columns) -> str:
    """Collapsed table saying what each column means: unit, better direction and the
    definition of `metrics.METRICS`."""
    from metrics.registry import describe
    t = describe(columns)
    if t.empty:
        return ""
    return ("<details><summary>What the columns mean (metrics.METRICS)</summary>"
            + t.to_html(index=False, border=0, classes="tbl") + "</details>")


def _count(manifest: dict, field: str) -> str:
    """A manifest's cell count for the page, "?" when not recorded (null, NaN, absent)."""
    v = manifest.get(field)
    return str(v) if isinstance(v, int) else "?"


def _heading(res: Path, manifest: dict, gaps: list[str]) -> list[str]:
    """HTML parts of the page's head: title, code version, git and cell counts, and what the
    results lack (`harness.sweep.results_schema.results_gaps`)."""
    parts = [f"<h1>Corner-radar evaluation: {html.escape(str(manifest.get('run_id', res.name)))}"
             "</h1>"]
    git = manifest.get("git") or {}
    line, warning = version_line(manifest)
    parts.append(f"<p>{html.escape(line)}" + (f"; <b>{html.escape(warning)}</b>" if warning
                                              else "") + "</p>")
    if plugins_line(manifest):  # which plugins made these results
        parts.append(f"<p>{html.escape(plugins_line(manifest))}</p>")
    parts.append(f"<p>git {html.escape(str(git.get('commit')))} (dirty: {git.get('dirty')}), "
                 f"{_count(manifest, 'n_ok')} of {_count(manifest, 'n_cells')} cells ok, "
                 f"{_count(manifest, 'n_error')} failed; written "
                 f"{html.escape(str(manifest.get('written_utc', '')))}.</p>")
    if gaps:
        parts.append("<p><b>Missing from these results:</b></p><ul>"
                     + "".join(f"<li>{html.escape(g)}</li>" for g in gaps) + "</ul>")
    return parts


def choose_frame(detections: pd.DataFrame, scenario: str, variant: str, seed: int) -> int | None:
    """The frame with the most TRUE detections of a cell's first scheme (ties: the earliest)."""
    first = scheme_order(detections)[:1]
    d = detections[(detections["scenario"] == scenario) & (detections["variant"] == variant)
                   & (detections["seed"] == seed) & detections["scheme"].isin(first)]
    if d.empty:
        return None
    t = d[d["label"] == "TRUE"]
    counts = (t if len(t) else d).groupby("frame").size()
    return int(counts.idxmax())


def doppler_azimuth_map(cfg, adc: np.ndarray, range_bin: int, n_azimuth_bins: int = 48):
    """Doppler-azimuth power of one range bin as the chain sees it (`pipeline.doppler_azimuth_map`).

    Returns
    -------
    velocity_mps : (D,) float, sorted ascending
    sin_az : (A,) float
    power_db : (D, A) float
    """
    import pipeline
    proc = pipeline.ProcessingConfig(
        angle=pipeline.config.AngleConfig(n_azimuth_bins=n_azimuth_bins))
    return pipeline.doppler_azimuth_map(cfg, adc, range_bin, proc)


def _birdseye(truth: pd.DataFrame, det: pd.DataFrame, frame: int | None, title: str):
    plt = _plt()
    from matplotlib.collections import LineCollection  # with pyplot: on first use
    schemes = scheme_order(det, mimo_only=True) or ["-"]
    fig, axes = plt.subplots(1, len(schemes), figsize=(5.5 * len(schemes), 5), sharex=True,
                             sharey=True, squeeze=False)
    axes = axes[0]
    for ax, scheme in zip(axes, schemes):
        d = det[det["scheme"] == scheme]
        if len(d) > 6000:  # keep the PNG small; the sample is deterministic
            d = d.iloc[np.linspace(0, len(d) - 1, 6000).astype(int)]
        for lab, col in _LABEL_COLOURS.items():
            s = d[d["label"] == lab]
            ax.scatter(s["y_m"], s["x_m"], s=6, c=col, label=f"{lab} ({(d['label'] == lab).sum()})",
                       alpha=0.6, linewidths=0)
        # every actor's track and the footprints at `frame`: one artist each (one line per
        # actor made the plotting cost grow with the guard rail's many segments)
        ax.add_collection(LineCollection(_tracks(truth), colors="k", linewidths=0.8, zorder=2))
        if frame is not None:
            ax.add_collection(LineCollection(_footprints(truth[truth["frame"] == frame]),
                                             colors="b", linewidths=1.2, zorder=2))
        # Frame the road users (and the radar), not the kilometres of guard rail.
        users = truth[truth["actor_class"] != "guard_rail"]
        xs = np.r_[0.0, users["x_radar_m"].to_numpy()]
        ys = np.r_[0.0, users["y_radar_m"].to_numpy()]
        ax.set_xlim(min(ys.max() + 20, 260), max(ys.min() - 20, -260))
        ax.set_ylim(max(xs.min() - 20, -260), min(xs.max() + 20, 260))
        ax.set_title(f"{title}: {scheme.upper()}")
        ax.set_xlabel("y radar (left +, drawn on the left), m")
        ax.legend(fontsize=7, loc="upper right")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("x radar (boresight), m")
    return fig


def _tracks(truth: pd.DataFrame) -> list[np.ndarray]:
    """Every actor's track in the bird's-eye axes: (n_frames, 2) arrays of (y, x) radar, m."""
    t = truth.sort_values("actor_id", kind="stable")
    yx = t[["y_radar_m", "x_radar_m"]].to_numpy(dtype=float)
    ids = t["actor_id"].to_numpy()
    starts = np.flatnonzero(np.r_[True, ids[1:] != ids[:-1]])
    return np.split(yx, starts[1:])


def _footprints(now: pd.DataFrame) -> np.ndarray:
    """Outline of every actor's box (length x width, yawed): (n, 5, 2) closed (y, x) polygons in
    the bird's-eye axes, m."""
    yaw = np.radians(now["yaw_radar_deg"].to_numpy(dtype=float))[:, None]
    hl = now["length_m"].to_numpy(dtype=float)[:, None] / 2 * np.array([1, 1, -1, -1, 1])
    hw = now["width_m"].to_numpy(dtype=float)[:, None] / 2 * np.array([1, -1, -1, 1, 1])
    xs = now["x_radar_m"].to_numpy(dtype=float)[:, None] + np.cos(yaw) * hl - np.sin(yaw) * hw
    ys = now["y_radar_m"].to_numpy(dtype=float)[:, None] + np.sin(yaw) * hl + np.cos(yaw) * hw
    return np.stack([ys, xs], axis=-1)


def _maps(cell_spec: dict, frame: int, det: pd.DataFrame):
    """Range-Doppler and Doppler-azimuth maps of one re-simulated frame (each MIMO scheme)."""
    import pipeline
    from harness.cell.run import simulate_cell_frame
    from harness.cell.spec import CellSpec
    spec = CellSpec(**cell_spec)
    radar, adc, _, _ = simulate_cell_frame(spec, frame)
    # One range bin for all schemes: the strongest TRUE detection of the first scheme in the
    # frame (else its strongest detection), so the Doppler-azimuth maps show the same target.
    fd = det[det["scheme"].isin(scheme_order(det)[:1]) & (det["frame"] == frame)]
    tru = fd[fd["label"] == "TRUE"]
    pick = tru if len(tru) else fd
    ref_range_m = float(pick.loc[pick["snr_db"].idxmax(), "range_m"]) if len(pick) else 50.0
    plt = _plt()
    fig, axes = plt.subplots(2, len(radar), figsize=(5.5 * len(radar), 8), squeeze=False)
    for col, m in enumerate(radar):
        cfg = radar[m]
        rd = pipeline.frame_spectra(cfg, adc[m])["range_doppler_db"]  # (range, doppler)
        n_d = rd.shape[1]
        rd = np.fft.fftshift(rd, axes=1)
        ax = axes[0, col]
        # The chain's own Doppler axis spans one Tx's slow-time sequence: all chirps at Tc for
        # DDMA, one slot per code period for TDMA/BPM, the fast set's slots for fast/slow.
        vmax = cfg.wavelength_m / (4 * cfg.scheme.slow_time_period_s(cfg))
        ax.imshow(rd, aspect="auto", origin="lower", cmap="viridis",
                  extent=[vmax, -vmax, 0, cfg.max_range_m],
                  vmin=np.percentile(rd, 50), vmax=rd.max())
        ax.set_title(f"{m.upper()} range-Doppler (frame {frame}, {n_d} Doppler bins, "
                     "before demodulation)", fontsize=9)
        ax.set_xlabel("velocity of the Doppler bin, m/s")
        ax.set_ylabel("range, m")
        rbin = int(np.clip(np.rint(ref_range_m / cfg.range_resolution_m), 1,
                           cfg.n_range_bins - 1))
        vel, sin_az, da = doppler_azimuth_map(cfg, adc[m], rbin)
        ax = axes[1, col]
        ax.imshow(da, aspect="auto", origin="lower", cmap="magma",
                  extent=[sin_az[0], sin_az[-1], vel[0], vel[-1]],
                  vmin=np.percentile(da, 50), vmax=da.max())
        ax.set_title(f"{m.upper()} Doppler-azimuth at range bin {rbin} "
                     f"({rbin * cfg.range_resolution_m:.1f} m)", fontsize=9)
        ax.set_xlabel("sin(azimuth) (48-point FFT grid; + = left)")
        ax.set_ylabel("radial velocity, m/s")
    fig.tight_layout()
    return fig


def _pd_vs_range(actors: pd.DataFrame):
    from metrics.association import AssociationConfig
    from metrics.detection import pd_vs_range
    bin_m, min_count = AssociationConfig().pd_range_bin_m, AssociationConfig().pd_min_count
    plt = _plt()
    schemes = scheme_order(actors) or ["-"]
    fig, axes = plt.subplots(1, len(schemes), figsize=(4.4 * len(schemes), 4), sharey=True,
                             squeeze=False)
    axes = axes[0]
    for ax, scheme in zip(axes, schemes):
        a = actors[actors["scheme"] == scheme]
        t = pd_vs_range(a, bin_m)
        for cls, g in t.groupby("actor_class"):
            g = g[g["n_frames"] >= min_count]
            ax.plot((g["range_lo_m"] + g["range_hi_m"]) / 2, g["detection_probability"], "o-",
                    ms=3, label=cls)
        ax.axhline(0.9, color="k", ls=":", lw=0.8)
        ax.set_title(f"{scheme}: Pd vs range ({bin_m:g} m bins, >= {min_count} actor-frames)",
                     fontsize=9)
        ax.set_xlabel("actor centre range, m")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("detection probability")
    return fig


def _snr_gain_hist(actors: pd.DataFrame, baseline: str):
    from metrics.detection import snr_gain_pairs
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4))
    for scheme in scheme_order(actors, mimo_only=True):
        if scheme == baseline:
            continue
        parts = [snr_gain_pairs(g, scheme, baseline)
                 for _, g in actors.groupby(["scenario", "variant", "seed"])]
        gains = pd.concat(parts)["snr_gain_db"].to_numpy() if parts else np.array([])
        if len(gains):
            ax.hist(gains, bins=60, range=(-10, 20), histtype="step", lw=1.5,
                    label=f"{scheme}: median {np.median(gains):.2f} dB (n = {len(gains)})")
    ax.axvline(10 * np.log10(4), color="tab:red", ls="--", label="10 log10 4 = 6.02 dB")
    ax.axvline(5.4, color="tab:orange", ls=":", label="empty-band DDMA expected 5.4 dB")
    ax.set_xlabel(f"scheme minus {baseline} peak SNR, same actor and frame, dB")
    ax.set_ylabel("actor-frames")
    ax.legend(fontsize=8)
    return fig


def _ghost_map(det: pd.DataFrame):
    plt = _plt()
    schemes = scheme_order(det) or ["-"]
    fig, axes = plt.subplots(1, len(schemes), figsize=(4.4 * len(schemes), 4.5), sharex=True,
                             sharey=True, squeeze=False)
    axes = axes[0]
    for ax, scheme in zip(axes, schemes):
        g = det[(det["scheme"] == scheme) & (det["label"] == "GHOST")]
        ax.hist2d(g["y_m"], g["x_m"], bins=[60, 60], range=[[-150, 150], [0, 250]],
                  cmap="Reds", cmin=1)
        ax.set_title(f"{scheme}: {len(g)} ghosts (radar frame)", fontsize=9)
        ax.set_xlabel("y radar, m")
        ax.invert_xaxis()
    axes[0].set_ylabel("x radar, m")
    return fig


_HEADLINE_LABELS = {
    "scheme": "scheme", "range_rmse_m": "range RMSE, m",
    "radial_velocity_rmse_mps": "velocity RMSE, m/s",
    "velocity_unambiguity_rate": "velocity unambiguous (road users)",
    "infrastructure_velocity_unambiguity_rate": "velocity unambiguous (guard rails)",
    "ghost_rate": "ghost rate",
    "snr_gain_pairs": "SNR-gain pairs", "gates": "gates",
}


def _aliasing_line(summary: pd.DataFrame) -> str:
    """The headline's sentence on velocity aliasing: the runs whose road users alias (a road
    user beyond the scheme's unambiguous span), with their rates, or that none do."""
    from metrics.suite import ALIASED_BELOW, aliased_runs
    al = aliased_runs(summary)
    if al.empty:
        return (f"<p>Velocity aliasing: no run's road users below "
                f"{ALIASED_BELOW:g} velocity unambiguous.</p>")
    items = [f"{r.scenario}{'/' + str(r.variant) if r.variant else ''} seed {r.seed} "
             f"{r.scheme} {r.velocity_unambiguity_rate:.2f} "
             f"({int(r.n_velocity_resolution_failures)} aliased)"
             for r in al.itertuples()]
    return ("<p><b>Velocity aliasing shown</b> (road users' velocity unambiguous below "
            f"{ALIASED_BELOW:g}, guard rails apart): " + html.escape("; ".join(items))
            + ".</p>")


def _headline_label(column: str) -> str:
    if column in _HEADLINE_LABELS:
        return _HEADLINE_LABELS[column]
    if column.startswith("pd_"):
        return f"Pd {column[3:]}"
    if column.startswith("first_detection_range_"):
        return f"first detection {column[len('first_detection_range_'):-2]}, m"
    if column.startswith("snr_gain_over_"):
        return f"SNR gain over {column[len('snr_gain_over_'):-3]}, dB"
    return column


def _gate_verdicts(summary: pd.DataFrame, manifest: dict):
    """Verdict per scheme (the shipped gates whose scheme pattern matches it, on its rows), the
    gate table as HTML and the case x scheme verdict table (`gates.verdict_table`)."""
    from harness.gates import check as gt
    shipped = gt.load_gates()
    usable = [x for x in shipped if x.metric in summary.columns]
    verdicts = {}
    for s in [s for s in dict.fromkeys(summary["scheme"]) if s]:
        mine = [g for g in usable if fnmatch.fnmatchcase(s, g.scheme)]
        res = gt.evaluate_gates(summary[summary["scheme"] == s], mine)
        failed = sorted({r.gate for r in res if r.status == "fail"})
        verdicts[s] = (f"FAIL: {', '.join(failed)}" if failed else
                       f"PASS ({len(mine)} gates)" if mine else "no gates")
    evaluated = gt.evaluate_gates(summary, usable, manifest)
    gres = gt.results_table(evaluated)
    n_fail = int((gres["status"] == "fail").sum())
    body = ""
    if len(usable) < len(shipped):
        body += "<p>not evaluated (metric not in this summary): " + html.escape(
            ", ".join(x.name for x in shipped if x not in usable)) + "</p>"
    body += table_html(gres.sort_values("status"), ["status", "gate", "where", "value",
                                                     "bound"])
    table = (f"<details><summary><h2>Gates (shipped thresholds): "
             f"{'FAIL' if n_fail else 'PASS'} <small>({len(gres)} evaluations, "
             f"{n_fail} failed; click to open)</small></h2></summary>{body}</details>")
    return verdicts, table, gt.verdict_table(evaluated)


def _case_section(summary, det, truth, specs, key, maps: bool) -> list[str]:
    """HTML parts of one case: its summary rows, bird's-eye view, maps of one frame."""
    return _draw_case(_case_inputs(summary, det, truth, specs, key, maps))


class _CaseInputs(NamedTuple):
    """What one case section draws (its rows of the tables, the chosen frame), small enough
    to send to a worker process."""

    key: tuple
    summary: pd.DataFrame
    det: pd.DataFrame
    truth: pd.DataFrame
    frame: int | None
    spec: dict | None   # the cell spec for the maps (None: no maps)


def _case_inputs(summary, det, truth, specs, key, maps: bool) -> _CaseInputs:
    sc, var, seed = key
    cd = det[(det["scenario"] == sc) & (det["variant"] == var) & (det["seed"] == seed)] \
        if len(det) else det
    ct = truth[(truth["scenario"] == sc) & (truth["variant"] == var) &
               (truth["seed"] == seed)] if len(truth) else truth
    frame = choose_frame(det, sc, var, seed) if len(det) else None
    rows = summary[(summary["scenario"] == sc) & (summary["variant"] == var)
                   & (summary["seed"] == seed)]
    spec = specs[key] if maps and frame is not None and key in specs else None
    return _CaseInputs(key, rows, cd, ct, frame, spec)


def _draw_case(c: _CaseInputs) -> list[str]:
    """HTML parts of one case from `_case_inputs`."""
    import scenarios
    sc, var, seed = c.key
    parts = [f"<h2>Case {html.escape(sc)} <small>({html.escape(var)}, seed {seed})</small></h2>"]
    parts.append(table_html(c.summary, _SUMMARY_COLUMNS))
    if len(c.truth):
        parts.append(_img(_birdseye(c.truth, c.det, c.frame, sc)))
    if c.spec is not None:
        # a case file is re-simulated from its path while it is still there
        if sc in scenarios.SCENARIOS or (scenarios.files.is_case_path(sc) and
                                         Path(sc).is_file()):
            parts.append(f"<h3>Range-Doppler and Doppler-azimuth maps, frame {c.frame}</h3>"
                         + _img(_maps(c.spec, c.frame, c.det)))
        else:
            parts.append(f"<p>maps not drawn: {html.escape(sc)} is neither a catalogue case "
                         "nor a case file here, so its frame cannot be re-simulated.</p>")
    return parts


#: Case sections are drawn in worker processes when a report has at least this many: each
#: takes a second or two of plotting (and, with maps, re-simulating a frame), so the default
#: run's 18 cases kept one core busy while the other idled. Fewer are drawn inline (starting
#: a pool costs more than it saves). Same sections, same order, either way.
PARALLEL_MIN_CASES = 4


def _case_sections(summary, det, truth, specs, keys: list, maps: bool) -> list[str]:
    """HTML parts of every case of `keys`, in order."""
    inputs = [_case_inputs(summary, det, truth, specs, k, maps) for k in keys]
    workers = min(os.cpu_count() or 1, len(inputs), 4)
    if len(inputs) < PARALLEL_MIN_CASES or workers < 2:
        drawn = [_draw_case(c) for c in inputs]
    else:
        drawn = _drawn_in_pool(inputs, workers)
    return [part for parts in drawn for part in parts]


def _drawn_in_pool(inputs: list, workers: int) -> list:
    """`_draw_case` of every input, in order, on a pool of `workers` processes that a stop
    signal stops at any moment, as a sweep's pool (`harness.runtime.stoppable_pool`: one
    landing while the pool forks its workers would otherwise be dropped). The workers
    leave Ctrl-C to this process (`prepare_worker`), so a terminal's Ctrl-C gives one line,
    not a traceback per worker."""
    with stoppable_pool(workers, prepare_worker, (os.getpid(),)) as pool:
        futs = [pool.executor.submit(_draw_case, c) for c in inputs]
        for _ in pool.completed(futs):
            pass
        return [f.result() for f in futs]


def build_report(results: str | Path, out: str | Path | None = None, *, maps: bool = True,
                 max_cases: int | None = None,
                 notify: Callable[[str], object] | None = None) -> Path:
    """Write ``report.html`` for a results directory and return its path.

    Parameters
    ----------
    results : path
        Directory written by `radar-harness sweep` (summary.parquet etc.).
    out : path, optional
        Output HTML (default ``<results>/report.html``).
    maps : bool
        Re-simulate one frame per catalogue case for the range-Doppler / Doppler-azimuth maps.
    max_cases : int, optional
        Limit the per-case sections.
    notify : callable(str), optional
        Called with each gap of the results (`harness.sweep.results_schema.results_gaps`: a
        baseline scheme not run, counts not recorded, metric columns without values), which
        the page states under its title too.

    Raises
    ------
    core.errors.BadInput
        No summary.parquet in ``results``; a damaged manifest or table
        (`harness.sweep.results_schema`), naming the file and the field.
    """
    from metrics.suite import headline_table

    res = Path(results)
    if not (res / "summary.parquet").exists():
        raise BadInput(f"no summary.parquet in {res} (run `radar-harness sweep`)")
    manifest = read_manifest(res)
    summary, det, actors, actor_summary, truth = (
        read_table(res, t, manifest)
        for t in ("summary", "detections", "actors", "actor_summary", "truth"))
    from harness.cell.spec import DEFAULT_BASELINE_SCHEME
    base = manifest.get("baseline_scheme") or DEFAULT_BASELINE_SCHEME
    gaps = results_gaps(summary, manifest, base)
    for gap in gaps if notify is not None else ():
        notify(gap)
    summary = summary.assign(**{c: np.nan for c in HEADLINE_INPUTS if c not in summary})
    parts = _heading(res, manifest, gaps)
    verdicts, gate_table, gate_verdicts = _gate_verdicts(summary, manifest)
    head = headline_table(summary, actor_summary, actors if len(actors) else None,
                          baseline=base, verdicts=verdicts)
    parts.append("<h2>Headline: every scheme over the whole suite</h2>")
    parts.append("<p>Pd: detected / visible actor-frames per class; first detection: median "
                 "range of each actor's first TRUE detection; RMSE pooled over every TRUE "
                 f"detection; SNR gain: median over noise-limited pairs against {html.escape(base)}"
                 " on the same actor and frame; gates: the shipped thresholds on that scheme's "
                 "rows.</p>")
    parts.append(table_html(head.rename(columns=_headline_label)))
    parts.append(_aliasing_line(summary))
    parts.append(_legend(["velocity_unambiguity_rate",
                          "infrastructure_velocity_unambiguity_rate", "ghost_rate",
                          "range_error_rmse_m",
                          "radial_velocity_error_rmse_mps", "first_detection_range_m",
                          "detection_probability", "snr_gain_noise_limited_median_db"]))
    if len(gate_verdicts):
        parts.append("<h2>Verdicts: every case and scheme against the shipped gates</h2>"
                     + gate_verdicts.to_html(border=0, classes="tbl"))
    if len(actors):
        parts.append("<h2>Detection probability versus range</h2>" + _img(_pd_vs_range(actors)))
        parts.append(f"<h2>SNR gain over {html.escape(base)}</h2>"
                     + _img(_snr_gain_hist(actors, base)))
    specs = {}
    cell_dirs = sorted((res / "cells").glob("*/cell.json")) if (res / "cells").exists() else []
    for f in cell_dirs:
        meta = read_meta(f.parent) or {}  # a damaged cell.json: no spec for its maps
        if meta.get("status") == "ok" and isinstance(meta.get("spec"), dict):
            sp = meta["spec"]
            specs.setdefault((sp["scenario"], sp["variant"], sp["seed"]), sp)
    ok_rows = summary[~failed_rows(summary)]
    keys = ok_rows[["scenario", "variant", "seed"]].drop_duplicates()
    keys = keys.drop_duplicates("scenario")  # one section per case: its first variant/seed
    if max_cases is not None:
        keys = keys.iloc[:max_cases]
    parts += _case_sections(summary, det, truth, specs,
                            [(k["scenario"], k["variant"], int(k["seed"]))
                             for _, k in keys.iterrows()], maps)
    if len(det):
        parts.append("<h2>Ghost map</h2>" + _img(_ghost_map(det)))
    inputs = ReportInputs(results=res, summary=summary, actors=actors, detections=det)
    parts += [section.render(inputs) for section in REPORT_SECTIONS.values()]
    parts.append("<details><summary><h2>Summary: every run</h2></summary>"
                 + table_html(summary, _SUMMARY_COLUMNS) + _legend(_SUMMARY_COLUMNS)
                 + "</details>")
    parts.append(gate_table)
    style = ("body{font-family:sans-serif;margin:2em;max-width:1400px}"
             ".tbl{border-collapse:collapse;font-size:12px}"
             ".tbl td,.tbl th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
             "summary h2{display:inline;cursor:pointer}"
             "img{max-width:100%}")
    page = ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>radar-harness report"
            f"</title><style>{style}</style></head><body>" + "\n".join(parts) +
            "</body></html>")
    out_p = Path(out) if out else res / "report.html"
    return atomic_write(out_p, lambda tmp: tmp.write_text(page, encoding="utf-8"))
