"""TI's multiObjBeamForming in the DDMA chain (`ProcessingConfig.azimuth_sidelobe_db`):
disabled keeps the strongest azimuth peak of a range-Doppler cell, enabled with threshold t
also a second peak whose magnitude exceeds t x the first's."""
import numpy as np

import pipeline
import radarsim
from radarsim.ti.processing_handlers import ONE_PEAK_DB
from tests.pipeline.test_chain import scene_at_snr


def test_two_targets_in_one_cell(make_config, make_scene):
    """Two 30 dB targets at one range and speed, -20 and +25 deg (well apart for the
    16-element row): one point with multiObjBeamForming disabled, two with it enabled at 0.5
    (their peaks differ by far less than 6 dB)."""
    cfg = make_config("ddma", antenna_pattern="isotropic")
    sc = scene_at_snr(cfg, make_scene, [[40.0, -20.0, 0.0, 3.0, 30.0],
                                        [40.0, 25.0, 0.0, 3.0, 30.0]])
    adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(11))
    counts = {}
    for name, db in (("disabled", ONE_PEAK_DB), ("enabled", -20 * np.log10(0.5))):
        pc = pipeline.process_frame(cfg, adc,
                                    pipeline.ProcessingConfig().replace(azimuth_sidelobe_db=db))
        cell = pc[((pc.range_m - 40.0).abs() < 1.0) & ((pc.radial_velocity_mps - 3.0).abs() < 0.5)]
        counts[name] = sorted(np.round(cell.azimuth_deg).astype(int))
    assert len(counts["disabled"]) == 1, counts
    assert len(counts["enabled"]) == 2, counts
    assert abs(counts["enabled"][0] + 20) <= 2 and abs(counts["enabled"][1] - 25) <= 2
