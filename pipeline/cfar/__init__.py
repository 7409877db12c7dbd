"""CFAR detection, in one folder: the modes, their threshold design, their detector and settings.

`base` holds the mode interface (`CfarMode`); `square_law` the CA, CAGO, CASO and OS modes (with
OS's compiled detector), `log_law` TI's log-magnitude CA family; `modes` the registry
`CFAR_MODES` of all of them and the functions that look a mode up by name (threshold scale from
a false-alarm probability, noise estimates, the full-map reference); `peaks` the chains'
detector (`cfar_peaks`); `gamma_law` the gamma distribution the threshold design integrates;
`config` the settings (`CfarConfig`). A new mode is a `CfarMode` subclass in its own module
and one `CFAR_MODES.register(mode)`.
"""
from .base import CfarMode, training_offsets
from .config import CfarConfig, default_os_rank
from .log_law import TI_DB_PER_CLI_DB, TI_LOG_MODES, LogCellAveraging, log_cfar_pfa, ti_log_mode
from .modes import (
                      CFAR_MODES,
                      cfar_map,
                      cfar_mode,
                      cfar_scale,
                      noise_estimate,
                      noise_mean_factor,
                      pfa_numeric,
                      pfa_of_scale,
)
from .peaks import candidate_cfar, cfar_peaks, training_table
from .square_law import CellAveraging, OrderStatistic, SideSelecting, rohling_os_pfa

__all__ = ["CfarMode", "CellAveraging", "SideSelecting", "OrderStatistic", "LogCellAveraging",
           "CFAR_MODES", "cfar_mode", "cfar_scale", "noise_mean_factor", "pfa_of_scale",
           "pfa_numeric", "training_offsets", "noise_estimate", "cfar_map", "rohling_os_pfa",
           "candidate_cfar", "cfar_peaks", "training_table", "CfarConfig", "default_os_rank",
           "TI_DB_PER_CLI_DB", "TI_LOG_MODES", "ti_log_mode", "log_cfar_pfa"]
