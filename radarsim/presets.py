"""Named radar configurations: the TI R79 DDMA demo ([TI-DDMA] table 2) and the same frame
timing for every registered MIMO scheme (`r79`)."""
from __future__ import annotations

from .mimo.schemes import scheme_of
from .radar_config import MimoSchedule, RadarConfig

__all__ = ["r79", "r79_ddma", "r79_tdma", "PRESETS"]


def r79(name: str, **overrides) -> RadarConfig:
    """The R79 frame timing (768 chirps of 23.81 us, 4 Tx, 4 Rx, [TI-DDMA] table 2) for the
    registered MIMO scheme `name` (`radarsim.MIMO_SCHEMES`); keyword arguments override fields as
`RadarConfig.replace` takes them: a part's table (``array={"n_rx": 2}``) or dotted keys
(``**{"array.n_rx": 2}``); a flat key (``n_rx=2``) works and warns for one release.

    Raises
    ------
    ValueError
        If `name` is not a registered scheme, or an override is invalid.

    Examples
    --------
    >>> import radarsim
    >>> [round(radarsim.presets.r79(s).max_unambiguous_velocity_mps, 2) for s in ("ddma", "tdma")]
    [40.88, 10.22]
    >>> radarsim.presets.r79("tdma", array={"n_rx": 2}).n_virtual
    8
    """
    scheme_of(name)
    base = RadarConfig(schedule=MimoSchedule(mimo=name))
    return base.replace(**overrides) if overrides else base


def r79_ddma(**overrides) -> RadarConfig:
    """The AWR2944 R79 corner-radar waveform of TI's TIDEP-01027 demo ([TI-DDMA] table 2).

    4 Tx / 4 Rx, 768 chirps of 23.81 us (6 empty-band DDMA sub-bands x 128 Doppler bins),
    384 real samples at 30 Msps, slope 8.883 MHz/us, start 77 GHz; Tx order Tx1, Tx3, Tx4, Tx2
    and floor-quantised 6-bit shifter codes (table 4). Keyword arguments override fields.

    Examples
    --------
    >>> import radarsim
    >>> cfg = radarsim.presets.r79_ddma()
    >>> round(cfg.range_resolution_m, 3), round(cfg.max_range_m), round(cfg.frame_time_s * 1e3, 2)
    (1.318, 253, 18.29)
    >>> cfg.phase_codes()[1].tolist()         # Tx2: 0, 180 deg ([TI-DDMA] table 4)
    [0, 32, 0, 32, 0, 32]
    """
    return r79("ddma", **overrides)


def r79_tdma(**overrides) -> RadarConfig:
    """TDMA baseline on the R79 waveform: same 768 chirps and frame time, one Tx per chirp in
    turn (Tx1, Tx3, Tx4, Tx2), so 192 chirps per Tx at 4 Tc (Vmax 10.22 m/s, [TI-VEXT]).

    Examples
    --------
    >>> import radarsim
    >>> cfg = radarsim.presets.r79_tdma()
    >>> cfg.n_doppler_bins, round(cfg.max_unambiguous_velocity_mps, 2)
    (192, 10.22)
    """
    return r79("tdma", **overrides)


#: Registry of presets by the name users type.
PRESETS = {"r79_ddma": r79_ddma, "r79_tdma": r79_tdma}
