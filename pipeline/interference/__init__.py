"""Interference mitigation of the chirp-level chain, in one folder.

`detection` flags the samples a burst hit (the HWA statistics and thresholds, TI SWRA725
sections 3.1-3.2; `INTF_THRESHOLD_MODES`), `row_statistics` does the same and the DC estimate
in one compiled pass; `masks` turns flags into the samples to repair and picks the clean
reference rows; `methods` holds the repair methods, subclasses of `RepairMethod` in one
registry (`MITIGATIONS`), whose fills are in `fills` (taper, line, AR, tones) and `lowrank`
(the fast-time subspace fill); `rows` gives the range stage the flagged rows, repaired;
`config` holds the settings (`InterferenceConfig`: thresholds, mode, hysteresis, repair
method or "off").
"""
from .config import REPAIR_OFF, InterferenceConfig
from .detection import (
    INTF_THRESHOLD_MODES,
    IntfThresholdMode,
    flagged_rows,
    interference_flags,
    zero_flagged,
)
from .masks import FrameRows, close_gaps, widen
from .methods import (
    CLOSE_GAP_SAMPLES,
    EXTEND_SAMPLES,
    MITIGATIONS,
    ArRepair,
    InterpolateRepair,
    LowrankRepair,
    RepairMethod,
    TaperRepair,
    ZeroRepair,
    get_mitigation,
    repair,
)
from .rows import RepairedRows, repaired_rows

__all__ = ["InterferenceConfig", "REPAIR_OFF", "INTF_THRESHOLD_MODES", "IntfThresholdMode",
           "flagged_rows", "interference_flags", "zero_flagged", "FrameRows", "close_gaps",
           "widen", "CLOSE_GAP_SAMPLES", "EXTEND_SAMPLES", "MITIGATIONS", "RepairMethod",
           "ZeroRepair", "TaperRepair", "InterpolateRepair", "ArRepair", "LowrankRepair",
           "get_mitigation", "repair", "RepairedRows", "repaired_rows"]
