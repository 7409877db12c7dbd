"""Interference-mitigation benchmark: every repair method on the interference cases.

`mitigation_table(results)` reads a results directory of a sweep whose variants set
``processing.intf_mitigation`` (``harness/sweeps/mitigation.toml``) and returns one row per
(case, method, scheme): the noise-floor rise without mitigation and with the method, the floor
it recovers (dB and fraction of the rise), the ghost rate with it and the ghosts it adds over
the same frames processed without mitigation (all summary columns, `metrics.interference`),
and the SNR of the case's target: the median over the frames in which it is detected of its
strongest TRUE detection's SNR (``actors.max_snr_db``; every road user of a traffic case).
`html_section(results)` renders it for the report.
"""
from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np
import pandas as pd

import scenarios
from core.errors import BadInput
from harness.sweep.store import failed_rows

__all__ = ["mitigation_table", "html_section", "COLUMNS"]

COLUMNS = ["scenario", "method", "scheme", "noise_floor_rise_unmitigated_db",
           "noise_floor_rise_db", "mitigation_floor_recovery_db",
           "mitigation_floor_recovery_fraction", "ghost_rate_unmitigated", "ghost_rate",
           "mitigation_ghost_rate_added", "target_snr_db", "target_pd"]


def _methods(results: Path) -> dict[str, str]:
    """Variant name -> its ``intf_mitigation`` (variants that set it)."""
    man = json.loads((results / "manifest.json").read_text())
    return {v["name"]: v["processing"]["intf_mitigation"]
            for v in man.get("sweep", {}).get("variants", [])
            if "intf_mitigation" in v.get("processing", {})}


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
        The results hold no variant that sets ``processing.intf_mitigation``.
    """
    results = Path(results)
    methods = _methods(results)
    if not methods:
        raise BadInput(f"{results}: no variant sets processing.intf_mitigation")
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


def html_section(results: str | Path) -> str:
    """HTML of the mitigation benchmark, or "" when no variant sets the method."""
    try:
        tab = mitigation_table(results)
    except (OSError, KeyError, ValueError):
        return ""
    body = tab.to_html(index=False, float_format=lambda x: f"{x:.3g}", border=0, na_rep="-",
                       classes="tbl")
    return ("<h2>Interference mitigation: the methods compared</h2>"
            f"<p>{html.escape(__doc__.splitlines()[0])} Floor: median over frames after the "
            "Doppler FFT, dB over thermal; ghosts added: ghost rate minus the same frames' "
            "without mitigation.</p>" + body)
