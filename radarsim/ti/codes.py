"""TI's numeric codes of the CLI arguments, in one table for the reader, the writer and the
pipeline's CFAR registry (which keys its modes by the names this table maps to).

References
----------
.. [1] TI, "CFAR algorithms in mmWave SDK" [TI-DPC], ``DPU_CFARProc_CfarCfg``: averageMode
   0 CA, 1 CAGO, 2 CASO, 3 OS; procDirection 0 range, 1 Doppler.
.. [2] TI, AWR2944 R79 demo (TIDEP-01027) ``mss/mmw_cli.c``: thresholdScale limit.
"""
from __future__ import annotations

__all__ = ["CFAR_AVERAGE_MODES", "CFAR_RANKED_CODES", "CFAR_RANKED_MODES", "CFAR_DIRECTIONS",
           "MAX_CFAR_THRESHOLD_DB", "cfar_code"]

MAX_CFAR_THRESHOLD_DB = 100.0  # R79 demo mmw_cli.c: "Maximum value for CFAR thresholdScale"

#: TI ``averageMode`` code -> CFAR mode name ([TI-DPC]; the pipeline's CFAR_MODES keys).
CFAR_AVERAGE_MODES = {0: "ca", 1: "cago", 2: "caso", 3: "os"}
#: ``averageMode`` codes whose noise estimate is an order statistic (they need ``osKvalue``).
CFAR_RANKED_CODES = frozenset({3})
CFAR_RANKED_MODES = frozenset(CFAR_AVERAGE_MODES[c] for c in CFAR_RANKED_CODES)
#: ``procDirection`` code -> direction name.
CFAR_DIRECTIONS = {0: "range", 1: "doppler"}


def cfar_code(mode: str) -> int:
    """TI ``averageMode`` code of a CFAR mode name (inverse of `CFAR_AVERAGE_MODES`)."""
    return {v: k for k, v in CFAR_AVERAGE_MODES.items()}[mode]
