"""The reader's state while it walks a profile's commands (`ParseState`), and which
`RadarConfig` fields the TI commands own."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from ..chips import Chip
from .profile import TiCfar
from .syntax import Line

__all__ = ["ParseState", "TI_FIELDS", "TI_DEFAULT_OVERRIDES"]

# RadarConfig fields that TI commands define (a directive may not set them).
TI_FIELDS = frozenset({"mimo", "n_tx", "n_rx", "start_freq_hz", "slope_hz_per_s",
                        "idle_time_s", "adc_start_time_s", "ramp_end_time_s", "n_samples",
                        "adc_rate_sps", "n_chirps", "tx_order", "tx_channels", "rx_channels",
                        "adc_mode", "adcbuf_interleaved"})
# Defaults of the fields a plain TI file leaves open: RadarConfig's, except the SDK's rounding.
TI_DEFAULT_OVERRIDES = {"phase_quantization": "round"}


@dataclass(slots=True)
class ParseState:
    """What the commands read so far define. `subframe` is the sub-frame this pass reads (None:
    a frame-mode profile); `advanced` is True when the profile runs advanced frames."""

    chip: Chip
    subframe: int | None = None
    advanced: bool = False
    fields: dict[str, Any] = dataclasses.field(default_factory=dict)
    field_lines: dict[str, Line] = dataclasses.field(default_factory=dict)
    seen: dict[str, Line] = dataclasses.field(default_factory=dict)
    profiles: dict[int, dict[str, Any]] = dataclasses.field(default_factory=dict)
    chirps: dict[int, tuple[int, int, Line, bool]] = dataclasses.field(default_factory=dict)
    tx_mask: int | None = None
    rx_mask: int | None = None
    adc_complex: bool | None = None
    frame: dict[str, Any] = dataclasses.field(default_factory=dict)
    cfar: dict[str, TiCfar] = dataclasses.field(default_factory=dict)
    ddm_order: tuple[int, ...] | None = None
    bpm: tuple | None = None
    ant_geometry: tuple | None = None
    adcbuf: dict[str, Any] = dataclasses.field(default_factory=dict)
    lvds: tuple | None = None
    extras: dict[str, Any] = dataclasses.field(default_factory=dict)
    processing: dict[str, Any] = dataclasses.field(default_factory=dict)
    processing_commands: dict[str, Line] = dataclasses.field(default_factory=dict)
    #: Which command wrote a `processing` field (when two commands can write the same one).
    processing_origin: dict[str, str] = dataclasses.field(default_factory=dict)
    antenna_calib: Line | None = None
    #: An enabled ``calibDcRangeSig``: (line, negativeBinIdx, positiveBinIdx, numAvg).
    dc_range_sig: tuple | None = None
    #: Board the ``% Platform:`` header names (None: the chip's default).
    board: str | None = None
    unmodelled: list[str] = dataclasses.field(default_factory=list)
    measure: tuple | None = None
    ignored: list[tuple[int, str]] = dataclasses.field(default_factory=list)
    notes: list[str] = dataclasses.field(default_factory=list)
    directives: dict[str, Any] = dataclasses.field(default_factory=dict)
    directive_lines: dict[str, Line] = dataclasses.field(default_factory=dict)

    def set(self, line: Line, **values: Any) -> None:
        for k, v in values.items():
            self.fields[k] = v
            self.field_lines[k] = line
