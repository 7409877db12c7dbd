"""Published RCS patterns of road users: the levels the scene model reproduces.

3GPP TR 38.901 (V19, clause 7.9.2.1) is the one source with machine-readable, measurement-based
aspect patterns for a passenger vehicle and a human: RCS model 2 writes the monostatic RCS of a
scattering point as a parabolic-in-dB lobe in azimuth and zenith (eq. 7.9.2-3 with the bistatic
angle beta = 0),

    sigma_dB(theta, phi) = max(G_max - min(-(sigma_V(theta) + sigma_H(phi)), sigma_max),
                               G_max - sigma_max)
    sigma_V = -min(12 ((theta - theta_c) / theta_3dB)^2, sigma_max)
    sigma_H = -min(12 ((phi - phi_c) / phi_3dB)^2, sigma_max)

in dBsm, with the lobe (front, left, back, right, roof) chosen by the range of (theta, phi) it
covers; and a log-normal large-scale factor sigma_S whose dB mean is tied to its spread so that
the linear mean is 1 (eq. 7.9.2-1: mu = -ln(10)/20 sigma^2). Angles are those of the direction
from the target to the radar in the target's frame: phi = 0 its front, 90 its left side, 180
its rear; theta = 90 horizontal, theta < 90 seen from above.

For the bicycle the one set of numbers reached is Belgiovane and Chen's 77 GHz sector means of
a bicycle as MathWorks encodes them for `backscatterBicyclist` ([2], [3]): -11.57 dBsm front and
rear (0-30 and 150-180 deg), -13.24 dBsm oblique (31-60, 121-150 deg), -8.1 dBsm side (61-120
deg), interpolated (pchip, linear m^2) through knots at 0/45/90/135/180 deg. They are about 10 dB
below a standing human (TR 38.901), so they are read as the bicycle's own echo, and a cyclist
(the scene's "bicycle" class: bicycle and rider, 1.8 m tall) is the incoherent sum of that
`SectorPattern` and the human's `Tr38901Pattern` (`IncoherentSum`).

Everything else in this module is what could be reached of the other sources the issue names
(see docs/rcs.md): they are recorded as `Reference` rows with their citation, and a class whose
pattern could not be sourced has ``pattern=None`` in `radarsim.rcs.CLASS_RCS` (its level stays the
geometric facet model calibrated to a class mean).

References
----------
.. [1] 3GPP TR 38.901 V19.x, "Study on channel model for frequencies from 0.5 to 100 GHz",
       clause 7.9.2.1, eqs. 7.9.2-1..3, Tables 7.9.2.1-1, -3, -4 (values as transcribed in the
       tr3gpp 0.2.0 package, data/TR-38.901/v19.4.0).
.. [2] D. Belgiovane, C. C. Chen, "Bicycles and human riders backscattering at 77 GHz for
       automotive radar", EuCAP 2016, pp. 1-5 (not reached itself; its sector means as [3]
       states them).
.. [3] MathWorks, Phased Array System Toolbox, ``backscatterBicyclist`` (R2019b+), internal
       function ``bicyclistrcs.m`` ("mean values of bicycle sectors from reference [3]",
       Copyright 2019 The MathWorks): frontRearRCS = 10^(-11.57/10), obliqueRCS =
       10^(-13.24/10), sideRCS = 10^(-8.1/10) m^2, pchip through 45-deg knots.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator

from core.errors import BadInput

__all__ = ["Lobe", "Tr38901Pattern", "SectorPattern", "IncoherentSum", "PATTERN_TYPES",
           "Reference", "VEHICLE_TR38901", "HUMAN_TR38901", "BICYCLE_BELGIOVANE",
           "CYCLIST_PATTERN", "REFERENCES", "lognormal_mu_db", "aspect_mean_dbsm"]


@dataclass(frozen=True, kw_only=True, slots=True)
class Lobe:
    """One scattering-point parameter set of TR 38.901 Tables 7.9.2.1-2..7 (angles in deg).

    ``phi_center_deg=None`` marks a lobe without azimuth dependence (the roof); the lobe serves
    directions with phi in [phi_lo, phi_hi) (mod 360) and theta in [theta_lo, theta_hi].
    """

    name: str
    phi_center_deg: float | None
    phi_3db_deg: float | None
    theta_center_deg: float
    theta_3db_deg: float
    g_max_db: float
    sigma_max_db: float
    theta_range_deg: tuple[float, float]
    phi_range_deg: tuple[float, float] = (0.0, 360.0)


def lognormal_mu_db(sigma_db: float) -> float:
    """dB mean of a unit-linear-mean log-normal factor of dB spread `sigma_db` (TR 38.901 eq.
    7.9.2-1): mu = -ln(10) / 20 sigma^2."""
    return -np.log(10.0) / 20.0 * sigma_db ** 2


def aspect_mean_dbsm(pattern, theta_deg: float = 90.0) -> float:
    """Mean linear RCS of `pattern` over azimuth (uniform, 0.1 deg grid) at one zenith, dBsm."""
    phi = np.arange(0.0, 360.0, 0.1)
    return float(10 * np.log10(np.mean(10 ** (pattern.rcs_dbsm(phi, theta_deg) / 10))))


@dataclass(frozen=True, kw_only=True, slots=True)
class Tr38901Pattern:
    """Monostatic RCS of a single-scattering-point target after TR 38.901 eq. 7.9.2-3.

    Parameters
    ----------
    lobes : tuple of Lobe
    sigma_s_db : float
        Spread of the log-normal large-scale factor sigma_S, dB.
    source : str
        Citation (table number).
    """

    lobes: tuple[Lobe, ...]
    sigma_s_db: float
    source: str

    def rcs_dbsm(self, phi_deg, theta_deg=90.0) -> np.ndarray:
        """RCS of the mean target (sigma_S = 1), dBsm.

        Parameters
        ----------
        phi_deg : array_like
            Azimuth of the radar seen from the target, deg (0 front, 90 left, 180 rear).
        theta_deg : array_like
            Zenith of the radar seen from the target, deg (90 horizontal).

        Returns
        -------
        numpy.ndarray
            Broadcast shape of the inputs, dBsm.
        """
        phi = np.mod(np.asarray(phi_deg, dtype=np.float64), 360.0)
        theta = np.asarray(theta_deg, dtype=np.float64)
        phi, theta = np.broadcast_arrays(phi, theta)
        out = np.full(phi.shape, np.nan)
        for lobe in self.lobes:
            lo, hi = lobe.phi_range_deg
            in_phi = np.mod(phi - lo, 360.0) < (hi - lo)
            in_theta = (theta >= lobe.theta_range_deg[0]) & (theta <= lobe.theta_range_deg[1])
            if lobe.theta_range_deg[1] < 180.0:  # half-open upper end, as the tables write it
                in_theta &= theta < lobe.theta_range_deg[1]
            sel = in_phi & in_theta & np.isnan(out)
            if not sel.any():      # e.g. the roof lobe for a radar near the horizon
                continue
            cap = lobe.sigma_max_db
            s_v = -np.minimum(12 * ((theta - lobe.theta_center_deg) / lobe.theta_3db_deg) ** 2,
                              cap)
            if lobe.phi_center_deg is None:
                s_h = 0.0
            else:
                dphi = np.angle(np.exp(1j * np.radians(phi - lobe.phi_center_deg)), deg=True)
                s_h = -np.minimum(12 * (dphi / lobe.phi_3db_deg) ** 2, cap)
            val = np.maximum(lobe.g_max_db - np.minimum(-(s_v + s_h), cap),
                             lobe.g_max_db - cap)
            out = np.where(sel, val, out)
        return out

    def aspect_mean_dbsm(self, theta_deg: float = 90.0) -> float:
        """Mean linear RCS over azimuth (uniform, 0.1 deg grid) at one zenith, dBsm."""
        return aspect_mean_dbsm(self, theta_deg)


@dataclass(frozen=True, kw_only=True, slots=True)
class SectorPattern:
    """Azimuth pattern through published sector means, mirror-symmetric about the actor's axis.

    The RCS is interpolated (shape-preserving pchip, in linear m^2, as [3] does) through knots
    at `aspects_deg` in [0, 180] and their mirror images; no zenith dependence (the sources give
    one elevation cut).

    Parameters
    ----------
    aspects_deg : tuple of float
        Knot aspects, strictly increasing, from 0 (front) to 180 (rear), deg.
    values_dbsm : tuple of float
        RCS at the knots, dBsm.
    sigma_s_db : float
        Log-normal spread used with this pattern, dB (>= 0).
    source : str
        Citation.
    """

    aspects_deg: tuple[float, ...]
    values_dbsm: tuple[float, ...]
    sigma_s_db: float
    source: str

    def __post_init__(self) -> None:
        a = np.asarray(self.aspects_deg, dtype=float)
        if a.size < 2 or a.size != len(self.values_dbsm) or a[0] != 0.0 or a[-1] != 180.0 \
                or np.any(np.diff(a) <= 0):
            raise BadInput(f"aspects_deg={self.aspects_deg!r} must rise strictly from 0 to "
                           f"180 deg with one value each (values_dbsm={self.values_dbsm!r})")
        if not np.all(np.isfinite(self.values_dbsm)) or not self.sigma_s_db >= 0:
            raise BadInput(f"values_dbsm={self.values_dbsm!r} must be finite and "
                           f"sigma_s_db={self.sigma_s_db!r} >= 0")

    def rcs_dbsm(self, phi_deg, theta_deg=90.0) -> np.ndarray:
        """RCS at azimuth `phi_deg` (0 front, 90 left, 180 rear; any zenith), dBsm; the
        broadcast shape of the inputs."""
        phi = np.asarray(phi_deg, dtype=np.float64)
        phi = np.broadcast_to(phi, np.broadcast_shapes(phi.shape, np.shape(theta_deg)))
        a = np.abs(np.mod(phi + 180.0, 360.0) - 180.0)          # |aspect| in [0, 180]
        knots = np.asarray(self.aspects_deg, dtype=float)
        lin = 10 ** (np.asarray(self.values_dbsm, dtype=float) / 10)
        # Mirror the knots about 0 and 180 so the interpolant is smooth across both axes.
        x = np.concatenate([-knots[:0:-1], knots, 360.0 - knots[-2::-1]])
        y = np.concatenate([lin[:0:-1], lin, lin[-2::-1]])
        return 10 * np.log10(PchipInterpolator(x, y)(a))

    def aspect_mean_dbsm(self, theta_deg: float = 90.0) -> float:
        """Mean linear RCS over azimuth, dBsm."""
        return aspect_mean_dbsm(self, theta_deg)


@dataclass(frozen=True, kw_only=True, slots=True)
class IncoherentSum:
    """Patterns of parts that add in power (parts far apart in wavelengths, random phases).

    Parameters
    ----------
    parts : tuple
        Patterns (`Tr38901Pattern`, `SectorPattern`) of the parts.
    sigma_s_db : float
        Log-normal spread of the whole, dB (>= 0).
    source : str
        Citation of the combination.
    """

    parts: tuple
    sigma_s_db: float
    source: str

    def __post_init__(self) -> None:
        if not self.parts or not all(isinstance(p, (Tr38901Pattern, SectorPattern))
                                     for p in self.parts):
            raise BadInput(f"parts={self.parts!r} must be Tr38901Pattern / SectorPattern")

    def rcs_dbsm(self, phi_deg, theta_deg=90.0) -> np.ndarray:
        """Power sum of the parts' RCS, dBsm."""
        return 10 * np.log10(sum(10 ** (p.rcs_dbsm(phi_deg, theta_deg) / 10)
                                 for p in self.parts))

    def aspect_mean_dbsm(self, theta_deg: float = 90.0) -> float:
        """Mean linear RCS over azimuth, dBsm."""
        return aspect_mean_dbsm(self, theta_deg)


