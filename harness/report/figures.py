"""The report's building blocks: matplotlib on the headless backend, figures as embedded PNGs,
tables as compact HTML, the schemes of a table in order.

Shared by the report page (`harness.report.page`) and its sections (`harness.report.sections`),
so a section never imports the page that includes it.
"""
from __future__ import annotations

import base64
import io

import pandas as pd

__all__ = ["pyplot", "png_img", "table_html", "scheme_order"]


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


def table_html(df: pd.DataFrame, columns=None) -> str:
    """A table as compact HTML (3 significant digits, "-" for missing); `columns` that the
    table lacks are skipped."""
    if df.empty:
        return "<p>(empty)</p>"
    cols = [c for c in (columns or df.columns) if c in df.columns]
    return df[cols].to_html(index=False, float_format=lambda v: f"{v:.3g}", na_rep="-",
                            border=0, classes="tbl")


def scheme_order(df: pd.DataFrame, mimo_only: bool = False) -> list[str]:
    """Schemes of a table in order of appearance; `mimo_only` keeps registered MIMO schemes
    (those with their own ADC frame), dropping chain variants such as ``tdma_raw``."""
    # unique() first: the detections table has a row per detection (10^5 in the default run)
    names = list(dict.fromkeys(df["scheme"].unique())) if "scheme" in df and len(df) else []
    names = [n for n in names if n]
    if mimo_only:
        import radarsim
        names = [n for n in names if n in radarsim.MIMO_SCHEMES]
    return names
