"""The radar configuration's public entry point: the `RadarConfig` value and its constants, and
the TI profile bridge's two functions.

    from radarsim.config import RadarConfig, from_ti_cfg, to_ti_cfg

`RadarConfig` itself is defined in `radarsim.radar_config`, a plain validated value that knows
nothing of TI profiles. The TI bridge (`radarsim.ti`) builds configs, so it imports that value;
this module sits above both, so ``radarsim.config.from_ti_cfg`` works without an import circle.
Modules inside `radarsim` import `radarsim.radar_config`, never this module.
"""
from __future__ import annotations

from .radar_config import (
                           ADC_FULL_SCALE_CODE,
                           ADC_MODES,
                           ANTENNA_PATTERNS,
                           BAND_MAX_HZ,
                           BAND_MIN_HZ,
                           C_MPS,
                           K_BOLTZMANN,
                           MAX_ADC_RATE_SPS,
                           MAX_IF_BANDWIDTH_HZ,
                           MAX_N_RX,
                           MAX_N_TX,
                           MIMO_SCHEMES,
                           PHASE_QUANTIZATIONS,
                           ArrayConfig,
                           Impairments,
                           MimoSchedule,
                           RadarConfig,
                           RfBudget,
                           ShifterConfig,
                           Waveform,
)
from .ti import from_ti_cfg, to_ti_cfg

__all__ = ["RadarConfig", "Waveform", "ArrayConfig", "MimoSchedule", "ShifterConfig",
           "Impairments", "RfBudget", "from_ti_cfg", "to_ti_cfg", "MIMO_SCHEMES",
           "PHASE_QUANTIZATIONS",
           "ANTENNA_PATTERNS", "ADC_MODES", "ADC_FULL_SCALE_CODE", "C_MPS", "K_BOLTZMANN",
           "MAX_ADC_RATE_SPS", "MAX_IF_BANDWIDTH_HZ", "BAND_MIN_HZ", "BAND_MAX_HZ", "MAX_N_TX",
           "MAX_N_RX"]
