"""DCA1000 raw ADC captures: write simulated frames, read recordings, real and complex.

File: the headerless ``adc_data.bin`` that TI's DCA1000 tools (``DCA1000EVM_CLI_Record`` with
``"dataFormatMode": 3`` raw, or mmWave Studio's packet-reorder/post-processing) leave after
stripping the UDP packet headers: a flat stream of little-endian int16 two's-complement words,
frame after frame, chirp after chirp, no header or padding. What the words of one chirp hold
depends on the ADC format and the ADC buffer interleaving the profile sets, and on the LVDS lane
count of the chip; each layout of `CAPTURE_LAYOUTS` names its source:

``real_noninterleaved`` (``adcCfg 2 0``, ``adcbufCfg ... <ChanInterleave> = 1``)
    chirp 0: Rx0 s0..s(N-1), Rx1 s0..s(N-1), ...; chirp 1: ... -- C order (chirp, Rx, sample).
    TI SWRA581 "mmWave Radar Device ADC Raw Data Capture", section "xWR16xx/IWR6843 real data
    format" and its ``readDCA1000.m`` (real branch: one row of numADCSamples x numRX per chirp,
    Rx r in columns r N .. (r+1) N - 1).
``real_interleaved`` (``adcbufCfg ... <ChanInterleave> = 0``, the AWR2944 R79 firmware)
    chirp 0: s0 of Rx0, Rx1, Rx2, Rx3, then s1 of Rx0..Rx3, ... -- (chirp, sample, Rx). The
    interleaved ADC buffer (mmWave SDK ADCBUF driver, "interleaved mode"; [TI-DPC] section on
    DPIF_RXCHAN_INTERLEAVE, [TI-DAZ] section 2) is what the LVDS/CBUFF session streams; it is
    also the order of a 4-lane capture in which lane k carries Rx k (DCA1000 user guide SPRUIJ4,
    "LVDS data format": lanes interleaved word by word).
``complex_noninterleaved`` (``adcCfg 2 1``/``2 2``, ``adcbufCfg -1 0 1 1 1``, 2 LVDS lanes:
    xWR16xx, xWR18xx, IWR6843 with the mmWave SDK)
    chirp 0: Rx0 I0 I1 Q0 Q1 I2 I3 Q2 Q3 ..., Rx1 ..., i.e. for each Rx the samples in pairs,
    two I words then the two Q words of the same pair. SWRA581 section "xWR16xx/IWR6843
    complex data format" (figure "2 lanes: I0 I1 Q0 Q1") and ``readDCA1000.m`` complex branch
    (``LVDS(counter) = adcData(i) + 1j adcData(i+2)``, ``LVDS(counter+1) = adcData(i+1) +
    1j adcData(i+3)`` for i = 1, 5, 9, ...); the same ordering as OpenRadar's
    ``DCA1000.organize`` (``ret[0::2] = raw[0::4] + 1j raw[2::4]``,
    ``ret[1::2] = raw[1::4] + 1j raw[3::4]``, reshaped to (chirps, Rx, samples)).

Chirp order within a frame is the transmit order of the chirp table (TDMA: Tx of `tx_order`
in turn). `read_capture` returns (n_frames, n_chirps, n_rx, n_samples): int16 for real
profiles, complex64 (integer-valued I, Q) for complex ones, in the chirp/Rx/sample order the
public readers give. Writing is atomic (temporary file in the target directory, then
`os.replace`); reading checks the size first: a truncated or mis-sized file raises a ValueError
naming both sizes and no partial frame is returned.
"""
from __future__ import annotations

import os
from pathlib import Path
from types import MappingProxyType
from typing import Callable, Iterable, Iterator, Mapping, NamedTuple

import numpy as np

from core.errors import BadInput
from core.fileio import atomic_write, check_input_file

from ..radar_config import RadarConfig

__all__ = ["SAMPLE_DTYPE", "CaptureLayout", "CAPTURE_LAYOUTS", "layout_of", "frame_shape",
           "frame_nbytes", "write_capture", "read_capture", "open_capture", "iter_capture",
           "capture_n_frames"]

#: Largest capture accepted, bytes (16 TiB: far beyond any DCA1000 recording).
MAX_CAPTURE_BYTES = 16 << 40
#: On-disk word type: int16, little-endian.
SAMPLE_DTYPE = np.dtype("<i2")


def _real_encode(x: np.ndarray) -> np.ndarray:
    return x


def _real_decode(w: np.ndarray, shape: tuple[int, int, int]) -> np.ndarray:
    return w.reshape(-1, *shape)


def _real_il_encode(x: np.ndarray) -> np.ndarray:
    return x.transpose(0, 1, 3, 2)


