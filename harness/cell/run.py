"""One sweep cell: scenario x radar/processing overrides x seed -> result tables.

A cell runs the scenario once, and for every processed frame builds the scatterers of the
scene, simulates one ADC frame per MIMO scheme of the cell (``CellSpec.schemes``, names of
``radarsim.MIMO_SCHEMES``; independent noise per `harness.sweep.streams`), processes each result
scheme (a registered scheme, or a chain variant, `harness.cell.spec.ResultScheme`), optionally
tracks each scheme, and scores everything with `metrics` (`metrics.scoring`: labels, velocity
check, summary row, case criteria and the case class's verdict). The SNR gain of each scheme
is taken over ``CellSpec.baseline_scheme`` on the same actor and frame. A case whose class asks
for it (``metrics.scoring.CASE_VERDICTS``: the interference cases) is also processed with
interference mitigation off, for the floor the mitigation recovers and the ghosts it adds.

Same spec -> bit-identical tables: all randomness comes from the seed, and no timing or host
information enters the tables (timings go to ``CellResult.elapsed_s``).
"""
from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from types import SimpleNamespace
from typing import NamedTuple

import numpy as np
import pandas as pd

from core.checks import require
from harness.cell.components import Components, default_components, mount_value
from harness.cell.config import build_configs, cell_association
from harness.cell.spec import CellSpec, result_schemes
from harness.runtime import single_thread_blas
from harness.sil.cell import ExternalCellRun
from harness.sweep.streams import frame_rng
from metrics import scoring as msc
from metrics.association import AssociationConfig, scatterer_table
from metrics.detection import ghost_stats
from metrics.interference import floor_summary, mitigation_stats

__all__ = ["CellResult", "run_cell", "cell_frame_threads", "FRAME_THREADS", "simulate_cell_frame",
           "frame_scatterers"]


@dataclass
class CellResult:
    """Tables of one cell plus its wall time (kept out of the tables for determinism)."""

    spec: CellSpec
    tables: dict[str, pd.DataFrame]
    elapsed_s: float


#: Columns of an empty point cloud (a scheme that detected nothing in any frame).
_CLOUD_COLUMNS = ("frame", "time_s", "range_m", "azimuth_deg", "elevation_deg",
                  "radial_velocity_mps", "snr_db", "x_m", "y_m", "z_m")


def concat_clouds(clouds: list[pd.DataFrame], frames=None, times_s=None) -> pd.DataFrame:
    """One scheme's point clouds of every frame as one table (typed columns when empty).

    With `frames` (and `times_s`), one per cloud, the table starts with the columns frame
    (int64) and time_s (float) of each cloud's rows (clouds as the chain returns them);
    without, the clouds carry them already.
    """
    pcs = pd.concat(clouds, ignore_index=True) if clouds else pd.DataFrame()
    if frames is not None and len(pcs.columns):
        n = [len(c) for c in clouds]
        pcs.insert(0, "frame", np.repeat(np.asarray(frames, dtype=np.int64), n))
        pcs.insert(1, "time_s", np.repeat(np.asarray(times_s, dtype=float), n))
    if pcs.empty:
        pcs = pd.DataFrame({c: pd.Series(dtype=float) for c in _CLOUD_COLUMNS})
        pcs["frame"] = pcs["frame"].astype(np.int64)
    return pcs


def _reference_procs(procs: dict, case: msc.CaseInfo) -> dict:
    """Processing with interference mitigation off, per result scheme whose processing has
    it on, when the case's class asks for that reference (interference cases)."""
    if not msc.CASE_VERDICTS[case.case_class].mitigation_reference:
        return {}
    return {s: p.unmitigated for s, p in procs.items() if p.interference.enabled}


def _label(points: pd.DataFrame, truth: pd.DataFrame, scat: pd.DataFrame, cfg,
           assoc: AssociationConfig) -> pd.DataFrame:
    """`metrics.scoring.label_detections` with the scheme's span and failure step."""
    return msc.label_detections(points, truth, scat,
                                velocity_span_mps=2 * cfg.max_unambiguous_velocity_mps,
                                failure_step_mps=cfg.scheme.velocity_failure_step_mps(cfg),
                                config=assoc)


