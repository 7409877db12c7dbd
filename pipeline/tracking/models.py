"""Motion models and the radar measurement model of the tracker, each with its Jacobian.

State: [x, y, vx, vy(, ax, ay)] in the vehicle frame (ISO 8855: x forward, y left), m, m/s,
m/s^2; the velocity is RELATIVE to the ego. Motion models are linear, so the Jacobian of the
transition is the transition matrix F itself; the measurement (range, radar-frame azimuth,
radial velocity) is not, and `RangeAzimuthDoppler.predict` returns h(x) with its Jacobian H.
A new motion model is one `MotionModel` entry of `MOTION_MODELS` (and, if it needs its own
noise intensity, one field of `TrackerConfig` that `sigma_field` names).

References
----------
.. [1] Y. Bar-Shalom, X. R. Li, T. Kirubarajan, "Estimation with Applications to Tracking and
       Navigation", Wiley 2001, sections 6.2 (discrete white-noise acceleration and jerk
       models) and 10.3 (EKF).
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["MotionModel", "MOTION_MODELS", "RangeAzimuthDoppler", "measurement_model",
           "wrap_pi"]


def wrap_pi(a: np.ndarray) -> np.ndarray:
    """Angle(s) wrapped to [-pi, pi), rad."""
    return (a + np.pi) % (2 * np.pi) - np.pi


@dataclass(frozen=True, slots=True)
class MotionModel:
    """A linear motion model of the 2D state [x, y, vx, vy(, ax, ay)].

    Attributes
    ----------
    name : str
    n_state : int
        4 (constant velocity) or 6 (constant acceleration).
    transition : callable(dt_s) -> (n_state, n_state) float
        F; for a linear model also the Jacobian of the transition.
    process_noise : callable(dt_s, sigma) -> (n_state, n_state) float
        Discrete white-noise acceleration (CV, sigma in m/s^2) or jerk (CA, m/s^3) [1].
    sigma_field : str
        The `TrackerConfig` field holding sigma.
    """

    name: str
    n_state: int
    transition: Callable[[float], np.ndarray]
    process_noise: Callable[[float, float], np.ndarray]
    sigma_field: str

    def jacobian(self, dt_s: float) -> np.ndarray:
        """d f(x) / d x = F (the model is linear)."""
        return self.transition(dt_s)


#: The per-axis identity of `_per_axis` (read-only).
_EYE2 = np.eye(2)
_EYE2.setflags(write=False)


def _per_axis(block: np.ndarray) -> np.ndarray:
    # State order is [x, y, vx, vy, ax, ay]: derivative order major, axis minor.
    # np.kron(block, eye(2)) as the one broadcast product kron computes (the same products,
    # signed zeros included), without kron's general-shape bookkeeping (two calls a frame).
    n = block.shape[0]
    return (block[:, None, :, None] * _EYE2[None, :, None, :]).reshape(2 * n, 2 * n)


def _cv_transition(dt: float) -> np.ndarray:
    return _per_axis(np.array([[1.0, dt], [0.0, 1.0]]))


def _cv_noise(dt: float, sigma: float) -> np.ndarray:
    g = np.array([dt * dt / 2, dt])
    return _per_axis(np.outer(g, g)) * sigma ** 2


def _ca_transition(dt: float) -> np.ndarray:
    return _per_axis(np.array([[1.0, dt, dt * dt / 2], [0.0, 1.0, dt], [0.0, 0.0, 1.0]]))


def _ca_noise(dt: float, sigma: float) -> np.ndarray:
    g = np.array([dt ** 3 / 6, dt * dt / 2, dt])
    return _per_axis(np.outer(g, g)) * sigma ** 2


#: Motion models by the name users type in `TrackerConfig.motion_model`.
MOTION_MODELS: dict[str, MotionModel] = {
    "cv": MotionModel("cv", 4, _cv_transition, _cv_noise, "process_noise_accel_mps2"),
    "ca": MotionModel("ca", 6, _ca_transition, _ca_noise, "process_noise_jerk_mps3"),
}


def measurement_model(state: np.ndarray, mount_xy_m: np.ndarray, mount_yaw_rad: float
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Predicted measurements and their Jacobians for a batch of states.

    Parameters
    ----------
    state : (T, n_state) float
        [x, y, vx, vy(, ax, ay)] in the vehicle frame, m, m/s (relative velocity).
    mount_xy_m : (2,) float
        Radar position in the vehicle frame, m.
    mount_yaw_rad : float
        Radar boresight yaw in the vehicle frame, rad.

    Returns
    -------
    h : (T, 3) float
        Range m, radar-frame azimuth rad, radial velocity m/s.
    jac : (T, 3, n_state) float
        d h / d state.
    """
    d = state[:, :2] - mount_xy_m
    v = state[:, 2:4]
    r2 = np.maximum(np.einsum("ti,ti->t", d, d), 1e-6)
    r = np.sqrt(r2)
    dv = np.einsum("ti,ti->t", d, v)
    h = np.column_stack([r, wrap_pi(np.arctan2(d[:, 1], d[:, 0]) - mount_yaw_rad), dv / r])
    jac = np.zeros((state.shape[0], 3, state.shape[1]))
    jac[:, 0, 0:2] = d / r[:, None]
    jac[:, 1, 0] = -d[:, 1] / r2
    jac[:, 1, 1] = d[:, 0] / r2
    jac[:, 2, 0:2] = v / r[:, None] - d * (dv / (r2 * r))[:, None]
    jac[:, 2, 2:4] = d / r[:, None]
    return h, jac


@dataclass(frozen=True, slots=True)
class RangeAzimuthDoppler:
    """The radar's point measurement: range, azimuth (radar frame), radial velocity.

    Parameters
    ----------
    mount_xy_m : (2,) float
        Radar position in the vehicle frame, m.
    mount_yaw_rad : float
        Radar boresight yaw in the vehicle frame, rad.
    noise_cov : (3, 3) float
        Per-point measurement covariance Rm: m^2, rad^2, (m/s)^2.
    """

    mount_xy_m: np.ndarray
    mount_yaw_rad: float
    noise_cov: np.ndarray

    def predict(self, state: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """h (T, 3) and Jacobian (T, 3, n_state) of states (T, n_state), see
        `measurement_model`."""
        return measurement_model(state, self.mount_xy_m, self.mount_yaw_rad)

    def position(self, range_m: np.ndarray, azimuth_rad: np.ndarray) -> np.ndarray:
        """(N, 2) vehicle-frame position of points at range and radar-frame azimuth, m."""
        theta = azimuth_rad + self.mount_yaw_rad
        return self.mount_xy_m + range_m[:, None] * np.column_stack([np.cos(theta),
                                                                      np.sin(theta)])
