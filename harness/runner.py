"""One sweep cell: scenario x radar/processing overrides x seed -> result tables.

A cell runs the scenario once, and for every processed frame builds the scatterers of the
scene, simulates one ADC frame per MIMO scheme of the cell (``CellSpec.schemes``, names of
``radarsim.MIMO_SCHEMES``; independent noise: generator ``SeedSequence([seed, frame, stream])``
with stream 0 = RCS model, 1 = DDMA ADC, 2 = TDMA ADC, 3 = the tracker's RANSAC (frame 0)
and, for every other scheme, a stream id derived from its name alone, so adding or removing a scheme never changes another scheme's
numbers), processes each result scheme (a registered scheme, or a variant its receive chain
declares in ``pipeline.MIMO_CHAINS``, e.g. ``tdma_raw`` = TDMA without velocity disambiguation
on the same TDMA ADC frame), optionally tracks each scheme, and scores everything with
`metrics`. The SNR gain of each scheme is taken over ``CellSpec.baseline_scheme`` on the same
actor and frame.

Same spec -> bit-identical tables: all randomness comes from the seed, and no timing or host
information enters the tables (timings go to ``CellResult.elapsed_s``).

The parts (scenario runner, RCS model, front end, chain, tracker) come through a `Components`
bundle of module-level callables, so tests can substitute fakes and the bundle pickles to
process-pool and Dask workers.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import re
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pandas as pd

from metrics import detection as mdet
from metrics.association import (AssociationConfig, actor_frames, associate, detection_errors,
                                 scatterer_table)

__all__ = ["CellSpec", "Components", "CellResult", "ResultScheme", "DEFAULT_SCHEMES",
           "DEFAULT_BASELINE_SCHEME", "SEED_STREAMS", "TABLES", "default_components", "run_cell",
           "frame_rng", "stream_id", "result_schemes", "known_schemes", "build_configs",
           "radar_config", "cell_association", "simulate_cell_frame", "frame_scatterers"]

#: Result schemes of a cell when none are given (the scheme column's values).
DEFAULT_SCHEMES: tuple[str, ...] = ("ddma", "tdma", "tdma_raw")
#: Scheme the SNR gain is taken over.
DEFAULT_BASELINE_SCHEME = "tdma"
#: Random streams of one frame with fixed ids: SeedSequence([seed, frame, stream]). Any other
#: stream (a MIMO scheme's ADC noise) gets `stream_id(name)`, derived from its name alone.
SEED_STREAMS: dict[str, int] = {"rcs": 0, "ddma": 1, "tdma": 2, "track": 3}
#: Tables a cell returns (all pandas DataFrames, written as Parquet).
TABLES = ("summary", "detections", "frames", "actors", "actor_summary", "truth", "tracks")

@dataclass(frozen=True, kw_only=True)
class CellSpec:
    """What one sweep cell runs.

    Parameters
    ----------
    scenario : str
        Catalogue name (``scenarios.SCENARIOS``).
    seed : int
        Scenario and noise seed (>= 0).
    variant : str
        Name of the config variant (the sweep's label for ``radar``/``processing``/...).
    radar : dict
        `RadarConfig` field overrides applied to both presets (e.g. phase_noise_deg_rms).
    processing : dict
        `ProcessingConfig` overrides; keys ``cfar_<field>`` change the CFAR.
    tracker : dict
        Tracker config overrides (if the tracker exists).
    frame_stride : int
        Process every k-th frame (>= 1).
    duration_s : float or None
        Scenario duration override, s (None: the case's own).
    schemes : tuple of str
        Result schemes, in table order: `radarsim.MIMO_SCHEMES` names or variants their
        chains declare (`known_schemes`).
    baseline_scheme : str
        Scheme the SNR gain is taken over (the gain columns of its own row are NaN, as are
        those of every scheme when it is not run).
    scene : dict
        Scene overrides (`SCENE_FIELDS`): ``equipped_share`` replaces the case's share of
        vehicles carrying radars (interference).
    association : dict
        `metrics.association.AssociationConfig` overrides (the sweep's ``[association]``);
        the radar-dependent settings otherwise come from the cell's configs
        (`cell_association`).

    ``radar`` may hold ``profile``: a TI .cfg path whose `RadarConfig` replaces the R79
    preset (the other radar keys then override the profile's fields).
    """

    scenario: str
    seed: int = 0
    variant: str = "baseline"
    radar: dict = field(default_factory=dict)
    processing: dict = field(default_factory=dict)
    tracker: dict = field(default_factory=dict)
    frame_stride: int = 1
    duration_s: float | None = None
    schemes: tuple[str, ...] = DEFAULT_SCHEMES
    baseline_scheme: str = DEFAULT_BASELINE_SCHEME
    scene: dict = field(default_factory=dict)
    association: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.scenario, str) or not self.scenario:
            raise ValueError(f"scenario={self.scenario!r} must be a non-empty name")
        check_scene(self.scene)
        object.__setattr__(self, "schemes", tuple(self.schemes))
        result_schemes(self.schemes)
        if not isinstance(self.baseline_scheme, str) or \
                self.baseline_scheme not in known_schemes():
            raise ValueError(f"baseline_scheme={self.baseline_scheme!r} is not one of "
                             f"{known_schemes()}")
        if not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise ValueError(f"seed={self.seed!r} must be an integer >= 0")
        if not isinstance(self.frame_stride, (int, np.integer)) or self.frame_stride < 1:
            raise ValueError(f"frame_stride={self.frame_stride!r} must be an integer >= 1")
        if self.duration_s is not None and not self.duration_s > 0:
            raise ValueError(f"duration_s={self.duration_s!r} must be > 0")

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @property
    def cell_id(self) -> str:
        """File-system safe, unique id: scenario, variant, seed and a hash of the overrides.

        The scheme fields enter the hash only when they differ from the defaults, so cells
        written before they existed keep their ids."""
        d = self.to_dict()
        if tuple(d["schemes"]) == DEFAULT_SCHEMES:
            del d["schemes"]
        if d["baseline_scheme"] == DEFAULT_BASELINE_SCHEME:
            del d["baseline_scheme"]
        if not d["scene"]:
            del d["scene"]
        if not d["association"]:
            del d["association"]
        blob = json.dumps(d, sort_keys=True, default=str)
        h = hashlib.sha1(blob.encode()).hexdigest()[:8]
        safe = re.sub(r"[^A-Za-z0-9_.=-]+", "-", f"{self.scenario}__{self.variant}")
        return f"{safe}__s{self.seed}__{h}"


@dataclass(frozen=True)
class Components:
    """The parts a cell wires together (module-level callables, so it pickles).

    run_scenario(name, seed, duration_s[, frame_rate_hz=]) -> object with ``truth``, ``ego``, ``mount``,
    ``case`` (and optionally ``radar_velocity_mps()``); scene_scatterers(truth_rows, rng,
    [radar_velocity_mps=, mount_height_m=]) -> Scatterers; simulate_frame(cfg, sc, rng) ->
    ADC (simulate_frame(cfg, sc, rng, interferers) when the frame has interferers);
    process_frame(cfg, adc, proc) -> point cloud; make_processing(overrides) ->
    ProcessingConfig; track(radar_cfg, clouds, times_s, ego_speeds_mps, mount, overrides,
    rng) -> tracks table (``frame`` = index in the sequence) or None;
    track_metrics(tracks, truth, mount) -> dict of numbers or None;
    equipment(run, seed, scene) -> per-actor radar table (empty: no interference);
    interferers(radar_cfg, truth_rows, equipment) -> radarsim.interference.Interferers;
    noise_floor(radar_cfg, adc, proc) -> (rise after range FFT, after Doppler FFT), dB;
    interference_to_noise(radar_cfg, interferers) -> dB (NaN without interferers).
    """

    run_scenario: Callable
    scene_scatterers: Callable
    simulate_frame: Callable
    process_frame: Callable
    make_processing: Callable
    track: Callable | None = None
    track_metrics: Callable | None = None
    equipment: Callable | None = None
    interferers: Callable | None = None
    noise_floor: Callable | None = None


#: highway-env integration rate of the catalogue's traffic, Hz (the sweep's 20 Hz frames).
TRAFFIC_SIM_RATE_HZ = 20.0


def _real_run_scenario(name, seed, duration_s, frame_rate_hz=20.0):
    import scenarios
    # A TI profile's frames can be slower than the traffic's integration (R79: 250 ms): integrate
    # in substeps so highway-env still steps at >= 20 Hz and the drivers decide at their 10 Hz.
    substeps = max(1, int(np.ceil(TRAFFIC_SIM_RATE_HZ / frame_rate_hz - 1e-9)))
    return scenarios.run_scenario(name, seed, duration_s=duration_s, frame_rate_hz=frame_rate_hz,
                                  substeps=substeps)


def _real_scene_scatterers(truth_rows, rng, radar_velocity_mps=None, mount_height_m=None):
    from radarsim import rcs
    return rcs.scene_scatterers(truth_rows, rng, radar_velocity_mps=radar_velocity_mps,
                                mount_height_m=mount_height_m)


def _real_make_processing(overrides: dict):
    import pipeline
    return pipeline.ProcessingConfig().replace(**overrides)


def _real_process_frame(cfg, adc, proc):
    import pipeline
    return pipeline.process_frame(cfg, adc, proc)


def _real_simulate_frame(cfg, sc, rng, interferers=None):
    import warnings

    import radarsim
    with warnings.catch_warnings():
        # Saturation is a property of the scene (a car at 2 m); it is counted, not fatal.
        warnings.simplefilter("ignore", radarsim.ADCSaturationWarning)
        return radarsim.simulate_frame(cfg, sc, rng, interferers)


def _real_track(radar_cfg, clouds, times_s, ego_speeds_mps, mount, overrides, rng):
    """Run the group tracker over one scheme's point clouds."""
    from pipeline import tracking as trk
    kw = dict(overrides)
    if mount is not None:
        for key in ("x_m", "y_m", "yaw_deg"):
            val = _mount_value(mount, key)
            if val is not None:
                kw.setdefault(f"mount_{key}", float(val))
    if len(times_s) > 1:
        kw.setdefault("frame_period_s", float(np.median(np.diff(times_s))))
    tcfg = trk.TrackerConfig(**kw)
    return trk.track_frames(list(zip(map(float, times_s), clouds)), tcfg,
                            ego_speeds_mps=None if ego_speeds_mps is None
                            else list(map(float, ego_speeds_mps)), rng=rng)


def _mount_value(mount, key):
    if isinstance(mount, dict):
        return mount.get(key)
    if isinstance(mount, pd.Series):
        return mount.get(key)
    return getattr(mount, key, None)


#: Scene overrides a sweep may give (``[vary] "scene.equipped_share" = [...]``).
SCENE_FIELDS = {"equipped_share": "share of vehicles carrying a radar (interferers), [0, 1]"}


def check_scene(scene) -> None:
    """Validate scene overrides: known keys (`SCENE_FIELDS`), equipped_share in [0, 1]."""
    if not isinstance(scene, dict):
        raise ValueError(f"scene must be a table of field = value, got {scene!r}")
    bad = sorted(set(scene) - set(SCENE_FIELDS))
    if bad:
        raise ValueError(f"unknown scene field(s) {bad}; known: {sorted(SCENE_FIELDS)}")
    share = scene.get("equipped_share", 0.0)
    if isinstance(share, bool) or not isinstance(share, (int, float)) or not 0 <= share <= 1:
        raise ValueError(f"scene.equipped_share={share!r} must be in [0, 1]")


def _real_equipment(run, seed, scene):
    """Radars of the run's actors: the case's explicit radars plus its (or the scene's)
    equipped share, drawn with the seed (`scenarios.equipment.equipment_table`)."""
    from scenarios.equipment import equipment_table
    case = getattr(run, "case", None)
    share = scene.get("equipped_share", getattr(case, "equipped_share", 0.0))
    radars = tuple(getattr(case, "radars", ()) or ())
    if not radars and not share:
        return None
    actors = run.truth.drop_duplicates("actor_id")[["actor_id", "actor_class", "length_m",
                                                    "width_m"]]
    table = equipment_table(actors, seed, equipped_share=float(share), radars=radars)
    return table if len(table) else None


def _real_interferers(cfg, rows, equipment):
    from radarsim.interference import interferers_from_truth
    return interferers_from_truth(cfg, rows, equipment)


def _real_noise_floor(cfg, adc, proc):
    from pipeline.chirp_level import noise_floor_rise
    return tuple(noise_floor_rise(cfg, adc, proc))


def _real_track_metrics(tracks, truth, mount):
    """`metrics.tracks.track_metrics` of one scheme."""
    from metrics import tracks as mtr
    return mtr.track_metrics(tracks, truth)


def default_components() -> Components:
    """The real scenario runner, ray RCS model, front end, chain and tracker."""
    return Components(run_scenario=_real_run_scenario, scene_scatterers=_real_scene_scatterers,
                      simulate_frame=_real_simulate_frame, process_frame=_real_process_frame,
                      make_processing=_real_make_processing, track=_real_track,
                      track_metrics=_real_track_metrics, equipment=_real_equipment,
                      interferers=_real_interferers, noise_floor=_real_noise_floor)


@dataclass
class CellResult:
    """Tables of one cell plus its wall time (kept out of the tables for determinism)."""

    spec: CellSpec
    tables: dict[str, pd.DataFrame]
    elapsed_s: float


def stream_id(stream: str) -> int:
    """Id of a random stream: `SEED_STREAMS` for the fixed ones, otherwise 2^16 plus the first
    31 bits of the SHA-256 of the name, so each scheme's stream depends on its name only."""
    if stream in SEED_STREAMS:
        return SEED_STREAMS[stream]
    if not isinstance(stream, str) or not stream:
        raise ValueError(f"stream={stream!r} must be a non-empty name")
    return 2 ** 16 + (int.from_bytes(hashlib.sha256(stream.encode()).digest()[:4], "big")
                      >> 1)


def frame_rng(seed: int, frame: int, stream: str) -> np.random.Generator:
    """Generator of one random stream of one frame: SeedSequence([seed, frame, stream id])."""
    return np.random.default_rng(np.random.SeedSequence([int(seed), int(frame),
                                                         stream_id(stream)]))


@dataclass(frozen=True)
class ResultScheme:
    """One value of the tables' ``scheme`` column.

    Attributes
    ----------
    name : str
        The column value.
    mimo : str
        The `radarsim.MIMO_SCHEMES` name whose ADC frame it processes.
    processing : dict
        `ProcessingConfig` overrides of a chain variant (empty for the scheme itself).
    """

    name: str
    mimo: str
    processing: dict = field(default_factory=dict)

    @property
    def is_variant(self) -> bool:
        return self.name != self.mimo


def _scheme_table() -> dict[str, ResultScheme]:
    import pipeline
    import radarsim
    out = {}
    for m in radarsim.MIMO_SCHEMES:
        out[m] = ResultScheme(m, m)
        chain = pipeline.MIMO_CHAINS.get(m)
        for v, overrides in (getattr(chain, "variants", None) or {}).items():
            out[v] = ResultScheme(v, m, dict(overrides))
    return out


def known_schemes() -> list[str]:
    """Names `CellSpec.schemes` accepts: every registered MIMO scheme and its chain's
    variants."""
    return list(_scheme_table())


def result_schemes(names=DEFAULT_SCHEMES) -> list[ResultScheme]:
    """Resolve result-scheme names against the registries.

    Raises
    ------
    ValueError
        Empty list, duplicates or unknown names (naming them and the known ones).
    """
    if isinstance(names, str) or not all(isinstance(n, str) for n in names):
        raise ValueError(f"schemes={names!r} must be a list of scheme names")
    names = list(names)
    if not names:
        raise ValueError("schemes: the list is empty")
    if len(set(names)) != len(names):
        raise ValueError(f"schemes={names!r} holds duplicates")
    table = _scheme_table()
    bad = [n for n in names if n not in table]
    if bad:
        raise ValueError(f"schemes: unknown scheme(s) {bad}; known: {list(table)}")
    return [table[n] for n in names]


def _mimos(schemes: list[ResultScheme]) -> list[str]:
    """The MIMO schemes whose ADC frames the result schemes need, in first-use order."""
    return list(dict.fromkeys(s.mimo for s in schemes))


def radar_config(overrides: dict, mimo: str):
    """`RadarConfig` of a cell for one MIMO scheme: the R79 preset with `overrides`, or, when
    they name a ``profile`` (TI .cfg path), that profile's radar run with `mimo` and the other
    overrides.

    Raises
    ------
    ValueError
        If the profile's chip cannot run `mimo` (e.g. DDMA on a chip without phase shifters),
        naming the profile and the scheme.
    """
    import radarsim
    ov = dict(overrides)
    path = ov.pop("profile", None)
    if path is None:
        return radarsim.presets.r79(mimo, **ov)
    from radarsim.ti import from_ti_cfg
    base = from_ti_cfg(Path(path))
    try:
        return base.replace(**{"mimo": mimo, **ov}) if base.mimo != mimo or ov else base
    except ValueError as exc:
        raise ValueError(f"radar.profile={str(path)!r} ({base.chip}, {base.mimo}) as scheme "
                         f"{mimo!r}: {exc}") from exc


def cell_association(radar: dict, overrides: dict | None = None) -> AssociationConfig:
    """Association settings of a cell from its radar configs, then `overrides`.

    The radar-dependent ones follow the configs, not the R79 numbers: the unambiguous-velocity
    window is the widest the cell's schemes report (max of `max_unambiguous_velocity_mps`,
    DDMA's lambda / (4 Tc)), the field of view is the board's (`radarsim.boards.Board.fov_deg`)
    and the maximum range the configs' `max_range_m` (N/2 or N bins x resolution).
    """
    from radarsim.boards import get_board
    cfgs = list(radar.values())
    kw = {"unambiguity_window_mps": max(c.max_unambiguous_velocity_mps for c in cfgs),
          "fov_deg": min(get_board(c.board).fov_deg for c in cfgs),
          "max_range_m": min(c.max_range_m for c in cfgs)}
    kw.update(overrides or {})
    return AssociationConfig(**kw)


def build_configs(spec: CellSpec, comps: Components):
    """(radar config per mimo, processing config per result scheme) of a cell."""
    schemes = result_schemes(spec.schemes)
    radar = {m: radar_config(spec.radar, m) for m in _mimos(schemes)}
    procs = {s.name: comps.make_processing({**spec.processing, **s.processing})
             for s in schemes}
    return radar, procs


def _case_info(run) -> dict[str, Any]:
    """Target actors and pass criteria of the scenario's case (read by attribute)."""
    case = getattr(run, "case", None)
    must = tuple(getattr(case, "must_detect", ()) or ())
    return {"target_ids": list(must) if must else None,
            "criteria": tuple(getattr(case, "criteria", ()) or ())}


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
    height = _mount_value(mount, "z_m") if mount is not None else None
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
    from .runtime import single_thread_blas
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


def run_cell(spec: CellSpec, comps: Components | None = None,
             assoc: AssociationConfig | None = None) -> CellResult:
    """Run one sweep cell and score it.

    Returns
    -------
    CellResult
        ``tables``: ``summary`` (one row per scheme; every scheme's row but the baseline's
        carries its SNR gain over ``spec.baseline_scheme``; chain variants such as
        ``tdma_raw`` share their scheme's ADC frame and get no gain), ``detections`` (long: every detection with its label and errors),
        ``frames`` (per scheme and frame: counts per label), ``actors`` (per scheme, actor and
        frame: visible / detected / peak SNR), ``actor_summary`` (per scheme and actor:
        detection probability, first-detection range), ``truth`` (processed frames), ``tracks``
        (per scheme, frame and track; empty without a tracker). Every table starts with the
        id columns scenario, variant, seed (and scheme where it applies).
    """
    t0 = time.perf_counter()
    comps = comps or default_components()
    run = comps.run_scenario(spec.scenario, spec.seed, spec.duration_s)
    radar, procs = build_configs(spec, comps)
    assoc = assoc or cell_association(radar, spec.association)
    schemes = result_schemes(spec.schemes)
    frames = _frames_of(run, spec.frame_stride)
    truth = run.truth[run.truth["frame"].isin(frames)].reset_index(drop=True)
    ego = getattr(run, "ego", None)
    if ego is not None and "time_s" in ego:
        times = ego.drop_duplicates("frame").set_index("frame")["time_s"]
    else:
        times = truth.groupby("frame")["time_s"].first()
    times = times.reindex(frames).astype(float)

    clouds: dict[str, list[pd.DataFrame]] = {s.name: [] for s in schemes}
    # Saturated (chirp, Rx) pairs per scheme and frame (pipeline.saturation).
    saturated: dict[str, list[int]] = {s.name: [] for s in schemes}
    scat = []
    ctx = _frame_context(run)
    equipment = comps.equipment(run, spec.seed, dict(spec.scene)) \
        if comps.equipment is not None else None
    floor_rows = []
    for f in frames:
        rows = truth[truth["frame"] == f]
        sc = _scatterers(comps, rows, frame_rng(spec.seed, f, "rcs"), ctx.get(int(f)))
        scat.append((f, sc))
        adc, inr = _simulate_frames(comps, radar, sc, spec.seed, f, rows, equipment)
        floor_rows += _noise_floors(comps, radar, adc, procs, schemes, f, inr)
        for rs in schemes:
            pc = comps.process_frame(radar[rs.mimo], adc[rs.mimo], procs[rs.name]) \
                .reset_index(drop=True)
            pc.insert(0, "frame", np.int64(f))
            pc.insert(1, "time_s", float(times.loc[f]))
            clouds[rs.name].append(pc)
            saturated[rs.name].append(int(pc.attrs.get("saturation", {})
                                          .get("n_saturated_chirp_rx", 0)))
    scat_df = scatterer_table(scat)

    info = _case_info(run)
    det_tables, frame_tables, actor_tables, track_tables, rows_out = [], [], [], [], []
    actor_summaries = []
    ego_speeds = None
    if ego is not None and "ego_speed_mps" in ego:
        ego_speeds = ego.drop_duplicates("frame").set_index("frame")["ego_speed_mps"] \
            .reindex(frames).to_numpy(dtype=float)
    for rs in schemes:
        s, m = rs.name, rs.mimo
        pcs = pd.concat(clouds[s], ignore_index=True) if clouds[s] else pd.DataFrame()
        if pcs.empty:
            pcs = pd.DataFrame({c: pd.Series(dtype=float) for c in (
                "frame", "time_s", "range_m", "azimuth_deg", "elevation_deg",
                "radial_velocity_mps", "snr_db", "x_m", "y_m", "z_m")})
            pcs["frame"] = pcs["frame"].astype(np.int64)
        span = 2 * radar[m].max_unambiguous_velocity_mps
        lab = associate(pcs, truth, velocity_span_mps=span, config=assoc, scatterers=scat_df)
        lab = detection_errors(lab, truth, scat_df)
        cfg_m = radar[m]
        lab["velocity_resolution_failure"] = mdet.velocity_resolution_failures(
            pcs, truth, cfg_m.scheme.velocity_failure_step_mps(cfg_m), config=assoc,
            scatterers=scat_df)
        af = actor_frames(lab, truth, scatterers=scat_df, config=assoc)
        row = mdet.summarize_scheme(lab, af, len(frames), assoc,
                                    target_ids=info["target_ids"])
        per_actor = mdet.actor_detection(af)
        actor_summaries.append(per_actor.assign(scheme=s))
        row.update(mdet.case_criteria(info["criteria"], lab, per_actor, row))
        row.update(mdet.velocity_failure_stats(lab))
        if comps.track is not None:
            tr = comps.track(radar[m], clouds[s], times.to_numpy(), ego_speeds,
                             getattr(run, "mount", None), dict(spec.tracker),
                             frame_rng(spec.seed, 0, "track"))
            if tr is not None:
                tr = tr.copy()
                # The tracker numbers frames 0.. in sequence order: map back to scene frames.
                tr["frame"] = np.asarray(frames)[tr["frame"].to_numpy(dtype=np.int64)]
                track_tables.append(tr.assign(scheme=s))
                tm = comps.track_metrics(tr, truth, getattr(run, "mount", None)) \
                    if comps.track_metrics is not None else None
                for k, v in dict(tm or {}).items():
                    if isinstance(v, (int, float, np.integer, np.floating)):
                        # Track metrics keep their names unless they collide (n_frames).
                        row[k if k not in row else f"track_{k}"] = v
        row["n_saturated_frames"] = int(np.count_nonzero(saturated[s]))
        rows_out.append({"scheme": s, **row})
        det_tables.append(lab.assign(scheme=s))
        fc = _frame_counts(lab, frames).assign(
            n_saturated_chirp_rx=np.asarray(saturated[s], dtype=np.int64)
            if saturated[s] else np.zeros(len(frames), dtype=np.int64), scheme=s)
        if floor_rows:
            fl = pd.DataFrame([r for r in floor_rows if r["scheme"] == s]).drop(columns="scheme")
            fc = fc.merge(fl, on="frame", how="left")
            rows_out[-1].update(_floor_summary(fl))
        frame_tables.append(fc)
        actor_tables.append(af.assign(scheme=s))

    actors = pd.concat(actor_tables, ignore_index=True)
    summary = pd.DataFrame(rows_out)
    base = spec.baseline_scheme
    gains = {rs.name: mdet.snr_gain_stats(mdet.snr_gain_pairs(actors, rs.name, base))
             for rs in schemes if not rs.is_variant and rs.name != base
             and base in spec.schemes}
    for k in mdet.snr_gain_stats(pd.DataFrame({"snr_gain_db": pd.Series(dtype=float)})):
        count = k.endswith("_n")
        summary[k] = np.array([gains[s][k] if s in gains else (0 if count else np.nan)
                               for s in summary["scheme"]],
                              dtype=np.int64 if count else float)
    summary["case_pass"] = summary["case_pass"].astype(float)

    ids = {"scenario": spec.scenario, "variant": spec.variant, "seed": int(spec.seed)}
    tracks = pd.concat(track_tables, ignore_index=True) if track_tables else \
        pd.DataFrame({"scheme": pd.Series(dtype=object), "frame": pd.Series(dtype="int64")})
    tables = {
        "summary": _with_ids(summary, ids),
        "detections": _with_ids(pd.concat(det_tables, ignore_index=True), ids),
        "frames": _with_ids(pd.concat(frame_tables, ignore_index=True), ids),
        "actors": _with_ids(actors, ids),
        "actor_summary": _with_ids(pd.concat(actor_summaries, ignore_index=True), ids),
        "truth": _with_ids(truth.copy(), ids, scheme=False),
        "tracks": _with_ids(tracks, ids),
    }
    return CellResult(spec=spec, tables=tables, elapsed_s=time.perf_counter() - t0)


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
                  inr: float) -> list[dict]:
    """Per scheme: noise-floor rise over thermal after the range and Doppler FFTs (the
    chirp-level chain of its processing config applied), and the frame's INR."""
    if comps.noise_floor is None:
        return []
    from pipeline.chirp_level import NOISE_FLOOR_FIELDS
    out, cache = [], {}
    for rs in schemes:
        p = procs[rs.name]
        key = (rs.mimo, *(getattr(p, f) for f in NOISE_FLOOR_FIELDS))
        if key not in cache:
            cache[key] = comps.noise_floor(radar[rs.mimo], adc[rs.mimo], p)
        r_db, d_db = cache[key]
        out.append({"scheme": rs.name, "frame": np.int64(frame),
                    "interference_to_noise_db": inr, "noise_floor_rise_range_db": r_db,
                    "noise_floor_rise_db": d_db})
    return out


def _floor_summary(fl: pd.DataFrame) -> dict:
    """Summary columns of one scheme: medians over frames (INR over frames that have
    interferers; NaN when none has)."""
    inr = fl["interference_to_noise_db"].to_numpy(dtype=float)
    return {"noise_floor_rise_db": float(np.median(fl["noise_floor_rise_db"])),
            "noise_floor_rise_range_db": float(np.median(fl["noise_floor_rise_range_db"])),
            "interference_to_noise_db": float(np.nanmedian(inr)) if np.isfinite(inr).any()
            else float("nan")}


def _frame_counts(lab: pd.DataFrame, frames: np.ndarray) -> pd.DataFrame:
    """Per frame: detections and label counts (frames without detections give zeros)."""
    from metrics.association import LABELS
    ct = pd.crosstab(lab["frame"], lab["label"]) if len(lab) else pd.DataFrame()
    ct = ct.reindex(index=frames, columns=list(LABELS), fill_value=0)
    out = pd.DataFrame({"frame": np.asarray(frames, dtype=np.int64)})
    names = {"TRUE": "n_true", "VELOCITY_AMBIGUOUS": "n_velocity_ambiguous",
             "GHOST": "n_ghost", "CLUTTER": "n_clutter"}
    for lab_name, col in names.items():
        out[col] = ct[lab_name].to_numpy(dtype=np.int64)
    out.insert(1, "n_detections", out[list(names.values())].sum(axis=1))
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
