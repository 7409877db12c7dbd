"""How `pipeline.ProcessingConfig.replace` addresses its nested settings: a dotted path
(``"cfar.pfa"``, ``"interference.repair"``) names a field of a sub-config; the flat keys of the
previous release (``"cfar_pfa"``, ``"intf_mitigation"``, ``"compression_ratio"``, ...) keep
working for one release with a `DeprecationWarning` naming the new key (`FLAT_KEYS`).

A sweep file's ``processing`` keys are these keys (``"processing.cfar.pfa" = [...]``); a TOML
table of a sub-config (``[base.processing.cfar]``) is the same as its dotted keys.

The mechanism is `core.config`'s (the one `radarsim.RadarConfig` uses); this module holds only
what is the processing settings' own: the table of flat keys, the ``cfar_*`` family, and the old
``interference_mitigation`` on/off switch folded into ``interference.repair``.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import Any

from core.config import dotted_changes, flat_given, replace_paths
from core.errors import BadInput

from .cfar import CfarConfig
from .chain_settings import AngleConfig, DopplerConfig, RangeConfig, VelocityConfig
from .compensation import CalibrationConfig
from .ege_format import CompressionConfig
from .fov import FovConfig
from .interference import InterferenceConfig

__all__ = ["FLAT_KEYS", "SUB_CONFIGS", "replace_keys", "dotted_keys"]

#: Top-level field of `pipeline.ProcessingConfig` -> its sub-config type.
SUB_CONFIGS: dict[str, type] = {
    "range": RangeConfig, "doppler": DopplerConfig, "cfar": CfarConfig, "angle": AngleConfig,
    "interference": InterferenceConfig, "compression": CompressionConfig,
    "velocity": VelocityConfig, "calibration": CalibrationConfig, "fov": FovConfig}
#: Every top-level field -> its type (`core.config.dotted_changes`'s groups).
_GROUPS: dict[str, type] = {**SUB_CONFIGS, "saturation_policy": str}

#: Flat key of the previous release -> dotted path of the nested setting.
FLAT_KEYS: dict[str, str] = {
    "range_window": "range.window", "dc_removal": "range.dc_removal",
    "min_range_bin": "range.min_bin", "range_peak_check": "range.peak_check",
    "correct_range_doppler_coupling": "range.doppler_coupling_correction",
    "doppler_window": "doppler.window", "clutter_removal": "doppler.clutter_removal",
    "n_azimuth_bins": "angle.n_azimuth_bins", "azimuth_sidelobe_db": "angle.azimuth_sidelobe_db",
    "interference_mitigation": "interference.repair", "intf_mitigation": "interference.repair",
    "intf_mag_snr_db": "interference.mag_snr_db",
    "intf_magdiff_snr_db": "interference.magdiff_snr_db",
    "intf_threshold_mode": "interference.threshold_mode",
    "intf_hysteresis_samples": "interference.hysteresis_samples",
    "intf_weak_burst_snr_db": "interference.weak_burst_snr_db",
    "intf_weak_burst_window_samples": "interference.weak_burst_window_samples",
    "compression": "compression.enabled", "compression_ratio": "compression.ratio",
    "compression_range_bins_per_block": "compression.range_bins_per_block",
    "tdma_disambiguation": "velocity.tdma_disambiguation",
    "fast_slow_threshold_db": "velocity.fast_slow_threshold_db",
    "fast_slow_search_bins": "velocity.fast_slow_search_bins",
    "fast_slow_min_coherence": "velocity.fast_slow_min_coherence",
    "fast_slow_keep_unassociated": "velocity.fast_slow_keep_unassociated",
    "range_bias_m": "calibration.range_bias_m", "channel_comp": "calibration.channel_comp",
    "dc_range_signature": "calibration.dc_range_signature",
    "range_fov_m": "fov.range_m", "velocity_fov_mps": "fov.velocity_mps",
    "azimuth_fov_deg": "fov.azimuth_deg", "elevation_fov_deg": "fov.elevation_deg",
}
#: The flat keys of the CFAR settings: ``cfar_<field>`` is ``cfar.<field>``.
_PREFIXES = {"cfar_": "cfar."}
#: The old on/off switch of interference mitigation, folded into ``interference.repair``.
_SWITCH = "interference_mitigation"
_OWNER = "ProcessingConfig"


def replace_keys(config, changes: dict[str, Any],
                 replace_sub: dict[str, Callable] | None = None):
    """Copy of `config` (a `pipeline.ProcessingConfig`) with `changes`: dotted paths, sub-config
    tables or whole sub-configs, and flat keys (one `DeprecationWarning` each, naming the new
    key), the old interference switch folded into the repair method
    (`core.config.dotted_changes`, `core.config.replace_paths` with `replace_sub`).

    Raises
    ------
    BadInput
        An unknown field (with the known ones), a switch that is no bool, or a sub-config that
        refuses its new values; a change given by a flat key is named by that key too.
    """
    rest = {k: v for k, v in changes.items() if k != _SWITCH}
    paths = dotted_changes(rest, _GROUPS, FLAT_KEYS, _OWNER, prefixes=_PREFIXES,
                           section="processing", check_fields=True, stacklevel=4)
    if _SWITCH in changes:
        on = changes[_SWITCH]
        dotted_changes({_SWITCH: on}, _GROUPS, FLAT_KEYS, _OWNER, section="processing",
                       stacklevel=4)  # its warning
        if not isinstance(on, bool):
            raise BadInput(f"{_SWITCH}={on!r} must be true or false (now "
                           f"interference.repair: 'off' or a method)")
        if not on:
            paths["interference.repair"] = "off"
        elif "interference.repair" not in paths and not config.interference.enabled:
            paths["interference.repair"] = InterferenceConfig().repair
    return replace_paths(config, paths, replace_sub,
                         given=flat_given(changes, FLAT_KEYS, _PREFIXES))


def dotted_keys(flat: dict[str, Any]) -> dict[str, Any]:
    """Settings given by flat keys (`FLAT_KEYS`) as dotted paths, without a warning: for a
    bridge from another vocabulary that still names the flat keys (the TI profile reader).
    The interference switch: False is ``"interference.repair": "off"``, True nothing (the
    default repair is on)."""
    out = dotted_changes({k: v for k, v in flat.items() if k != _SWITCH}, _GROUPS, FLAT_KEYS,
                         _OWNER, prefixes=_PREFIXES, check_fields=True, warn=False)
    if _SWITCH in flat and not flat[_SWITCH]:
        out["interference.repair"] = "off"
    return out