def _frames_of(run, stride: int) -> np.ndarray:
    src = run.ego if getattr(run, "ego", None) is not None and len(run.ego) else run.truth
    frames = np.unique(src["frame"].to_numpy())
    return frames[::stride]


def _frame_context(run) -> dict[int, dict]:
    """Per frame: radar velocity over the ground (radar frame, m/s; for ground clutter) and
    mount height, from the scenario run when it provides them."""
    ctx: dict[int, dict] = {}
    ego, mount = getattr(run, "ego", None), getattr(run, "mount", None)
    if ego is None or not hasattr(run, "radar_velocity_mps"):
        return ctx
    vel = np.asarray(run.radar_velocity_mps(), dtype=float)
    height = mount_value(mount, "z_m") if mount is not None else None
    for f, v in zip(ego["frame"].to_numpy(), vel):
        ctx[int(f)] = {"radar_velocity_mps": v,
                       "mount_height_m": None if height is None else float(height)}
    return ctx


def _scatterers(comps: Components, rows, rng, ctx: dict | None):
    if not ctx:
        return comps.scene_scatterers(rows, rng)
    return comps.scene_scatterers(rows, rng, **ctx)


def frame_scatterers(comps: Components, run, frame: int, seed: int):
    """Scatterers of one frame of a scenario run exactly as `run_cell` builds them."""
    rows = run.truth[run.truth["frame"] == frame]
    return _scatterers(comps, rows, frame_rng(seed, frame, "rcs"),
                       _frame_context(run).get(int(frame)))


def simulate_cell_frame(spec: CellSpec, frame: int, comps: Components | None = None, run=None):
    """Re-simulate one frame of a cell exactly as `run_cell` did (for the report's maps).

    Returns (radar configs by mimo, ADC frames by mimo, Scatterers, run). Runs with one BLAS
    thread, as every sweep path does, so the report's maps show the sweep's bits.
    """
    single_thread_blas()
    comps = comps or default_components()
    run = run if run is not None else comps.run_scenario(spec.scenario, spec.seed,
                                                         spec.duration_s)
    radar, _ = build_configs(spec, comps)
    sc = frame_scatterers(comps, run, frame, spec.seed)
    equipment = comps.equipment(run, spec.seed, dict(spec.scene)) \
        if comps.equipment is not None else None
    adc, _ = _simulate_frames(comps, radar, sc, spec.seed, frame,
                              run.truth[run.truth["frame"] == frame], equipment)
    return radar, adc, sc, run


class _FrameOutputs(NamedTuple):
    """What the frame loop of a cell leaves for scoring."""

    clouds: dict[str, list[pd.DataFrame]]   # point clouds per result scheme, one per frame
    #                                         (as the chain returns them: no frame column)
    saturated: dict[str, list[int]]         # saturated (chirp, Rx) pairs per scheme and frame
    scatterers: pd.DataFrame                # `metrics.association.scatterer_table`
    floor_rows: list[dict]                  # `_noise_floors` rows of every frame
    reference: dict[str, list[pd.DataFrame]]  # clouds with mitigation off (`_reference_procs`)
    external_s: dict[str, float]            # wall time of each external chain's command, s


#: Frames of a cell processed at once (threads) when the cell would otherwise leave a core idle
#: (the only cell running, or among the last ones of a sweep; `cell_frame_threads`): the frame
#: loop is numpy / scipy / numba work that releases the GIL, so two frame threads keep two cores
#: busy. Results do not depend on it: every frame draws from its own streams.
FRAME_THREADS = 2


