"""The TI demos' detection filters as ProcessingConfig fields: field of view (cfarFovCfg /
aoaFovCfg: detections outside dropped) and static clutter removal (clutterRemoval)."""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim


@pytest.fixture(scope="module")
def two_targets():
    """R79 TDMA frame with reflectors at 30 m / +20 deg / -5 m/s and 80 m / -30 deg / +3 m/s."""
    cfg = radarsim.presets.r79_tdma()
    sc = radarsim.Scatterers.from_spherical(np.array([30.0, 80.0]), np.array([20.0, -30.0]),
                                            np.zeros(2), np.array([-5.0, 3.0]),
                                            np.array([10.0, 10.0]))
    adc = radarsim.simulate_frame(cfg, sc, rng=np.random.default_rng(1))
    return cfg, adc


def _near(pc, r_m):
    return bool((abs(pc["range_m"] - r_m) < 2.0).any())


@pytest.mark.parametrize("limits, keeps_30, keeps_80", [
    ({}, True, True),
    ({"fov.range_m": (0.0, 50.0)}, True, False),
    ({"fov.velocity_mps": (0.0, 10.0)}, False, True),
    ({"fov.azimuth_deg": (0.0, 60.0)}, True, False),
    ({"fov.elevation_deg": (5.0, 20.0)}, False, False),
])
def test_detections_outside_the_field_of_view_are_dropped(two_targets, limits, keeps_30,
                                                          keeps_80):
    cfg, adc = two_targets
    pc = pipeline.process_frame(cfg, adc, pipeline.ProcessingConfig().replace(**limits))
    assert (_near(pc, 30.0), _near(pc, 80.0)) == (keeps_30, keeps_80)
    for field, column in pipeline.fov.FOV_FIELDS.items():
        if f"fov.{field}" in limits:
            assert pc[column].between(*limits[f"fov.{field}"]).all()


@pytest.mark.parametrize("value, pattern", [((5.0, 1.0), r"min <= max"),
                                            ((0.0, float("inf")), r"finite"),
                                            ("wide", r"\(min, max\) pair")])
def test_bad_field_of_view_is_refused(value, pattern):
    with pytest.raises(ValueError, match=rf"range_fov_m=.*{pattern}"):
        pipeline.ProcessingConfig().replace(range_fov_m=value)


def test_static_clutter_removal_drops_zero_doppler_returns():
    """clutterRemoval (SDK 3.x DopplerProc): each virtual channel's mean over the frame's
    chirps is subtracted, so a static reflector vanishes and a moving one stays (TDMA, BPM);
    a chain without it refuses the setting."""
    cfg = radarsim.presets.r79_tdma()
    sc = radarsim.Scatterers.from_spherical(np.array([30.0, 60.0]), np.zeros(2), np.zeros(2),
                                            np.array([0.0, -4.0]), np.array([10.0, 10.0]))
    adc = radarsim.simulate_frame(cfg, sc, rng=np.random.default_rng(3))
    plain = pipeline.process_frame(cfg, adc, pipeline.ProcessingConfig())
    removed = pipeline.process_frame(cfg, adc,
                                     pipeline.ProcessingConfig().replace(clutter_removal=True))
    assert _near(plain, 30.0) and _near(plain, 60.0)
    assert not _near(removed, 30.0) and _near(removed, 60.0)
    ddma = radarsim.presets.r79_ddma()
    with pytest.raises(ValueError, match=r"clutter_removal=True: the ddma chain has no static "
                                         r"clutter removal"):
        pipeline.process_frame(ddma, radarsim.simulate_frame(ddma, sc, np.random.default_rng(3)),
                               pipeline.ProcessingConfig().replace(clutter_removal=True))
