"""Signal chain: ADC frame -> point cloud (DDMA and TDMA) -> tracks.

    pc = pipeline.process_frame(cfg, adc)          # pandas.DataFrame, one row per detection
"""
from .cfar import CFAR_MODES, cfar_scale, noise_mean_factor
from .chain import (MIMO_CHAINS, POINT_CLOUD_COLUMNS, detection_map, frame_spectra,
                    process_frame)
from .config import CfarConfig, ProcessingConfig

__all__ = ["process_frame", "frame_spectra", "detection_map", "ProcessingConfig", "CfarConfig", "CFAR_MODES",
           "MIMO_CHAINS", "POINT_CLOUD_COLUMNS", "cfar_scale", "noise_mean_factor"]
