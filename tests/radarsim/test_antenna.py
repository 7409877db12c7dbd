"""Element gain pattern (radarsim.antenna): isotropic option and the documented cosine pattern.

Reference: the module docstring (n_az = 1.2: -3 dB one way at +/-56 deg, -9 dB at +/-80 deg;
n_el = 4: -3 dB at 33 deg) and cos^n patterns (Balanis sec. 2.5)."""
from __future__ import annotations

import numpy as np
import pytest

import radarsim
from radarsim.antenna import element_gain_linear


def _db(x):
    return 10 * np.log10(x)


def test_isotropic_is_flat(make_config):
    cfg = make_config(antenna_pattern="isotropic")
    az = np.radians(np.linspace(-179, 179, 37))
    el = np.radians(np.linspace(-80, 80, 37))
    g = element_gain_linear(cfg, az, el, 10.0)
    np.testing.assert_allclose(g, 10.0)


def test_cosine_pattern_beamwidths_match_docstring(make_config):
    cfg = make_config()
    assert cfg.antenna_pattern == "cosine"
    zero = np.zeros(1)
    g = lambda az, el: _db(element_gain_linear(cfg, np.radians([az]), np.radians([el]), 0.0))[0]  # noqa: E731
    assert g(0, 0) == pytest.approx(0.0)
    # Azimuth: -3 dB at +/-56 deg, -9.1 dB at +/-80 deg, symmetric.
    for s in (1, -1):
        assert g(s * 56, 0) == pytest.approx(-3.0, abs=0.1)
        assert g(s * 80, 0) == pytest.approx(1.2 * _db(np.cos(np.radians(80))), abs=1e-9)
        assert -10 < g(s * 80, 0) < -8
    # Elevation: -3 dB at 33 deg.
    assert g(0, 33) == pytest.approx(-3.0, abs=0.15)
    # Monotonic fall-off across the FOV and nothing behind the radar.
    az = np.radians(np.arange(0, 90, 5))
    gg = element_gain_linear(cfg, az, np.zeros_like(az), 0.0)
    assert np.all(np.diff(gg) < 0)
    assert element_gain_linear(cfg, np.radians([120.0]), zero, 10.0)[0] == 0.0


def test_pattern_reaches_received_power_two_way(make_config, make_scene):
    """Two-way (Tx and Rx element) pattern in the radar equation: at 80 deg azimuth the echo is
    2 x 9.12 = 18.2 dB weaker than at boresight; isotropic: no change."""
    scene = make_scene([(50.0, 0.0, 0.0, 0.0, 10.0), (50.0, 80.0, 0.0, 0.0, 10.0),
                        (50.0, -80.0, 0.0, 0.0, 10.0)])
    p = radarsim.received_power_w(make_config(), scene)
    expected = 2 * 1.2 * _db(np.cos(np.radians(80)))
    assert _db(p[1] / p[0]) == pytest.approx(expected, abs=1e-6)
    assert _db(p[2] / p[0]) == pytest.approx(expected, abs=1e-6)
    p_iso = radarsim.received_power_w(make_config(antenna_pattern="isotropic"), scene)
    np.testing.assert_allclose(p_iso, p_iso[0])
