"""Bird's-eye views of a scenario run: a PNG (one frame plus all trajectories) and a GIF.

Both are drawn in the ego's vehicle frame (x forward drawn to the right, y left drawn up), with
each actor's box, guard rails, and the radar's azimuth field of view as a wedge from the mount.
matplotlib's Agg backend (no display) draws them; the GIF uses matplotlib's Pillow writer.
"""
from __future__ import annotations

from pathlib import Path as FsPath

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib.animation import FuncAnimation, PillowWriter  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.patches import Wedge  # noqa: E402

from core.fileio import atomic_write  # noqa: E402

from .traffic import ScenarioRun  # noqa: E402

__all__ = ["box_corners", "plot_birdseye", "animate_birdseye", "write_views", "CLASS_COLORS",
           "FOV_HALF_ANGLE_DEG"]

#: Published azimuth FOV of the AWR2944 corner radar, +/- deg (design.md 4.1).
FOV_HALF_ANGLE_DEG = 80.0
CLASS_COLORS = {"car": "tab:blue", "truck": "tab:purple", "motorcycle": "tab:red",
                "bicycle": "tab:orange", "pedestrian": "tab:green", "guard_rail": "0.55"}


def box_corners(x, y, yaw_deg, length, width) -> np.ndarray:
    """(N, 4, 2) footprint corners of N boxes (centre, yaw, size), same frame as x, y."""
    x, y, yaw = (np.atleast_1d(np.asarray(a, float)) for a in (x, y, np.radians(yaw_deg)))
    hl = 0.5 * np.atleast_1d(np.asarray(length, float))
    hw = 0.5 * np.atleast_1d(np.asarray(width, float))
    sx = np.array([1, 1, -1, -1])
    sy = np.array([1, -1, -1, 1])
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    lx, ly = sx * hl[:, None], sy * hw[:, None]
    return np.stack([x[:, None] + c * lx - s * ly, y[:, None] + s * lx + c * ly], axis=-1)


def _extent(run: ScenarioRun) -> tuple[float, float, float, float]:
    t = run.truth
    mv = t[t["actor_class"] != "guard_rail"]
    xs = np.concatenate([[-10.0, 10.0], mv["x_m"].to_numpy()])
    ys = np.concatenate([[-10.0, 10.0], mv["y_m"].to_numpy()])
    x0, x1 = np.clip([xs.min() - 8, xs.max() + 8], -160, 160)
    y0, y1 = np.clip([ys.min() - 8, ys.max() + 8], -160, 160)
    # Keep metres square and the picture not too thin.
    half = 0.5 * max(x1 - x0, 2 * (y1 - y0)) / 2
    cy = 0.5 * (y0 + y1)
    return x0, x1, min(y0, cy - half), max(y1, cy + half)


def _base_axes(run: ScenarioRun, extent):
    fig, ax = plt.subplots(figsize=(10, 5.5), dpi=90)
    m = run.mount
    reach = 1.5 * max(abs(extent[0]), abs(extent[1]), abs(extent[2]), abs(extent[3]))
    ax.add_patch(Wedge((m.x_m, m.y_m), reach, m.yaw_deg - FOV_HALF_ANGLE_DEG,
                       m.yaw_deg + FOV_HALF_ANGLE_DEG, color="gold", alpha=0.18, lw=0,
                       label=f"{m.name} FOV +/-{FOV_HALF_ANGLE_DEG:g} deg"))
    ego = box_corners(0.0, 0.0, 0.0, 5.0, 2.0)[0]
    ax.fill(ego[:, 0], ego[:, 1], color="k", alpha=0.8, label="ego")
    ax.plot(m.x_m, m.y_m, marker="^", color="gold", mec="k", ms=8)
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m, ego forward)")
    ax.set_ylabel("y (m, ego left)")
    ax.grid(alpha=0.3)
    return fig, ax


def _frame_polys(rows: pd.DataFrame):
    corners = box_corners(rows["x_m"], rows["y_m"], rows["yaw_deg"], rows["length_m"],
                          rows["width_m"])
    colors = [CLASS_COLORS.get(c, "tab:gray") for c in rows["actor_class"]]
    return corners, colors


def plot_birdseye(run: ScenarioRun, path, frame: int | None = None) -> FsPath:
    """Write a PNG: actors at `frame` (default: the middle one) and every actor's track.

    Returns
    -------
    pathlib.Path
        The written file.
    """
    t = run.truth
    frame = run.n_frames // 2 if frame is None else int(frame)
    extent = _extent(run)
    fig, ax = _base_axes(run, extent)
    mv = t[t["actor_class"] != "guard_rail"]
    for aid, g in mv.groupby("actor_id"):
        ax.plot(g["x_m"], g["y_m"], lw=0.8, color=CLASS_COLORS.get(g["actor_class"].iloc[0]),
                alpha=0.6)
    rows = t[t["frame"] == frame]
    corners, colors = _frame_polys(rows)
    ax.add_collection(PolyCollection(corners, facecolors=colors, edgecolors="k", lw=0.5))
    for cls in sorted(set(rows["actor_class"])):
        ax.fill([], [], color=CLASS_COLORS.get(cls, "tab:gray"), label=cls)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"{run.case.name} (seed {run.seed}), t = {frame / run.frame_rate_hz:.2f} s")
    out = FsPath(path)
    atomic_write(out, lambda tmp: fig.savefig(tmp, format=out.suffix.lstrip(".") or "png"))
    plt.close(fig)
    return out


def animate_birdseye(run: ScenarioRun, path, max_frames: int = 40, fps: float = 10.0) -> FsPath:
    """Write an animated GIF of the run (at most `max_frames` frames, evenly spaced)."""
    t = run.truth
    extent = _extent(run)
    fig, ax = _base_axes(run, extent)
    frames = np.unique(np.linspace(0, run.n_frames - 1, min(max_frames, run.n_frames))
                       .round().astype(int))
    groups = {f: g for f, g in t.groupby("frame")}
    coll = PolyCollection([], edgecolors="k", lw=0.5)
    ax.add_collection(coll)
    title = ax.set_title("")

    def draw(f):
        rows = groups.get(f, t.iloc[0:0])
        corners, colors = _frame_polys(rows)
        coll.set_verts(list(corners))
        coll.set_facecolors(colors)
        title.set_text(f"{run.case.name}, t = {f / run.frame_rate_hz:.2f} s")
        return coll, title

    anim = FuncAnimation(fig, draw, frames=frames, blit=False)
    out = FsPath(path)
    atomic_write(out, lambda tmp: anim.save(tmp, writer=PillowWriter(fps=fps)))
    plt.close(fig)
    return out


def write_views(run: ScenarioRun, out_dir=".") -> tuple[FsPath, FsPath]:
    """Write `<case>.png` and `<case>.gif` into `out_dir` (created if needed)."""
    d = FsPath(out_dir)
    d.mkdir(parents=True, exist_ok=True)
    png = plot_birdseye(run, d / f"{run.case.name}.png")
    gif = animate_birdseye(run, d / f"{run.case.name}.gif")
    return png, gif
