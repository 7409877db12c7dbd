"""Every catalogue case through the ray-based RCS model, every frame (slow: ~10 s)."""
from __future__ import annotations

import numpy as np
import pytest

from radarsim.rcs import GROUND_ACTOR_ID, scene_scatterers
from scenarios import SCENARIOS, run_scenario


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SCENARIOS))
def test_every_case_full_duration_gives_scatterers(name, catalogue_run):
    case = SCENARIOS[name]
    run = catalogue_run(name)
    rng = np.random.default_rng(0)
    seen = dict.fromkeys(case.must_detect, 0)
    for f in run.frames():
        sc = scene_scatterers(f.truth, rng, radar_velocity_mps=f.radar_velocity_mps,
                              mount_height_m=f.mount_height_m)
        assert 0 < len(sc) < 1000
        ids = set(sc.actor_id.tolist()) - {GROUND_ACTOR_ID, -1}
        assert ids <= set(f.truth.actor_id.tolist())
        for a in seen:
            seen[a] += a in ids
    for a, n in seen.items():
        assert n >= 0.9 * run.n_frames, f"actor {a} illuminated in {n}/{run.n_frames} frames"


def test_first_frame_of_each_case_gives_scatterers():
    """Fast version of the above: frame 0 of every case."""
    for name, case in SCENARIOS.items():
        f = next(iter(run_scenario(name, seed=0, duration_s=0.05)))
        sc = scene_scatterers(f.truth, np.random.default_rng(0),
                              radar_velocity_mps=f.radar_velocity_mps,
                              mount_height_m=f.mount_height_m)
        for a in case.must_detect:
            assert np.any(sc.actor_id == a), name
