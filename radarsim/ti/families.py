"""What a TI profile's processing commands mean, per demo family: the `ProcessingConfig` fields
each command sets and the value a command the profile leaves out takes -- that family's demo
default, never another family's.

A TI demo's CLI handler fills a zeroed configuration (``memset`` in each
``MmwDemo_CLI...Cfg``), so a processing command the profile leaves out keeps the feature off:
no velocity extension without ``extendedMaxVelocity``, no EGE compression without
``compressionCfg``, no interference mitigation without ``intfMitigCfg``. A command that is not
one of the family's demo commands (``compressionCfg`` in an xWR68xx profile: the SDK 3.x demo's
CLI refuses it) is kept and ignored with a note, and that family's default stands.

Families (`DEMO_FAMILIES`, chosen by `family_of` from the chip and the MIMO scheme):

``sdk3``
    mmWave SDK 2.x/3.x out-of-box demo, xWR14xx/16xx/18xx/68xx (TDM, BPM on xWR18/68): user
    guide sec. "Configuration (.cfg) File Format" (SDK 3.5 ``mmwave_sdk_user_guide.pdf``).
``mcu_plus_tdm``
    mmWave MCU+ SDK AWR294x TDM demo (``mmw_demo``): MCU+ SDK user guide, same commands as
    SDK 3.x plus ``antGeometryCfg``.
``mcu_plus_ddm``
    mmWave MCU+ SDK DDM demo of the AWR2944/AWR2x44P/AWR2544 (and the R79 corner-radar demo,
    TIDEP-01027 ``mss/mmw_cli.c``): ``compressionCfg``, ``intfMitigCfg``, ``localMaxCfg``,
    ``ddmPhaseShiftAntOrder``; DDMA is unambiguous over +/-lambda/(4 Tc), so there is no
    ``extendedMaxVelocity``.
"""
from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Mapping

from ..chips import Chip

__all__ = ["DemoFamily", "DEMO_FAMILIES", "PROCESSING_COMMANDS", "family_of"]


@dataclass(frozen=True, slots=True)
class ProcessingCommand:
    """One processing command: the `ProcessingConfig` fields it sets (empty: read but not
    modelled, listed in a note when it asks for something) and the TI document section."""

    fields: tuple[str, ...]
    source: str


#: Every processing command of the SDK 3.x and MCU+ demos the reader knows.
PROCESSING_COMMANDS: Mapping[str, ProcessingCommand] = MappingProxyType({
    "cfarCfg": ProcessingCommand(("cfar",), "SDK 3.x UG cfarCfg; [TI-DPC] DPU_CFARProc_CfarCfg"),
    "extendedMaxVelocity": ProcessingCommand(("tdma_disambiguation",),
                                             "SDK 3.x UG extendedMaxVelocity; AoA DPU"),
    "compressionCfg": ProcessingCommand(("compression", "compression_ratio",
                                         "compression_range_bins_per_block"),
                                        "MCU+ SDK DDM demo mmw_cli.c compressionCfg"),
    "intfMitigCfg": ProcessingCommand(("interference_mitigation", "intf_mag_snr_db",
                                       "intf_magdiff_snr_db"),
                                      "MCU+ SDK DDM demo mmw_cli.c intfMitigCfg"),
    "multiObjBeamForming": ProcessingCommand(("azimuth_sidelobe_db",),
                                             "SDK 3.x UG multiObjBeamForming; AoAProcHWA"),
    "cfarFovCfg": ProcessingCommand(("range_fov_m", "velocity_fov_mps"),
                                    "SDK 3.x UG cfarFovCfg"),
    "aoaFovCfg": ProcessingCommand(("azimuth_fov_deg", "elevation_fov_deg"),
                                   "SDK 3.x UG aoaFovCfg"),
    "compRangeBiasAndRxChanPhase": ProcessingCommand(("range_bias_m", "channel_comp"),
                                                     "SDK 3.x UG sec. range bias and Rx "
                                                     "channel gain/phase compensation"),
    "antennaCalibParams": ProcessingCommand(("channel_comp",),
                                            "MCU+ SDK DDM demo mmw_cli.c "
                                            "MmwDemo_CLIAntennaCalibParams; DPU_DopplerProcHWA"),
    "clutterRemoval": ProcessingCommand(("clutter_removal",), "SDK 3.x UG clutterRemoval; "
                                        "DopplerProc static clutter removal"),
    "calibDcRangeSig": ProcessingCommand((), "SDK 3.x UG calibDcRangeSig"),
    "measureRangeBiasAndRxChanPhase": ProcessingCommand((), "SDK 3.x UG measureRangeBias..."),
    "CQRxSatMonitor": ProcessingCommand((), "SDK 3.x UG CQRxSatMonitor"),
})


