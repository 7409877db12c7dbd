"""Shared factory fixtures."""
from __future__ import annotations

import numpy as np
import pytest

import radarsim


@pytest.fixture
def make_config():
    """make_config(mimo="ddma", **overrides) -> RadarConfig based on the R79 preset."""
    def _make(mimo: str = "ddma", **overrides) -> radarsim.RadarConfig:
        return radarsim.presets.PRESETS[f"r79_{mimo}"](**overrides)
    return _make


@pytest.fixture
def make_scene():
    """make_scene(targets) -> Scatterers from (range_m, azimuth_deg, elevation_deg,
    radial_velocity_mps, rcs_m2) tuples (velocity purely radial)."""
    def _make(targets) -> radarsim.Scatterers:
        t = np.atleast_2d(np.asarray(targets, dtype=float))
        if t.size == 0:
            return radarsim.Scatterers.empty()
        r, az, el, vr, rcs = (t[:, i] for i in range(5))
        az, el = np.radians(az), np.radians(el)
        u = np.column_stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        return radarsim.Scatterers(position_m=r[:, None] * u, velocity_mps=vr[:, None] * u,
                                   rcs_m2=rcs, actor_id=np.arange(len(r)))
    return _make


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
