"""DCA1000 raw ADC captures of the real-only AWR2944 chain: write simulated frames, read recordings.

File layout (the headerless ``adc_data.bin`` that TI's DCA1000 tools leave after stripping the
UDP packet headers): a flat stream of int16 two's-complement samples, little-endian, frame after
frame with no header or padding. Within a frame, for real ADC data with a non-interleaved ADC
buffer (``adcbufCfg ... <ChanInterleave>=1``, TI's default for DCA1000 capture, e.g. the
AWR294X ``profile_LVDS.cfg``), the order is

    chirp 0: Rx0 samples 0..N-1, Rx1 samples 0..N-1, ..., Rx(R-1) samples 0..N-1
    chirp 1: ...

i.e. a C-order array ``(n_frames, n_chirps, n_rx, n_samples)``, the canonical cube order of this
project. Source: TI SWRA581 "mmWave Radar Device ADC Raw Data Capture", section "xWR16xx and
IWR6843 with DCA1000 Data Format", and its ``readDCA1000.m``: for real data
``LVDS = reshape(adcData, numADCSamples*numRX, numChirps).'`` and Rx r of chirp c is columns
``(r-1)*numADCSamples+1 : r*numADCSamples`` of row c (copy in FebianFebian1/
Radar_TI_AWR1642_MATLAB_Postproc, readDCA1000.m). With an interleaved ADC buffer
(``ChanInterleave`` = 0) the samples of the Rx channels alternate instead:
``(n_frames, n_chirps, n_samples, n_rx)``; pass ``interleaved=True``.

Writing is atomic (temporary file in the target directory, then `os.replace`), and reading
checks the size against the configuration first: a truncated or mis-sized file raises a
ValueError naming both sizes, and no partial frame is ever returned.
"""
from __future__ import annotations

import os
import uuid
from pathlib import Path
from typing import Iterable, Iterator

import numpy as np

from .config import RadarConfig

__all__ = ["SAMPLE_DTYPE", "frame_shape", "frame_nbytes", "write_capture", "read_capture",
           "open_capture", "iter_capture", "capture_n_frames"]

#: On-disk sample type: int16, little-endian.
SAMPLE_DTYPE = np.dtype("<i2")


def frame_shape(cfg: RadarConfig) -> tuple[int, int, int]:
    """Shape of one frame in the canonical order: (n_chirps, n_rx, n_samples)."""
    return (int(cfg.n_chirps), int(cfg.n_rx), int(cfg.n_samples))


def frame_nbytes(cfg: RadarConfig) -> int:
    """Bytes of one frame on disk: n_chirps x n_rx x n_samples x 2."""
    return int(np.prod(frame_shape(cfg))) * SAMPLE_DTYPE.itemsize


def _as_frame(frame: np.ndarray, shape: tuple[int, int, int] | None, index: int) -> np.ndarray:
    arr = np.asarray(frame)
    if arr.dtype != np.int16:
        raise ValueError(f"frame {index}: dtype {arr.dtype} is not int16 (ADC samples); "
                         "convert explicitly, captures are written bit-exact")
    if arr.ndim != 3:
        raise ValueError(f"frame {index}: shape {arr.shape} is not (n_chirps, n_rx, n_samples)")
    if shape is not None and arr.shape != shape:
        raise ValueError(f"frame {index}: shape {arr.shape} differs from the first frame's "
                         f"{shape}")
    return arr


def _iter_frames(frames: np.ndarray | Iterable[np.ndarray]) -> Iterator[np.ndarray]:
    if isinstance(frames, np.ndarray):
        if frames.ndim == 3:
            frames = frames[None]
        if frames.ndim != 4:
            raise ValueError(f"frames shape {frames.shape} is not (n_frames, n_chirps, n_rx, "
                             "n_samples)")
        yield from frames
    else:
        yield from frames


