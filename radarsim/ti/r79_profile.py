"""The AWR2944 R79 corner-radar demo (TIDEP-01027) as a TI profile: its CFAR, its demo
commands, the firmware's hard-coded command list and the shipped ``radarsim/data/r79_ddma.cfg``."""
from __future__ import annotations

from importlib import resources
from pathlib import Path

from ..presets import r79_ddma
from .profile import TiCfar
from .writer import to_ti_cfg

__all__ = ["R79_CFAR", "R79_DEMO_LINES", "R79_FIRMWARE_LINES", "R79_COMMENTS", "r79_cfg_text",
           "r79_cfg_path"]


#: The R79 demo's CFAR (AWR2944 R79 mmw_cli.c): OS-CFAR along Doppler, 16 cells a side, no
#: guard, k = 24, cyclic, 12 dB; the range CFAR (15 dB) is disabled there by ``rangeCfar 0``.
R79_CFAR = {
    "doppler": TiCfar(direction="doppler", mode="os", window_cells=16, guard_cells=0,
                      noise_div_shift=0, cyclic=True, threshold_db=12.0, peak_grouping=False,
                      os_rank=24, os_edge_k_scale=False),
    "range": TiCfar(direction="range", mode="os", window_cells=16, guard_cells=0,
                    noise_div_shift=0, cyclic=True, threshold_db=15.0, peak_grouping=False,
                    os_rank=7, os_edge_k_scale=False),
}


#: Commands of the AWR2944 R79 demo (TIDEP-01027 mmw_cli.c) that configure its on-chip
#: processing, UART output and tracker: shipped in r79_ddma.cfg, reported as ignored here.
R79_DEMO_LINES = (
    "guiMonitor -1 1 0 0 0 0 0",
    "compressionCfg -1 1 0 0.5 8",
    "intfMitigCfg -1 15 18",
    "localMaxCfg -1 4 40",
    "antennaCalibParams " + " ".join(["0 1"] * 16),
    "analogMonitor 0 0",
    "calibData 0 0 0",
    "appSceneryParams 0.0 0.0 1.0 -25.0 0.0 -14.0 14.0 1.0 231.0 -5.0 5.0",
    "appGatingParams 8.0 10.0 8.0 4.0 40.0",
    "appStateParams 3 2 10 100 10 0",
    "appAllocParams 20.0 20.0 1.0 6 4.0 20.0",
    "gtrack 1 800 30 0.0 40.8781 0.1065 1.0 10.0 0.0 0.250 0",
    "ransac 1 200 1.0",
    "rangeCfar 0",
)
#: The command list the R79 demo firmware hard-codes (TIDEP-01027 ``mss/mmw_cli.c``,
#: ``gHardcodedCliConfigs``): no ddmPhaseShiftAntOrder (the firmware's DDM order is Tx1, Tx3,
#: Tx4, Tx2), no antGeometryCfg (the EVM array), an interleaved ADC buffer.
R79_FIRMWARE_LINES = (
    "sensorStop", "flushCfg", "dfeDataOutputMode 1", "channelCfg 15 15 0", "adcCfg 2 0",
    "adcbufCfg -1 1 0 0 1", "lowPower 0 0",
    "profileCfg 0 77 5 5 18.81 0 0 8.883 0 384 30000 0 0 42",
    "chirpCfg 0 5 0 0 0 0 0 15", "frameCfg 0 5 128 0 384 250 1 0",
    "guiMonitor -1 3 0 0 0 0 0",
    "cfarCfg -1 1 3 16 0 0 1 12.0 0 24 0", "cfarCfg -1 0 3 16 0 0 1 15.0 0 7 0",
    *R79_DEMO_LINES[1:10],
    "appSceneryParams 0.0 0.0 1.0 0.0 0.0 -14.0 14.0 1.0 231.0 -5.0 5.0",
    *R79_DEMO_LINES[11:],
    "sensorStart",
)
R79_COMMENTS = (
    "TI R79 corner-radar DDMA waveform (TIDEP-01027; [TI-DDMA] table 2): the R79 demo's",
    "profileCfg/chirpCfg/frameCfg/cfarCfg and demo commands, plus ddmPhaseShiftAntOrder and",
    "antGeometryCfg of the MCU+ SDK DDM demo. Phase codes floor-quantised as [TI-DDMA] table 4.",
)


def r79_cfg_text() -> str:
    """The text of ``radarsim/data/r79_ddma.cfg``, regenerated from the R79 preset."""
    return to_ti_cfg(r79_ddma(), cfar=R79_CFAR, extra_lines=R79_DEMO_LINES,
                     comments=R79_COMMENTS)


def r79_cfg_path() -> Path:
    """Path of the shipped R79 DDMA profile, ``radarsim/data/r79_ddma.cfg``."""
    return Path(str(resources.files("radarsim") / "data" / "r79_ddma.cfg"))
