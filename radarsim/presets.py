"""Named radar configurations: the TI R79 DDMA demo (seed 000 table 2) and the same frame
timing for every registered MIMO scheme (`r79`)."""
from __future__ import annotations

from .config import RadarConfig
from .mimo import scheme_of

__all__ = ["r79", "r79_ddma", "r79_tdma", "PRESETS"]


def r79(name: str, **overrides) -> RadarConfig:
    """The R79 frame timing (768 chirps of 23.81 us, 4 Tx, 4 Rx, seed 000 table 2) for the
    registered MIMO scheme `name` (`radarsim.MIMO_SCHEMES`); keyword arguments override fields.

    Raises
    ------
    ValueError
        If `name` is not a registered scheme, or an override is invalid.
    """
    scheme_of(name)
    base = RadarConfig(mimo=name)
    return base.replace(**overrides) if overrides else base


def r79_ddma(**overrides) -> RadarConfig:
    """The AWR2944 R79 corner-radar waveform of TI's TIDEP-01027 demo (seed 000 table 2).

    4 Tx / 4 Rx, 768 chirps of 23.81 us (6 empty-band DDMA sub-bands x 128 Doppler bins),
    384 real samples at 30 Msps, slope 8.883 MHz/us, start 77 GHz; Tx order Tx1, Tx3, Tx4, Tx2
    and floor-quantised 6-bit shifter codes (table 4). Keyword arguments override fields.
    """
    return r79("ddma", **overrides)


def r79_tdma(**overrides) -> RadarConfig:
    """TDMA baseline on the R79 waveform: same 768 chirps and frame time, one Tx per chirp in
    turn (Tx1, Tx3, Tx4, Tx2), so 192 chirps per Tx at 4 Tc (Vmax 10.22 m/s, seed 001)."""
    return r79("tdma", **overrides)


#: Registry of presets by the name users type.
PRESETS = {"r79_ddma": r79_ddma, "r79_tdma": r79_tdma}