@dataclass(frozen=True, slots=True)
class DemoFamily:
    """One TI demo: its processing commands and the field values each takes when absent."""

    name: str
    description: str
    defaults: Mapping[str, Mapping[str, Any]]

    def has(self, command: str) -> bool:
        return command in self.defaults


_OFF = MappingProxyType({})
_SDK3 = {
    "cfarCfg": _OFF,  # mandatory in the demo; without it the chain's design-Pfa CFAR runs
    "extendedMaxVelocity": {"tdma_disambiguation": False},
    "multiObjBeamForming": _OFF,
    "cfarFovCfg": {"range_fov_m": None, "velocity_fov_mps": None},
    "aoaFovCfg": {"azimuth_fov_deg": None, "elevation_fov_deg": None},
    "compRangeBiasAndRxChanPhase": {"range_bias_m": 0.0, "channel_comp": None},
    "clutterRemoval": {"clutter_removal": False}, "calibDcRangeSig": _OFF,
    "measureRangeBiasAndRxChanPhase": _OFF, "CQRxSatMonitor": _OFF,
    # Not commands of these demos: their chains have no EGE compression and no
    # interference mitigation.
    "_absent": {"compression": False, "interference_mitigation": False},
}
_DDM = {
    "cfarCfg": _OFF,
    "compressionCfg": {"compression": False},
    "intfMitigCfg": {"interference_mitigation": False},
    "compRangeBiasAndRxChanPhase": {"range_bias_m": 0.0, "channel_comp": None},
    "antennaCalibParams": {"channel_comp": None},
    "cfarFovCfg": {"range_fov_m": None, "velocity_fov_mps": None},
    "aoaFovCfg": {"azimuth_fov_deg": None, "elevation_fov_deg": None},
    "CQRxSatMonitor": _OFF, "measureRangeBiasAndRxChanPhase": _OFF,
}

#: The demo families by name (see the module docstring for their sources).
DEMO_FAMILIES: Mapping[str, DemoFamily] = MappingProxyType({
    "sdk3": DemoFamily("sdk3", "mmWave SDK 2.x/3.x demo (xWR14/16/18/68xx)",
                       MappingProxyType(_SDK3)),
    "mcu_plus_tdm": DemoFamily("mcu_plus_tdm", "mmWave MCU+ SDK TDM demo (AWR294x)",
                               MappingProxyType(_SDK3)),
    "mcu_plus_ddm": DemoFamily("mcu_plus_ddm", "mmWave MCU+ SDK DDM demo (AWR294x, R79)",
                               MappingProxyType(_DDM)),
})


def family_of(chip: Chip, scheme) -> DemoFamily:
    """The demo a profile for `chip` running `scheme` (a `radarsim.mimo.MimoScheme`) belongs
    to: MCU+ SDK chips run the DDM demo for the phase-shifter (Doppler-division) schemes and
    the TDM demo otherwise; the other chips run the SDK 3.x demo."""
    if not chip.mcu_plus_sdk:
        return DEMO_FAMILIES["sdk3"]
    return DEMO_FAMILIES["mcu_plus_ddm" if scheme.needs_phase_shifter else "mcu_plus_tdm"]
