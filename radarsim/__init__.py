"""AWR2944 corner-radar front-end model: configuration, presets, scatterers, ADC synthesis.

    cfg = radarsim.presets.r79_ddma()
    adc = radarsim.simulate_frame(cfg, radarsim.Scatterers(P, V, S), rng=np.random.default_rng(0))
"""
from . import mimo_fast_slow, presets, shifter  # noqa: F401  (mimo_fast_slow registers)
from .boards import BOARDS, Board, register_board
from .calibration import (
                          ShifterCalibration,
                          calibrate_shifters,
                          measure_shifters,
                          resolve_calibration,
)
from .chips import CHIPS, Chip, register_chip
from .frontend import (
                          ADCSaturationWarning,
                          expected_sample_snr_db,
                          received_power_w,
                          saturation_fraction,
                          simulate_frame,
                          simulate_frame_weights,
                          transmit_phasors,
)
from .mimo import MIMO_SCHEMES, MimoScheme, register_scheme
from .radar_config import RadarConfig
from .scatterers import Scatterers
from .shifter import ShifterErrorSpec

__all__ = ["RadarConfig", "MIMO_SCHEMES", "MimoScheme", "register_scheme", "Scatterers",
           "presets", "simulate_frame",
           "received_power_w", "expected_sample_snr_db", "saturation_fraction",
           "transmit_phasors", "ADCSaturationWarning", "shifter", "calibrate_shifters",
           "measure_shifters", "ShifterCalibration", "ShifterErrorSpec",
           "simulate_frame_weights", "CHIPS", "Chip", "register_chip", "BOARDS", "Board",
           "register_board", "resolve_calibration"]