def write_capture(path: str | os.PathLike, frames: np.ndarray | Iterable[np.ndarray], *,
                  cfg: RadarConfig | None = None, interleaved: bool = False) -> int:
    """Write ADC frames as a DCA1000 raw capture (atomically).

    Parameters
    ----------
    path : path-like
        Output file; replaced only once the whole capture is written.
    frames : (n_frames, n_chirps, n_rx, n_samples) int16 array, or iterable of
        (n_chirps, n_rx, n_samples) int16 frames
        The frames (an iterable is streamed, so a long scenario never sits in memory).
    cfg : RadarConfig, optional
        If given, every frame must have its shape (n_chirps, n_rx, n_samples).
    interleaved : bool
        Write the interleaved-ADC-buffer order (chirp, sample, Rx) instead of (chirp, Rx,
        sample).

    Returns
    -------
    int
        Number of frames written.

    Raises
    ------
    ValueError
        On a frame that is not int16 or whose shape differs from `cfg` or the first frame;
        nothing is written then.
    """
    path = Path(path)
    shape = frame_shape(cfg) if cfg is not None else None
    # A unique sibling (same file system, so os.replace is atomic), created with the usual
    # permissions (mkstemp's would be 0600).
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex}.tmp")
    n = 0
    try:
        with open(tmp, "xb") as fh:
            for n, frame in enumerate(_iter_frames(frames), start=1):
                arr = _as_frame(frame, shape, n - 1)
                shape = arr.shape
                if interleaved:
                    arr = arr.transpose(0, 2, 1)
                fh.write(np.ascontiguousarray(arr, dtype=SAMPLE_DTYPE).tobytes())
            fh.flush()
            os.fsync(fh.fileno())
        if n == 0:
            raise ValueError("no frames to write")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return n


def capture_n_frames(path: str | os.PathLike, cfg: RadarConfig) -> int:
    """Number of whole frames in a capture, checking that the size is an exact multiple.

    Raises
    ------
    ValueError
        If the file is empty or its size is not a whole number of frames (truncated capture,
        or a profile that does not match the recording).
    """
    size = Path(path).stat().st_size
    per_frame = frame_nbytes(cfg)
    n_frames, rest = divmod(size, per_frame)
    n_c, n_r, n_s = frame_shape(cfg)
    if size == 0:
        raise ValueError(f"capture {str(path)!r} is empty")
    if rest:
        raise ValueError(
            f"capture {str(path)!r} has {size} bytes, not a whole number of frames of "
            f"{per_frame} bytes ({n_c} chirps x {n_r} Rx x {n_s} samples x 2 bytes): "
            f"{n_frames} whole frame(s) and {rest} stray bytes; the file is truncated or the "
            "profile does not match the recording")
    return n_frames


def open_capture(path: str | os.PathLike, cfg: RadarConfig, *,
                 interleaved: bool = False) -> np.ndarray:
    """Memory-map a capture, read-only, without loading it.

    Returns
    -------
    (n_frames, n_chirps, n_rx, n_samples) int16 array
        A read-only view on the file (a transposed view when `interleaved`).
    """
    n_frames = capture_n_frames(path, cfg)
    n_c, n_r, n_s = frame_shape(cfg)
    disk = (n_frames, n_c, n_s, n_r) if interleaved else (n_frames, n_c, n_r, n_s)
    mm = np.memmap(path, dtype=SAMPLE_DTYPE, mode="r", shape=disk)
    return mm.transpose(0, 1, 3, 2) if interleaved else mm


def read_capture(path: str | os.PathLike, cfg: RadarConfig, *,
                 interleaved: bool = False) -> np.ndarray:
    """Read a whole DCA1000 capture into memory.

    Parameters
    ----------
    path : path-like
        Headerless capture (see the module docstring for the layout).
    cfg : RadarConfig
        Supplies n_chirps, n_rx, n_samples.
    interleaved : bool
        The capture uses the interleaved-ADC-buffer order (chirp, sample, Rx).

    Returns
    -------
    (n_frames, n_chirps, n_rx, n_samples) int16
        Native-endian, C-contiguous copy.

    Raises
    ------
    ValueError
        If the file size is not a whole number of frames for `cfg` (no partial frame is
        returned).
    """
    mm = open_capture(path, cfg, interleaved=interleaved)
    # A real in-memory copy (np.ascontiguousarray would hand back the memmap itself).
    return np.array(mm, dtype=np.int16, order="C", subok=False)


def iter_capture(path: str | os.PathLike, cfg: RadarConfig, *, interleaved: bool = False,
                 max_frames: int | None = None) -> Iterator[np.ndarray]:
    """Frames of a capture one at a time, each a (n_chirps, n_rx, n_samples) int16 copy.

    The size is checked before the first frame is yielded, so a mis-sized file yields nothing.
    """
    mm = open_capture(path, cfg, interleaved=interleaved)
    n = mm.shape[0] if max_frames is None else min(int(max_frames), mm.shape[0])
    for i in range(n):
        yield np.array(mm[i], dtype=np.int16, order="C", subok=False)
