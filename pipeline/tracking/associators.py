"""Association: each point of a frame to at most one track, chosen among the hypotheses (an
injected tracker part).

An associator only chooses (Stone Soup's split): the hypothesiser
(`pipeline.tracking.hypothesis`) has already predicted, linearised and gated every track-point
pair. `GatedMaximumLikelihood` is TI's gtrack rule: among its gated tracks a point joins the
most likely one (smallest d^2 + ln det S); `GatedNearestNeighbour` joins the nearest (smallest
d^2). Both keep static points off DETECT tracks unless ``allow_static_tracks``. Any object with
the same `associate` method can replace them (``GroupTracker(cfg, associator=...)``), or a
registered one can be picked by name (``TrackerConfig(associator="nearest")``,
`pipeline.tracking.parts`).

References
----------
.. [1] TI mmWave SDK, "Group tracker" (gtrack) design: gating with group dispersion.
.. [2] Stone Soup: ``stonesoup.dataassociator.neighbour.NearestNeighbour``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from core.checks import require

from .hypothesis import Hypotheses
from .track_state import Association, Tracks

__all__ = ["AssociationRules", "Associator", "GatedMaximumLikelihood", "GatedNearestNeighbour"]


@dataclass(frozen=True, kw_only=True, slots=True)
class AssociationRules:
    """What an associator reads (its registry entry takes the value from
    ``TrackerConfig.allocation.allow_static_tracks``: whether static points may start tracks
    is also whether they may confirm them).

    Parameters
    ----------
    allow_static_tracks : bool
        Static points may update DETECT tracks too (otherwise only ACTIVE ones: a track started
        by a false alarm next to a guard rail is not confirmed by the rail).
    """

    allow_static_tracks: bool = False

    def __post_init__(self) -> None:
        require(self, "allow_static_tracks", "bool")


class Associator(Protocol):
    """What the tracker asks of an associator."""

    def associate(self, hypotheses: Hypotheses, tracks: Tracks,
                  static: np.ndarray) -> Association:
        """Track index per point (-1: none), its innovation, and the tracks' Jacobians."""
        ...


class GatedMaximumLikelihood:
    """Among the gated tracks, the most likely: smallest d^2 + ln det S (TI gtrack).

    Parameters
    ----------
    cfg : AssociationRules
    """

    def __init__(self, cfg: AssociationRules) -> None:
        self.cfg = cfg

    def _score(self, hyp: Hypotheses) -> np.ndarray:
        """(K,) score of each candidate pair: smallest wins."""
        return hyp.distance2 + hyp.log_det[hyp.track]

    def associate(self, hypotheses: Hypotheses, tracks: Tracks,
                  static: np.ndarray) -> Association:
        hyp = hypotheses
        t, n = hyp.n_tracks, hyp.n_points
        index = np.full(n, -1, dtype=np.int64)
        innovation = np.zeros((n, 3))
        if n == 0 or t == 0:
            return Association(index, innovation, np.zeros((t, 3, tracks.x.shape[1])))
        gated = hyp.gated
        if not self.cfg.allow_static_tracks:
            gated = gated & ~(static[hyp.point] & ~tracks.active[hyp.track])
        score = np.full((t, n), np.inf)
        score[hyp.track, hyp.point] = np.where(gated, self._score(hyp), np.inf)
        best = np.argmin(score, axis=0)
        ok = np.isfinite(score[best, np.arange(n)])
        # The chosen pair's innovation (a finite score is a candidate pair).
        pair = np.full((t, n), -1, dtype=np.int64)
        pair[hyp.track, hyp.point] = np.arange(hyp.track.size)
        chosen = pair[best[ok], np.flatnonzero(ok)]
        index[ok] = best[ok]
        innovation[ok] = hyp.innovation[chosen]
        return Association(index, innovation, hyp.jacobian)


class GatedNearestNeighbour(GatedMaximumLikelihood):
    """Among the gated tracks, the nearest: smallest d^2 (no ln det S term, so a track with a
    large covariance is not penalised)."""

    def _score(self, hyp: Hypotheses) -> np.ndarray:
        return hyp.distance2
