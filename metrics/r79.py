"""UN R79 ACSF category C (lane change): the critical distance and the rear-sensor verdict.

A lane change may only start if a vehicle approaching in the target lane is farther than the
critical distance

    S_crit = (v_app - v) t_B + (v_app - v)^2 / (2 a) + v t_G

(UN R79 rev. 4, para. 5.6.4.7; constants as design.md 6 gives them: the approaching vehicle at
v_app = 130 km/h, its deceleration a = 3 m/s^2 after a reaction time t_B = 0.4 s, and a gap
t_G = 1 s it keeps behind the ego at the ego's speed v), and the rear sensor must see such a
vehicle at least S_rear = 55 m away (para. 5.6.4.8.1, tested with an L3 motorcycle). The
verdict of a case: the approaching vehicle's first detection range (TRUE and velocity-correct,
`metrics.detection.actor_detection`) >= max(S_crit, S_rear).

Sources: the paragraph numbers and constants follow design.md section 6 and the catalogue's
case files; the regulation text itself was not retrievable with the tools of this session
(a public GRVA amendment, GRVA-07-19, names para. 5.6.4.7 as the lane-change critical
distances), so the constants are the ones design.md 6 quotes, reproduced by the tests
(87.5 m at 60 km/h, 59.9 m at 80 km/h, 42.7 m at 100 km/h).

References
----------
.. [1] UN Regulation No. 79, rev. 4, paras. 5.6.4.7 and 5.6.4.8.1.
.. [2] design.md section 6.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from core.checks import require
from core.errors import BadInput
from scenarios.catalog import KMH  # m/s per km/h, the catalogue's one constant

__all__ = ["R79Constants", "R79", "critical_distance_m", "r79_verdict", "KMH"]


@dataclass(frozen=True, kw_only=True, slots=True)
class R79Constants:
    """The regulation's constants (UN R79 rev. 4, para. 5.6.4.7 and 5.6.4.8.1).

    Parameters
    ----------
    approach_speed_mps : float
        v_app, the approaching vehicle's speed the regulation assumes, m/s (130 km/h).
    decel_mps2 : float
        a, its deceleration, m/s^2 (3).
    reaction_time_s : float
        t_B, its reaction time before braking, s (0.4).
    gap_time_s : float
        t_G, the time gap it keeps after braking, s (1.0).
    min_rear_range_m : float
        S_rear, the least range at which the rear sensor must see it, m (55).
    """

    approach_speed_mps: float = 130 * KMH
    decel_mps2: float = 3.0
    reaction_time_s: float = 0.4
    gap_time_s: float = 1.0
    min_rear_range_m: float = 55.0

    def __post_init__(self) -> None:
        require(self, ("approach_speed_mps", "decel_mps2", "min_rear_range_m"), gt=0)
        require(self, ("reaction_time_s", "gap_time_s"), ge=0, unit="s")


#: The shipped constants.
R79 = R79Constants()


def critical_distance_m(ego_speed_mps: float, approach_speed_mps: float | None = None,
                        constants: R79Constants = R79) -> float:
    """S_crit = (v_app - v) t_B + (v_app - v)^2 / (2 a) + v t_G, m.

    Parameters
    ----------
    ego_speed_mps : float
        v, the ego's speed, m/s (>= 0).
    approach_speed_mps : float, optional
        v_app, the approaching vehicle's speed, m/s (default: the regulation's 130 km/h). A
        case evaluates it with its own approaching vehicle's speed.
    constants : R79Constants

    Raises
    ------
    ValueError
        A speed that is negative or not finite, or an approaching vehicle slower than the ego
        (nothing approaches: the formula does not apply).

    Examples
    --------
    >>> round(critical_distance_m(60 * KMH), 1), round(critical_distance_m(80 * KMH), 1)
    (87.5, 59.9)
    >>> round(critical_distance_m(100 * KMH), 1)
    42.7
    """
    v_app = constants.approach_speed_mps if approach_speed_mps is None else approach_speed_mps
    for name, v in (("ego_speed_mps", ego_speed_mps), ("approach_speed_mps", v_app)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
            raise BadInput(f"{name}={v!r} must be a finite speed >= 0 m/s")
    dv = v_app - ego_speed_mps
    if dv < 0:
        raise BadInput(f"approach_speed_mps={v_app:g} is below ego_speed_mps="
                       f"{ego_speed_mps:g}: no vehicle approaches, S_crit does not apply")
    return (dv * constants.reaction_time_s + dv * dv / (2 * constants.decel_mps2)
            + ego_speed_mps * constants.gap_time_s)


def r79_verdict(first_detection_range_m: float, ego_speed_mps: float,
                approach_speed_mps: float, constants: R79Constants = R79) -> dict[str, float]:
    """The category C verdict of one run.

    Returns
    -------
    dict
        ``s_critical_m`` (`critical_distance_m` of the case's speeds), ``r79_required_range_m``
        = max(S_crit, S_rear), ``r79_margin_m`` = first detection range minus it (NaN if never
        detected) and ``r79_pass`` (1.0 if the first detection range reaches it, 0.0
        otherwise: never detected fails).

    Examples
    --------
    >>> v = r79_verdict(117.0, 80 * KMH, 130 * KMH)
    >>> round(v["s_critical_m"], 1), round(v["r79_margin_m"], 1), v["r79_pass"]
    (59.9, 57.1, 1.0)
    >>> r79_verdict(50.0, 100 * KMH, 130 * KMH)["r79_pass"]  # S_crit 42.7 m, S_rear 55 m
    0.0
    """
    s = critical_distance_m(ego_speed_mps, approach_speed_mps, constants)
    need = max(s, constants.min_rear_range_m)
    r = float(first_detection_range_m)
    return {"s_critical_m": s, "r79_required_range_m": need, "r79_margin_m": r - need,
            "r79_pass": float(math.isfinite(r) and r >= need)}
