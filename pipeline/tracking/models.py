"""Motion models and the radar measurement model of the tracker, each with its Jacobian.

State: [x, y, vx, vy(, ax, ay)] in the vehicle frame (ISO 8855: x forward, y left), m, m/s,
m/s^2; the velocity is RELATIVE to the ego. Motion models are linear, so the Jacobian of the
transition is the transition matrix F itself; the measurement (range, radar-frame azimuth,
radial velocity) is not, and `RangeAzimuthDoppler.predict` returns h(x) with its Jacobian H.
A new motion model is one `MotionModel` entry of `MOTION_MODELS` (and, if it needs its own
noise intensity, one field of `MotionConfig` that `sigma_field` names). The settings read here
are the tracker's `motion`, `mount` and `noise` sub-configs (`MotionConfig`, `MountConfig`,
`MeasurementNoise`).

References
----------
.. [1] Y. Bar-Shalom, X. R. Li, T. Kirubarajan, "Estimation with Applications to Tracking and
       Navigation", Wiley 2001, sections 6.2 (discrete white-noise acceleration and jerk
       models) and 10.3 (EKF).
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from core.checks import one_of, require

__all__ = ["MotionModel", "MOTION_MODELS", "MotionConfig", "MountConfig", "MeasurementNoise",
           "RangeAzimuthDoppler", "measurement_model", "wrap_pi"]


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
        The `MotionConfig` field holding sigma.
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


#: Motion models by the name users type in `MotionConfig.motion_model`.
MOTION_MODELS: dict[str, MotionModel] = {
    "cv": MotionModel("cv", 4, _cv_transition, _cv_noise, "process_noise_accel_mps2"),
    "ca": MotionModel("ca", 6, _ca_transition, _ca_noise, "process_noise_jerk_mps3"),
}


@dataclass(frozen=True, kw_only=True, slots=True)
class MotionConfig:
    """How tracks move between frames (the predictor's settings; ``TrackerConfig.motion``).

    Parameters
    ----------
    motion_model : {"cv", "ca"}
        Constant velocity or constant acceleration, a key of `MOTION_MODELS`.
    frame_period_s : float
        Time step used for the first frame (afterwards the difference of the frame times), s.
    process_noise_accel_mps2 : float
        CV model: standard deviation of the white-noise acceleration (includes the ego's).
    process_noise_jerk_mps3 : float
        CA model: standard deviation of the white-noise jerk.

    Raises
    ------
    core.errors.BadInput
        On a value out of its domain, naming the field, the value and the limit.
    """

    motion_model: str = "cv"
    frame_period_s: float = 0.05
    process_noise_accel_mps2: float = 3.0
    process_noise_jerk_mps3: float = 10.0

    def __post_init__(self) -> None:
        one_of("motion_model", self.motion_model, MOTION_MODELS)
        require(self, ("frame_period_s", "process_noise_accel_mps2",
                       "process_noise_jerk_mps3"), gt=0)

    @property
    def model(self) -> MotionModel:
        """The selected `MotionModel`."""
        return MOTION_MODELS[self.motion_model]

    @property
    def n_state(self) -> int:
        """Length of the state vector (4 for CV, 6 for CA)."""
        return self.model.n_state

    @property
    def process_noise_sigma(self) -> float:
        """The process-noise intensity of the selected motion model (the field its
        `MotionModel.sigma_field` names)."""
        return getattr(self, self.model.sigma_field)


@dataclass(frozen=True, kw_only=True, slots=True)
class MountConfig:
    """Radar pose in the vehicle frame: p_vehicle = Rz(yaw) p_radar + mount
    (``TrackerConfig.mount``).

    Parameters
    ----------
    mount_x_m, mount_y_m : float
        Radar position in the vehicle frame (ISO 8855: x forward, y left), m.
    mount_yaw_deg : float
        Radar boresight yaw in the vehicle frame, deg.
    """

    mount_x_m: float = 0.0
    mount_y_m: float = 0.0
    mount_yaw_deg: float = 0.0

    def __post_init__(self) -> None:
        require(self, ("mount_x_m", "mount_y_m", "mount_yaw_deg"))


@dataclass(frozen=True, kw_only=True, slots=True)
class MeasurementNoise:
    """Per-point measurement noise, the diagonal of Rm (``TrackerConfig.noise``); the gate,
    the same-group test, the allocator and the static labels read it through the sensor.

    Parameters
    ----------
    range_std_m, azimuth_std_deg, radial_velocity_std_mps : float
        Standard deviations of a point's range (m), azimuth (deg) and radial velocity (m/s).
    """

    range_std_m: float = 0.25
    azimuth_std_deg: float = 1.5
    radial_velocity_std_mps: float = 0.15

    def __post_init__(self) -> None:
        require(self, ("range_std_m", "azimuth_std_deg", "radial_velocity_std_mps"), gt=0)

    @property
    def covariance(self) -> np.ndarray:
        """Rm, (3, 3): range m^2, azimuth rad^2, (m/s)^2."""
        return np.diag([self.range_std_m ** 2, math.radians(self.azimuth_std_deg) ** 2,
                        self.radial_velocity_std_mps ** 2])


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
    mount : MountConfig
        Radar pose in the vehicle frame.
    noise : MeasurementNoise
        Per-point measurement noise.

    Attributes
    ----------
    mount_xy_m : (2,) float
        Radar position in the vehicle frame, m.
    mount_yaw_rad : float
        Radar boresight yaw in the vehicle frame, rad.
    noise_cov : (3, 3) float
        Per-point measurement covariance Rm: m^2, rad^2, (m/s)^2.
    """

    mount: MountConfig = MountConfig()
    noise: MeasurementNoise = MeasurementNoise()
    mount_xy_m: np.ndarray = field(init=False, repr=False, compare=False)
    mount_yaw_rad: float = field(init=False, repr=False, compare=False)
    noise_cov: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        # The arrays every frame reads, computed once.
        object.__setattr__(self, "mount_xy_m",
                           np.array([self.mount.mount_x_m, self.mount.mount_y_m]))
        object.__setattr__(self, "mount_yaw_rad", math.radians(self.mount.mount_yaw_deg))
        object.__setattr__(self, "noise_cov", self.noise.covariance)

    def predict(self, state: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """h (T, 3) and Jacobian (T, 3, n_state) of states (T, n_state), see
        `measurement_model`."""
        return measurement_model(state, self.mount_xy_m, self.mount_yaw_rad)

    def position(self, range_m: np.ndarray, azimuth_rad: np.ndarray) -> np.ndarray:
        """(N, 2) vehicle-frame position of points at range and radar-frame azimuth, m."""
        theta = azimuth_rad + self.mount_yaw_rad
        return self.mount_xy_m + range_m[:, None] * np.column_stack([np.cos(theta),
                                                                      np.sin(theta)])
