"""The TI profile an external chain reads: a cell's radar and processing as the chip's
``.cfg``, written so that `radar-harness process` reading it runs what the cell runs.

The radar travels exactly (`radarsim.ti.to_ti_cfg` round-trips a `RadarConfig`). The processing
travels as the demo family's commands (`radarsim.ti.writer.processing_lines`: velocity
disambiguation, compression, interference mitigation, fields of view, ...) and the Doppler CFAR
as a ``cfarCfg`` line whose thresholdScale is the cell's threshold for the chain's looks per
cell (a CFAR designed by Pfa has no TI form: its scale is written as the dB it gives). Whatever
the format cannot carry is listed (`CellProfile.differences`), never dropped silently.
"""
from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np

__all__ = ["CellProfile", "cell_profile"]


class CellProfile(NamedTuple):
    """A cell's ``.cfg`` text and what a reader of it runs differently.

    Attributes
    ----------
    text : str
        The TI CLI profile.
    differences : list of str
        ``field: cell value -> profile value`` for every `ProcessingConfig` field the profile,
        read back by `harness.cell.ti_profile.processing_from_profile`, does not reproduce.
    """

    text: str
    differences: list[str]


def _looks(radar, proc) -> int:
    """Looks per cell of the chain's CFAR map (its threshold depends on them)."""
    from pipeline.mimo import chain_of
    adc = np.zeros((radar.n_chirps, radar.n_rx, radar.n_samples), dtype=radar.adc_dtype)
    return int(chain_of(radar).detection_map(radar, adc, proc).looks)


def _ti_cfar(radar, proc):
    from radarsim.ti import TiCfar
    cf = proc.cfar
    scale = cf.scale(looks=_looks(radar, proc))
    return TiCfar(direction="doppler", mode=cf.mode.removeprefix("ti_log_"),
                  window_cells=cf.window_cells, guard_cells=cf.guard_cells,
                  threshold_db=10 * math.log10(scale),
                  os_rank=cf.os_rank if cf.mode == "os" else None)


def cell_profile(radar, proc, frame_period_s: float) -> CellProfile:
    """The TI profile of one result scheme of a cell.

    Parameters
    ----------
    radar : radarsim.RadarConfig
        The cell's radar for the scheme.
    proc : pipeline.ProcessingConfig
        The scheme's processing in the cell.
    frame_period_s : float
        ``framePeriodicity``, s (the cell's frame period).

    Returns
    -------
    CellProfile
    """
    from harness.cell.ti_profile import processing_from_profile
    from radarsim.ti import parse_ti_cfg, to_ti_cfg
    bare = parse_ti_cfg(to_ti_cfg(radar, frame_period_s=frame_period_s))
    # A profile's processing values use the flat names of the TI command handlers.
    keys = set(bare.processing) | {"tdma_disambiguation", "compression", "clutter_removal",
                                   "interference_mitigation", "compression_ratio",
                                   "compression_range_bins_per_block", "intf_mag_snr_db",
                                   "intf_magdiff_snr_db"}
    values = {k: _flat_value(proc, k) for k in keys}
    profile = dataclasses.replace(bare, processing=values, cfar={"doppler": _ti_cfar(radar, proc)})
    text = to_ti_cfg(profile)
    back = processing_from_profile(parse_ti_cfg(text))
    diffs = []
    for f in dataclasses.fields(proc):
        a, b = getattr(proc, f.name), getattr(back, f.name)
        if f.name == "cfar":
            for g in dataclasses.fields(a):
                x, y = getattr(a, g.name), getattr(b, g.name)
                if x != y:
                    diffs.append(f"cfar.{g.name}: {x!r} -> {y!r}")
        elif not _same(a, b):
            diffs.append(f"{f.name}: {a!r} -> {b!r}")
    return CellProfile(text, diffs)


def _flat_value(proc, key: str):
    """The value of a flat (TI handler) processing key in a nested `ProcessingConfig`
    (`pipeline.config_keys.FLAT_KEYS`; the old mitigation switch: a repair method is on)."""
    from pipeline.config_keys import FLAT_KEYS
    if key == "interference_mitigation":
        return proc.interference.repair != "off"
    value = proc
    for part in FLAT_KEYS[key].split("."):
        value = getattr(value, part)
    return value


def _same(a, b) -> bool:
    try:
        return bool(np.all(a == b)) if isinstance(a, np.ndarray) or isinstance(b, np.ndarray) \
            else a == b
    except (ValueError, TypeError):
        return False