#: Passenger vehicle, single scattering point: TR 38.901 Table 7.9.2.1-4 (10 lg sigma_M =
#: 11.25 dBsm, sigma_S = 3.41 dB).
VEHICLE_TR38901 = Tr38901Pattern(
    lobes=(
        Lobe(name="roof", phi_center_deg=None, phi_3db_deg=None, theta_center_deg=0.0,
             theta_3db_deg=18.13, g_max_db=21.26, sigma_max_db=14.19,
             theta_range_deg=(0.0, 30.0)),
        Lobe(name="front", phi_center_deg=0.0, phi_3db_deg=40.54, theta_center_deg=71.75,
             theta_3db_deg=29.13, g_max_db=15.52, sigma_max_db=8.45,
             theta_range_deg=(30.0, 180.0), phi_range_deg=(-45.0, 45.0)),
        Lobe(name="left", phi_center_deg=90.0, phi_3db_deg=26.90, theta_center_deg=79.70,
             theta_3db_deg=44.42, g_max_db=20.75, sigma_max_db=13.68,
             theta_range_deg=(30.0, 180.0), phi_range_deg=(45.0, 135.0)),
        Lobe(name="back", phi_center_deg=180.0, phi_3db_deg=36.32, theta_center_deg=79.65,
             theta_3db_deg=36.73, g_max_db=14.56, sigma_max_db=7.50,
             theta_range_deg=(30.0, 180.0), phi_range_deg=(135.0, 225.0)),
        Lobe(name="right", phi_center_deg=270.0, phi_3db_deg=26.90, theta_center_deg=79.70,
             theta_3db_deg=44.42, g_max_db=20.75, sigma_max_db=13.68,
             theta_range_deg=(30.0, 180.0), phi_range_deg=(225.0, 315.0)),
    ),
    sigma_s_db=3.41, source="3GPP TR 38.901 Table 7.9.2.1-4 (vehicle, RCS model 2)")

