"""`pipeline.cfar.gamma_law.Gamma` is `scipy.stats.gamma` bit for bit (the CFAR threshold design
integrates it: a different last bit would move every threshold scale)."""
from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from pipeline import cfar
from pipeline.cfar.gamma_law import Gamma

#: Shapes of the CFAR estimates (looks, N x looks, N/2 x looks) and their scales (1, 1/N).
SHAPES = (0.5, 1, 2, 3, 8, 12, 16, 24, 192, 384)
SCALES = (1.0, 1 / 24, 1 / 12, 1 / 16, 1 / 3, 0.1, 2.5)
EDGES = (0.0, -0.0, -1.0, np.inf, -np.inf, np.nan, 5e-324, 1e-300, 1e300)


def _points(rng):
    return np.concatenate([EDGES, np.logspace(-8, 4, 400), rng.exponential(5.0, 400)])


def _same_bits(a, b) -> bool:
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("shape", SHAPES)
def test_every_value_is_scipy_stats_gamma_bit_for_bit(shape, rng):
    x = _points(rng)
    with np.errstate(invalid="ignore"):  # pdf(inf) is inf - inf in both
        for scale in SCALES:
            ours, ref = Gamma(shape, scale=scale), stats.gamma(shape, scale=scale)
            for f in ("pdf", "cdf", "sf"):
                assert _same_bits(getattr(ours, f)(x), getattr(ref, f)(x)), (shape, scale, f)
                for xi in x[:len(EDGES) + 20]:  # quad calls with Python floats
                    a, b = getattr(ours, f)(float(xi)), getattr(ref, f)(float(xi))
                    assert type(a) is type(b) and _same_bits(a, b), (shape, scale, f, xi)


def test_cfar_threshold_design_unchanged():
    """The numeric OS / CA / CAGO designs of multi-look maps, to the bit the scipy.stats
    integration gave (recorded with main 8f53c28, before `Gamma` replaced it)."""
    assert cfar.cfar_scale(1e-6, "os", 24, 18, 16).hex() == "0x1.3ceac00a96954p+1"
    assert cfar.cfar_scale(1e-6, "ca", 16, 0, 4).hex() == "0x1.8af72a4b7c2c1p+2"
    assert cfar.noise_mean_factor("cago", 24, 0, 16).hex() == "0x1.0a6aaf3b53472p+0"


@pytest.mark.parametrize("field, value", [("a", 0.0), ("a", np.nan), ("scale", -1.0)])
def test_bad_parameters_are_refused(field, value):
    with pytest.raises(ValueError, match=f"{field}="):
        Gamma(**{"a": 2.0, field: value})