def cell_frame_threads(queued: int, workers: int, cores: int | None = None) -> int:
    """Frame threads for a cell that starts on a pool of `workers` processes with `queued`
    cells submitted after it: 1 while the cells behind it keep every other worker busy for
    as long as it runs (``queued >= workers``) and the workers fill the `cores` (default
    ``os.cpu_count()``), else `FRAME_THREADS`.

    Two frame threads cost CPU (a threaded cell frame takes 1-2.5 ms more CPU than the same
    frame on one thread: two frames' working sets share the cache and memory bandwidth) and
    buy wall time only where a core would be idle: the cell running alone, or one of the
    last `workers` cells of a sweep, which finish while the other workers run out of cells.

    Examples
    --------
    >>> [cell_frame_threads(q, workers=2, cores=2) for q in (5, 2, 1, 0)]
    [1, 1, 2, 2]
    >>> cell_frame_threads(5, workers=1, cores=2)  # one worker: the other core is free
    2
    """
    cores = (os.cpu_count() or 1) if cores is None else cores
    return 1 if workers >= cores and queued >= workers else FRAME_THREADS


def run_cell(spec: CellSpec, comps: Components | None = None,
             assoc: AssociationConfig | None = None,
             frame_threads: int = FRAME_THREADS) -> CellResult:
    """Run one sweep cell and score it.

    `frame_threads` frames are processed at a time (an integer >= 1; `cell_frame_threads`: 1
    where other cells keep the other cores busy); the tables do not depend on it.

    Returns
    -------
    CellResult
        ``tables``: ``summary`` (one row per scheme; every scheme's row but the baseline's
        carries its SNR gain over ``spec.baseline_scheme``; chain variants such as
        ``tdma_raw`` share their scheme's ADC frame and get no gain), ``detections`` (long:
        every detection with its label and errors), ``frames`` (per scheme and frame: counts
        per label), ``actors`` (per scheme, actor and frame: visible / detected / peak SNR),
        ``actor_summary`` (per scheme and actor: detection probability, first-detection
        range), ``truth`` (processed frames), ``tracks`` (per scheme, frame and track; empty
        without a tracker). Every table starts with the id columns scenario, variant, seed
        (and scheme where it applies).
    """
    require(SimpleNamespace(frame_threads=frame_threads), "frame_threads", "integer", ge=1)
    t0 = time.perf_counter()
    comps = comps or default_components()
    run = comps.run_scenario(spec.scenario, spec.seed, spec.duration_s)
    radar, procs = build_configs(spec, comps)
    assoc = assoc or cell_association(radar, spec.association)
    schemes = result_schemes(spec.schemes, spec.external_chains)
    frames = _frames_of(run, spec.frame_stride)
    truth = run.truth[run.truth["frame"].isin(frames)].reset_index(drop=True)
    times = _frame_times(run, truth, frames)
    case = msc.case_info(getattr(run, "case", None))
    refs = _reference_procs(procs, case)
    out = _process_frames(spec, comps, run, radar, procs, schemes, frames, truth, times, refs,
                          frame_threads)

    ego_speeds = _ego_speeds(run, frames)
    parts: dict[str, list[pd.DataFrame]] = {t: [] for t in ("detections", "frames", "actors",
                                                             "actor_summary", "tracks")}
    rows_out = []
    for rs in schemes:
        s, cfg = rs.name, radar[rs.mimo]
        lab = _label(concat_clouds(out.clouds[s], frames, times.to_numpy()), truth,
                     out.scatterers, cfg, assoc)
        sc = msc.score_scheme(lab, truth, out.scatterers, len(frames), assoc, case)
        row = sc.row
        if s in out.reference:
            ref = _label(concat_clouds(out.reference[s]), truth, out.scatterers, cfg, assoc)
            row.update(mitigation_stats(row["ghost_rate"],
                                        ghost_stats(ref, len(frames))["ghost_rate"]))
        parts["actor_summary"].append(sc.actors.assign(scheme=s))
        if comps.track is not None:
            tr, tm = _track_scheme(spec, comps, run, cfg, out.clouds[s], frames, times,
                                   ego_speeds, truth)
            if tr is not None:
                parts["tracks"].append(tr.assign(scheme=s))
                msc.add_track_metrics(row, tm)
        row["n_saturated_frames"] = int(np.count_nonzero(out.saturated[s]))
        if s in out.external_s:  # the external command's own wall time (SIL chains)
            row["external_call_s_per_frame"] = out.external_s[s] / max(len(frames), 1)
        rows_out.append({"scheme": s, **row})
        parts["detections"].append(lab.assign(scheme=s))
        fc = msc.frame_counts(lab, frames).assign(
            n_saturated_chirp_rx=np.asarray(out.saturated[s], dtype=np.int64)
            if out.saturated[s] else np.zeros(len(frames), dtype=np.int64), scheme=s)
        if out.floor_rows:
            fl = pd.DataFrame([r for r in out.floor_rows if r["scheme"] == s]) \
                .drop(columns="scheme")
            fc = fc.merge(fl, on="frame", how="left")
            rows_out[-1].update(floor_summary(fl.assign(
                time_s=times.reindex(fl["frame"]).to_numpy())))
        parts["frames"].append(fc)
        parts["actors"].append(sc.actor_frames.assign(scheme=s))

    actors = pd.concat(parts["actors"], ignore_index=True)
    summary = pd.DataFrame(rows_out)
    names = [rs.name for rs in schemes]
    base = spec.baseline_scheme
    msc.add_snr_gains(summary, actors, [rs.name for rs in schemes if not rs.is_variant
                                        and rs.name != base and base in names], base)
    if "external_call_s_per_frame" in summary:  # a timing: NaN for the built-in chains
        summary["external_call_s_per_frame"] = summary["external_call_s_per_frame"].astype(float)
    ids = {"scenario": spec.scenario, "variant": spec.variant, "seed": int(spec.seed)}
    tracks = pd.concat(parts["tracks"], ignore_index=True) if parts["tracks"] else \
        pd.DataFrame({"scheme": pd.Series(dtype=object), "frame": pd.Series(dtype="int64")})
    tables = {
        "summary": _with_ids(summary, ids),
        "detections": _with_ids(pd.concat(parts["detections"], ignore_index=True), ids),
        "frames": _with_ids(pd.concat(parts["frames"], ignore_index=True), ids),
        "actors": _with_ids(actors, ids),
        "actor_summary": _with_ids(pd.concat(parts["actor_summary"], ignore_index=True), ids),
        "truth": _with_ids(truth.copy(), ids, scheme=False),
        "tracks": _with_ids(tracks, ids),
    }
    return CellResult(spec=spec, tables=tables, elapsed_s=time.perf_counter() - t0)


