"""How `pipeline.ProcessingConfig.replace` addresses its nested settings: a dotted path
(``"cfar.pfa"``, ``"interference.repair"``) names a field of a sub-config; the flat keys of the
previous release (``"cfar_pfa"``, ``"intf_mitigation"``, ``"compression_ratio"``, ...) keep
working for one release with a `DeprecationWarning` naming the new key (`FLAT_KEYS`).

A sweep file's ``processing`` keys are these keys (``"processing.cfar.pfa" = [...]``); a TOML
table of a sub-config (``[base.processing.cfar]``) is the same as its dotted keys.
"""
from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable
from typing import Any

from core.errors import BadInput

__all__ = ["FLAT_KEYS", "replace_nested", "nested_changes", "dotted_keys"]

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
#: The old on/off switch of interference mitigation, folded into ``interference.repair``.
_SWITCH = "interference_mitigation"


def _new_key(key: str) -> str | None:
    if key in FLAT_KEYS:
        return FLAT_KEYS[key]
    if key.startswith("cfar_"):
        return "cfar." + key[len("cfar_"):]
    return None


def nested_changes(config, changes: dict[str, Any]) -> tuple[dict[str, Any], dict[str, list]]:
    """`changes` as dotted paths: flat keys translated (one `DeprecationWarning` each), the
    old interference switch folded into the repair method, tables of a sub-config expanded.

    Returns
    -------
    paths : dict
        Dotted path (or top-level field) -> value.
    old : dict
        Top-level field -> the (flat key, value) pairs that changed it (named in errors).
    """
    paths: dict[str, Any] = {}
    old: dict[str, list] = {}
    for key, value in changes.items():
        new = _new_key(key)
        if new is not None:
            warnings.warn(f"ProcessingConfig key {key!r} is deprecated: use {new!r} (sweep "
                          f"files: 'processing.{new}')", DeprecationWarning, stacklevel=3)
            old.setdefault(new.partition(".")[0], []).append((key, value))
            if key == _SWITCH:
                continue  # folded in below, after the method
            key = new
        if isinstance(value, dict):
            for sub, v in _flatten(value):
                paths[f"{key}.{sub}"] = v
        else:
            paths[key] = value
    if _SWITCH in changes:
        on = changes[_SWITCH]
        if not isinstance(on, bool):
            raise BadInput(f"{_SWITCH}={on!r} must be true or false (now "
                           f"interference.repair: 'off' or a method)")
        if not on:
            paths["interference.repair"] = "off"
        elif "interference.repair" not in paths and not config.interference.enabled:
            paths["interference.repair"] = type(config.interference)().repair
    return paths, old


def dotted_keys(flat: dict[str, Any]) -> dict[str, Any]:
    """Settings given by flat keys (`FLAT_KEYS`) as dotted paths, without a warning: for a
    bridge from another vocabulary that still names the flat keys (the TI profile reader).
    The interference switch: False is ``"interference.repair": "off"``, True nothing (the
    default repair is on)."""
    out: dict[str, Any] = {}
    for key, value in flat.items():
        if key == _SWITCH:
            if not value:
                out["interference.repair"] = "off"
            continue
        out[_new_key(key) or key] = value
    return out


def _flatten(table: dict, prefix: str = ""):
    for k, v in table.items():
        if isinstance(v, dict):
            yield from _flatten(v, f"{prefix}{k}.")
        else:
            yield f"{prefix}{k}", v


def replace_nested(config, paths: dict[str, Any], old: dict[str, list],
                   replace_sub: dict[str, Callable] | None = None):
    """Copy of the frozen dataclass `config` with `paths` (dotted paths or top-level fields,
    `nested_changes`) changed; a sub-config named in `replace_sub` is replaced by that
    function (sub-config, its changes) instead of `dataclasses.replace`.

    Raises
    ------
    BadInput
        An unknown field (with the known ones), or a sub-config that refuses its new values;
        a change given by a flat key is named by that key too.
    """
    names = {f.name for f in dataclasses.fields(config)}
    top: dict[str, Any] = {}
    nested: dict[str, dict[str, Any]] = {}
    for path, value in paths.items():
        head, _, rest = path.partition(".")
        if head not in names:
            raise BadInput(f"unknown {type(config).__name__} field(s) [{path!r}]; known: "
                           f"{sorted(names)}")
        if rest:
            nested.setdefault(head, {})[rest] = value
        else:
            top[head] = value
    for head, changes in nested.items():
        sub = top.get(head, getattr(config, head))
        try:
            if replace_sub and head in replace_sub:
                top[head] = replace_sub[head](sub, changes)
            else:
                top[head] = replace_nested(sub, *nested_changes_plain(changes))
        except BadInput as exc:
            raise _named(exc, head, old) from None
    try:
        return dataclasses.replace(config, **top)
    except BadInput as exc:
        raise _named(exc, None, old) from None


def nested_changes_plain(changes: dict[str, Any]) -> tuple[dict[str, Any], dict]:
    """`changes` of a sub-config (no flat keys there) in `replace_nested`'s form."""
    return dict(changes), {}


def _named(exc: BadInput, head: str | None, old: dict[str, list]) -> BadInput:
    keys = [kv for h, kvs in old.items() if head is None or h == head for kv in kvs]
    if not keys:
        return exc
    named = ", ".join(f"{k}={v!r} (now {_new_key(k)})" for k, v in keys)
    return BadInput(f"{named}: {exc}")
