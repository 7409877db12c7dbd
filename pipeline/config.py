"""Processing configuration of the signal chain: one frozen sub-config per stage.

`ProcessingConfig` holds the settings of the range and Doppler FFTs, the CFAR, the azimuth FFT,
interference mitigation, EGE compression, velocity disambiguation, the board corrections and the
field of view, each a frozen dataclass that validates itself and is declared next to the part
that reads it; `ProcessingConfig.replace` addresses them by dotted paths (`config_keys`).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

from core.checks import one_of
from core.errors import BadInput

from .cfar import CfarConfig, default_os_rank
from .chain_settings import WINDOWS, AngleConfig, DopplerConfig, RangeConfig, VelocityConfig
from .compensation import CalibrationConfig, check_channel_comp
from .config_keys import FLAT_KEYS, SUB_CONFIGS, replace_keys
from .ege_format import CompressionConfig
from .fov import FovConfig
from .interference import INTF_THRESHOLD_MODES, REPAIR_OFF, InterferenceConfig, IntfThresholdMode
from .saturation import SATURATION_POLICIES

__all__ = ["CfarConfig", "ProcessingConfig", "WINDOWS", "INTF_THRESHOLD_MODES",
           "IntfThresholdMode", "default_os_rank", "RangeConfig", "DopplerConfig", "AngleConfig",
           "VelocityConfig", "InterferenceConfig", "CompressionConfig", "CalibrationConfig",
           "FovConfig", "FLAT_KEYS"]

@dataclass(frozen=True, kw_only=True, slots=True)
class ProcessingConfig:
    """Signal-chain settings shared by every chain (DDMA, TDMA, BPM, fast/slow).

    Parameters
    ----------
    range : RangeConfig
        Range window, DC removal, first range bin, range peak check, range-Doppler coupling.
    doppler : DopplerConfig
        Doppler window and static clutter removal.
    cfar : CfarConfig
        Doppler CFAR (on the Doppler-azimuth map for DDMA, on the non-coherent range-Doppler
        map for TDMA).
    angle : AngleConfig
        Azimuth FFT length and the DDMA azimuth sidelobe gate.
    interference : pipeline.interference.InterferenceConfig
        Interference flags and repair (``intfMitigCfg``; ``repair="off"`` turns it off).
    compression : pipeline.ege_format.CompressionConfig
        EGE compression of the range-FFT cube (``compressionCfg``).
    velocity : VelocityConfig
        Velocity disambiguation (slot-coded hypotheses, fast/slow unfolding).
    calibration : pipeline.compensation.CalibrationConfig
        ``compRangeBiasAndRxChanPhase`` and ``calibDcRangeSig``.
    fov : pipeline.fov.FovConfig
        Field of view of the reported detections (``cfarFovCfg``, ``aoaFovCfg``).
    saturation_policy : {"flag", "drop"}
        What a frame with saturated ADC samples does to its detections
        (`pipeline.saturation`): "flag" keeps them with ``saturated = True``, "drop" removes
        them.
    """

    range: RangeConfig = field(default_factory=RangeConfig)
    doppler: DopplerConfig = field(default_factory=DopplerConfig)
    cfar: CfarConfig = field(default_factory=CfarConfig)
    angle: AngleConfig = field(default_factory=AngleConfig)
    interference: InterferenceConfig = field(default_factory=InterferenceConfig)
    compression: CompressionConfig = field(default_factory=CompressionConfig)
    velocity: VelocityConfig = field(default_factory=VelocityConfig)
    calibration: CalibrationConfig = field(default_factory=CalibrationConfig)
    fov: FovConfig = field(default_factory=FovConfig)
    saturation_policy: str = "flag"

    def __post_init__(self) -> None:
        for name, kind in SUB_CONFIGS.items():
            value = getattr(self, name)
            if not isinstance(value, kind):
                raise BadInput(f"{name} must be a {kind.__name__}, got {type(value).__name__}")
        one_of("saturation_policy", self.saturation_policy, SATURATION_POLICIES)

    def check_doppler_axis(self, n_doppler_bins: int) -> None:
        """Raise if the CFAR's cyclic window does not fit the Doppler axis of a radar.

        The training cells reach ``guard_cells + window_cells x training_stride`` bins to each
        side; both sides and the cell under test must fit in ``n_doppler_bins`` (DDMA: chirps
        per sub-band, TDMA: chirps per Tx), or the cyclic window would train on the cell itself.
        """
        c = self.cfar
        span = 2 * (c.guard_cells + c.window_cells * c.training_stride) + 1
        if span > n_doppler_bins:
            raise BadInput(f"cfar window_cells={c.window_cells} (guard_cells={c.guard_cells}, "
                           f"training_stride={c.training_stride}) spans {span} Doppler bins, "
                           f"more than the {n_doppler_bins} bins of the radar's Doppler axis")

    def check_compression(self, n_rx: int, n_range_bins: int) -> None:
        """Raise if EGE compression cannot run on a radar's range-FFT cube
        (`pipeline.ege_format.CompressionConfig.check_cube`)."""
        self.compression.check_cube(n_rx, n_range_bins)

    def check_radar(self, cfg) -> None:
        """Raise if these settings cannot process `cfg`'s frames (`check_doppler_axis`,
        `check_compression`, the ``compRangeBiasAndRxChanPhase`` count of the chip,
        `check_search_width`): what a sweep checks for every cell before it starts."""
        self.check_doppler_axis(cfg.n_doppler_bins)
        self.check_compression(cfg.n_rx, cfg.n_range_bins)
        check_channel_comp(cfg, self.calibration.channel_comp)
        self.check_search_width(cfg.scheme.candidate_separation_bins(cfg))

    def check_search_width(self, separation_bins: float) -> None:
        """Raise if two velocity candidates' slow-map search windows (2 w + 1 bins each,
        ``velocity.fast_slow_search_bins`` = w) could overlap: a radar's candidates sit
        `separation_bins` apart (`radarsim.mimo.MimoScheme.candidate_separation_bins`; inf for
        schemes without a verifying map)."""
        w = self.velocity.fast_slow_search_bins
        if 2 * w + 1 > separation_bins:
            raise BadInput(f"fast_slow_search_bins={w}: the search window (2 x {w} + 1 bins) "
                           f"exceeds the {separation_bins:.3g} slow Doppler bins between two "
                           f"unfolding candidates of the radar (limit "
                           f"{int((separation_bins - 1) // 2)})")

    @property
    def unmitigated(self) -> "ProcessingConfig":
        """These settings with interference mitigation off (``interference.repair = "off"``,
        every other field kept; the settings themselves when it is off already): an
        interference case's mitigation reference, and what a frame whose mitigation has
        nothing to repair gives bit for bit (`pipeline.chirp_level.idle_mitigation`)."""
        return _unmitigated(self)

    def replace(self, **changes: Any) -> "ProcessingConfig":
        """Copy with changes: a top-level field (a sub-config), a dotted path into one
        (``**{"cfar.pfa": 1e-5, "interference.repair": "off"}``), or a dict of a sub-config's
        fields under its name (``cfar={"pfa": 1e-5}``). The flat keys of the previous release
        (``cfar_pfa``, ``intf_mitigation``, ``interference_mitigation=False``, ...,
        `pipeline.config_keys.FLAT_KEYS`) still work and warn (`DeprecationWarning`) with the
        new key."""
        return replace_keys(self, changes, {"cfar": _replace_cfar})


@lru_cache(maxsize=64)
def _unmitigated(proc: ProcessingConfig) -> ProcessingConfig:
    """`ProcessingConfig.unmitigated`, built once per settings value (a frozen config:
    building one validates every field, and a sweep asks for the same few in every frame)."""
    if not proc.interference.enabled:
        return proc
    return dataclasses.replace(
        proc, interference=dataclasses.replace(proc.interference, repair=REPAIR_OFF))


def _replace_cfar(cfar: CfarConfig, changes: dict[str, Any]) -> CfarConfig:
    """`dataclasses.replace` of a CfarConfig that never keeps a stale OS rank.

    A new ``window_cells`` without an ``os_rank`` re-derives the default rank (3/4 N) when the
    old rank was the old default; an explicitly chosen rank is never carried over silently to
    another window: the caller must give ``os_rank`` too.
    """
    changes = dict(changes)
    if "window_cells" in changes and "os_rank" not in changes and \
            changes["window_cells"] != cfar.window_cells:
        if cfar.os_rank == default_os_rank(cfar.n_training):
            changes["os_rank"] = None
        else:
            raise BadInput(f"cfar_window_cells={changes['window_cells']!r} changes the training "
                           f"window, but os_rank={cfar.os_rank} was chosen for window_cells="
                           f"{cfar.window_cells}: give cfar_os_rank too (None: 3/4 of the "
                           "training cells)")
    return dataclasses.replace(cfar, **changes)
