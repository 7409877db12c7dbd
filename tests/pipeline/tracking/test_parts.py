"""Injected tracker parts: a user's part replaces the default without editing the tracker, and
the default parts leave their inputs untouched."""
from __future__ import annotations

import copy
import dataclasses

import numpy as np
import pandas as pd
import pytest

from pipeline.tracking import (
    ASSOCIATORS,
    MOTION_MODELS,
    AllocationConfig,
    Association,
    AssociationRules,
    GateConfig,
    GatedMaximumLikelihood,
    GatedNearestNeighbour,
    GroupGateHypothesiser,
    GroupTracker,
    GroupUpdateConfig,
    Hypotheses,
    KalmanPredictor,
    LeaderClusterAllocator,
    Points,
    TrackerConfig,
    Tracks,
)
from pipeline.tracking.config import FIELD_GROUP

from .test_tracker import synth_points, tracker_cfg

CAR = (30.0, 5.0, -4.0, 0.0, 4.5, 1.8)


class NoAssociation:
    """An associator that never associates: every frame's points are unassociated."""

    def __init__(self):
        self.calls = 0

    def associate(self, hypotheses: Hypotheses, tracks: Tracks,
                  static: np.ndarray) -> Association:
        self.calls += 1
        n = hypotheses.n_points
        return Association(np.full(n, -1), np.zeros((n, 3)),
                           np.zeros((tracks.size, 3, tracks.x.shape[1])))


def test_swapped_associator_is_used(rng):
    cfg = tracker_cfg(merge_tracks=False)
    part = NoAssociation()
    tracker = GroupTracker(cfg, associator=part)
    for i in range(4):
        tab = tracker.step(synth_points(rng, [CAR]), 0.05 * i, 0.0)
    assert part.calls == 4
    # without association no track is ever hit twice: all stay DETECT, one new per frame
    assert set(tab.state) == {"DETECT"} and tab.age_frames.min() == 1


def test_swapped_motion_model_through_the_predictor(rng):
    """A predictor with a different process-noise intensity changes the covariance only."""
    cfg = tracker_cfg()
    loose = GroupTracker(cfg, predictor=KalmanPredictor(MOTION_MODELS["cv"], 30.0))
    tight = GroupTracker(cfg)
    for i in range(6):
        pc = synth_points(rng, [CAR])
        a, b = loose.step(pc, 0.05 * i, 0.0), tight.step(pc, 0.05 * i, 0.0)
    assert (a.var_vx_m2ps2 > b.var_vx_m2ps2).all()


@pytest.mark.parametrize("part", ["associator", "allocator"])
def test_default_parts_do_not_edit_their_inputs(rng, part):
    cfg = TrackerConfig()
    tracker = GroupTracker(cfg)
    for i in range(3):
        tracker.step(synth_points(rng, [CAR]), 0.05 * i, 0.0)
    tracks = tracker.tracks
    pts = Points.from_frame(synth_points(rng, [CAR, (50.0, -10.0, 5.0, 0.0, 4.5, 1.8)]))
    static = np.zeros(pts.size, bool)
    before = copy.deepcopy((tracks, pts, static))
    if part == "associator":
        hyp = GroupGateHypothesiser(cfg.gating, tracker.sensor).hypothesise(tracks, pts)
        GatedMaximumLikelihood(AssociationRules()).associate(hyp, tracks, static)
    else:
        new = LeaderClusterAllocator(cfg.allocation, tracker.sensor, merging=cfg.merging,
                                     n_state=cfg.n_state).allocate(pts, ~static, None, tracks,
                                                                   10)
        assert new.size >= 1 and new.members.size == new.member_track.size
    for x, y in zip(_arrays(tracks, pts, static), _arrays(*before)):
        np.testing.assert_array_equal(x, y)


def _arrays(tracks: Tracks, pts: Points, static: np.ndarray) -> list[np.ndarray]:
    return [*(getattr(tracks, f.name) for f in dataclasses.fields(tracks)), *pts, static]


# ----------------------------------------------------------------------------- per-part configs
@pytest.mark.parametrize("part_cfg", [GateConfig, AssociationRules, GroupUpdateConfig,
                                      AllocationConfig], ids=lambda c: c.__name__)
