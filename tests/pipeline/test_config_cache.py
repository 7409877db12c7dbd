"""`pipeline.config_cache.per_config`: entries by the configuration's identity, bounded."""
import radarsim
from pipeline.config_cache import per_config
from pipeline.kernels import array_layout, layout_of


def test_entries_by_identity_oldest_dropped_first():
    calls = []

    @per_config(maxsize=2)
    def f(cfg, k):
        calls.append((cfg, k))
        return [cfg, k]

    a, b, c = ["a"], ["a"], ["c"]  # a and b equal, distinct objects
    first = f(a, 1)
    assert f(a, 1) is first and len(calls) == 1
    assert f(b, 1) == first and f(b, 1) is not first and len(calls) == 2
    f(c, 1)  # a's entry is the oldest: dropped
    assert len(calls) == 3 and f(b, 1) == first and len(calls) == 3  # b's entry is kept
    f(a, 1)
    assert len(calls) == 4
    f.cache_clear()
    f(c, 1)
    assert len(calls) == 5


def test_layout_of_is_the_layout_of_each_config():
    for scheme in ("ddma", "tdma"):
        cfg = radarsim.presets.r79(scheme)
        got = layout_of(cfg)
        want = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
        assert layout_of(cfg) is got
        assert all((g == w).all() if hasattr(g, "all") else g == w for g, w in zip(got, want))
