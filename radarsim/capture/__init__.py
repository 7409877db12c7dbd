"""Raw ADC captures: DCA1000 files written from simulated frames and read from recordings.

`dca1000` holds the file layouts (real and complex, interleaved or not, 2 and 4 LVDS lanes)
and reading / writing frames; `subframes` the captures of advanced frames (sub-frames back to
back); `regroup` the slow time of one-chirp-per-frame recordings (N frames read as one). The
package re-exports `dca1000`'s names: ``radarsim.capture.read_capture(path, cfg)``.
"""
from .dca1000 import (
    CAPTURE_LAYOUTS,
    SAMPLE_DTYPE,
    CaptureLayout,
    capture_n_frames,
    frame_nbytes,
    frame_shape,
    iter_capture,
    layout_of,
    open_capture,
    read_capture,
    write_capture,
)

__all__ = ["SAMPLE_DTYPE", "CaptureLayout", "CAPTURE_LAYOUTS", "layout_of", "frame_shape",
           "frame_nbytes", "write_capture", "read_capture", "open_capture", "iter_capture",
           "capture_n_frames"]
