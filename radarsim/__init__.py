"""AWR2944 corner-radar front-end model: configuration, presets, scatterers, ADC synthesis.

    cfg = radarsim.presets.r79_ddma()
    adc = radarsim.simulate_frame(cfg, radarsim.Scatterers(P, V, S), rng=np.random.default_rng(0))
"""
from . import presets
from .config import RadarConfig
from .mimo import MIMO_SCHEMES, MimoScheme, register_scheme
from .frontend import (ADCSaturationWarning, expected_sample_snr_db, received_power_w,
                       saturation_fraction, simulate_frame, transmit_phasors)
from .scatterers import Scatterers

__all__ = ["RadarConfig", "MIMO_SCHEMES", "MimoScheme", "register_scheme", "Scatterers",
           "presets", "simulate_frame",
           "received_power_w", "expected_sample_snr_db", "saturation_fraction",
           "transmit_phasors", "ADCSaturationWarning"]
