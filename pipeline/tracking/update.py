"""Kalman prediction and the group EKF update (injected tracker parts).

`KalmanPredictor` propagates every track with its motion model (x = F x, P = F P F' + Q).
`GroupEkfUpdater` updates each track with the centroid of its associated points: the
innovation is the mean point residual, the centroid noise Rc = Rm / n + (alpha + w / n) D
(TI's Rc = Rm / n + alpha D, alpha = (N_est - n) / ((N_est - 1) n) [1], [2], plus w D / n for
a body whose reflection points change from frame to frame), and the group dispersion D is a
running estimate of the points' spread, floored at the point noise.

References
----------
.. [1] TI mmWave SDK, "Group tracker" (gtrack) design.
.. [2] Y. Bar-Shalom, "Multitarget-Multisensor Tracking", vol. II, p. 117 (centroid noise).
.. [3] Y. Bar-Shalom, X. R. Li, T. Kirubarajan, "Estimation with Applications to Tracking and
       Navigation", Wiley 2001, section 10.3 (EKF).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple, Protocol

import numpy as np

from core.checks import require

from .models import MotionConfig, MotionModel
from .track_state import Association, Tracks

__all__ = ["Predictor", "Updater", "KalmanPredictor", "GroupEkfUpdater", "UpdateResult",
           "GroupUpdateConfig"]


@dataclass(frozen=True, kw_only=True, slots=True)
class GroupUpdateConfig:
    """What the group EKF update reads (``TrackerConfig.update``).

    Parameters
    ----------
    centroid_jitter_weight : float
        w of the centroid noise Rc = Rm / n + (alpha + w / n) D, >= 0: w = 0 is TI's formula
        (a fixed set of reflection points), w = 1 treats each frame's points as a fresh
        sample of the body.
    dispersion_update_weight : float
        Weight of a frame's sample dispersion in the running estimate, (0, 1].
    """

    centroid_jitter_weight: float = 1.0
    dispersion_update_weight: float = 0.2

    def __post_init__(self) -> None:
        require(self, "centroid_jitter_weight", ge=0)
        require(self, "dispersion_update_weight", gt=0, le=1)


class Predictor(Protocol):
    def predict(self, tracks: Tracks, dt_s: float) -> Tracks:
        """The tracks propagated by dt_s."""
        ...


class UpdateResult(NamedTuple):
    """Updated tracks and the number of points each track took this frame, (T,) int."""

    tracks: Tracks
    n_points: np.ndarray


class Updater(Protocol):
    def update(self, tracks: Tracks, association: Association) -> UpdateResult:
        ...


class KalmanPredictor:
    """x = F x, P = F P F' + Q of a linear `MotionModel` with intensity `sigma`."""

    def __init__(self, model: MotionModel, sigma: float) -> None:
        self.model = model
        self.sigma = sigma

    @classmethod
    def from_config(cls, cfg: MotionConfig) -> "KalmanPredictor":
        """The predictor of `cfg`'s motion model with its process-noise intensity."""
        return cls(cfg.model, cfg.process_noise_sigma)

    def predict(self, tracks: Tracks, dt_s: float) -> Tracks:
        if not tracks.size:
            return tracks
        f = self.model.transition(dt_s)
        q = self.model.process_noise(dt_s, self.sigma)
        return tracks.replace(x=tracks.x @ f.T, p=f @ tracks.p @ f.T + q)


def _scatter(t: int, rows: np.ndarray, values: np.ndarray) -> np.ndarray:
    out = np.zeros((t,) + values.shape[1:])
    out[rows] = values
    return out


class GroupEkfUpdater:
    """Group EKF update with the centroid of each track's points (see module docstring).

    Parameters
    ----------
    cfg : GroupUpdateConfig
        centroid_jitter_weight (w) and dispersion_update_weight.
    noise_cov : (3, 3) float
        Per-point measurement covariance Rm.
    """

    def __init__(self, cfg: GroupUpdateConfig, noise_cov: np.ndarray) -> None:
        self.cfg = cfg
        self.rm = noise_cov

    def update(self, tracks: Tracks, association: Association) -> UpdateResult:
        cfg = self.cfg
        assoc, innov, jac = association
        t = tracks.size
        hit = assoc >= 0
        counts = np.bincount(assoc[hit], minlength=t).astype(np.int64)
        upd = np.flatnonzero(counts > 0)
        if upd.size == 0:
            return UpdateResult(tracks, counts)
        idx = assoc[hit]
        y = innov[hit]                                                            # (K, 3)
        nk = counts[upd].astype(float)
        ybar = np.zeros((t, 3))
        np.add.at(ybar, idx, y)
        ybar = ybar[upd] / nk[:, None]
        # Sample dispersion of the points about their centroid (measurement space).
        dev = y - _scatter(t, upd, ybar)[idx]
        scat = np.zeros((t, 3, 3))
        np.add.at(scat, idx, dev[:, :, None] * dev[:, None, :])
        scat = scat[upd]
        # Centroid noise: TI's Rc = Rm / n + alpha D treats D as a fixed set of members of
        # which n are seen; a vehicle's reflection points change from frame to frame, so the
        # centroid also jitters by D / n (sampling of the body).
        n_est = np.maximum(tracks.n_est[upd], nk)
        n_est = n_est + 0.1 * (nk - n_est)
        alpha = np.where(n_est > 1, np.maximum(n_est - nk, 0) / (np.maximum(n_est - 1, 1e-9) * nk),
                         0.0)
        disp = tracks.dispersion[upd]
        r_c = (self.rm / nk[:, None, None]
               + (alpha + cfg.centroid_jitter_weight / nk)[:, None, None] * disp)
        p, jac = tracks.p[upd], jac[upd]
        pht = p @ jac.transpose(0, 2, 1)
        s = jac @ pht + r_c
        gain = np.linalg.solve(s, pht.transpose(0, 2, 1)).transpose(0, 2, 1)     # (U, n, 3)
        x_all, p_all = tracks.x.copy(), tracks.p.copy()
        x_all[upd] += np.einsum("uij,uj->ui", gain, ybar)
        p_new = p - gain @ s @ gain.transpose(0, 2, 1)
        p_all[upd] = 0.5 * (p_new + p_new.transpose(0, 2, 1))
        # Running dispersion from groups with >= 2 points, floored at the measurement noise.
        disp_all = tracks.dispersion
        multi = nk >= 2
        if multi.any():
            w = cfg.dispersion_update_weight
            sample = scat[multi] / (nk[multi] - 1)[:, None, None]
            disp[multi] = (1 - w) * disp[multi] + w * sample
            diag = np.einsum("uii->ui", disp)
            np.einsum("uii->ui", disp)[...] = np.maximum(diag, np.diag(self.rm))
            disp_all = disp_all.copy()
            disp_all[upd] = disp
        n_est_all = tracks.n_est.copy()
        n_est_all[upd] = n_est
        return UpdateResult(tracks.replace(x=x_all, p=p_all, dispersion=disp_all,
                                           n_est=n_est_all), counts)