def _frame_times(run, truth: pd.DataFrame, frames: np.ndarray) -> pd.Series:
    """Time of every processed frame, s (the ego table's when the run has one)."""
    ego = getattr(run, "ego", None)
    if ego is not None and "time_s" in ego:
        times = ego.drop_duplicates("frame").set_index("frame")["time_s"]
    else:
        times = truth.groupby("frame")["time_s"].first()
    return times.reindex(frames).astype(float)


def _ego_speeds(run, frames: np.ndarray) -> np.ndarray | None:
    """Ego speed of every processed frame, m/s (None when the run has none)."""
    ego = getattr(run, "ego", None)
    if ego is not None and "ego_speed_mps" in ego:
        return ego.drop_duplicates("frame").set_index("frame")["ego_speed_mps"] \
            .reindex(frames).to_numpy(dtype=float)
    return None


def _process_frames(spec: CellSpec, comps: Components, run, radar: dict, procs: dict,
                    schemes, frames: np.ndarray, truth: pd.DataFrame,
                    times: pd.Series, refs: dict | None = None,
                    frame_threads: int = FRAME_THREADS) -> _FrameOutputs:
    """Scatterers, ADC frames (one per mimo) and point clouds (one per result scheme) of every
    processed frame, plus the noise-floor rows; with `refs` (processing per scheme) also the
    reference point clouds of the same ADC frames. Frames run `frame_threads` at a time (1: on
    the calling thread) and are collected in frame order."""
    from pipeline.chirp_level import shared_range_stage  # after the caller's BLAS setting
    from pipeline.threads import inline
    refs = refs or {}
    ctx = _frame_context(run)
    equipment = comps.equipment(run, spec.seed, dict(spec.scene)) \
        if comps.equipment is not None else None

    def one(f):
        with inline():  # the frames already keep the cores busy (`pipeline.threads.inline`)
            return _one(f)

    def _one(f):
        rows = truth.iloc[np.flatnonzero(truth_frame == f)]  # = truth[truth["frame"] == f]
        sc = _scatterers(comps, rows, frame_rng(spec.seed, f, "rcs"), ctx.get(int(f)))
        adc, inr = _simulate_frames(comps, radar, sc, spec.seed, f, rows, equipment)
        # The chains of schemes sharing an ADC frame and the noise-floor metric read one
        # range cube per frame and chirp-level setting. The chains first: the first of them
        # makes the cube in its own (blockwise, windowed) pass and keeps it for the others
        # (`windowed_range_stage`); the floor then reads it (the same cube either way).
        # External chains: the frame goes to disk; their calls run after the loop.
        sat = {name: ext.add_frame(f, adc[mimo_of[name]]) for name, ext in external.items()}
        with shared_range_stage():
            # The settings of one ADC frame in one call: the chain computes the stages they
            # share once (TDMA and tdma_raw: everything up to the velocity hypotheses).
            jobs = {**{("scheme", rs.name): (rs.mimo, procs[rs.name])
                       for rs in schemes if rs.external is None},
                    **{("reference", name): (mimo_of[name], p) for name, p in refs.items()}}
            clouds = _point_clouds(comps, radar, adc, jobs)
            pcs = {name: pc for (kind, name), pc in clouds.items() if kind == "scheme"}
            ref = {name: pc for (kind, name), pc in clouds.items() if kind == "reference"}
            floor = _noise_floors(comps, radar, adc, procs, schemes, f, inr, refs)
        return sc, floor, pcs, ref, sat

    mimo_of = {rs.name: rs.mimo for rs in schemes}
    period = float(np.median(np.diff(times.to_numpy()))) if len(times) > 1 else 0.05
    external = {rs.name: ExternalCellRun(rs.external, radar[rs.mimo], procs[rs.name], period)
                for rs in schemes if rs.external is not None}
    truth_frame = truth["frame"].to_numpy()
    clouds: dict[str, list[pd.DataFrame]] = {s.name: [] for s in schemes}
    reference: dict[str, list[pd.DataFrame]] = {s: [] for s in refs}
    # Saturated (chirp, Rx) pairs per scheme and frame (pipeline.saturation).
    saturated: dict[str, list[int]] = {s.name: [] for s in schemes}
    scat, floor_rows = [], []
    pool = ThreadPoolExecutor(frame_threads, thread_name_prefix="cell-frame") \
        if frame_threads > 1 else None
    try:
        done = pool.map(one, frames) if pool is not None else map(one, frames)
        for f, (sc, floor, pcs, ref, sat) in zip(frames, done):
            scat.append((f, sc))
            floor_rows += floor
            for name, pc in pcs.items():
                clouds[name].append(pc)  # frame and time columns: once, in concat_clouds
                saturated[name].append(int(pc.attrs.get("saturation", {})
                                           .get("n_saturated_chirp_rx", 0)))
            for name, pc in ref.items():
                reference[name].append(pc.reset_index(drop=True).assign(frame=np.int64(f)))
            for name, n in sat.items():
                saturated[name].append(n)
        if pool is not None:
            pool.shutdown(wait=True)
        for name, ext in external.items():
            clouds[name] = ext.run(frames)
    finally:
        if pool is not None:  # an error or ^C leaves no frame running
            pool.shutdown(wait=True, cancel_futures=True)
        for ext in external.values():
            ext.close()
    return _FrameOutputs(clouds, saturated, scatterer_table(scat), floor_rows, reference,
                         {name: ext.elapsed_s for name, ext in external.items()})


