"""Random streams of a cell: one `numpy.random.Generator` per (seed, frame, stream).

Generator ``SeedSequence([seed, frame, stream])`` with stream 0 = RCS model, 1 = DDMA ADC,
2 = TDMA ADC, 3 = the tracker's RANSAC (frame 0) and, for every other scheme, a stream id
derived from its name alone, so adding or removing a scheme never changes another scheme's
numbers.
"""
from __future__ import annotations

import hashlib

import numpy as np

from core.errors import BadInput

__all__ = ["SEED_STREAMS", "stream_id", "frame_rng"]


#: Random streams of one frame with fixed ids: SeedSequence([seed, frame, stream]). Any other
#: stream (a MIMO scheme's ADC noise) gets `stream_id(name)`, derived from its name alone.
SEED_STREAMS: dict[str, int] = {"rcs": 0, "ddma": 1, "tdma": 2, "track": 3}


def stream_id(stream: str) -> int:
    """Id of a random stream: `SEED_STREAMS` for the fixed ones, otherwise 2^16 plus the first
    31 bits of the SHA-256 of the name, so each scheme's stream depends on its name only."""
    if stream in SEED_STREAMS:
        return SEED_STREAMS[stream]
    if not isinstance(stream, str) or not stream:
        raise BadInput(f"stream={stream!r} must be a non-empty name")
    return 2 ** 16 + (int.from_bytes(hashlib.sha256(stream.encode()).digest()[:4], "big")
                      >> 1)


def frame_rng(seed: int, frame: int, stream: str) -> np.random.Generator:
    """Generator of one random stream of one frame: SeedSequence([seed, frame, stream id])."""
    return np.random.default_rng(np.random.SeedSequence([int(seed), int(frame),
                                                         stream_id(stream)]))