#: Human, RCS model 2: TR 38.901 Table 7.9.2.1-3 (sigma_S = 3.94 dB).
HUMAN_TR38901 = Tr38901Pattern(
    lobes=(
        Lobe(name="front", phi_center_deg=0.0, phi_3db_deg=216.65, theta_center_deg=90.0,
             theta_3db_deg=55.7, g_max_db=2.14, sigma_max_db=7.7, theta_range_deg=(0.0, 180.0),
             phi_range_deg=(-90.0, 90.0)),
        Lobe(name="back", phi_center_deg=180.0, phi_3db_deg=216.65, theta_center_deg=90.0,
             theta_3db_deg=55.7, g_max_db=2.14, sigma_max_db=7.7, theta_range_deg=(0.0, 180.0),
             phi_range_deg=(90.0, 270.0)),
    ),
    sigma_s_db=3.94, source="3GPP TR 38.901 Table 7.9.2.1-3 (human, RCS model 2)")

#: Bicycle alone, 77 GHz sector means of Belgiovane & Chen (EuCAP 2016) as MathWorks'
#: backscatterBicyclist encodes them (bicyclistrcs.m). No spread is given: sigma_s_db 0.
BICYCLE_BELGIOVANE = SectorPattern(
    aspects_deg=(0.0, 45.0, 90.0, 135.0, 180.0),
    values_dbsm=(-11.57, -13.24, -8.1, -13.24, -11.57), sigma_s_db=0.0,
    source="Belgiovane & Chen, EuCAP 2016, bicycle sector means at 77 GHz, as encoded in "
           "MathWorks backscatterBicyclist (bicyclistrcs.m)")

