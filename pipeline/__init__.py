"""Signal chain: ADC frame -> point cloud (one chain per MIMO scheme) -> tracks.

    pc = pipeline.process_frame(cfg, adc)          # pandas.DataFrame, one row per detection
"""
from core.numba_cache import install_cache_lock

from .cfar import CFAR_MODES, cfar_scale, noise_mean_factor
from .chain import (
                    MIMO_CHAINS,
                    POINT_CLOUD_COLUMNS,
                    detection_map,
                    doppler_azimuth_map,
                    frame_spectra,
                    process_frame,
                    process_frames,
)
from .config import CfarConfig, ProcessingConfig
from .mimo import DetectionMap, MimoChain, register_chain
from .tracking import (
                    EGO_MODELS,
                    MOTION_MODELS,
                    TRACK_COLUMNS,
                    TRACK_STATES,
                    EgoMotionConfig,
                    EgoMotionEstimate,
                    GroupTracker,
                    TrackerConfig,
                    estimate_ego_motion,
                    ground_radial_velocity,
                    static_mask,
                    track_frames,
)

__all__ = ["process_frame", "process_frames", "frame_spectra", "detection_map",
           "doppler_azimuth_map",
           "ProcessingConfig", "CfarConfig", "CFAR_MODES", "MIMO_CHAINS", "POINT_CLOUD_COLUMNS",
           "MimoChain", "register_chain", "DetectionMap",
           "cfar_scale", "noise_mean_factor",
           "GroupTracker", "TrackerConfig", "track_frames", "MOTION_MODELS", "TRACK_COLUMNS",
           "TRACK_STATES", "EgoMotionConfig", "EgoMotionEstimate", "EGO_MODELS",
           "estimate_ego_motion", "static_mask", "ground_radial_velocity", "install_cache_lock"]