def _point_clouds(comps: Components, radar: dict, adc: dict, jobs: dict) -> dict:
    """Point cloud of every job (key -> (mimo, processing config)), keys in `jobs`' order:
    one `process_frames` call per ADC frame where the components have it, else
    `process_frame` per job."""
    if comps.process_frames is None:
        return {key: comps.process_frame(radar[m], adc[m], p) for key, (m, p) in jobs.items()}
    by_mimo: dict[str, list] = {}
    for key, (m, p) in jobs.items():
        by_mimo.setdefault(m, []).append((key, p))
    out = {}
    for m, items in by_mimo.items():
        out.update(zip([key for key, _ in items],
                       comps.process_frames(radar[m], adc[m], [p for _, p in items])))
    return {key: out[key] for key in jobs}


def _track_scheme(spec: CellSpec, comps: Components, run, cfg, clouds: list[pd.DataFrame],
                  frames: np.ndarray, times: pd.Series, ego_speeds, truth: pd.DataFrame):
    """Tracks of one scheme (frames mapped back to scene frames) and their metrics, or
    (None, None) when the tracker returns nothing."""
    tr = comps.track(cfg, clouds, times.to_numpy(), ego_speeds, getattr(run, "mount", None),
                     dict(spec.tracker), frame_rng(spec.seed, 0, "track"))
    if tr is None:
        return None, None
    tr = tr.copy()
    # The tracker numbers frames 0.. in sequence order: map back to scene frames.
    tr["frame"] = np.asarray(frames)[tr["frame"].to_numpy(dtype=np.int64)]
    tm = comps.track_metrics(tr, truth, getattr(run, "mount", None)) \
        if comps.track_metrics is not None else None
    return tr, tm


