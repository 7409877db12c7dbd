"""End to end: the R79 motorcycle case through scenario, RCS model, front end, DDMA chain and
group tracker; UN R79 5.6.4.8.1 asks for the approaching L3 motorcycle to be seen at
S_rear >= 55 m."""
from __future__ import annotations

import numpy as np
import pytest

from harness.cell import components
from harness.cell import config as cellconfig
from harness.cell import run as cell
from harness.cell import spec as cellspec
from harness.sweep import streams
from metrics.tracks import per_actor_track_metrics, track_metrics
from pipeline.tracking import TrackerConfig, track_frames

SCENARIO, SEED = "r79_motorcycle_rear", 0


@pytest.fixture(scope="module")
def ddma_clouds():
    """Per frame (time_s, DDMA point cloud), the ego speeds, the truth and the mount."""
    comps = components.default_components()
    run = comps.run_scenario(SCENARIO, SEED, None)
    radar, procs = cellconfig.build_configs(cellspec.CellSpec(scenario=SCENARIO, seed=SEED), comps)
    ego = run.ego.drop_duplicates("frame").set_index("frame")
    frames = ego.index.to_numpy()
    clouds = []
    for f in frames:
        sc = cell.frame_scatterers(comps, run, int(f), SEED)
        adc = comps.simulate_frame(radar["ddma"], sc, streams.frame_rng(SEED, int(f), "ddma"))
        clouds.append((float(ego.loc[f, "time_s"]),
                       comps.process_frame(radar["ddma"], adc, procs["ddma"])))
    return clouds, ego["ego_speed_mps"].to_numpy(float), run.truth, run.mount


@pytest.mark.slow
@pytest.mark.parametrize("ego_source", ["bus", "ransac"])
def test_r79_motorcycle_confirmed_beyond_55_m(ddma_clouds, ego_source):
    clouds, ego_speed, truth, mount = ddma_clouds
    cfg = TrackerConfig.from_fields(
        mount_x_m=mount.x_m, mount_y_m=mount.y_m, mount_yaw_deg=mount.yaw_deg,
        frame_period_s=float(np.median(np.diff([t for t, _ in clouds]))))
    tracks = track_frames(clouds, cfg, ego_speeds_mps=ego_speed if ego_source == "bus" else None,
                          rng=np.random.default_rng(SEED))
    # track_frames numbers frames 0.. in sequence order; the scenario's frames start at 0 too.
    moto = truth[truth.actor_class == "motorcycle"].actor_id.unique()
    assert moto.size == 1
    actors = per_actor_track_metrics(tracks, truth).set_index("actor_id")
    assert actors.loc[moto[0], "track_confirm_range_m"] >= 55.0
    # One track all along, and the guard rails (static clutter) start no confirmed track.
    assert actors.loc[moto[0], "n_track_ids"] == 1
    assert track_metrics(tracks, truth)["n_false_tracks"] == 0
