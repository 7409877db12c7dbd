"""Fixtures of the chirp-level tests."""
from __future__ import annotations

import pytest

import radarsim


@pytest.fixture(scope="package")
def cfg():
    return radarsim.presets.r79_ddma(antenna_pattern="isotropic")
