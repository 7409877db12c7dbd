"""TI mmWave CLI profiles (.cfg) modelled on real ones of every chip family (TI Visualizer, SDK
demos, ROS driver, lab firmwares; our own numbers), as users bring them. Each test that reads
one states its hand-computed values next to it."""
from __future__ import annotations

from pathlib import Path

__all__ = ["profile_text", "PROFILE_DIR"]

PROFILE_DIR = Path(__file__).resolve().parent


def profile_text(name: str) -> str:
    """Text of ``<name>.cfg`` in this folder."""
    return (PROFILE_DIR / f"{name}.cfg").read_text()
