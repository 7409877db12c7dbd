"""Coherent patch sums against Knott's closed forms: flat plate (PO) and square trihedral
(shooting and bouncing rays), design.md 8."""
from __future__ import annotations

import numpy as np
import pytest

from radarsim.scene.canonical import plate_rcs_po, trihedral_rcs_sbr

LAM = 299_792_458.0 / 77e9


def test_plate_normal_incidence_is_19_2_dbsm():
    """10 cm square plate at 77 GHz: 4 pi A^2 / lambda^2 = 19.2 dBsm (design.md 8)."""
    got = 10 * np.log10(plate_rcs_po(0.1, 0.1, 0.0, LAM))
    assert got == pytest.approx(10 * np.log10(4 * np.pi * 0.01 ** 2 / LAM ** 2), abs=1e-9)
    assert got == pytest.approx(19.2, abs=0.05)


def test_plate_pattern_is_symmetric_sinc_squared_with_its_first_null():
    """sigma(theta) = 4 pi A^2 / lambda^2 cos^2 sinc^2(2 a sin / lambda), even in theta; the
    strip sum of 400 strips is exact while the path across a strip stays << lambda."""
    a, b = 0.2, 0.1
    theta = np.radians(np.linspace(-20, 20, 161))
    got = plate_rcs_po(a, b, theta, LAM, n_patches=2000)
    closed = (4 * np.pi * (a * b) ** 2 / LAM ** 2 * np.cos(theta) ** 2
              * np.sinc(2 * a * np.sin(theta) / LAM) ** 2)
    np.testing.assert_allclose(got, closed, rtol=0, atol=1e-3 * closed.max())
    np.testing.assert_allclose(got, got[::-1], rtol=1e-9, atol=1e-12 * got.max())
    null = np.arcsin(LAM / (2 * a))
    assert plate_rcs_po(a, b, null, LAM) < 1e-9 * closed.max()


@pytest.mark.parametrize("edge_m", [0.05, 0.1, 0.2])
def test_square_trihedral_boresight(edge_m):
    """12 pi a^4 / lambda^2 (Knott table 6.1). The ray grid resolves the aperture's edge to
    one cell (2 a sqrt(2/3) / 400): A_eff within ~1 %, sigma within 0.1 dB."""
    got = 10 * np.log10(trihedral_rcs_sbr(edge_m, LAM, n_rays=400))
    assert got == pytest.approx(10 * np.log10(12 * np.pi * edge_m ** 4 / LAM ** 2), abs=0.1)