def _real_il_decode(w: np.ndarray, shape: tuple[int, int, int]) -> np.ndarray:
    c, r, n = shape
    return w.reshape(-1, c, n, r).transpose(0, 1, 3, 2)


def _cplx_encode(x: np.ndarray) -> np.ndarray:
    # (F, C, R, N) complex -> (F, C, R, N/2, [I, Q], [even, odd]) int16 words.
    f, c, r, n = x.shape
    pairs = x.reshape(f, c, r, n // 2, 2)
    return np.stack([pairs.real, pairs.imag], axis=-2)


def _cplx_decode(w: np.ndarray, shape: tuple[int, int, int]) -> np.ndarray:
    c, r, n = shape
    q = w.reshape(-1, c, r, n // 2, 2, 2).astype(np.float32)
    out = np.empty(q.shape[:4] + (2,), dtype=np.complex64)
    out.real = q[..., 0, :]
    out.imag = q[..., 1, :]
    return out.reshape(-1, c, r, n)


def _cplx4_encode(x: np.ndarray) -> np.ndarray:
    # (F, C, R, N) complex -> (F, C, N, [I, Q], R) int16 words: per sample, the I of the four
    # lanes (lane k = Rx k), then their Q.
    return np.stack([x.real, x.imag], axis=-1).transpose(0, 1, 3, 4, 2)


def _cplx4_decode(w: np.ndarray, shape: tuple[int, int, int]) -> np.ndarray:
    c, r, n = shape
    q = w.reshape(-1, c, n, 2, r).astype(np.float32)
    out = np.empty((q.shape[0], c, r, n), dtype=np.complex64)
    out.real = q[..., 0, :].transpose(0, 1, 3, 2)
    out.imag = q[..., 1, :].transpose(0, 1, 3, 2)
    return out


class CaptureLayout(NamedTuple):
    """One DCA1000 word layout: how a (F, C, R, N) block of samples maps to int16 words."""

    name: str
    is_complex: bool
    words_per_sample: int
    #: (F, C, R, N) int16 or complex -> int16 words in file order (any shape, C order)
    encode: Callable[[np.ndarray], np.ndarray]
    #: (F, words) int16 -> (F, C, R, N) int16 or complex64
    decode: Callable[[np.ndarray, tuple[int, int, int]], np.ndarray]
    source: str


#: Layouts by name (module docstring: the order of each and its TI source).
CAPTURE_LAYOUTS: Mapping[str, CaptureLayout] = MappingProxyType({
    "real_noninterleaved": CaptureLayout("real_noninterleaved", False, 1, _real_encode,
                                         _real_decode, "SWRA581 real format; readDCA1000.m"),
    "real_interleaved": CaptureLayout("real_interleaved", False, 1, _real_il_encode,
                                      _real_il_decode,
                                      "ADCBUF interleaved mode; [TI-DAZ] sec. 2; SPRUIJ4"),
    "complex_noninterleaved": CaptureLayout("complex_noninterleaved", True, 2, _cplx_encode,
                                            _cplx_decode,
                                            "SWRA581 2-lane complex (I0 I1 Q0 Q1); "
                                            "readDCA1000.m; OpenRadar DCA1000.organize"),
    "complex_4lane": CaptureLayout("complex_4lane", True, 2, _cplx4_encode, _cplx4_decode,
                                   "SWRA581 4-lane complex (xWR1243/1443/2243 with mmWave "
                                   "Studio): per sample I of lanes 0-3 then their Q, lane k = "
                                   "Rx k; TI's readDCA1000.m 4-lane branch"),
})


def _radar(cfg) -> RadarConfig:
    radar = getattr(cfg, "radar", cfg)  # a radarsim.ti.TiProfile carries its RadarConfig
    if not isinstance(radar, RadarConfig):
        raise BadInput(f"cfg must be a RadarConfig or TiProfile, got {type(cfg).__name__}")
    return radar


def layout_of(cfg, interleaved: bool | None = None) -> CaptureLayout:
    """The layout the profile implies: complex ADC -> ``complex_4lane`` on the 4-LVDS-lane
    chips (xWR1243/1443/2243), else ``complex_noninterleaved`` (the only buffer mode the
    complex-capable 2-lane SDK demos stream); real -> interleaved or not as
    ``adcbufCfg`` ChanInterleave (`RadarConfig.adcbuf_interleaved`). `interleaved` overrides the
    profile's buffer mode (real data only)."""
    radar = _radar(cfg)
    il = radar.adcbuf_interleaved if interleaved is None else bool(interleaved)
    if radar.is_complex and radar.chip_spec.lvds_lanes == 4:
        # 4-lane front ends (xWR1243/1443/2243): each lane carries one Rx; TI's reader assumes
        # all four lanes ("unused lanes are populated with 0").
        if radar.n_rx != 4:
            raise BadInput(f"n_rx={radar.n_rx}: the 4-lane complex capture layout is modelled "
                           "for 4 Rx (TI fills unused lanes with zeros)")
        return CAPTURE_LAYOUTS["complex_4lane"]
    if radar.is_complex:
        if il:
            raise BadInput("interleaved complex captures are not modelled (the xWR16/18/68 "
                           "SDK demos stream only the non-interleaved ADC buffer)")
        if radar.n_samples % 2:
            raise BadInput(f"n_samples={radar.n_samples}: the 2-lane complex layout packs "
                           "sample pairs (I0 I1 Q0 Q1), so n_samples must be even")
        return CAPTURE_LAYOUTS["complex_noninterleaved"]
    return CAPTURE_LAYOUTS["real_interleaved" if il else "real_noninterleaved"]


def frame_shape(cfg) -> tuple[int, int, int]:
    """Shape of one frame in the canonical order: (n_chirps, n_rx, n_samples)."""
    radar = _radar(cfg)
    return (int(radar.n_chirps), int(radar.n_rx), int(radar.n_samples))


def frame_nbytes(cfg) -> int:
    """Bytes of one frame on disk: n_chirps x n_rx x n_samples x 2 (x 2 again for I/Q)."""
    words = 2 if _radar(cfg).is_complex else 1
    return int(np.prod(frame_shape(cfg))) * words * SAMPLE_DTYPE.itemsize


def _as_frame(frame: np.ndarray, shape: tuple[int, int, int] | None, is_complex: bool,
              index: int) -> np.ndarray:
    arr = np.asarray(frame)
    if is_complex:
        if not np.iscomplexobj(arr):
            raise BadInput(f"frame {index}: dtype {arr.dtype} is not complex (complex ADC "
                           "profile)")
        parts = arr.view(arr.real.dtype)
        if not np.array_equal(parts, np.clip(np.rint(parts), -32768, 32767)):
            raise BadInput(f"frame {index}: I/Q parts are not int16 values; captures are "
                           "written bit-exact")
    elif arr.dtype != np.int16:
        raise BadInput(f"frame {index}: dtype {arr.dtype} is not int16 (ADC samples); "
                       "convert explicitly, captures are written bit-exact")
    if arr.ndim != 3:
        raise BadInput(f"frame {index}: shape {arr.shape} is not (n_chirps, n_rx, n_samples)")
    if shape is not None and arr.shape != shape:
        raise BadInput(f"frame {index}: shape {arr.shape} differs from the expected {shape}")
    return arr


def _iter_frames(frames: np.ndarray | Iterable[np.ndarray]) -> Iterator[np.ndarray]:
    if isinstance(frames, np.ndarray):
        if frames.ndim == 3:
            frames = frames[None]
        if frames.ndim != 4:
            raise BadInput(f"frames shape {frames.shape} is not (n_frames, n_chirps, n_rx, "
                           "n_samples)")
        yield from frames
    else:
        yield from frames


def write_capture(path: str | os.PathLike, frames: np.ndarray | Iterable[np.ndarray], *,
                  cfg=None, interleaved: bool | None = None,
                  layout: str | None = None) -> int:
    """Write ADC frames as a DCA1000 raw capture (atomically).

    Parameters
    ----------
    path : path-like
        Output file; replaced only once the whole capture is written.
    frames : (n_frames, n_chirps, n_rx, n_samples) array, or iterable of frames
        int16 for real profiles, complex with int16-valued parts for complex ones (an iterable
        is streamed, so a long scenario never sits in memory).
    cfg : RadarConfig or TiProfile, optional
        The profile: frame shape and layout (`layout_of`). Without it the layout follows the
        frames' dtype (real: non-interleaved unless `interleaved`).
    interleaved : bool, optional
        Override the profile's ADC buffer interleaving (real data).
    layout : str, optional
        A `CAPTURE_LAYOUTS` name, overriding both.

    Returns
    -------
    int
        Number of frames written.

    Raises
    ------
    core.errors.BadInput
        On a frame of the wrong dtype or shape; nothing is written then.
    core.errors.OutputError
        The file could not be written (``cannot write '{path}': no space left on the device``,
        a read-only folder, ...); `path` is left as it was.
    """
    path = Path(path)
    shape = frame_shape(cfg) if cfg is not None else None
    lay = CAPTURE_LAYOUTS[layout] if layout is not None else \
        layout_of(cfg, interleaved) if cfg is not None else None
    n = 0

    def write(tmp: Path) -> None:  # `atomic_write`: a full disk is named with `path`
        nonlocal n, lay, shape
        with open(tmp, "xb") as fh:
            for n, frame in enumerate(_iter_frames(frames), start=1):
                if lay is None:
                    cplx = np.iscomplexobj(frame)
                    lay = CAPTURE_LAYOUTS["complex_noninterleaved" if cplx else
                                          "real_interleaved" if interleaved else
                                          "real_noninterleaved"]
                arr = _as_frame(frame, shape, lay.is_complex, n - 1)
                shape = arr.shape
                words = lay.encode(arr[None])
                fh.write(np.ascontiguousarray(words, dtype=SAMPLE_DTYPE).tobytes())
        if n == 0:
            raise BadInput("no frames to write")

    atomic_write(path, write)
    return n


def capture_n_frames(path: str | os.PathLike, cfg) -> int:
    """Number of whole frames in a capture, checking that the size is an exact multiple.

    Raises
    ------
    ValueError
        If the path is not a regular file (a FIFO, a device, a directory, a symbolic link
        loop: named), the file is empty or its size is not a whole number of frames (truncated
        capture, or a profile that does not match the recording).
    """
    # A FIFO, device or directory is refused by name (a FIFO would block, /dev/zero read as
    # an "empty" capture); the file is memory-mapped, so the size bound is only a sanity one.
    check_input_file(path, "capture", max_bytes=MAX_CAPTURE_BYTES)
    size = Path(path).stat().st_size
    per_frame = frame_nbytes(cfg)
    n_frames, rest = divmod(size, per_frame)
    n_c, n_r, n_s = frame_shape(cfg)
    words = 2 if _radar(cfg).is_complex else 1
    if size == 0:
        raise BadInput(f"capture {str(path)!r} is empty")
    if rest:
        raise BadInput(
            f"capture {str(path)!r} has {size} bytes, not a whole number of frames of "
            f"{per_frame} bytes ({n_c} chirps x {n_r} Rx x {n_s} samples x {2 * words} bytes): "
            f"{n_frames} whole frame(s) and {rest} stray bytes; the file is truncated or the "
            "profile does not match the recording")
    return n_frames


def open_capture(path: str | os.PathLike, cfg, *, interleaved: bool | None = None,
                 layout: str | None = None) -> np.ndarray:
    """Memory-map a capture read-only: (n_frames, words per frame) int16 words in file order.

    Decode frames with ``layout_of(cfg).decode``; `iter_capture` and `read_capture` do."""
    n_frames = capture_n_frames(path, cfg)
    words = frame_nbytes(cfg) // SAMPLE_DTYPE.itemsize
    return np.memmap(path, dtype=SAMPLE_DTYPE, mode="r", shape=(n_frames, words))


def _layout(cfg, interleaved, layout) -> CaptureLayout:
    lay = CAPTURE_LAYOUTS[layout] if layout is not None else layout_of(cfg, interleaved)
    if lay.is_complex != _radar(cfg).is_complex:
        raise BadInput(f"layout {lay.name!r} does not match the profile's "
                       f"{_radar(cfg).adc_mode} ADC")
    return lay


def read_capture(path: str | os.PathLike, cfg, *, interleaved: bool | None = None,
                 layout: str | None = None) -> np.ndarray:
    """Read a whole DCA1000 capture into memory.

    Parameters
    ----------
    path : path-like
        Headerless capture (see the module docstring for the layouts).
    cfg : RadarConfig or TiProfile
        The profile it was recorded with: shape, ADC format and buffer interleaving.
    interleaved, layout : optional
        Overrides, as in `write_capture`.

    Returns
    -------
    (n_frames, n_chirps, n_rx, n_samples) int16 (real) or complex64 (complex profiles)
        C-contiguous copy.

    Raises
    ------
    ValueError
        If the file size is not a whole number of frames for `cfg` (no partial frame is
        returned).
    """
    lay = _layout(cfg, interleaved, layout)
    words = open_capture(path, cfg)
    out = lay.decode(words, frame_shape(cfg))
    return np.array(out, dtype=np.complex64 if lay.is_complex else np.int16, order="C")


def iter_capture(path: str | os.PathLike, cfg, *, interleaved: bool | None = None,
                 layout: str | None = None,
                 max_frames: int | None = None) -> Iterator[np.ndarray]:
    """Frames of a capture one at a time, each a (n_chirps, n_rx, n_samples) copy.

    The size is checked before the first frame is yielded, so a mis-sized file yields nothing.
    """
    lay = _layout(cfg, interleaved, layout)
    words = open_capture(path, cfg)
    shape = frame_shape(cfg)
    n = words.shape[0] if max_frames is None else min(int(max_frames), words.shape[0])
    dtype = np.complex64 if lay.is_complex else np.int16
    for i in range(n):
        yield np.array(lay.decode(words[i: i + 1], shape)[0], dtype=dtype, order="C")