def _simulate_frames(comps: Components, radar: dict, sc, seed: int, frame, rows, equipment):
    """ADC frame per mimo (with the equipped actors' radars as interferers) and the in-burst
    interference-to-noise ratio at the victim's ADC, dB (NaN without interferers)."""
    itf = None
    inr = float("nan")
    if equipment is not None and comps.interferers is not None:
        from radarsim.interference import interference_to_noise_db
        first = next(iter(radar.values()))
        itf = comps.interferers(first, rows, equipment)
        inr = interference_to_noise_db(first, itf) if len(itf) else inr
    adc = {}
    for m in radar:
        rng = frame_rng(seed, frame, m)
        adc[m] = comps.simulate_frame(radar[m], sc, rng, itf) if itf is not None and len(itf) \
            else comps.simulate_frame(radar[m], sc, rng)
    return adc, inr


def _noise_floors(comps: Components, radar: dict, adc: dict, procs: dict, schemes, frame,
                  inr: float, refs: dict | None = None) -> list[dict]:
    """Per scheme: noise-floor rise over thermal after the range and Doppler FFTs (the
    chirp-level chain of its processing config applied), and the frame's INR; for the schemes
    of `refs` also the Doppler floor with their reference (mitigation-off) processing."""
    if comps.noise_floor is None:
        return []
    from pipeline.chirp_level import noise_floor_key
    out, cache = [], {}

    def floor(mimo, p):
        key = (mimo, *noise_floor_key(p))
        if key not in cache:
            cache[key] = comps.noise_floor(radar[mimo], adc[mimo], p)
        return cache[key]
    for rs in schemes:
        r_db, d_db = floor(rs.mimo, procs[rs.name])
        row = {"scheme": rs.name, "frame": np.int64(frame), "interference_to_noise_db": inr,
               "noise_floor_rise_range_db": r_db, "noise_floor_rise_db": d_db}
        if refs and rs.name in refs:
            row["noise_floor_rise_unmitigated_db"] = floor(rs.mimo, refs[rs.name])[1]
        out.append(row)
    return out


def _with_ids(df: pd.DataFrame, ids: dict, scheme: bool = True) -> pd.DataFrame:
    df = df.copy()
    for i, (k, v) in enumerate(ids.items()):
        if k in df.columns:
            df = df.drop(columns=k)
        df.insert(i, k, v)
    if scheme and "scheme" in df.columns:
        col = df.pop("scheme")
        df.insert(len(ids), "scheme", col)
    return df
