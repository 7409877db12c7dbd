"""Interference-mitigation benchmark: every repair method on the interference cases.

`mitigation_table(results)` reads a results directory of a sweep whose variants set
``processing.interference.repair`` (``harness/sweeps/mitigation.toml``) and returns one row per
(case, method, scheme): the noise-floor rise without mitigation and with the method, the floor
it recovers (dB and fraction of the rise), the ghost rate with it and the ghosts it adds over
the same frames processed without mitigation (all summary columns, `metrics.interference`),
and the SNR of the case's target: the median over the frames in which it is detected of its
strongest TRUE detection's SNR (``actors.max_snr_db``; every road user of a traffic case).
`recovery_vs_inr(results)` gives each method's recovered fraction of the floor rise per frame,
binned by the frame's in-burst INR (the interferer's approach: weak bursts, which the chip's
fixed threshold partly misses, at the low end). `html_section(results)` renders both for the
report.
"""
from __future__ import annotations

import html
from pathlib import Path

import numpy as np
import pandas as pd

import scenarios
from core.errors import BadInput
from harness.report.figures import png_img, pyplot
from harness.sweep.results_schema import read_manifest
from harness.sweep.store import failed_rows
from metrics.interference import MIN_RISE_TO_RECOVER_DB

__all__ = ["mitigation_table", "recovery_vs_inr", "html_section", "COLUMNS", "INR_BIN_DB"]

COLUMNS = ["scenario", "method", "scheme", "noise_floor_rise_unmitigated_db",
           "noise_floor_rise_db", "mitigation_floor_recovery_db",
           "mitigation_floor_recovery_fraction", "mitigation_floor_recovery_fraction_worst_1s",
           "ghost_rate_unmitigated", "ghost_rate", "mitigation_ghost_rate_added",
           "target_snr_db", "target_pd"]
#: Width of the in-burst INR bins of `recovery_vs_inr`, dB.
INR_BIN_DB = 1.0


#: The processing keys of a variant's repair method: the nested one, and the flat key of
#: results written before the nested configs.
_METHOD_KEYS = ("interference.repair", "intf_mitigation")


def _methods(results: Path) -> dict[str, str]:
    """Variant name -> its repair method (variants that set one, `_METHOD_KEYS`); refused when
    no variant sets one (the results are no mitigation sweep)."""
    man = read_manifest(results)
    out = {}
    for v in man.get("sweep", {}).get("variants", []):
        proc = v.get("processing", {})
        key = next((k for k in _METHOD_KEYS if k in proc), None)
        if key is not None:
            out[v["name"]] = proc[key]
    if not out:
        raise BadInput(f"{results}: no variant sets processing.interference.repair")
    return out


def _targets(scenario: str) -> list[int] | None:
    is_file = scenarios.files.is_case_path(scenario) and Path(scenario).is_file()
    case = scenarios.get_case(scenario) if is_file else scenarios.SCENARIOS.get(scenario)
    must = list(getattr(case, "must_detect", ()) or ())
    return must or None


def mitigation_table(results: str | Path) -> pd.DataFrame:
    """One row per (case, method, scheme) of a mitigation sweep (columns `COLUMNS`).

    Raises
    ------
    ValueError
        The results hold no variant that sets ``processing.interference.repair``.
    """
    results = Path(results)
    methods = _methods(results)
    summ = pd.read_parquet(results / "summary.parquet")
    summ = summ[~failed_rows(summ) & summ["variant"].isin(methods)].copy()
    summ["method"] = summ["variant"].map(methods)
    act = pd.read_parquet(results / "actors.parquet")
    act = act[act["variant"].isin(methods) & act["visible"]]
    rows = []
    for (sc, var, scheme), a in act.groupby(["scenario", "variant", "scheme"]):
        t = _targets(sc)
        if t is not None:
            a = a[a["actor_id"].isin(t)]
        det = a[a["detected"]]
        rows.append({"scenario": sc, "variant": var, "scheme": scheme,
                     "target_snr_db": float(det["max_snr_db"].median()) if len(det)
                     else np.nan,
                     "target_pd": float(len(det) / len(a)) if len(a) else np.nan})
    snr = pd.DataFrame(rows, columns=["scenario", "variant", "scheme", "target_snr_db",
                                      "target_pd"])
    out = summ.merge(snr, on=["scenario", "variant", "scheme"], how="left")
    for c in COLUMNS:
        if c not in out:
            out[c] = np.nan
    order = {m: i for i, m in enumerate(dict.fromkeys(methods.values()))}
    out = out.assign(_o=out["method"].map(order)).sort_values(["scenario", "scheme", "_o"],
                                                               kind="stable")
    return out[COLUMNS].reset_index(drop=True)