#: Cyclist (bicycle + rider): the rider as a TR 38.901 human plus the bicycle's sector means,
#: added in power. The rider carries ~90 % of the power at every aspect, so the whole takes the
#: human's published spread (3.94 dB).
CYCLIST_PATTERN = IncoherentSum(
    parts=(HUMAN_TR38901, BICYCLE_BELGIOVANE), sigma_s_db=HUMAN_TR38901.sigma_s_db,
    source="rider: 3GPP TR 38.901 Table 7.9.2.1-3 (human, model 2) + bicycle: Belgiovane & "
           "Chen 2016 sector means (MathWorks bicyclistrcs.m), power sum")

#: Pattern types a class may carry (`radarsim.scene.rcs_classes.ClassRcs.pattern`).
PATTERN_TYPES = (Tr38901Pattern, SectorPattern, IncoherentSum)


@dataclass(frozen=True, kw_only=True, slots=True)
class Reference:
    """One published value (or pattern) for a class, with its citation.

    Parameters
    ----------
    source : str
        Short citation.
    values_dbsm : dict
        Aspect (deg, 0 front / 90 left / 180 rear, or "mean" for an aspect average) -> dBsm.
    spread_db : float or None
        The source's own dB spread of the level (its log-normal sigma), if it gives one.
    note : str
        Band, conditions, what the number is.
    """

    source: str
    values_dbsm: dict
    spread_db: float | None = None
    note: str = ""


def _pattern_reference(pattern, note: str, mean_dbsm: float | None = None) -> Reference:
    aspects = (0.0, 45.0, 90.0, 135.0, 180.0)
    vals = {a: float(pattern.rcs_dbsm(a)) for a in aspects}
    vals["mean"] = pattern.aspect_mean_dbsm() if mean_dbsm is None else mean_dbsm
    return Reference(source=pattern.source, values_dbsm=vals, spread_db=pattern.sigma_s_db,
                     note=note)


#: Published values per class (docs/rcs.md lists what could not be sourced and why).
REFERENCES: dict[str, tuple[Reference, ...]] = {
    "car": (_pattern_reference(
        VEHICLE_TR38901, "horizontal incidence (theta = 90 deg); 'mean' is the table's "
        "10 lg sigma_M", 11.25),),
    "pedestrian": (
        _pattern_reference(HUMAN_TR38901, "horizontal incidence; 'mean' is model 1's "
                           "10 lg sigma_M (Table 7.9.2.1-1)", -1.37),
        Reference(source="3GPP TR 38.901 Table 7.9.2.1-1 (human, RCS model 1)",
                  values_dbsm={"mean": -1.37}, spread_db=3.94,
                  note="angle-independent mean of the linear monostatic RCS"),
    ),
    "bicycle": (
        _pattern_reference(CYCLIST_PATTERN, "cyclist = rider (human, model 2) + bicycle, "
                           "horizontal incidence; 'mean' over azimuth"),
        _pattern_reference(BICYCLE_BELGIOVANE, "bicycle alone, 77 GHz sector means: front/rear "
                           "0-30/150-180, oblique 31-60/121-150, side 61-120 deg"),
    ),
}