def test_each_part_reads_its_own_few_fields(part_cfg):
    """A part's config is built from the TrackerConfig's same-named fields, and holds only
    what the part reads (far fewer than the tracker's)."""
    cfg = TrackerConfig.from_fields(gate_width_m=2.5, centroid_jitter_weight=0.5,
                                    alloc_min_points=2, allow_static_tracks=True)
    names = [f.name for f in dataclasses.fields(part_cfg)]
    assert set(names) <= set(FIELD_GROUP)
    assert len(names) < len(FIELD_GROUP) // 2
    built = GroupTracker(cfg)
    parts = {GateConfig: built.hypothesiser, AssociationRules: built.associator,
             GroupUpdateConfig: built.updater, AllocationConfig: built.allocator}
    assert isinstance(parts[part_cfg].cfg, part_cfg)
    assert all(getattr(parts[part_cfg].cfg, n) == getattr(cfg, n) for n in names)


@pytest.mark.parametrize("part_cfg,kw,match", [
    (GateConfig, dict(gate_mahalanobis=0.0), r"gate_mahalanobis=0.0 must be"),
    (AssociationRules, dict(allow_static_tracks=1), r"allow_static_tracks=1 must be"),
    (GroupUpdateConfig, dict(dispersion_update_weight=1.5), r"dispersion_update_weight=1.5"),
    (AllocationConfig, dict(alloc_min_points=0), r"alloc_min_points=0 must be")],
    ids=["gate", "rules", "update", "allocation"])
def test_part_configs_validate(part_cfg, kw, match):
    good = part_cfg()
    with pytest.raises(ValueError, match=match):
        dataclasses.replace(good, **kw)


def test_a_sweep_picks_the_associator_by_name(rng):
    """TrackerConfig(associator=...) (a sweep's tracker section) builds the registered part;
    an unknown name is refused naming the known ones."""
    assert sorted(ASSOCIATORS) == ["max_likelihood", "nearest"]
    near = GroupTracker(tracker_cfg(associator="nearest"))
    assert isinstance(near.associator, GatedNearestNeighbour)
    tab = None
    for i in range(5):
        tab = near.step(synth_points(rng, [CAR]), 0.05 * i, 0.0)
    assert (tab.state == "ACTIVE").sum() == 1
    with pytest.raises(ValueError, match=r"associator='gnn' is not one of \['max_likelihood', "
                                         r"'nearest'\]"):
        TrackerConfig.from_fields(associator="gnn")


def test_the_hypothesiser_gates_and_the_associator_only_chooses(rng):
    """The hypothesiser's innovations and gates drive the choice: with every pair ungated no
    point is associated, whatever the distances."""
    cfg = TrackerConfig()
    tracker = GroupTracker(cfg)
    for i in range(3):
        tracker.step(synth_points(rng, [CAR]), 0.05 * i, 0.0)
    pts = Points.from_frame(synth_points(rng, [CAR]))
    hyp = tracker.hypothesiser.hypothesise(tracker.tracks, pts)
    k = hyp.track.size
    assert hyp.innovation.shape == (k, 3) and hyp.distance2.shape == hyp.gated.shape == (k,)
    assert hyp.gated.any() and hyp.n_points == pts.size and hyp.n_tracks == tracker.n_tracks
    # Candidates are the pairs within the velocity limit; the innovation is point minus h(x).
    h, _ = tracker.sensor.predict(tracker.tracks.x)
    np.testing.assert_array_equal(hyp.innovation[:, 2],
                                  pts.radial_velocity_mps[hyp.point] - h[hyp.track, 2])
    assert (np.abs(hyp.innovation[:, 2]) <= cfg.gate_velocity_mps).all()
    static = np.zeros(pts.size, bool)
    chosen = GatedMaximumLikelihood(AssociationRules()).associate(hyp, tracker.tracks, static)
    hit = chosen.track_index >= 0
    assert hit.any()
    pair = {(int(a), int(b)): i for i, (a, b) in enumerate(zip(hyp.track, hyp.point))}
    for p in np.flatnonzero(hit):
        i = pair[(int(chosen.track_index[p]), int(p))]
        assert hyp.gated[i]
        np.testing.assert_array_equal(chosen.innovation[p], hyp.innovation[i])
    closed = GatedMaximumLikelihood(AssociationRules()).associate(
        hyp._replace(gated=np.zeros_like(hyp.gated)), tracker.tracks, static)
    assert (closed.track_index == -1).all()


