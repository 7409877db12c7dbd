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

Everything else in this module is what could be reached of the other sources the issue names
(see docs/rcs.md): they are recorded as `Reference` rows with their citation, and a class whose
pattern could not be sourced has ``pattern=None`` in `radarsim.rcs.CLASS_RCS` (its level stays the
geometric facet model calibrated to a class mean).

References
----------
.. [1] 3GPP TR 38.901 V19.x, "Study on channel model for frequencies from 0.5 to 100 GHz",
       clause 7.9.2.1, eqs. 7.9.2-1..3, Tables 7.9.2.1-1, -3, -4 (values as transcribed in the
       tr3gpp 0.2.0 package, data/TR-38.901/v19.4.0).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Lobe", "Tr38901Pattern", "Reference", "VEHICLE_TR38901", "HUMAN_TR38901",
           "REFERENCES", "lognormal_mu_db"]


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
        phi = np.arange(0.0, 360.0, 0.1)
        return float(10 * np.log10(np.mean(10 ** (self.rcs_dbsm(phi, theta_deg) / 10))))


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


def _pattern_reference(pattern: Tr38901Pattern, note: str, mean_dbsm: float) -> Reference:
    aspects = (0.0, 45.0, 90.0, 135.0, 180.0)
    vals = {a: float(pattern.rcs_dbsm(a)) for a in aspects}
    vals["mean"] = mean_dbsm
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
}
