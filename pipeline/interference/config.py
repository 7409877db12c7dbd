"""The interference settings of the chirp-level chain (``intfMitigCfg``): the thresholds that
flag a burst and the method that repairs it, one setting for on/off and method alike."""
from __future__ import annotations

from dataclasses import dataclass

from core.checks import one_of, require
from core.errors import BadInput

from .detection import INTF_THRESHOLD_MODES
from .methods import MITIGATIONS, RepairMethod
from .residual import BLOCK

__all__ = ["InterferenceConfig", "REPAIR_OFF"]

#: `InterferenceConfig.repair` of a chain that neither flags nor repairs (the chip's default
#: without ``intfMitigCfg``).
REPAIR_OFF = "off"


@dataclass(frozen=True, kw_only=True, slots=True)
class InterferenceConfig:
    """Interference mitigation: flag the samples a burst hit, repair them.

    Parameters
    ----------
    repair : str
        "off" (nothing flagged, nothing repaired), or how the flagged samples are repaired: a
        key of `pipeline.interference.MITIGATIONS`. Default "lowrank" (the gap predicted from
        the chirp's kept samples by the frame's fast-time signal subspace): on the head-on
        case it recovers 91 % (DDMA) / 94 % (TDMA) of the floor rise and adds no ghosts,
        where "ar" recovers 65 % / 69 % and adds 0.035 / 0.067, and the chip's "zero",
        whose slow-time modulation of every echo manufactures ghosts, 17 % / 20 % and adds
        0.16 / 0.21 (`harness/sweeps/mitigation.toml`, README).
    mag_snr_db, magdiff_snr_db : float
        ``intfMitigCfg`` magSNRdB and magDiffSNRdB: thresholds over the chirp's mean |x| and
        mean |x_n - x_{n-1}|, amplitude dB (the demo profile: 15, 18), in (0, 60].
    threshold_mode : str
        Which statistic flags a sample, see `INTF_THRESHOLD_MODES` (the demo: "magdiff").
    hysteresis_samples : int
        Samples zeroed on each side of a flagged run (the demo's hysteresis order 3), 0..32.
    weak_burst_snr_db : float or None
        Weak bursts the chip's fixed threshold misses (`pipeline.interference.residual`): in a
        frame where the chip flagged a chirp, a window of another chirp whose energy outside
        the frame's fast-time echo subspace exceeds the chirp's own level by this, dB, is
        flagged too, and repaired as the chip's flags are. Default 11 dB, in (0, 60]; None
        off (the chip's flags alone). On the head-on case the worst 1-second window's recovery
        goes from 0.47 (DDMA) / 0.56 (TDMA) to about 1.
    weak_burst_window_samples : int
        Samples per window of that test, a multiple of 4 in [4, 128]; default 32 (1.07 us,
        the shortest burst of interest, 2 B_IF / |S_v - S_i| for 30 MHz/us).
    """

    repair: str = "lowrank"
    mag_snr_db: float = 15.0
    magdiff_snr_db: float = 18.0
    threshold_mode: str = "magdiff"
    hysteresis_samples: int = 3
    weak_burst_snr_db: float | None = 11.0
    weak_burst_window_samples: int = 32

    def __post_init__(self) -> None:
        if self.repair != REPAIR_OFF:
            one_of("repair", self.repair, MITIGATIONS)
        require(self, ("mag_snr_db", "magdiff_snr_db"), gt=0, le=60, unit="dB")
        one_of("threshold_mode", self.threshold_mode, INTF_THRESHOLD_MODES)
        require(self, "hysteresis_samples", "integer", ge=0, le=32)
        require(self, "weak_burst_snr_db", gt=0, le=60, unit="dB", none_ok=True)
        require(self, "weak_burst_window_samples", "integer", ge=BLOCK, le=128)
        if self.weak_burst_window_samples % BLOCK:
            raise BadInput(f"weak_burst_window_samples={self.weak_burst_window_samples} must "
                           f"be a multiple of {BLOCK}")

    @property
    def enabled(self) -> bool:
        """Whether the chain flags and repairs interference at all."""
        return self.repair != REPAIR_OFF

    @property
    def method(self) -> RepairMethod:
        """The repair method (`MITIGATIONS`); only when `enabled`."""
        return MITIGATIONS.lookup(self.repair)
