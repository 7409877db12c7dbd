"""Radar equipment of road users: which vehicles carry radars, where, and with which waveform.

Other vehicles carry automotive radars in the same 76-81 GHz band. A `RadarEquipment` is one
such radar: its mount on the vehicle (ISO 8855 vehicle frame, height above the ground), its
boresight yaw and its FMCW waveform (start frequency, slope, chirp period, active ramp time,
chirp timing offset, Tx power, antenna gain and cosine pattern). A case gives radars per actor
in TOML (``[[radars]]`` tables, see `RadarSpec`) and/or a share of its vehicles that carry one
radar drawn with the seed from `WAVEFORM_FAMILIES`, a documented distribution of typical
corner and front radar waveforms. `equipment_table` turns all of it into the plain table the
front end reads (`radarsim.interference.EQUIPMENT_COLUMNS`); this package knows nothing of
radar signal processing.

References
----------
.. [1] [TI-DDMA] table 2 (the R79 corner DDMA waveform: 8.883 MHz/us, 23.81 us).
.. [2] MOSARIM D1.5 (2012), sec. 3: automotive radar waveform survey (LRR 76-77 GHz ramps of
       10-30 MHz/us; SRR/corner 77-81 GHz ramps of 20-100 MHz/us).
.. [3] ETSI EN 301 091 (76-77 GHz, 55 dBm peak EIRP) and EN 302 264 (77-81 GHz).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
import pandas as pd

from core.checks import check_keys, check_types, require
from core.errors import BadInput

__all__ = ["RadarEquipment", "WaveformFamily", "WAVEFORM_FAMILIES", "RadarSpec",
           "EQUIPPED_CLASSES", "draw_equipment", "equipment_table", "FAMILY_WEIGHTS",
           "EQUIPMENT_STREAM"]

#: Road-user classes that may carry radars (cyclists, pedestrians and guard rails do not).
EQUIPPED_CLASSES = ("car", "truck", "motorcycle")


@dataclass(frozen=True, kw_only=True, slots=True)
class RadarEquipment:
    """One radar on a road user.

    Parameters
    ----------
    mount_x_m, mount_y_m : float
        Position on the vehicle, vehicle frame (x forward, y left), m, within +/-10 / +/-3.
    mount_z_m : float
        Height above the ground, m, in (0, 3].
    mount_yaw_deg : float
        Boresight yaw from the vehicle's x axis, deg, in [-180, 180].
    start_freq_hz, slope_hz_per_s : float
        Ramp start frequency (76-81 GHz band, ramp inside it) and slope (negative: down-chirp,
        |slope| in [1e12, 2e14] Hz/s).
    chirp_period_s, ramp_time_s : float
        Chirp repetition period and active ramp time (ramp <= period, both in (1, 1000] us).
    chirp_offset_s : float
        Start of the radar's ramp 0 relative to the victim's first ramp, s, within +/-1 s
        (ramps repeat every period, so any offset beyond a frame period is one within it; the
        bound keeps the burst timing exact in float64).
    tx_power_dbm, antenna_gain_dbi : float
        Power at the antenna port, [-40, 20] dBm, and boresight gain, [-10, 35] dBi.
    pattern_exponent_az, pattern_exponent_el : float
        Cosine power-pattern exponents, [0, 1000] (1000: a 3 dB beam of about 3 deg).
    phase_rad : float
        Fixed carrier phase offset, rad, within +/-2 pi.
    """

    mount_x_m: float = 2.3
    mount_y_m: float = 0.0
    mount_z_m: float = 0.5
    mount_yaw_deg: float = 0.0
    start_freq_hz: float = 76.5e9
    slope_hz_per_s: float = 15e12
    chirp_period_s: float = 40e-6
    ramp_time_s: float = 30e-6
    chirp_offset_s: float = 0.0
    tx_power_dbm: float = 12.0
    antenna_gain_dbi: float = 20.0
    pattern_exponent_az: float = 4.0
    pattern_exponent_el: float = 8.0
    phase_rad: float = 0.0

    def __post_init__(self) -> None:
        require(self, [f.name for f in fields(self)])
        require(self, "mount_x_m", ge=-10, le=10, unit="m")
        require(self, "mount_y_m", ge=-3, le=3, unit="m")
        require(self, "mount_z_m", gt=0, le=3, unit="m")
        require(self, "mount_yaw_deg", ge=-180, le=180, unit="deg")
        if not 1e12 <= abs(self.slope_hz_per_s) <= 2e14:
            raise BadInput(f"slope_hz_per_s={self.slope_hz_per_s!r}: |slope| must be in "
                           "[1e12, 2e14] Hz/s")
        require(self, ("chirp_period_s", "ramp_time_s"), gt=1e-6, le=1e-3, unit="s")
        if self.ramp_time_s > self.chirp_period_s:
            raise BadInput(f"ramp_time_s={self.ramp_time_s!r} must be <= chirp_period_s="
                           f"{self.chirp_period_s!r}")
        end = self.start_freq_hz + self.slope_hz_per_s * self.ramp_time_s
        if min(self.start_freq_hz, end) < 76e9 or max(self.start_freq_hz, end) > 81e9:
            raise BadInput(f"start_freq_hz={self.start_freq_hz:g}: the ramp "
                           f"{self.start_freq_hz:g}..{end:g} Hz leaves the 76-81 GHz band")
        require(self, "chirp_offset_s", ge=-1.0, le=1.0, unit="s")
        require(self, "tx_power_dbm", ge=-40, le=20, unit="dBm")
        require(self, "antenna_gain_dbi", ge=-10, le=35, unit="dBi")
        require(self, ("pattern_exponent_az", "pattern_exponent_el"), ge=0, le=1000)
        require(self, "phase_rad", ge=-2 * math.pi, le=2 * math.pi, unit="rad")


@dataclass(frozen=True, kw_only=True, slots=True)
class WaveformFamily:
    """A class of radars and the ranges their parameters are drawn from (uniform).

    Parameters
    ----------
    description : str
    mounts : tuple of (x_m, y_m, z_m, yaw_deg) with x, y as fractions of the half length and
        half width
        Where on a vehicle such a radar sits; one is drawn.
    band_hz : (lo, hi)
        The ramp stays inside this band.
    slope_hz_per_s, chirp_period_s : (lo, hi)
    ramp_fraction : (lo, hi)
        Active ramp time / chirp period.
    tx_power_dbm, antenna_gain_dbi : float
    pattern_exponent_az, pattern_exponent_el : float
    down_chirp_probability : float
        Share of radars of this family that sweep downwards.
    """

    description: str
    mounts: tuple[tuple[float, float, float, float], ...]
    band_hz: tuple[float, float]
    slope_hz_per_s: tuple[float, float]
    chirp_period_s: tuple[float, float]
    ramp_fraction: tuple[float, float]
    tx_power_dbm: float
    antenna_gain_dbi: float
    pattern_exponent_az: float
    pattern_exponent_el: float
    down_chirp_probability: float = 0.0


_CORNERS = ((1.0, 1.0, 0.5, 45.0), (1.0, -1.0, 0.5, -45.0), (-1.0, 1.0, 0.5, 135.0),
            (-1.0, -1.0, 0.5, -135.0))

#: Typical waveforms of road users' radars. The R79 corner family is the victim's own
#: waveform (same slope: ghost targets when their IF overlaps); the others sweep at other
#: slopes and cross the victim's IF band in short bursts.
WAVEFORM_FAMILIES: dict[str, WaveformFamily] = {
    "corner_r79": WaveformFamily(
        description="TI R79-style corner radar, 77 GHz, 8.883 MHz/us, 23.81 us [TI-DDMA]",
        mounts=_CORNERS, band_hz=(77.0e9, 77.0e9 + 8.883e12 * 18.81e-6),
        slope_hz_per_s=(8.883e12, 8.883e12), chirp_period_s=(23.81e-6, 23.81e-6),
        ramp_fraction=(18.81 / 23.81, 18.81 / 23.81), tx_power_dbm=12.0,
        antenna_gain_dbi=10.0, pattern_exponent_az=1.2, pattern_exponent_el=4.0),
    "corner_srr": WaveformFamily(
        description="77 GHz short-range corner radar in the lower part of 77-81 GHz "
                    "(76.5-78.5 GHz assumed: most 77 GHz corner radars use 1-2 GHz near the "
                    "band start), 20-60 MHz/us, 20-40 us chirps",
        mounts=_CORNERS, band_hz=(76.5e9, 78.5e9), slope_hz_per_s=(20e12, 60e12),
        chirp_period_s=(20e-6, 40e-6), ramp_fraction=(0.6, 0.85), tx_power_dbm=12.0,
        antenna_gain_dbi=10.0, pattern_exponent_az=1.2, pattern_exponent_el=4.0,
        down_chirp_probability=0.2),
    "front_lrr": WaveformFamily(
        description="76-77 GHz front long-range radar, 10-25 MHz/us, 30-60 us chirps",
        mounts=((1.0, 0.0, 0.5, 0.0),), band_hz=(76.0e9, 77.0e9),
        slope_hz_per_s=(10e12, 25e12), chirp_period_s=(30e-6, 60e-6),
        ramp_fraction=(0.6, 0.85), tx_power_dbm=12.0, antenna_gain_dbi=22.0,
        pattern_exponent_az=8.0, pattern_exponent_el=12.0, down_chirp_probability=0.3),
}
#: Probability of each family for a randomly equipped vehicle.
FAMILY_WEIGHTS: dict[str, float] = {"corner_r79": 0.25, "corner_srr": 0.35, "front_lrr": 0.40}


@dataclass(frozen=True, kw_only=True, slots=True)
class RadarSpec:
    """A radar given per actor in a case file (``[[radars]]``).

    Parameters
    ----------
    actor_id : int
        The scripted actor carrying it (>= 0).
    family : str or None
        Draw the unspecified parameters from this `WAVEFORM_FAMILIES` entry (with the seed);
        None: `RadarEquipment` defaults for everything not given.
    overrides : dict
        `RadarEquipment` fields given explicitly (they win over the family draw).
    """

    actor_id: int
    family: str | None = None
    overrides: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        if isinstance(self.actor_id, bool) or not isinstance(self.actor_id, int) \
                or self.actor_id < 0:
            raise BadInput(f"radars: actor_id={self.actor_id!r} must be an integer >= 0")
        if self.family is not None and self.family not in WAVEFORM_FAMILIES:
            raise BadInput(f"radars: family={self.family!r} unknown; known: "
                           f"{sorted(WAVEFORM_FAMILIES)}")
        names = {f.name for f in fields(RadarEquipment)}
        bad = sorted(k for k, _ in self.overrides if k not in names)
        if bad:
            raise BadInput(f"radars: unknown RadarEquipment field(s) {bad}; known: "
                           f"{sorted(names)}")

    @classmethod
    def from_table(cls, table: dict, where: str = "radars") -> "RadarSpec":
        """From a TOML table: actor_id, optional family, and RadarEquipment fields, under the
        case-file policy of `core.checks` (unknown keys, wrong units and types named)."""
        equipment = {f.name for f in fields(RadarEquipment)}
        t = check_keys(table, {"actor_id", "family", *equipment}, f"{where}.")
        check_types({k: v for k, v in t.items() if k in equipment}, RadarEquipment, f"{where}.")
        if "actor_id" not in t:
            raise BadInput(f"{where}.actor_id: required key missing")
        actor_id = t.pop("actor_id")
        family = t.pop("family", None)
        try:
            spec = cls(actor_id=actor_id, family=family, overrides=tuple(sorted(t.items())))
            RadarEquipment(**dict(spec.overrides))  # values checked early (defaults elsewhere)
        except ValueError as exc:
            raise BadInput(f"{where}: {exc}") from None
        except TypeError as exc:
            raise BadInput(f"{where}: {exc}") from None
        return spec


def draw_equipment(rng: np.random.Generator, family: str, length_m: float = 5.0,
                   width_m: float = 2.0, **overrides) -> RadarEquipment:
    """One radar of `family` on a vehicle of the given size, drawn with `rng`.

    Mount: one of the family's mounts (x, y scaled to the half length and half width, 0.2 m
    inside the corner); start frequency, slope, period, ramp fraction uniform in the family's
    ranges (ramp inside its band), chirp offset uniform in [0, period), phase uniform in
    [0, 2 pi), down-chirp with the family's probability.
    """
    fam = WAVEFORM_FAMILIES[family]
    mx, my, mz, myaw = fam.mounts[int(rng.integers(len(fam.mounts)))]
    slope = float(rng.uniform(*fam.slope_hz_per_s))
    period = float(rng.uniform(*fam.chirp_period_s))
    ramp = period * float(rng.uniform(*fam.ramp_fraction))
    sweep = slope * ramp
    lo, hi = fam.band_hz
    if sweep > hi - lo:  # the drawn ramp would leave the band: shorten it
        ramp = (hi - lo) / slope
        sweep = hi - lo
    f0 = float(rng.uniform(lo, hi - sweep)) if hi - sweep > lo else lo
    down = rng.random() < fam.down_chirp_probability
    offset = float(rng.uniform(0, period))
    phase = float(rng.uniform(0, 2 * np.pi))
    kw = dict(mount_x_m=mx * max(0.5 * length_m - 0.2, 0.0),
              mount_y_m=my * max(0.5 * width_m - 0.2, 0.0), mount_z_m=mz, mount_yaw_deg=myaw,
              start_freq_hz=f0 + sweep if down else f0,
              slope_hz_per_s=-slope if down else slope, chirp_period_s=period,
              ramp_time_s=ramp, chirp_offset_s=offset, tx_power_dbm=fam.tx_power_dbm,
              antenna_gain_dbi=fam.antenna_gain_dbi,
              pattern_exponent_az=fam.pattern_exponent_az,
              pattern_exponent_el=fam.pattern_exponent_el, phase_rad=phase)
    kw.update(overrides)
    return RadarEquipment(**kw)


#: Stream id of the equipment draws: SeedSequence([seed, EQUIPMENT_STREAM, actor_id]).
EQUIPMENT_STREAM = 14


def _actor_rng(seed: int, actor_id: int) -> np.random.Generator:
    return np.random.default_rng(np.random.SeedSequence([int(seed), EQUIPMENT_STREAM,
                                                         int(actor_id)]))


def equipment_table(actors: pd.DataFrame, seed: int, *,
                    equipped_share: float = 0.0, radars=(),
                    family_weights: dict[str, float] | None = None) -> pd.DataFrame:
    """The radars of a scenario run, one row per equipped actor.

    Parameters
    ----------
    actors : pandas.DataFrame
        One row per actor: ``actor_id``, ``actor_class``, ``length_m``, ``width_m`` (e.g. the
        first truth row of each actor).
    seed : int
        Scenario seed. Actor a draws from SeedSequence([seed, EQUIPMENT_STREAM, a]): first a
        uniform that decides whether it is equipped (u < share, so a lower share's equipped
        set is a subset of a higher share's, with the same radars), then its family and radar.
    equipped_share : float
        Share of the `EQUIPPED_CLASSES` actors without an explicit radar that carry one, in
        [0, 1]; each is equipped independently with this probability.
    radars : sequence of RadarSpec
        Explicit radars (they always exist, whatever the share).
    family_weights : dict, optional
        Family probabilities for the random radars (default `FAMILY_WEIGHTS`).

    Returns
    -------
    pandas.DataFrame
        ``actor_id`` then the `RadarEquipment` fields, sorted by actor_id.
    """
    if isinstance(equipped_share, bool) or not 0 <= equipped_share <= 1:
        raise BadInput(f"equipped_share={equipped_share!r} must be in [0, 1]")
    weights = dict(FAMILY_WEIGHTS if family_weights is None else family_weights)
    unknown = sorted(set(weights) - set(WAVEFORM_FAMILIES))
    if unknown:
        raise BadInput(f"family_weights: unknown families {unknown}")
    names = list(weights)
    p = np.array([weights[n] for n in names], dtype=float)
    p = p / p.sum()
    acts = actors.drop_duplicates("actor_id").sort_values("actor_id")
    by_id = {int(r.actor_id): r for r in acts.itertuples(index=False)}
    rows = []
    explicit = set()
    for spec in radars:
        r = by_id.get(spec.actor_id)
        if r is None:
            raise BadInput(f"radars: actor_id={spec.actor_id} is not an actor of the run")
        ov = dict(spec.overrides)
        if spec.family is None:
            eq = RadarEquipment(**ov)
        else:
            eq = draw_equipment(_actor_rng(seed, spec.actor_id), spec.family,
                                float(r.length_m), float(r.width_m), **ov)
        rows.append({"actor_id": spec.actor_id, **_as_dict(eq)})
        explicit.add(spec.actor_id)
    for a, r in by_id.items():
        if a in explicit or r.actor_class not in EQUIPPED_CLASSES:
            continue
        g = _actor_rng(seed, a)
        if g.random() < equipped_share:
            fam = names[int(g.choice(len(names), p=p))]
            eq = draw_equipment(g, fam, float(r.length_m), float(r.width_m))
            rows.append({"actor_id": a, **_as_dict(eq)})
    cols = ["actor_id"] + [f.name for f in fields(RadarEquipment)]
    if not rows:
        return pd.DataFrame({c: pd.Series(dtype=np.int64 if c == "actor_id" else float)
                             for c in cols})
    return pd.DataFrame(rows)[cols].sort_values("actor_id").reset_index(drop=True)


def _as_dict(eq: RadarEquipment) -> dict:
    return {f.name: float(getattr(eq, f.name)) for f in fields(RadarEquipment)}
