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
