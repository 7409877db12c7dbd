"""The chip-independent limits of a `radarsim.RadarConfig` and the rules that join its parts:
numbers, ramp timing, per-channel errors. Each part checks its own values with these limits
(`radarsim.radar_parts`).

The chip's and the board's own rules live with them (`radarsim.chips.Chip.validate`,
`radarsim.boards.Board.validate`), the MIMO scheme's with the scheme (`radarsim.mimo`) and the
shifter tables' in `radarsim.shifter`; `RadarConfig.__post_init__` calls them in turn. Each
check takes the config being built (read by attribute) and raises a `ValueError` naming the
field, the value and the limit.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from core.errors import BadInput

__all__ = ["RF_BUDGET_LIMITS", "TX_ERROR_LIMITS", "MAX_RANGE_BIAS_M", "ADC_FULL_SCALE_CODE",
           "check_numbers", "check_timing", "channel_errors", "integers", "is_number"]

#: Full-scale code of the signed 16-bit ADC samples.
ADC_FULL_SCALE_CODE = 32767

#: Plausible RF budget of a radar front end: field -> (low, high). Beyond these the radar
#: equation overflows (10^(5000/10) W) or the value is a typo; the AWR2944 EVM sits far inside
#: (12 dBm per Tx, 10 dBi elements, 12 dB noise figure).
RF_BUDGET_LIMITS = {
    "tx_power_dbm": (-40.0, 40.0),          # 40 dBm = 10 W per transmitter
    "tx_antenna_gain_dbi": (-30.0, 50.0),
    "rx_antenna_gain_dbi": (-30.0, 50.0),
    "noise_figure_db": (0.0, 60.0),
    "system_loss_db": (0.0, 100.0),
    "adc_full_scale_dbm": (-100.0, 30.0),
    "temperature_k": (1.0, 1000.0),
    "phase_noise_deg_rms": (0.0, 180.0),
}
#: Per-Tx static errors: field -> (low, high). A gain error far below 0 dB mutes a Tx (tests
#: use -300 dB); above +40 dB it is a typo that overflows the received power.
TX_ERROR_LIMITS = {"tx_gain_error_db": (-400.0, 40.0), "tx_phase_error_deg": (-360.0, 360.0),
                   "rx_gain_error_db": (-400.0, 40.0), "rx_phase_error_deg": (-360.0, 360.0)}
#: Largest board range bias, m: feed lines and internal delays of a real board amount to
#: centimetres; beyond 10 m the value is a typo (TI's measurement searches a few bins).
MAX_RANGE_BIAS_M = 10.0


def is_number(v) -> bool:
    return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)


def check_numbers(cfg) -> None:
    """Every numeric field holds a number (a string or bool would fail later without the field
    name)."""
    for f in dataclasses.fields(cfg):
        v = getattr(cfg, f.name)
        if is_number(f.default) and not is_number(v):
            raise BadInput(f"{f.name}={v!r} must be a number")


def integers(value, name: str, what: str) -> tuple[int, ...]:
    """A sequence of integers, refused (not coerced) otherwise: ``(1.7, 3.9)`` must not become
    (1, 3), nor the string ``'1342'`` the tuple (1, 3, 4, 2)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__") or not all(
            isinstance(c, (int, np.integer)) and not isinstance(c, (bool, np.bool_))
            for c in value):
        raise BadInput(f"{name}={value!r} must be a sequence of integers ({what})")
    return tuple(int(c) for c in value)


def channel_errors(cfg) -> dict[str, tuple[float, ...]]:
    """Static per-Tx and per-Rx phase and gain errors, one finite value per channel (None:
    zeros)."""
    out = {}
    for name, n, what in (("tx_phase_error_deg", cfg.n_tx, "Tx"),
                          ("tx_gain_error_db", cfg.n_tx, "Tx"),
                          ("rx_phase_error_deg", cfg.n_rx, "Rx"),
                          ("rx_gain_error_db", cfg.n_rx, "Rx")):
        val = getattr(cfg, name)
        if val is None:
            out[name] = (0.0,) * n
            continue
        val = tuple(float(v) for v in val)
        if len(val) != n or not all(math.isfinite(v) for v in val):
            raise BadInput(f"{name} must hold {n} finite values (one per {what}), "
                           f"got {val!r}")
        out[name] = val
    return out


def check_timing(cfg) -> None:
    """The ADC window inside the ramp; the chirp period equal to idle + ramp end time."""
    adc_end = cfg.adc_start_time_s + cfg.n_samples / cfg.adc_rate_sps
    if adc_end > cfg.ramp_end_time_s * (1 + 1e-9):
        raise BadInput(f"n_samples={cfg.n_samples}: ADC window ends at "
                       f"adc_start_time_s + n_samples / adc_rate_sps = {adc_end:g} s, "
                       f"after ramp_end_time_s={cfg.ramp_end_time_s:g} s")
    period = cfg.idle_time_s + cfg.ramp_end_time_s
    if not math.isclose(cfg.chirp_period_s, period, rel_tol=1e-6):
        raise BadInput(f"chirp_period_s={cfg.chirp_period_s:g} must equal idle_time_s + "
                       f"ramp_end_time_s = {period:g} s")
