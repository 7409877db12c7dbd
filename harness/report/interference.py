"""Report section: noise-floor rise, INR and detection probability versus range of the
interference cases (every case with interferers, or whose name says so)."""
from __future__ import annotations

import pandas as pd

from harness.report.figures import png_img, pyplot, scheme_order, table_html
from metrics.association import AssociationConfig
from metrics.detection import pd_vs_range

__all__ = ["html_section"]


def html_section(summary: pd.DataFrame, actors: pd.DataFrame) -> str:
    """HTML of the interference section: per interference case, the noise-floor
    rise after the Doppler FFT (median over frames) and the INR for every variant and scheme,
    then Pd versus range per variant (e.g. equipped share x mitigation on/off). Empty when the
    summary has no interference columns or no case with interferers."""
    need = {"noise_floor_rise_db", "interference_to_noise_db"}
    if not need <= set(summary.columns):
        return ""
    cases = [c for c in summary["scenario"].unique()
             if "interfer" in c or summary.loc[summary["scenario"] == c,
                                               "interference_to_noise_db"].notna().any()]
    if not cases:
        return ""
    plt = pyplot()
    parts = ["<h2>Interference: noise-floor rise and Pd versus range</h2>",
             "<p>Noise-floor rise: median over frames of the Doppler-FFT floor over thermal "
             "(chirp-level chain of each variant applied); INR: in-burst interference-to-noise "
             "ratio at the ADC (median over frames with interferers).</p>"]
    cols = ["scenario", "variant", "scheme", "noise_floor_rise_db", "noise_floor_rise_range_db",
            "interference_to_noise_db", "ghost_rate", "n_detections"]
    sub = summary[summary["scenario"].isin(cases)]
    parts.append(table_html(sub, [c for c in cols if c in sub.columns]))
    schemes = scheme_order(sub) or ["-"]
    fig, axes = plt.subplots(1, len(cases), figsize=(5.5 * len(cases), 4), squeeze=False)
    for ax, case in zip(axes[0], cases):
        g = sub[sub["scenario"] == case].groupby(["variant", "scheme"])["noise_floor_rise_db"] \
            .median().unstack("scheme")
        g = g.reindex(columns=[s for s in schemes if s in g.columns])
        g.plot.bar(ax=ax, rot=75, fontsize=7)
        ax.set_title(f"{case}: noise-floor rise", fontsize=9)
        ax.set_ylabel("dB over thermal (after Doppler FFT)")
        ax.grid(alpha=0.3, axis="y")
    parts.append(png_img(fig))
    a = actors[actors["scenario"].isin(cases)] if len(actors) else actors
    if len(a):
        bin_m, min_count = AssociationConfig().pd_range_bin_m, AssociationConfig().pd_min_count
        fig, axes = plt.subplots(1, len(schemes), figsize=(5 * len(schemes), 4), sharey=True,
                                 squeeze=False)
        for ax, scheme in zip(axes[0], schemes):
            for var, g in a[a["scheme"] == scheme].groupby("variant"):
                t = pd_vs_range(g.assign(actor_class="all"), bin_m)
                t = t[t["n_frames"] >= min_count]
                ax.plot((t["range_lo_m"] + t["range_hi_m"]) / 2, t["detection_probability"],
                        "o-", ms=3, label=var)
            ax.axhline(0.9, color="k", ls=":", lw=0.8)
            ax.set_title(f"{scheme}: Pd vs range, interference cases", fontsize=9)
            ax.set_xlabel("actor centre range, m")
            ax.grid(alpha=0.3)
            if ax.get_legend_handles_labels()[1]:
                ax.legend(fontsize=6)
        axes[0][0].set_ylabel("detection probability")
        parts.append(png_img(fig))
    return "\n".join(parts)
