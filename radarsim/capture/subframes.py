"""DCA1000 captures of advanced frames: each frame is the sub-frames' chirps back to back.

A capture recorded with an advanced-frame profile (``dfeDataOutputMode 3``,
`radarsim.ti.TiProfile.subframes`) streams, frame after frame, sub-frame 0's chirps, then
sub-frame 1's, ..., each in the layout of its own radar (`radarsim.capture.layout_of`: the
sample count and so the words per chirp may differ between sub-frames). The LVDS stream carries
the ADC data of every chirp as it is sampled (DCA1000 user guide SPRUIJ4, "LVDS data
capture"), so sub-frame k of frame f starts after the words of sub-frames 0..k-1 of that frame.
A frame-mode profile is the one-sub-frame case.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Iterator, NamedTuple

import numpy as np

from core.errors import BadInput
from core.fileio import check_input_file

from .dca1000 import MAX_CAPTURE_BYTES, SAMPLE_DTYPE, frame_nbytes, frame_shape, layout_of

__all__ = ["SubFrameData", "advanced_frame_nbytes", "capture_n_advanced_frames",
           "iter_subframes", "encode_frame"]


class SubFrameData(NamedTuple):
    """One sub-frame of one frame: indices and its (n_chirps, n_rx, n_samples) ADC block."""

    frame: int
    subframe: int
    adc: np.ndarray


def _parts(profile) -> tuple:
    parts = getattr(profile, "parts", None)
    if parts is None:
        raise BadInput(f"profile must be a radarsim.ti.TiProfile, got "
                       f"{type(profile).__name__}")
    return parts


def advanced_frame_nbytes(profile) -> int:
    """Bytes of one frame: the sum of the sub-frames' `radarsim.capture.frame_nbytes`."""
    return sum(frame_nbytes(p.radar) for p in _parts(profile))


def capture_n_advanced_frames(path: str | os.PathLike, profile) -> int:
    """Whole frames in a capture of `profile`.

    Raises
    ------
    ValueError
        If the file is empty or not a whole number of frames (naming both sizes).
    """
    check_input_file(path, "capture", max_bytes=MAX_CAPTURE_BYTES)  # FIFO, device: named
    size = Path(path).stat().st_size
    per_frame = advanced_frame_nbytes(profile)
    n_frames, rest = divmod(size, per_frame)
    if size == 0:
        raise BadInput(f"capture {str(path)!r} is empty")
    if rest:
        sizes = " + ".join(str(frame_nbytes(p.radar)) for p in _parts(profile))
        raise BadInput(f"capture {str(path)!r} has {size} bytes, not a whole number of "
                       f"frames of {per_frame} bytes (sub-frames {sizes}): {n_frames} whole "
                       f"frame(s) and {rest} stray bytes; the file is truncated or the "
                       "profile does not match the recording")
    return n_frames


def iter_subframes(path: str | os.PathLike, profile, *, interleaved: bool | None = None,
                   max_frames: int | None = None) -> Iterator[SubFrameData]:
    """Every sub-frame of every frame, in recording order.

    Parameters
    ----------
    path : path-like
        Headerless DCA1000 capture.
    profile : radarsim.ti.TiProfile
        The (advanced-frame or frame-mode) profile it was recorded with.
    interleaved : bool, optional
        Real ADC buffer order override for every sub-frame (default: each sub-frame's
        ``adcbufCfg``).
    max_frames : int, optional
        Stop after this many frames.

    Yields
    ------
    SubFrameData
        ``adc`` is (n_chirps, n_rx, n_samples) int16 (real) or complex64 (complex), a copy.
    """
    parts = _parts(profile)
    n_frames = capture_n_advanced_frames(path, profile)
    words = np.memmap(path, dtype=SAMPLE_DTYPE, mode="r",
                      shape=(n_frames, advanced_frame_nbytes(profile) // SAMPLE_DTYPE.itemsize))
    layouts = [layout_of(p.radar, interleaved) for p in parts]
    bounds = np.cumsum([0] + [frame_nbytes(p.radar) // SAMPLE_DTYPE.itemsize for p in parts])
    n = n_frames if max_frames is None else min(int(max_frames), n_frames)
    for f in range(n):
        for k, (part, lay) in enumerate(zip(parts, layouts)):
            block = words[f:f + 1, bounds[k]:bounds[k + 1]]
            dtype = np.complex64 if lay.is_complex else np.int16
            adc = np.array(lay.decode(block, frame_shape(part.radar))[0], dtype=dtype, order="C")
            yield SubFrameData(f, k, adc)


def encode_frame(profile, adcs, *, interleaved: bool | None = None) -> np.ndarray:
    """The int16 words of one frame: each sub-frame's (n_chirps, n_rx, n_samples) block in its
    layout, in sub-frame order (what a DCA1000 records; append them to write a capture).

    Raises
    ------
    ValueError
        If the number of blocks or a block's shape does not match the profile's sub-frames.
    """
    parts = _parts(profile)
    if len(adcs) != len(parts):
        raise BadInput(f"{len(adcs)} ADC blocks for a frame of {len(parts)} sub-frame(s)")
    words = []
    for k, (part, adc) in enumerate(zip(parts, adcs)):
        adc = np.asarray(adc)
        if adc.shape != frame_shape(part.radar):
            raise BadInput(f"sub-frame {k}: ADC block of shape {adc.shape}, expected "
                           f"{frame_shape(part.radar)}")
        words.append(np.asarray(layout_of(part.radar, interleaved).encode(adc[None]),
                                dtype=SAMPLE_DTYPE).ravel())
    return np.concatenate(words)
