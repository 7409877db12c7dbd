"""The tracker's Kalman maths against an independent implementation and against theory.

* One predict/update step of the tracker's parts (CV predictor, gated associator, group EKF
  updater) equals filterpy's ExtendedKalmanFilter with F, Q from filterpy and a numerically
  differentiated measurement function.
* Consistency (Bar-Shalom, Li, Kirubarajan 2001, section 5.4): over Monte Carlo runs of a
  target that moves exactly as the CV model says, the average NEES of each step and the
  time-average NIS lie inside their chi-square bounds.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from pipeline.tracking import GroupTracker, TrackerConfig, Tracks
from pipeline.tracking.models import measurement_model
from pipeline.tracking.track_state import Association, Points

filterpy_kalman = pytest.importorskip("filterpy.kalman")
filterpy_common = pytest.importorskip("filterpy.common")

DT_S = 0.05
MOUNT = (1.0, 0.5, 30.0)  # x_m, y_m, yaw_deg


def _hx(x: np.ndarray) -> np.ndarray:
    """Range, radar-frame azimuth, radial velocity of state [x, y, vx, vy], written
    independently of pipeline.tracking.models."""
    dx, dy = x[0] - MOUNT[0], x[1] - MOUNT[1]
    r = math.hypot(dx, dy)
    return np.array([r, math.atan2(dy, dx) - math.radians(MOUNT[2]),
                     (dx * x[2] + dy * x[3]) / r])


def _numeric_jacobian(x: np.ndarray, step: float = 1e-6) -> np.ndarray:
    return np.column_stack([(_hx(x + e) - _hx(x - e)) / (2 * step)
                            for e in np.eye(x.size) * step])


def _tracker(**kw) -> GroupTracker:
    cfg = TrackerConfig.from_fields(mount_x_m=MOUNT[0], mount_y_m=MOUNT[1],
                                    mount_yaw_deg=MOUNT[2], frame_period_s=DT_S,
                                    centroid_jitter_weight=0.0, **kw)
    return GroupTracker(cfg)


def _tracks(x0: np.ndarray, p0: np.ndarray) -> Tracks:
    """ACTIVE tracks at states x0 (T, 4), covariances p0 (T, 4, 4), no dispersion, n_est 1."""
    t = x0.shape[0]
    return Tracks(np.arange(t), x0, p0, np.zeros((t, 3, 3)), np.ones(t), np.ones(t, np.int64),
                  np.zeros(t, np.int64), np.ones(t, np.int64), np.ones(t, bool))


def test_measurement_jacobian_matches_finite_differences():
    x = np.array([[30.0, 12.0, -8.0, 1.5]])
    _, jac = measurement_model(x, np.array(MOUNT[:2]), math.radians(MOUNT[2]))
    np.testing.assert_allclose(jac[0], _numeric_jacobian(x[0]), rtol=1e-6, atol=1e-9)


def test_one_step_equals_filterpy_ekf():
    """Single point, n_est = 1 and centroid_jitter_weight = 0: the group update is the plain
    EKF update with Rc = Rm (alpha = 0), so both filters must agree to rounding."""
    trk = _tracker()
    x0 = np.array([30.0, 12.0, -8.0, 1.5])
    p0 = np.diag([0.5, 0.8, 2.0, 4.0])
    p0[0, 1] = p0[1, 0] = 0.1

    ekf = filterpy_kalman.ExtendedKalmanFilter(dim_x=4, dim_z=3)
    ekf.x, ekf.P = x0.copy(), p0.copy()
    ekf.F = np.eye(4) + np.diag([DT_S, DT_S], k=2)
    ekf.Q = filterpy_common.Q_discrete_white_noise(
        dim=2, dt=DT_S, var=trk.cfg.process_noise_accel_mps2 ** 2, block_size=2,
        order_by_dim=False)
    ekf.predict()
    z = _hx(ekf.x) + np.array([0.3, 0.01, 0.2])  # a point that passes the gate
    ekf.update(z, _numeric_jacobian, _hx, R=trk.cfg.measurement_noise)

    tracks = trk.predictor.predict(_tracks(x0[None], p0[None]), DT_S)
    np.testing.assert_allclose(tracks.x[0], ekf.x_prior, rtol=1e-12)
    np.testing.assert_allclose(tracks.p[0], ekf.P_prior, rtol=1e-12)
    points = Points(np.array([z[0]]), np.array([z[1]]), np.array([z[2]]), np.array([20.0]))
    assoc = trk.associator.associate(trk.hypothesiser.hypothesise(tracks, points), tracks,
                                     np.zeros(1, bool))
    assert assoc.track_index.tolist() == [0]
    updated, n_points = trk.updater.update(tracks, assoc)
    assert n_points.tolist() == [1]
    np.testing.assert_allclose(updated.x[0], ekf.x, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(updated.p[0], ekf.P, rtol=1e-6, atol=1e-10)


def test_nees_and_nis_within_chi_square_bounds():
    """M Monte Carlo runs (one track each, vectorised as M tracks) of a CV target with
    white-noise acceleration, one point per frame with noise Rm. For a consistent filter
    M x ANEES_k ~ chi2(M n_x) at every step k and the NIS of all M K innovations sums to
    chi2(M K n_z) (innovations are white); bounds at 99.9 %."""
    trk = _tracker()
    cfg = trk.cfg
    rng = np.random.default_rng(11)
    m_runs, k_steps, n_x, n_z = 400, 30, 4, 3
    sigma_a = cfg.process_noise_accel_mps2
    rm = cfg.measurement_noise
    f = np.eye(4) + np.diag([DT_S, DT_S], k=2)
    g = np.array([[DT_S ** 2 / 2, 0], [0, DT_S ** 2 / 2], [DT_S, 0], [0, DT_S]])

    x_est = np.tile([40.0, 25.0, -6.0, 2.0], (m_runs, 1))
    p0 = np.diag([1.0, 1.0, 4.0, 4.0])
    truth = x_est + rng.standard_normal((m_runs, 4)) @ np.linalg.cholesky(p0).T
    tracks = _tracks(x_est, np.tile(p0, (m_runs, 1, 1)))
    sensor = trk.sensor
    anees, nis_sum = [], 0.0
    for _ in range(k_steps):
        truth = truth @ f.T + (rng.standard_normal((m_runs, 2)) * sigma_a) @ g.T
        h_true, _ = measurement_model(truth, sensor.mount_xy_m, sensor.mount_yaw_rad)
        z = h_true + rng.standard_normal((m_runs, 3)) @ np.linalg.cholesky(rm).T
        tracks = trk.predictor.predict(tracks, DT_S)
        h, jac = sensor.predict(tracks.x)
        s = jac @ tracks.p @ jac.transpose(0, 2, 1) + rm
        nu = z - h
        nis_sum += np.einsum("mi,mij,mj->", nu, np.linalg.inv(s), nu)
        tracks, _ = trk.updater.update(tracks, Association(np.arange(m_runs), nu, jac))
        e = truth - tracks.x
        anees.append(np.einsum("mi,mij,mj->m", e, np.linalg.inv(tracks.p), e).mean())
    lo, hi = (stats.chi2.ppf([0.0005, 0.9995], m_runs * n_x) / m_runs)
    assert np.all((np.array(anees) > lo) & (np.array(anees) < hi)), (lo, hi, anees)
    n_nis = m_runs * k_steps
    lo, hi = stats.chi2.ppf([0.0005, 0.9995], n_nis * n_z) / n_nis
    assert lo < nis_sum / n_nis < hi
