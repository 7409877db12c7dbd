"""Element gain pattern of a board's patch arrays (`radarsim.boards`: each board's exponents).

The default is a cosine power pattern, G(az, el) = G0 cos(az)^n_az cos(el)^n_el for
|az| < 90 deg (zero behind the radar). With n_az = 1.2 the one-way gain is -3 dB at +/-56 deg and
-9 dB at +/-80 deg, so the published +/-80 deg azimuth FOV is usable but some 18 dB weaker
(two-way) at its edges; n_el = 4 gives a -3 dB half-angle of 33 deg in elevation, a typical
vertically narrower series-fed patch (the AWR2944 EVM's values; other boards' exponents give
their user guides' half-power field of view, `radarsim.boards.cos_exponent_for_half_power`). The
isotropic option returns G0 everywhere (tests).

References
----------
.. [1] C. A. Balanis, Antenna Theory, 4th ed., sec. 2.5 (cos^n patterns and directivity).
.. [2] TI, AWR2944 EVM user guide: azimuth FOV +/-80 deg ([TI-DDMA] section 1).
"""
from __future__ import annotations

import numpy as np

from .radar_config import RadarConfig

__all__ = ["element_gain_linear"]


def element_gain_linear(cfg: RadarConfig, azimuth_rad: np.ndarray, elevation_rad: np.ndarray,
                        boresight_gain_dbi: float) -> np.ndarray:
    """One-way element power gain (linear) towards each direction.

    Parameters
    ----------
    cfg : RadarConfig
        Supplies `antenna_pattern` and the cosine exponents.
    azimuth_rad, elevation_rad : (K,) float
        Direction in the radar frame, rad.
    boresight_gain_dbi : float
        Peak gain G0, dBi.

    Returns
    -------
    (K,) float
        Power gain, linear (not dB).
    """
    az = np.asarray(azimuth_rad, dtype=np.float64)
    el = np.asarray(elevation_rad, dtype=np.float64)
    g0 = 10 ** (boresight_gain_dbi / 10)
    if cfg.antenna_pattern == "isotropic":
        return np.full(np.broadcast(az, el).shape, g0)
    cos_az = np.clip(np.cos(az), 0.0, None)
    cos_el = np.clip(np.cos(el), 0.0, None)
    return g0 * cos_az ** cfg.pattern_exponent_az * cos_el ** cfg.pattern_exponent_el