def test_the_gate_distance_is_the_innovation_under_the_group_covariance(rng):
    """distance2 = y' S^-1 y with S = H P H' + Rm + D per track: bit for bit what numpy's
    stacked (1 x 3) @ (3 x 3) product gives (the gate sums its terms in that order)."""
    tracker = GroupTracker(TrackerConfig())
    for i in range(3):
        tracker.step(synth_points(rng, [CAR, (60.0, -15.0, 6.0, 0.0, 4.5, 1.8)]), 0.05 * i, 0.0)
    tracks = tracker.tracks
    pts = Points.from_frame(synth_points(rng, [CAR, (60.0, -15.0, 6.0, 0.0, 4.5, 1.8)]))
    hyp = tracker.hypothesiser.hypothesise(tracks, pts)
    assert hyp.track.size > 0
    _, jac = tracker.sensor.predict(tracks.x)
    s_inv = np.linalg.inv(jac @ tracks.p @ jac.transpose(0, 2, 1) + tracker.sensor.noise_cov
                          + tracks.dispersion)[hyp.track]
    y = hyp.innovation
    np.testing.assert_array_equal(hyp.distance2,
                                  np.sum((y[:, None, :] @ s_inv)[:, 0, :] * y, axis=-1))


def test_points_from_frame_reads_the_columns_whatever_else_the_frame_holds():
    """The whole-frame conversion gives each column's own float64 values: float32 and int
    columns, extra bool columns, a string column (the column-by-column path), attrs."""
    rng = np.random.default_rng(3)
    n = 7
    base = pd.DataFrame({"range_m": rng.uniform(1, 90, n), "azimuth_deg": rng.uniform(-60, 60, n),
                         "radial_velocity_mps": rng.normal(0, 9, n),
                         "snr_db": rng.uniform(10, 40, n).astype(np.float32)})
    want = [base[c].to_numpy(dtype=np.float64) for c in base.columns]
    want[1] = np.radians(want[1])
    extra = {"ints": base.assign(range_bin=np.arange(n), saturated=False,
                                 range_m=np.arange(1, n + 1)),
             "strings": base.assign(label=["TRUE"] * n)}
    extra["ints"].attrs["saturation"] = {"n_saturated_chirp_rx": 0}
    for name, frame in extra.items():
        got = Points.from_frame(frame)
        ref = [frame[c].to_numpy(dtype=np.float64)
               for c in ("range_m", "azimuth_deg", "radial_velocity_mps", "snr_db")]
        ref[1] = np.radians(ref[1])
        for g, w in zip(got, ref):
            assert g.dtype == np.float64 and g.flags.c_contiguous
            np.testing.assert_array_equal(g, w, err_msg=name)
    np.testing.assert_array_equal(Points.from_frame(base).snr_db, want[3])


@pytest.mark.parametrize("name", sorted(MOTION_MODELS))
def test_motion_model_matrices_are_the_per_axis_kronecker_products(name):
    """F and Q of each model are kron(block, I2) of the 1-D block, bit for bit (the state is
    derivative-major, axis-minor); the 1-D CV block at dt is [[1, dt], [0, 1]]."""
    from pipeline.tracking.models import _per_axis
    g = np.random.default_rng(5)
    for n in (2, 3):
        for _ in range(50):
            block = g.normal(size=(n, n)) * 10 ** g.uniform(-4, 4)
            block[g.random((n, n)) < 0.3] = 0.0
            assert _per_axis(block).tobytes() == np.kron(block, np.eye(2)).tobytes()
    model = MOTION_MODELS[name]
    f = model.transition(0.05)
    assert f.shape == (model.n_state, model.n_state)
    assert f[0, 2] == 0.05 and f[1, 3] == 0.05 and f[0, 3] == 0.0 and f[0, 0] == 1.0
    q = model.process_noise(0.05, 2.0)
    np.testing.assert_array_equal(q, q.T)