def recovery_vs_inr(results: str | Path, bin_db: float = INR_BIN_DB) -> pd.DataFrame:
    """Recovered fraction of the floor rise versus the frame's in-burst INR, per method.

    Per frame of a mitigation sweep (``frames.parquet``: ``interference_to_noise_db``,
    ``noise_floor_rise_unmitigated_db``, ``noise_floor_rise_db``), the frames whose
    unmitigated rise is at least `MIN_RISE_TO_RECOVER_DB` binned by INR (`bin_db` wide bins,
    centred on multiples of `bin_db`).

    Returns
    -------
    DataFrame
        Columns scenario, method, scheme, inr_db (bin centre), n_frames,
        noise_floor_rise_unmitigated_db and noise_floor_rise_db (bin medians),
        recovery_fraction (1 - median mitigated / median unmitigated rise of the bin).

    Raises
    ------
    BadInput
        The results hold no variant that sets ``processing.interference.repair``.
    """
    results = Path(results)
    methods = _methods(results)
    cols = ["scenario", "method", "scheme", "inr_db", "n_frames",
            "noise_floor_rise_unmitigated_db", "noise_floor_rise_db", "recovery_fraction"]
    fr = pd.read_parquet(results / "frames.parquet")
    need = {"interference_to_noise_db", "noise_floor_rise_unmitigated_db", "noise_floor_rise_db"}
    if not need <= set(fr.columns):
        return pd.DataFrame(columns=cols)
    fr = fr[fr["variant"].isin(methods)
            & (fr["noise_floor_rise_unmitigated_db"] >= MIN_RISE_TO_RECOVER_DB)
            & fr["interference_to_noise_db"].notna()].copy()
    fr["method"] = fr["variant"].map(methods)
    fr["inr_db"] = np.round(fr["interference_to_noise_db"] / bin_db) * bin_db
    g = fr.groupby(["scenario", "method", "scheme", "inr_db"], sort=False)
    out = g.agg(n_frames=("noise_floor_rise_db", "size"),
                noise_floor_rise_unmitigated_db=("noise_floor_rise_unmitigated_db", "median"),
                noise_floor_rise_db=("noise_floor_rise_db", "median")).reset_index()
    out["recovery_fraction"] = 1 - out["noise_floor_rise_db"] / \
        out["noise_floor_rise_unmitigated_db"]
    order = {m: i for i, m in enumerate(dict.fromkeys(methods.values()))}
    out = out.assign(_o=out["method"].map(order)).sort_values(
        ["scenario", "scheme", "_o", "inr_db"], kind="stable")
    return out[cols].reset_index(drop=True)


def _recovery_figure(curve: pd.DataFrame) -> str:
    """One panel per (case, scheme): recovered fraction versus in-burst INR, a line per
    method."""
    plt = pyplot()
    keys = list(dict.fromkeys(zip(curve["scenario"], curve["scheme"])))
    fig, axes = plt.subplots(1, len(keys), figsize=(4.4 * len(keys), 3.6), sharey=True,
                             squeeze=False)
    for ax, (sc, scheme) in zip(axes[0], keys):
        c = curve[(curve["scenario"] == sc) & (curve["scheme"] == scheme)]
        for m, g in c.groupby("method", sort=False):
            ax.plot(g["inr_db"], g["recovery_fraction"], marker="o", ms=3, label=m)
        ax.axhline(2 / 3, color="0.6", lw=0.8, ls="--")
        ax.set_title(f"{sc}, {scheme}", fontsize=9)
        ax.set_xlabel("in-burst INR, dB")
    axes[0][0].set_ylabel("floor rise recovered (fraction)")
    axes[0][-1].legend(fontsize=7)
    return png_img(fig)


def html_section(results: str | Path) -> str:
    """HTML of the mitigation benchmark, or "" when no variant sets the method."""
    try:
        tab = mitigation_table(results)
    except (OSError, KeyError, ValueError):
        return ""
    body = tab.to_html(index=False, float_format=lambda x: f"{x:.3g}", border=0, na_rep="-",
                       classes="tbl")
    out = ("<h2>Interference mitigation: the methods compared</h2>"
           f"<p>{html.escape(__doc__.splitlines()[0])} Floor: median over frames after the "
           "Doppler FFT, dB over thermal; worst 1 s: the least recovered fraction of the "
           "case's 1-second windows; ghosts added: ghost rate minus the same frames' without "
           "mitigation.</p>" + body)
    curve = recovery_vs_inr(results)
    if len(curve):
        out += ("<h3>Recovered floor rise versus in-burst INR</h3><p>Per frame with an "
                f"unmitigated rise of at least {MIN_RISE_TO_RECOVER_DB:g} dB, binned by "
                f"in-burst INR ({INR_BIN_DB:g} dB bins, bin medians); dashed: two thirds."
                "</p>" + _recovery_figure(curve))
    return out
