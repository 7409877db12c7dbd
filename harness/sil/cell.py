"""An external chain inside a sweep cell: its frames on disk, its calls, its point clouds.

`ExternalCellRun` collects the cell's ADC frames of the chain's scheme as the frame loop makes
them (each frame encoded once into the DCA1000 layout, `radarsim.capture.write_capture`,
exactly as `radar-harness simulate` writes it), then runs the calls (``frames_per_call``
frames each, or the whole cell) and returns one point cloud per frame in the columns of
`pipeline.process_frame` (x/y/z from range and angles; bins -1: a point file has none). The
profile of every call is `harness.sil.profile.cell_profile` of the cell's radar and the
scheme's processing. The scratch folder is removed when the run closes.
"""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

from harness.sil.call import check_points, read_points, run_command
from harness.sil.profile import cell_profile
from harness.sil.spec import ExternalChain

__all__ = ["ExternalCellRun", "cloud_of"]

_CLOUD_DTYPES = {"range_bin": np.int64, "doppler_bin": np.int64, "azimuth_bin": np.int64}


def cloud_of(points: pd.DataFrame) -> pd.DataFrame:
    """A point cloud (`pipeline.POINT_CLOUD_COLUMNS`) from checked points of one frame."""
    r = points["range_m"].to_numpy()
    az = np.radians(points["azimuth_deg"].to_numpy())
    el = np.radians(points["elevation_deg"].to_numpy())
    n = len(points)
    return pd.DataFrame({
        "range_m": r, "azimuth_deg": points["azimuth_deg"].to_numpy(),
        "elevation_deg": points["elevation_deg"].to_numpy(),
        "radial_velocity_mps": points["radial_velocity_mps"].to_numpy(),
        "snr_db": points["snr_db"].to_numpy(),
        "x_m": r * np.cos(el) * np.cos(az), "y_m": r * np.cos(el) * np.sin(az),
        "z_m": r * np.sin(el),
        **{k: np.full(n, -1, dtype=t) for k, t in _CLOUD_DTYPES.items()},
        "saturated": np.zeros(n, dtype=bool)})


class ExternalCellRun:
    """The external chain `chain` over one cell (module docstring).

    Parameters
    ----------
    chain : ExternalChain
    radar : radarsim.RadarConfig
        The cell's radar of ``chain.scheme``.
    proc : pipeline.ProcessingConfig
        The chain's processing in the cell (what the profile expresses).
    frame_period_s : float
        The cell's frame period, s (the profile's ``framePeriodicity``).
    """

    def __init__(self, chain: ExternalChain, radar, proc, frame_period_s: float) -> None:
        self.chain, self.radar = chain, radar
        self.profile = cell_profile(radar, proc, frame_period_s)
        self.dir = Path(tempfile.mkdtemp(prefix=f"radar-harness-sil-{chain.name}-"))
        (self.dir / "frames").mkdir()
        self.elapsed_s = 0.0
        self.n_calls = 0

    def _frame_path(self, frame: int) -> Path:
        return self.dir / "frames" / f"{int(frame):07d}.bin"

    def add_frame(self, frame: int, adc: np.ndarray) -> int:
        """Keep one ADC frame (thread-safe: one file per frame); returns its saturated
        (chirp, Rx) pairs (`pipeline.saturation.monitor`, as a built-in chain counts them)."""
        from pipeline.saturation import monitor
        from radarsim.capture import write_capture
        write_capture(self._frame_path(frame), [adc], cfg=self.radar)
        return int(monitor(adc).n_saturated_chirp_rx)

    def _calls(self, frames) -> list[list[int]]:
        n = self.chain.frames_per_call
        frames = [int(f) for f in frames]
        step = len(frames) if n == "cell" else n
        return [frames[i:i + step] for i in range(0, len(frames), max(step, 1))]

    def run(self, frames) -> list[pd.DataFrame]:
        """Run every call; one point cloud per frame of `frames`, in order.

        Raises
        ------
        harness.sil.call.ExternalChainError
            The first failing call (naming the chain, the call and its frames).
        """
        clouds: list[pd.DataFrame] = []
        calls = self._calls(frames)
        for k, group in enumerate(calls):
            what = (f"external chain {self.chain.name!r} call {k + 1}/{len(calls)} (frames "
                    f"{group[0]}..{group[-1]})")
            d = self.dir / f"call{k:05d}"
            d.mkdir()
            cfg, adc, pts = d / "profile.cfg", d / "adc.bin", d / self.chain.points
            cfg.write_text(self.profile.text)
            with open(adc, "wb") as out:
                for f in group:
                    with open(self._frame_path(f), "rb") as src:
                        shutil.copyfileobj(src, out)
            self.elapsed_s += run_command(self.chain.argv(str(cfg), str(adc), str(pts)), d,
                                          self.chain.timeout_s, what)
            self.n_calls += 1
            points = check_points(read_points(pts, what, d / "stderr.txt"), self.radar,
                                  len(group), what)
            by_frame = points.groupby("frame", sort=True)
            for i in range(len(group)):
                rows = by_frame.get_group(i) if i in by_frame.groups else points.iloc[:0]
                clouds.append(cloud_of(rows.reset_index(drop=True)))
            shutil.rmtree(d, ignore_errors=True)
        return clouds

    def close(self) -> None:
        """Remove the scratch folder."""
        shutil.rmtree(self.dir, ignore_errors=True)
