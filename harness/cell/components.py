"""The parts a cell wires together: scenario runner, RCS model, front end, chain, tracker.

They come through a `Components` bundle of module-level callables, so tests can substitute
fakes and the bundle pickles to process-pool and Dask workers. `default_components` gives the
real ones (imported when first called, so the CLI starts fast).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import pandas as pd

__all__ = ["Components", "default_components", "TRAFFIC_SIM_RATE_HZ", "mount_value",
           "tracker_config"]


@dataclass(frozen=True)
class Components:
    """The parts a cell wires together (module-level callables, so it pickles).

    run_scenario(name, seed, duration_s[, frame_rate_hz=]) -> object with ``truth``, ``ego``,
    ``mount``,
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
    interference_to_noise(radar_cfg, interferers) -> dB (NaN without interferers);
    process_frames(cfg, adc, procs) -> one point cloud per processing config, in order, each
    what process_frame gives (the chain computes the stages they share once); None: the cell
    calls process_frame per config. A bundle that replaces process_frame sets it too, or None.
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
    process_frames: Callable | None = None

    def __post_init__(self) -> None:
        if self.process_frames is _real_process_frames \
                and self.process_frame is not _real_process_frame:
            raise ValueError("Components: process_frame is replaced but process_frames is "
                             "still the built-in chain's; set process_frames=None (or to the "
                             "replacement's own batch form)")


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


def _real_process_frames(cfg, adc, procs):
    import pipeline
    return pipeline.process_frames(cfg, adc, procs)


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
    tcfg = tracker_config(overrides, mount, times_s)
    return trk.track_frames(list(zip(map(float, times_s), clouds)), tcfg,
                            ego_speeds_mps=None if ego_speeds_mps is None
                            else list(map(float, ego_speeds_mps)), rng=rng)


def tracker_config(overrides: dict, mount=None, times_s=()):
    """`TrackerConfig` of a cell: the sweep's tracker `overrides` (dotted keys, sub-config
    tables or objects; a flat key of the previous release warns with the new key), the case's
    radar mount and the frames' median period where the overrides do not set them."""
    from pipeline import tracking as trk
    kw = trk.tracker_paths(overrides, stacklevel=4)
    if mount is not None and "mount" not in kw:
        for key in ("x_m", "y_m", "yaw_deg"):
            val = mount_value(mount, key)
            if val is not None:
                kw.setdefault(f"mount.mount_{key}", float(val))
    if len(times_s) > 1 and "motion" not in kw:
        kw.setdefault("motion.frame_period_s", float(np.median(np.diff(times_s))))
    return trk.TrackerConfig().replace(**kw)


def mount_value(mount, key):
    if isinstance(mount, dict):
        return mount.get(key)
    if isinstance(mount, pd.Series):
        return mount.get(key)
    return getattr(mount, key, None)


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
                      interferers=_real_interferers, noise_floor=_real_noise_floor,
                      process_frames=_real_process_frames)
