"""MIMO schemes: how the transmitters share a frame, one registry entry per scheme.

`schemes` holds the `MimoScheme` base, its registry (`MIMO_SCHEMES`, `register_scheme`,
`scheme_of`) and the built-in DDMA, TDMA and BPM schemes; `fast_slow` the fast/slow chirp
scheme (registered on import). A new scheme is one module here plus one `register_scheme` call.

    >>> from radarsim.mimo import MIMO_SCHEMES
    >>> {"ddma", "tdma", "bpm", "fast_slow"} <= set(MIMO_SCHEMES)
    True
"""
from .fast_slow import ChirpSets, FastSlowScheme, hypothesis_separation_bins
from .schemes import (
    BPM_BLIND_SHARE,
    BPM_COLUMN_SIGNS,
    MIMO_SCHEMES,
    BpmScheme,
    ChirpTiming,
    DdmaScheme,
    MimoScheme,
    SlowTimeLayout,
    TdmaScheme,
    TiFrame,
    TransmitCode,
    hadamard,
    register_scheme,
    scheme_of,
)

__all__ = ["MimoScheme", "TransmitCode", "SlowTimeLayout", "TiFrame", "ChirpTiming",
           "MIMO_SCHEMES", "register_scheme", "scheme_of", "DdmaScheme", "TdmaScheme",
           "BpmScheme", "hadamard", "BPM_COLUMN_SIGNS", "BPM_BLIND_SHARE", "FastSlowScheme",
           "ChirpSets", "hypothesis_separation_bins"]
