"""The chain's configuration-only quantities: cached by the configuration's value
(`functools.lru_cache`; `RadarConfig` keeps its hash)."""
import radarsim
from pipeline.kernels import array_layout, layout_of


def test_layout_of_is_the_layout_of_each_config():
    for scheme in ("ddma", "tdma"):
        cfg = radarsim.presets.r79(scheme)
        got = layout_of(cfg)
        want = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
        assert layout_of(cfg) is got
        assert layout_of(radarsim.presets.r79(scheme)) is got  # an equal configuration
        assert all((g == w).all() if hasattr(g, "all") else g == w for g, w in zip(got, want))
