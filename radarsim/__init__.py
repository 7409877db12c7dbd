"""77 GHz radar simulator: configuration, scene, MIMO schemes, front end, captures, TI profiles.

    cfg = radarsim.presets.r79_ddma()
    adc = radarsim.simulate_frame(cfg, radarsim.Scatterers(P, V, S), rng=np.random.default_rng(0))

Subpackages: `scene` (scatterers, the RCS model, ray cast, multipath, road clutter; its model
is also published as `radarsim.rcs`), `mimo` (the scheme registry and schemes), `capture`
(DCA1000 raw files, advanced-frame captures, frame regrouping) and `ti` (TI profiles and
mmWave Studio setups). The modules at this level describe the radar (`radar_config`, `chips`,
`boards`, `presets`) and synthesise its ADC frames (`frontend`, `antenna`, `receiver`,
`shifter`, `calibration`, `interference`).
"""
from . import mimo, presets, shifter  # noqa: F401  (importing mimo registers fast_slow)
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
from .mimo.schemes import MIMO_SCHEMES, MimoScheme, register_scheme
from .radar_config import (
                          ArrayConfig,
                          Impairments,
                          MimoSchedule,
                          RadarConfig,
                          RfBudget,
                          ShifterConfig,
                          Waveform,
)
from .scene.scatterers import Scatterers
from .shifter import ShifterErrorSpec

__all__ = ["RadarConfig", "Waveform", "ArrayConfig", "MimoSchedule", "ShifterConfig",
           "Impairments", "RfBudget", "MIMO_SCHEMES", "MimoScheme", "register_scheme", "Scatterers",
           "presets", "simulate_frame",
           "received_power_w", "expected_sample_snr_db", "saturation_fraction",
           "transmit_phasors", "ADCSaturationWarning", "shifter", "calibrate_shifters",
           "measure_shifters", "ShifterCalibration", "ShifterErrorSpec",
           "simulate_frame_weights", "CHIPS", "Chip", "register_chip", "BOARDS", "Board",
           "register_board", "resolve_calibration"]
