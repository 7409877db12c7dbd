"""`METRICS`: the one definition of every number the harness reports.

Each `Metric` says what a column means (unit, description, which direction is better), which
function computes it from which table (detections, actor-frames, tracks, truth, the case, the
noise floor), whether a CI gate may threshold it and whether a case may state a pass criterion
on it (and how that criterion is measured for one actor or the whole run). The summary table's
numeric columns, the report's column legend, gate files and case criteria all read it: a gate
or criterion naming a metric not in it is refused with the list of known ones.

Families that depend on a registry (detection range at Pd 90 % per actor class, the value of
each criterion) are generated from that registry here, so they too are defined once.

Examples
--------
>>> from metrics import METRICS
>>> METRICS["ghost_rate"].unit, METRICS["ghost_rate"].better
('', 'lower')
>>> METRICS["first_detection_range_m"].unit
'm'
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
import pandas as pd

from core.errors import BadInput
from core.registry import Registry

from . import detection as det
from . import interference as itf
from . import r79
from . import tracks as trk
from .association import ROAD_USER_CLASSES
from .velocity import FAILURE, RIGHT

__all__ = ["Metric", "METRICS", "register_metric", "CriterionContext", "get_metric",
           "check_criterion",
           "criterion_metrics", "case_criteria", "BETTER", "TABLES", "describe"]

#: Which direction of a metric is better.
BETTER = ("higher", "lower", "none")
#: Tables a metric is computed from.
TABLES = ("detections", "actors", "tracks", "frames", "case", "pairs")


class CriterionContext(NamedTuple):
    """What a case criterion is measured on: one scheme of one run.

    Attributes
    ----------
    labelled : DataFrame
        Labelled detections with the velocity check (`metrics.scoring`).
    actors : DataFrame
        `detection.actor_detection` per actor (indexed by actor_id or with that column).
    row : dict
        The summary row computed so far.
    """

    labelled: pd.DataFrame
    actors: pd.DataFrame
    row: dict


@dataclass(frozen=True, kw_only=True, slots=True)
class Metric:
    """One reported number.

    Parameters
    ----------
    name : str
        Column / key name (unit suffix in the name: ``_m``, ``_mps``, ``_db``, ``_s``).
    unit : str
        Unit ("" for counts, fractions and flags).
    description : str
        What the number is, how it is computed, in one or two sentences.
    better : str
        "higher", "lower" or "none" (a count or a setting: no better direction).
    table : str
        Table it is computed from (`TABLES`).
    source : callable
        The function that computes it (its docstring is the full definition).
    gate : bool
        Whether a CI gate may threshold it (gates read summary rows: a per-actor metric
        cannot be gated, its summary form can).
    criterion : callable or None
        ``criterion(ctx, actor_id) -> float``: how a case criterion on it is measured, for
        one actor (``actor_id``) or the whole run (None); None: it cannot be a criterion.
    per_actor : bool or None
        For a criterion metric: True it needs an actor, False it is run-wide only, None
        either.
    row_value : callable or None
        ``row_value(labelled, actor_frames) -> float``: the value of a metric a plugin adds
        (`register_metric`), computed for every scheme's summary row from its labelled
        detections and its per-actor-and-frame table (`metrics.scoring.score_scheme`); None
        for the built-in metrics, whose values the scoring functions compute.
    """

    name: str
    unit: str
    description: str
    better: str
    table: str
    source: Callable
    gate: bool = True
    criterion: Callable | None = None
    per_actor: bool | None = None
    row_value: Callable | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.unit, str) or not isinstance(self.description, str) \
                or not self.description.strip():
            raise BadInput(f"metric {self.name!r}: unit and description must be strings "
                           f"(a non-empty description), got unit={self.unit!r}, "
                           f"description={self.description!r}")
        if self.row_value is not None and not callable(self.row_value):
            raise BadInput(f"metric {self.name!r}: row_value={self.row_value!r} is not callable")
        if self.better not in BETTER:
            raise BadInput(f"better={self.better!r} is not one of {BETTER}")
        if self.table not in TABLES:
            raise BadInput(f"table={self.table!r} is not one of {TABLES}")

    @property
    def source_name(self) -> str:
        """``module.function`` that computes it."""
        return f"{self.source.__module__}.{self.source.__qualname__}"


# ----------------------------------------------------------------------- criterion measures
def _actor_value(column: str, run_column: str | None = None):
    def measure(ctx: CriterionContext, actor_id) -> float:
        if actor_id is None:
            return float(ctx.row.get(run_column, np.nan)) if run_column else float("nan")
        a = ctx.actors.set_index("actor_id") if "actor_id" in ctx.actors else ctx.actors
        return float(a.loc[actor_id, column]) if actor_id in a.index else float("nan")
    return measure


def _run_value(column: str):
    def measure(ctx: CriterionContext, actor_id) -> float:
        return float(ctx.row.get(column, np.nan))
    return measure


def _actor_velocity_rate(ctx: CriterionContext, actor_id) -> float:
    if actor_id is None:
        return float(ctx.row.get("velocity_unambiguity_rate", np.nan))
    lab = ctx.labelled
    mine = lab[lab["velocity_actor_id"] == actor_id]["velocity_check"]
    n_right, n_fail = int((mine == RIGHT).sum()), int((mine == FAILURE).sum())
    return n_right / (n_right + n_fail) if n_right + n_fail else float("nan")


# ----------------------------------------------------------------------------- the registry
def _cloud_metrics(add) -> None:
    """Counts and rates of the point cloud."""
    cnt = det.summarize_scheme
    # counts and rates of the point cloud
    add("n_frames", "", "none", "detections", cnt, "frames processed")
    add("n_detections", "", "none", "detections", cnt, "detections of the run")
    add("n_true", "", "higher", "detections", cnt,
        "TRUE detections: inside a road user's footprint gate, supported by one of its "
        "scatterers, velocity within the gate (metrics.association)")
    add("n_velocity_ambiguous", "", "lower", "detections", cnt,
        "VELOCITY_AMBIGUOUS detections: at a road user's position (2D gate, velocity off by "
        "k 2 Vmax) or at its range with the velocity off by whole resolution steps "
        "(metrics.velocity)")
    add("n_ghost", "", "lower", "detections", cnt,
        "GHOST detections: on no modelled object, not an aliased echo of one")
    add("n_clutter", "", "none", "detections", cnt,
        "CLUTTER detections: on modelled static infrastructure (guard rail, ground cells)")
    add("ghost_rate", "", "lower", "detections", det.ghost_stats,
        "ghosts / detections of the run", criterion=_run_value("ghost_rate"),
        per_actor=False)
    add("ghosts_per_frame", "", "lower", "detections", det.ghost_stats, "ghosts per frame")
    add("clutter_per_frame", "", "none", "detections", det.ghost_stats,
        "clutter detections per frame")
    add("detections_per_frame", "", "none", "detections", det.ghost_stats,
        "detections per frame")


def _accuracy_metrics(add) -> None:
    """Accuracy of TRUE detections and velocity resolution."""
    # accuracy of TRUE detections
    es = det.error_stats
    for q, what in (("rmse", "RMS"), ("median", "median |.|"), ("p95", "95th percentile |.|")):
        add(f"range_error_{q}_m", "m", "lower", "detections", es,
            f"{what} of the range error of TRUE detections against the nearest scatterer "
            "of their actor", **({"criterion": _run_value("range_error_rmse_m"),
                                  "per_actor": False} if q == "rmse" else {}))
        add(f"radial_velocity_error_{q}_mps", "m/s", "lower", "detections", es,
            f"{what} of the radial-velocity error of TRUE detections against the nearest "
            "scatterer of their actor")
    add("azimuth_error_rmse_deg", "deg", "lower", "detections", es,
        "RMS azimuth error of TRUE detections against the nearest scatterer of their actor")
    add("n_error_samples", "", "none", "detections", es,
        "TRUE detections with a range error (the weight of the pooled RMSE)")
    # velocity resolution
    add("velocity_unambiguity_rate", "", "higher", "detections", det.velocity_stats,
        "detections at a road user's range with the right radial velocity / those with the "
        "right one or one off by whole resolution steps (one DDMA sub-band, a TDMA/BPM "
        "slot span), whatever the 2D association said; no velocity window; road users only "
        "(infrastructure: infrastructure_velocity_unambiguity_rate)",
        criterion=_actor_velocity_rate, per_actor=None)
    add("velocity_unambiguity_rate_in_span", "", "higher", "detections", det.velocity_stats,
        "velocity_unambiguity_rate over the detections whose truth |radial velocity| is "
        "within the run's unambiguity window (the widest span the run's schemes promise, "
        "R79 DDMA 40.8 m/s)")
    add("n_velocity_right", "", "none", "detections", det.velocity_stats,
        "detections at a road user's range with the right radial velocity (the weight of the "
        "pooled velocity_unambiguity_rate)")
    add("n_velocity_resolution_failures", "", "lower", "detections", det.velocity_stats,
        "detections at a road user's range whose radial velocity is off by a non-zero "
        "multiple of the scheme's resolution step (demodulation, assignment, "
        "disambiguation failures, aliasing)")
    add("infrastructure_velocity_unambiguity_rate", "", "higher", "detections",
        det.velocity_stats,
        "velocity_unambiguity_rate over the detections matched to modelled static "
        "infrastructure (guard rails; right or off by whole unambiguous spans), apart from "
        "the road users")
    add("n_infrastructure_velocity_right", "", "none", "detections", det.velocity_stats,
        "detections on modelled infrastructure with the right radial velocity (the weight of "
        "the pooled infrastructure_velocity_unambiguity_rate)")
    add("n_infrastructure_velocity_failures", "", "lower", "detections", det.velocity_stats,
        "detections on modelled infrastructure whose radial velocity is off by a non-zero "
        "multiple of the unambiguous span")


def _actor_and_case_metrics(add) -> None:
    """Detection of actors, case criteria and R79 verdicts."""
    # detection of actors
    cnt = det.summarize_scheme
    ad = det.actor_detection
    add("detection_probability", "", "higher", "actors", ad,
        "detected / visible frames of one actor (one-to-one assignment of TRUE detections); "
        "per actor, not a summary column", gate=False,
        criterion=_actor_value("detection_probability", "detection_probability_min"),
        per_actor=None)
    add("detection_probability_mean", "", "higher", "actors", cnt,
        "mean per-actor detection probability over actors visible in >= pd_min_count frames")
    add("detection_probability_min", "", "higher", "actors", cnt,
        "least per-actor detection probability over actors visible in >= pd_min_count frames")
    add("first_detection_range_m", "m", "higher", "actors", ad,
        "truth range of the actor at its first detection: a TRUE (footprint and "
        "velocity-correct) detection assigned to it; per actor, not a summary column (gate "
        "target_first_detection_range_m)", gate=False,
        criterion=_actor_value("first_detection_range_m", "target_first_detection_range_m"),
        per_actor=None)
    add("target_first_detection_range_m", "m", "higher", "actors",
        det.target_first_detection_range_m,
        "least first_detection_range_m over the case's target actors (NaN if one is never "
        "detected)")
    for c in ROAD_USER_CLASSES:
        add(f"pd90_max_range_{c}_m", "m", "higher", "actors", det.max_range_pd90,
            f"farthest range bin edge where {c}s are detected with Pd >= 0.9")
    # case criteria and verdicts
    cc = case_criteria
    add("case_pass", "", "higher", "case", cc,
        "1 if every pass criterion of the case holds (NaN without criteria)")
    add("case_criteria_n", "", "none", "case", cc, "criteria of the case")
    add("s_critical_m", "m", "none", "case", r79.critical_distance_m,
        "UN R79 5.6.4.7 critical distance from the case's ego and approaching speeds "
        "(R79 cases only)")
    add("r79_required_range_m", "m", "none", "case", r79.r79_verdict,
        "max(S_crit, S_rear = 55 m): the range at which the approaching vehicle must first "
        "be detected (R79 cases only)")
    add("r79_margin_m", "m", "higher", "case", r79.r79_verdict,
        "the approaching vehicle's first detection range minus r79_required_range_m (NaN if "
        "never detected; R79 cases only)")
    add("r79_pass", "", "higher", "case", r79.r79_verdict,
        "1 if the approaching vehicle's first detection range >= r79_required_range_m "
        "(UN R79 category C; R79 cases only)")


def external_call_time(total_s: float, n_frames: int) -> float:
    """Wall time of an external (software-in-the-loop) chain's command per processed frame, s:
    its calls' total over the cell's frames (process start, file I/O and its own processing;
    the harness's writing of the profile and capture excluded)."""
    return total_s / max(n_frames, 1)


def _snr_and_front_end_metrics(add) -> None:
    """SNR gain over the baseline scheme, front end and interference."""
    add("external_call_s_per_frame", "s", "lower", "frames", external_call_time,
        "an external chain's command wall time per frame (NaN for built-in chains)")
    # SNR gain over the baseline scheme
    sg = det.snr_gain_stats
    for name, text in (("median", "median"), ("p25", "25th percentile"),
                       ("p75", "75th percentile"), ("std", "standard deviation")):
        add(f"snr_gain_{name}_db", "dB", "higher" if name != "std" else "lower", "pairs", sg,
            f"{text} of the scheme's minus the baseline scheme's peak SNR on the same actor "
            "and frame")
    add("snr_gain_n", "", "none", "pairs", sg, "actor-frames detected by both schemes")
    add("snr_gain_noise_limited_median_db", "dB", "higher", "pairs", sg,
        "median SNR gain over noise-limited pairs (baseline peak SNR <= 25 dB; NaN with "
        "fewer than 10 pairs)")
    add("snr_gain_noise_limited_n", "", "none", "pairs", sg, "noise-limited pairs")
    # front end and interference
    add("n_saturated_frames", "", "lower", "frames", det.summarize_scheme,
        "frames with at least one saturated (chirp, Rx) ADC row")
    nf = itf.floor_summary
    add("noise_floor_rise_db", "dB", "lower", "frames", nf,
        "median over frames of the noise floor after the Doppler FFT over thermal, with the "
        "scheme's chirp-level chain (mitigation as configured)")
    add("noise_floor_rise_range_db", "dB", "lower", "frames", nf,
        "the same after the range FFT")
    add("interference_to_noise_db", "dB", "none", "frames", nf,
        "in-burst interference-to-noise ratio at the ADC (median over frames with "
        "interferers)")
    add("noise_floor_rise_unmitigated_db", "dB", "none", "frames", nf,
        "noise_floor_rise_db with interference mitigation switched off (interference cases "
        "run with mitigation on)")
    add("mitigation_floor_recovery_db", "dB", "higher", "frames", nf,
        "noise_floor_rise_unmitigated_db - noise_floor_rise_db: floor recovered by the "
        "mitigation")
    add("mitigation_floor_recovery_fraction", "", "higher", "frames", nf,
        "mitigation_floor_recovery_db / noise_floor_rise_unmitigated_db (NaN when the "
        "unmitigated rise is below 0.5 dB: nothing to recover)")
    add("mitigation_floor_recovery_fraction_worst_1s", "", "higher", "frames",
        itf.worst_window_recovery,
        "the least mitigation_floor_recovery_fraction of the run's 1-second windows (window "
        "medians; windows whose median unmitigated rise is >= 1 dB): what a case median hides "
        "while an interferer is still weak")
    add("ghost_rate_unmitigated", "", "none", "detections", itf.mitigation_stats,
        "ghost_rate of the same frames processed with interference mitigation off")
    add("mitigation_ghost_rate_added", "", "lower", "detections", itf.mitigation_stats,
        "ghost_rate - ghost_rate_unmitigated: ghosts the mitigation added (negative: removed)")


def _track_metrics(add) -> None:
    """The tracker's metrics (`metrics.tracks.track_metrics`)."""
    # tracks (metrics.tracks.track_metrics; its n_frames is stored as track_n_frames)
    tm = trk.track_metrics
    track = {
        "track_n_frames": ("", "none", "frames the tracker scored"),
        "duration_s": ("s", "none", "duration of the tracked run"),
        "n_actors": ("", "none", "actors in view of the tracker"),
        "n_actors_confirmed": ("", "higher", "actors with a confirmed track"),
        "track_confirm_time_s_min": ("s", "lower", "earliest confirmation time"),
        "track_confirm_latency_s_median": ("s", "lower",
                                           "median time from first view to confirmation"),
        "track_confirm_latency_s_max": ("s", "lower", "longest time from view to confirmation"),
        "track_confirm_range_m_max": ("m", "higher", "largest range at confirmation"),
        "track_confirm_range_m_median": ("m", "higher", "median range at confirmation"),
        "track_id_switches": ("", "lower", "identity switches (CLEAR MOT)"),
        "track_fragmentations": ("", "lower", "track fragmentations (CLEAR MOT)"),
        "track_coverage_mean": ("", "higher", "mean fraction of in-view frames tracked"),
        "n_false_tracks": ("", "lower", "confirmed tracks mostly matched to no actor"),
        "false_tracks_per_min": ("", "lower", "false tracks per minute of run"),
        "gospa_mean_m": ("m", "lower", "mean GOSPA (c = 10 m, p = 2, alpha = 2)"),
        "gospa_localization_mean_m": ("m", "lower", "mean GOSPA localisation part"),
        "gospa_missed_per_frame": ("", "lower", "GOSPA missed actors per frame"),
        "gospa_false_per_frame": ("", "lower", "GOSPA false tracks per frame"),
        "track_pos_rmse_m": ("m", "lower", "RMS position error of matched tracks"),
        "track_vel_rmse_mps": ("m/s", "lower", "RMS velocity error of matched tracks"),
    }
    for name, (unit, better, text) in track.items():
        add(name, unit, better, "tracks", tm, text)


class _MetricRegistry(Registry[Metric]):
    """`Registry` of metrics whose lookup error lists the known names comma-separated (the
    message gate files and case criteria have always given)."""

    def missing_message(self, name) -> str:  # noqa: D102 - Registry API
        return f"unknown metric {name!r}; known: {', '.join(sorted(self))}"


def _metrics() -> Registry[Metric]:
    out = _MetricRegistry("metric", kind=Metric, identifier=True)

    def add(name, unit, better, table, source, description, **kw):
        if name in out:
            raise BadInput(f"metric {name!r} defined twice")
        out.register(Metric(name=name, unit=unit, better=better, table=table, source=source,
                            description=description, **kw))

    for section in (_cloud_metrics, _accuracy_metrics, _actor_and_case_metrics,
                    _snr_and_front_end_metrics, _track_metrics):
        section(add)
    cc = case_criteria
    # the measured value of each criterion metric (case_<metric>)
    for name in [n for n, m in out.items() if m.criterion is not None]:
        m = out[name]
        add(f"case_{name}", m.unit, m.better, "case", cc,
            f"{name} as the case's first criterion on it measures it")
    return out


def register_metric(metric: Metric, *, replace: bool = False) -> Metric:
    """Add a metric to `METRICS` (a plugin's own number) and return it.

    A metric with ``row_value`` gets a column of that name in every summary row, computed by
    `metrics.scoring.score_scheme`; with ``gate=True`` (the default) gate files may threshold
    it like a built-in one.

    Raises
    ------
    ValueError
        A taken name (without `replace`), a name that is not an identifier, a bad field.

    Examples
    --------
    >>> from metrics.registry import METRICS, Metric, register_metric
    >>> def n_true(labelled, actor_frames):
    ...     return float((labelled["label"] == "TRUE").sum())
    >>> register_metric(Metric(name="n_true_example", unit="", better="higher",
    ...                        table="detections", source=n_true, row_value=n_true,
    ...                        description="TRUE detections of the run")).unit
    ''
    >>> _ = METRICS.unregister("n_true_example")
    """
    return METRICS.register(metric, replace=replace)


def get_metric(name: str) -> Metric:
    """The metric of that name.

    Raises
    ------
    ValueError
        Unknown name, with the known ones.
    """
    return METRICS.lookup(name)


def criterion_metrics() -> list[str]:
    """Names of the metrics a case criterion may state."""
    return sorted(n for n, m in METRICS.items() if m.criterion is not None)


def check_criterion(metric: str, actor_id=None) -> Metric:
    """Validate a criterion's metric (and its actor) against the registry.

    Raises
    ------
    ValueError
        Unknown metric (with the known ones), a metric that cannot be a criterion (with the
        ones that can), or a run-wide metric given an actor.

    Examples
    --------
    >>> check_criterion("ghost_rate").name
    'ghost_rate'
    >>> check_criterion("n_frames")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    core.errors.BadInput: criterion metric 'n_frames' cannot be a case criterion; criterion
    metrics: ...
    """
    m = get_metric(metric)
    if m.criterion is None:
        raise BadInput(f"criterion metric {metric!r} cannot be a case criterion; criterion "
                       f"metrics: {', '.join(criterion_metrics())}")
    if m.per_actor is False and actor_id is not None:
        raise BadInput(f"criterion metric {metric!r} is run-wide: actor_id={actor_id!r} "
                       "must be left out")
    return m


def describe(names) -> pd.DataFrame:
    """Legend of the given column names: name, unit, better, description (names not in the
    registry are left out)."""
    rows = [{"column": n, "unit": METRICS[n].unit, "better": METRICS[n].better,
             "description": METRICS[n].description} for n in names if n in METRICS]
    return pd.DataFrame(rows, columns=["column", "unit", "better", "description"])


#: Comparison operators of a criterion.
_OPS = {">=": np.greater_equal, "<=": np.less_equal, ">": np.greater, "<": np.less}


def case_criteria(criteria, labelled: pd.DataFrame, actors: pd.DataFrame,
                  row: dict) -> dict[str, object]:
    """Evaluate a case's pass criteria (``metric op value`` for an actor or the whole run).

    ``criteria`` are objects with ``metric``, ``op``, ``value`` and ``actor_id`` (the
    catalogue's ``scenarios.Criterion``; read by attribute, so this package does not import
    the scenarios). Each metric is measured as its `Metric.criterion` says (the same
    definition as its column); a NaN measurement fails (an actor never detected has no
    first-detection range).

    Returns
    -------
    dict
        ``case_pass`` (1.0 all criteria met, 0.0 otherwise, NaN without criteria),
        ``case_criteria_n``, ``case_criteria_failed`` (";"-joined descriptions, "" if none)
        and ``case_<metric>`` (the measured value of the first criterion on each metric).

    Raises
    ------
    ValueError
        A criterion on an unknown metric, on one that cannot be a criterion, or with an
        unknown operator.
    """
    out: dict[str, object] = {"case_pass": float("nan"), "case_criteria_n": 0,
                              "case_criteria_failed": ""}
    crits = list(criteria or ())
    if not crits:
        return out
    ctx = CriterionContext(labelled, actors, row)
    failed = []
    for c in crits:
        aid = getattr(c, "actor_id", None)
        m = check_criterion(c.metric, aid)
        if c.op not in _OPS:
            raise BadInput(f"criterion op {c.op!r} is not one of {sorted(_OPS)}")
        v = float(m.criterion(ctx, aid))
        ok = bool(np.isfinite(v) and _OPS[c.op](v, c.value))
        out.setdefault(f"case_{m.name}", v)
        if not ok:
            who = f" actor {aid}" if aid is not None else ""
            failed.append(f"{m.name}{who} = {v:.4g} not {c.op} {c.value:g}")
    out["case_pass"] = float(not failed)
    out["case_criteria_n"] = len(crits)
    out["case_criteria_failed"] = "; ".join(failed)
    return out


#: Every reported metric, by name.
METRICS: Registry[Metric] = _metrics()
