"""Matplotlib figures as self-contained HTML: the headless backend and embedded PNGs.

Shared by the report (`harness.report`) and its sections (`harness.shifter_report`), so the
sections need not import the report that includes them.
"""
from __future__ import annotations

import base64
import io

__all__ = ["pyplot", "png_img"]


def pyplot():
    """`matplotlib.pyplot` on the non-interactive Agg backend (imported on first use, so the
    CLI starts without matplotlib)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def png_img(fig) -> str:
    """<img> tag with the figure as an embedded PNG (80 dpi); closes the figure."""
    plt = pyplot()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80, bbox_inches="tight")
    plt.close(fig)
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    return f'<img alt="plot" src="data:image/png;base64,{data}">'
