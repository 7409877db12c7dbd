"""Velocity resolution of detections: right, or off by whole resolution steps (aliasing).

One definition serves the velocity-unambiguity rate, the velocity-resolution failures (summary
columns, case criteria, the shifter report) and the relabelling of aliased detections that the
position gate of the association misses.

A detection is checked against the scatterers of the road users in its frame, in range and
radial velocity only:

- it is *in the footprint* of an actor when one of the actor's scatterers lies within
  ``range_gate_m`` of its range. Angle is deliberately not used: a wrong velocity hypothesis
  also corrupts the Doppler-phase compensation of the later Tx slots of TDMA/BPM
  (X'(m, n) = X(m, n) exp(-j m dphi), [TI-VEXT] eq. 8-10), which rotates the virtual array and
  moves the azimuth by tens of degrees, so a 2D footprint gate throws exactly the aliased
  detections away (they became ghosts);
- its velocity is *right* if some such scatterer has a radial velocity within
  ``velocity_gate_mps`` of it, and *off by a resolution step* (a velocity-resolution failure)
  if, for none right, some such scatterer has a radial velocity within ``velocity_gate_mps``
  of it after removing a non-zero multiple k of the scheme's failure step
  (`radarsim.mimo.MimoScheme.velocity_failure_step_mps`: one sub-band for DDMA, whose
  aliasing beyond +/-Vmax is also a whole number of sub-bands; the unambiguous span 2 Vmax of
  one Tx's slow time for TDMA and BPM).

The rate of right velocities among the two, ``n_right / (n_right + n_failures)``, is the
velocity-unambiguity rate (design.md 7): whatever label the 2D association gave a detection.

References
----------
.. [1] design.md section 7 (VELOCITY-AMBIGUOUS, velocity-resolution failures).
.. [2] [TI-VEXT] section 2 (TDMA Doppler-phase compensation, eq. 8-10) and section 4
       (hypotheses Vest + 2k Vmax).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd
from scipy.spatial import cKDTree

from core.errors import BadInput

from .association import ROAD_USER_CLASSES, AssociationConfig
from .joins import rows_by_frame

__all__ = ["VelocityCheck", "velocity_check", "RIGHT", "FAILURE", "UNMATCHED"]

RIGHT = "right"
FAILURE = "failure"
UNMATCHED = ""


class VelocityCheck(NamedTuple):
    """Per detection (row order of the input): the verdict and the actor it refers to.

    Attributes
    ----------
    verdict : (n,) object
        `RIGHT`, `FAILURE` or `UNMATCHED` ("": no road-user scatterer within the range gate
        whose velocity is right or off by whole steps).
    actor_id : (n,) int64
        Actor of the matching scatterer (-1 when unmatched).
    alias_k : (n,) int64
        Multiple of the step removed (0 when right or unmatched).
    truth_radial_velocity_mps : (n,) float
        Radial velocity of the matching scatterer, m/s (NaN when unmatched).
    """

    verdict: np.ndarray
    actor_id: np.ndarray
    alias_k: np.ndarray
    truth_radial_velocity_mps: np.ndarray


def velocity_check(detections: pd.DataFrame, scatterers: pd.DataFrame, truth: pd.DataFrame,
                   step_mps: float, config: AssociationConfig | None = None, *,
                   classes=ROAD_USER_CLASSES, candidates: np.ndarray | None = None
                   ) -> VelocityCheck:
    """Check every detection's radial velocity against the objects at its range.

    Parameters
    ----------
    detections : DataFrame
        Columns frame, range_m (m), radial_velocity_mps (m/s); n rows.
    scatterers : DataFrame
        `association.scatterer_table` of the run: frame, actor_id, range_m,
        radial_velocity_mps.
    truth : DataFrame
        The run's truth (actor_id, actor_class): which scatterers belong to `classes`.
    step_mps : float
        The scheme's failure step, m/s (> 0).
    config : AssociationConfig, optional
        ``range_gate_m`` and ``velocity_gate_mps``.
    classes : tuple of str
        Actor classes checked against (default the road users).
    candidates : (n,) bool, optional
        Detections to check (others stay unmatched); default all.

    Returns
    -------
    VelocityCheck

    Raises
    ------
    ValueError
        If ``step_mps`` is not a finite positive number, or is not wider than twice the
        velocity gate (a right and an aliased match could not be told apart).

    Examples
    --------
    >>> import pandas as pd
    >>> sc = pd.DataFrame({"frame": [0], "actor_id": [0], "range_m": [50.0],
    ...                    "radial_velocity_mps": [-15.0]})
    >>> truth = pd.DataFrame({"actor_id": [0], "actor_class": ["car"]})
    >>> det = pd.DataFrame({"frame": [0, 0, 0], "range_m": [50.3, 50.2, 80.0],
    ...                     "radial_velocity_mps": [-15.1, 5.44, -15.0]})
    >>> velocity_check(det, sc, truth, step_mps=20.44).verdict.tolist()
    ['right', 'failure', '']
    """
    cfg = config or AssociationConfig()
    if not (np.isfinite(step_mps) and step_mps > 2 * cfg.velocity_gate_mps):
        raise BadInput(f"step_mps={step_mps!r} must be finite and > 2 velocity_gate_mps = "
                       f"{2 * cfg.velocity_gate_mps:g} m/s")
    n = len(detections)
    verdict = np.full(n, UNMATCHED, dtype=object)
    actor = np.full(n, -1, dtype=np.int64)
    alias = np.zeros(n, dtype=np.int64)
    v_true = np.full(n, np.nan)
    if n == 0 or scatterers is None or scatterers.empty:
        return VelocityCheck(verdict, actor, alias, v_true)
    users = truth.loc[truth["actor_class"].isin(classes), "actor_id"].unique()
    sc = scatterers[scatterers["actor_id"].isin(users)]
    det_frame = detections["frame"].to_numpy()
    if candidates is not None:
        det_frame = np.where(np.asarray(candidates, dtype=bool), det_frame, -(2 ** 62))
    det_r = detections["range_m"].to_numpy(dtype=float)
    det_v = detections["radial_velocity_mps"].to_numpy(dtype=float)
    best_rank = _best_matches(sc, det_frame, det_r, det_v, step_mps, cfg, actor, alias, v_true)
    verdict[best_rank == 0] = RIGHT
    verdict[best_rank == 1] = FAILURE
    return VelocityCheck(verdict, actor, alias, v_true)


def _best_matches(sc: pd.DataFrame, det_frame: np.ndarray, det_r: np.ndarray,
                  det_v: np.ndarray, step_mps: float, cfg: AssociationConfig,
                  actor: np.ndarray, alias: np.ndarray, v_true: np.ndarray) -> np.ndarray:
    """(n,) rank of each detection's best scatterer match (0 right, 1 failure, 9 none);
    fills `actor`, `alias` and `v_true` of the matched detections in place.

    Rank of a (detection, scatterer) pair: right 0 before failure 1; then the smallest
    velocity residual. Pairs come from a range-only ball query per frame."""
    n = det_frame.size
    best_rank = np.full(n, 9)
    best_cost = np.full(n, np.inf)
    # Columns once; per frame only index arrays (groupby's row positions, in table order).
    sc_r = sc["range_m"].to_numpy(dtype=float)
    sc_v = sc["radial_velocity_mps"].to_numpy(dtype=float)
    sc_actor = sc["actor_id"].to_numpy()
    det_rows = rows_by_frame(det_frame)
    for frame, at in sc.groupby("frame", sort=False).indices.items():
        rows = det_rows.get(frame)
        if rows is None:
            continue
        pairs = cKDTree(det_r[rows, None]).sparse_distance_matrix(
            cKDTree(sc_r[at][:, None]), cfg.range_gate_m, output_type="ndarray")
        if not pairs.size:
            continue
        d_idx = rows[pairs["i"]]
        s_idx = at[pairs["j"].astype(np.int64)]
        vs = sc_v[s_idx]
        dv = det_v[d_idx] - vs
        k = np.rint(dv / step_mps).astype(np.int64)
        resid = np.abs(dv - k * step_mps)
        ok = resid <= cfg.velocity_gate_mps
        rank = np.where(k == 0, 0, 1)
        cost = rank * 1e6 + resid
        cost[~ok] = np.inf
        order = np.lexsort((cost, d_idx))
        d_sorted = d_idx[order]
        first = np.r_[True, d_sorted[1:] != d_sorted[:-1]]
        pick = order[first]
        pick = pick[np.isfinite(cost[pick])]
        di = d_idx[pick]
        better = cost[pick] < best_cost[di]
        di, pick = di[better], pick[better]
        best_cost[di] = cost[pick]
        best_rank[di] = rank[pick]
        actor[di] = sc_actor[s_idx[pick]]
        alias[di] = k[pick]
        v_true[di] = vs[pick]
    return best_rank
