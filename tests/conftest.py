"""Shared factory fixtures."""
from __future__ import annotations

import numpy as np
import pytest

import radarsim


@pytest.fixture
def make_config():
    """make_config(mimo="ddma", **overrides) -> RadarConfig based on the R79 preset."""
    def _make(mimo: str = "ddma", **overrides) -> radarsim.RadarConfig:
        return radarsim.presets.r79(mimo, **overrides)
    return _make


@pytest.fixture
def make_scene():
    """make_scene(targets) -> Scatterers from (range_m, azimuth_deg, elevation_deg,
    radial_velocity_mps, rcs_m2) tuples (velocity purely radial)."""
    def _make(targets) -> radarsim.Scatterers:
        t = np.atleast_2d(np.asarray(targets, dtype=float))
        if t.size == 0:
            return radarsim.Scatterers.empty()
        return radarsim.Scatterers.from_spherical(*t[:, :5].T, actor_id=np.arange(len(t)))
    return _make


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture
def make_x18():
    """make_x18(adc_mode) -> an xWR18xx TDMA profile at 10 Msps, 128 samples, 30 MHz/us (IF
    corner 5.5 MHz real, 11 MHz I/Q), isotropic elements: a second chip family and the
    complex ADC modes next to the R79 preset."""
    def _make(adc_mode: str = "complex1x") -> radarsim.RadarConfig:
        return radarsim.RadarConfig(chip="AWR1843", adc_mode=adc_mode, mimo="tdma", n_tx=3,
                                    n_chirps=96, n_samples=128, adc_rate_sps=10e6,
                                    slope_hz_per_s=30e12, ramp_end_time_s=18.81e-6,
                                    idle_time_s=5e-6, antenna_pattern="isotropic")
    return _make
