"""Bad ADC frames and chain arguments: ValueError naming the argument and the value."""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim

CFG = radarsim.presets.r79("ddma")
SHAPE = (CFG.n_chirps, CFG.n_rx, CFG.n_samples)

CASES = {
    "float_frame": (np.zeros(SHAPE, np.float32), CFG, None, r"adc dtype must be int16"),
    "int32_frame": (np.zeros(SHAPE, np.int32), CFG, None, r"adc dtype must be int16"),
    "list_frame": ([[[0]]], CFG, None, r"adc must be a numpy\.ndarray, got list"),
    "wrong_shape": (np.zeros((768, 4, 256), np.int16), CFG, None,
                    r"adc shape \(768, 4, 256\) does not match"),
    "transposed": (np.zeros((384, 4, 768), np.int16), CFG, None, r"adc shape \(384, 4, 768\)"),
    "cfg_not_radar_config": (np.zeros(SHAPE, np.int16), {"mimo": "ddma"}, None,
                             r"cfg must be a radarsim\.RadarConfig, got dict"),
    "proc_not_processing_config": (np.zeros(SHAPE, np.int16), CFG, {"cfar": "os"},
                                   r"proc must be a pipeline\.ProcessingConfig, got dict"),
    "cfar_wider_than_doppler": (np.zeros(SHAPE, np.int16), CFG,
                                pipeline.ProcessingConfig().replace(cfar_window_cells=70),
                                r"cfar window_cells=70 .* spans 285 Doppler bins, more than "
                                r"the 128"),
}


@pytest.mark.parametrize("adc, cfg, proc, match", list(CASES.values()), ids=list(CASES))
def test_process_frame_rejects(adc, cfg, proc, match):
    with pytest.raises(ValueError, match=match):
        pipeline.process_frame(cfg, adc, proc)


def test_detection_map_checks_the_cfar_window_too():
    with pytest.raises(ValueError, match=r"cfar window_cells=70"):
        pipeline.detection_map(CFG, np.zeros(SHAPE, np.int16),
                               pipeline.ProcessingConfig().replace(cfar_window_cells=70))


def test_doppler_azimuth_map_rejects_a_range_bin_outside_the_axis():
    with pytest.raises(ValueError, match=r"range_bin=192"):
        pipeline.doppler_azimuth_map(CFG, np.zeros(SHAPE, np.int16), 192)


N_KINDS = len(CASES) + 2
