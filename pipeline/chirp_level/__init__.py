"""The chip's chirp-level chain before the radar cube is stored (R79 demo RangeProc DPU).

[TI-DAZ] section 2 / [TI-DDMA] section 5.1 (table 5): per chirp, the HWA estimates and removes
the DC of each Rx (param 2-3), gathers interference statistics (param 3), zeroes the samples the
statistics flag and takes the windowed range FFT (param 4), then EGE-compresses the range FFT to
50 % in blocks of 4 antennas x 8 range bins (param 5, section 5.2); the Doppler stage
decompresses first (section 5.3). Each step is switchable in `ProcessingConfig`
(`dc_removal`, `interference_mitigation`, `compression`); `range_stage` is the hook the chains
call instead of a bare range FFT.

One step per module: `dc` (DC estimation and removal), `ege` (EGE compression model; its block
format in `pipeline.ege_format`),
`stage` (the steps in the demo's order; `shared_range_stage` runs them once per frame and
setting for every chain and metric that reads the frame) and `noise_floor` (the floor-rise
metric). The interference statistics, flags and repair are a package of their own,
`pipeline.interference`.

References
----------
.. [1] [TI-DDMA] section 5.1-5.3 (tables 5-8), [TI-DAZ] section 2-4.
.. [2] TI SWRA725, "Interference Mitigation for AWR294x" (2021), sections 3.1-3.3.
.. [3] TI MMWAVE-MCUPLUS-SDK, DDM demo: ``MmwDemo_CLIIntfMitigCfg`` (mmw_cli.c),
       ``rangeProcHWADDMA_findIntfStatsStaticParams``, ``rangeProcHWA_ConfigHWACommon``
       (EGEKparam, compression LFSR) and ``rangeProcHWA_ConfigHWA`` (mitigation and
       compression paramsets) in datapath/dpu/rangeprocDDMA/rangeprochwaDDMA.c; the DPC's
       ``hwaInterfMitigWindow`` (16-point Hann, Q5); MCU+ SDK HWA driver API
       ``HWA_PreProcessing.interfMitigation``, ``HWA_AccelModeCompress``.
"""
from ..interference import INTF_THRESHOLD_MODES, interference_flags, zero_flagged
from .dc import remove_dc
from .ege import (
                  EGE_HEADER_BITS,
                  EGE_K_ARRAY,
                  HWA_OUTPUT_SCALE,
                  ege_block_bits,
                  ege_compress,
                  ege_min_ratio,
)
from .noise_floor import NoiseFloor, noise_floor_key, noise_floor_rise
from .stage import (
                    idle_mitigation,
                    range_stage,
                    range_stage_key,
                    shared_range_stage,
                    windowed_range_stage,
)

__all__ = ["range_stage", "windowed_range_stage", "remove_dc", "interference_flags", "zero_flagged",
           "ege_compress", "ege_block_bits", "ege_min_ratio", "NoiseFloor", "noise_floor_rise",
           "noise_floor_key", "INTF_THRESHOLD_MODES", "HWA_OUTPUT_SCALE", "EGE_K_ARRAY",
           "EGE_HEADER_BITS", "shared_range_stage", "range_stage_key", "idle_mitigation"]
