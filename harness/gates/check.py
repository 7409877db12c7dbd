"""CI performance gates: thresholds on summary columns -> pass/fail, JUnit XML, Markdown.

A gates file is TOML with one ``[[gate]]`` table per rule::

    [[gate]]
    name = "ddma_snr_gain"              # unique, used in reports and JUnit
    metric = "snr_gain_median_db"       # a key of metrics.METRICS that may be gated
    min = 5.0                           # and/or max = ...
    scheme = "ddma"                     # optional filters (fnmatch patterns): scheme,
    scenario = "*"                      #   scenario, variant
    case_class = "*"                    # or one of scenarios.CASE_CLASSES (ordinary,
                                        #   interference, r79)
    aggregate = "each"                  # each (every matching row must pass) | mean |
                                        #   median | min | max (one value over the rows)
    allow_missing = false               # NaN values / no matching rows: skip instead of fail
    description = "DDMA promise: ..."

Every summary row that names an ``error`` (a sweep cell that raised) fails the built-in gate
``sweep_cells_ok``; so do cells the manifest lists as missing. Every scheme the run computed
must be addressed by at least one gate (built-in gate ``schemes_gated``): a regression of an
ungated scheme would go unseen. `verdict_table` condenses the evaluations into one pass/fail
per scheme and case with the deciding numbers.
"""
from __future__ import annotations

import fnmatch
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

import scenarios
from core.checks import build_from_table, check_keys, one_of, read_toml, require
from core.errors import BadInput
from core.fileio import MAX_TABLE_FILE_BYTES, check_input_file
from harness.sweep.provenance import read_manifest
from harness.sweep.store import failed_rows
from metrics.registry import METRICS, get_metric
from scenarios.catalog import CASE_CLASSES

__all__ = ["Gate", "GateResult", "load_gates", "evaluate_gates", "load_summary",
           "junit_xml", "markdown", "verdict_table", "DEFAULT_GATES_PATH", "AGGREGATES"]

DEFAULT_GATES_PATH = Path(__file__).with_name("gates.toml")
#: How the matching rows are reduced before the comparison.
AGGREGATES = {"each": None, "mean": np.nanmean, "median": np.nanmedian, "min": np.nanmin,
              "max": np.nanmax}
_ID = ["scenario", "variant", "seed", "scheme"]


@dataclass(frozen=True)
class Gate:
    """One threshold rule (see module docstring)."""

    name: str
    metric: str
    min: float | None = None
    max: float | None = None
    scheme: str = "*"
    scenario: str = "*"
    variant: str = "*"
    case_class: str = "*"
    aggregate: str = "each"
    allow_missing: bool = False
    description: str = ""

    def __post_init__(self) -> None:
        require(self, ("name", "metric", "scheme", "scenario", "variant", "case_class",
                       "description"), "str")
        require(self, "allow_missing", "bool")
        if not get_metric(self.metric).gate:
            raise BadInput(f"metric={self.metric!r} cannot be gated (per actor, not a "
                           "summary column): "
                           f"{get_metric(self.metric).description}")
        if self.case_class != "*":
            one_of("case_class", self.case_class, CASE_CLASSES)
        if self.min is None and self.max is None:
            raise BadInput(f"min/max: gate {self.name!r} needs min and/or max")
        require(self, ("min", "max"), none_ok=True)
        if self.min is not None and self.max is not None and self.min > self.max:
            raise BadInput(f"min/max: gate {self.name!r} has min={self.min!r} > "
                           f"max={self.max!r}: no value can pass")
        one_of("aggregate", self.aggregate, AGGREGATES)

    def check(self, value: float) -> bool:
        return (self.min is None or value >= self.min) and \
            (self.max is None or value <= self.max)

    @property
    def bound(self) -> str:
        parts = []
        if self.min is not None:
            parts.append(f">= {self.min:g}")
        if self.max is not None:
            parts.append(f"<= {self.max:g}")
        return " and ".join(parts)


@dataclass(frozen=True)
class GateResult:
    """Outcome of one gate on one row (aggregate "each") or on the aggregated rows."""

    gate: str
    metric: str
    where: str
    value: float
    bound: str
    status: str  # "pass" | "fail" | "skip"
    message: str = ""


def case_classes_of(summary: pd.DataFrame) -> pd.Series:
    """The ``case_class`` of every summary row: its column, or (tables written before it
    existed) the catalogue case's class; "ordinary" for a case not in the catalogue."""
    if "case_class" in summary and summary["case_class"].notna().all():
        return summary["case_class"].astype(str)
    known = {n: c.case_class for n, c in scenarios.SCENARIOS.items()}
    derived = summary["scenario"].map(lambda s: known.get(s, "ordinary"))
    if "case_class" in summary:
        return summary["case_class"].fillna(derived).astype(str)
    return derived.astype(str)


def load_gates(path: str | Path | None = None) -> list[Gate]:
    """Read a gates TOML (None: the shipped ``harness/gates/gates.toml``).

    Raises
    ------
    ValueError
        Malformed TOML, no ``[[gate]]``, unknown keys, duplicate names, bad bounds.
    FileNotFoundError
        The file does not exist.
    """
    p = Path(path) if path is not None else DEFAULT_GATES_PATH
    data = read_toml(p, "gates file")
    try:
        check_keys(data, {"gate"})
        raw = data.get("gate")
        if not isinstance(raw, list) or not raw:
            raise BadInput("no [[gate]] tables")
        gates = [build_from_table(Gate, g, f"gate[{i}].") for i, g in enumerate(raw)]
    except BadInput as exc:
        raise BadInput(f"{p}: {exc}") from None
    names = [g.name for g in gates]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise BadInput(f"{p}: duplicate gate name(s) {dup}")
    return gates


def load_summary(results: str | Path) -> tuple[pd.DataFrame, dict]:
    """summary table and manifest of a results directory (or a summary .parquet file).

    Raises
    ------
    FileNotFoundError
        No such directory / no summary.parquet in it.
    ValueError
        The file is not a readable summary table.
    """
    p = Path(results)
    f = p / "summary.parquet" if p.is_dir() else p
    if not f.exists():
        raise BadInput(f"no results summary at {f} (run `radar-harness sweep` first)")
    check_input_file(f, "summary table", max_bytes=MAX_TABLE_FILE_BYTES)
    try:
        summary = pd.read_parquet(f)
    except Exception as exc:  # noqa: BLE001 - pyarrow raises several types
        raise BadInput(f"{f}: not a readable Parquet summary table: {exc}") from exc
    missing = [c for c in ("scenario", "scheme") if c not in summary.columns]
    if missing:
        raise BadInput(f"{f}: summary lacks column(s) {missing}")
    return summary, read_manifest(f.parent)


def _where(row) -> str:
    return "/".join(str(row[c]) for c in _ID if c in row and str(row[c]) != "")


def evaluate_gates(summary: pd.DataFrame, gates: list[Gate],
                   manifest: dict | None = None) -> list[GateResult]:
    """Apply every gate to the summary table.

    Raises
    ------
    ValueError
        A gate names a metric that is not a summary column (bad input, not a failure).
    """
    unknown = sorted({g.metric for g in gates} - set(summary.columns))
    bad = [m for m in unknown if m not in METRICS]
    if bad:
        raise BadInput(f"unknown metric(s) {bad}; known: {', '.join(sorted(METRICS))}")
    summary = summary.assign(**{m: np.nan for m in unknown})  # defined, not in this run
    summary = summary.assign(case_class=case_classes_of(summary))
    for g in gates:
        col = summary[g.metric]
        if not (pd.api.types.is_numeric_dtype(col) or col.isna().all()):
            raise BadInput(f"gate {g.name!r}: metric {g.metric!r} is not numeric (dtype "
                           f"{col.dtype}); a threshold cannot apply to it")
    out: list[GateResult] = []
    failed = failed_rows(summary)
    bad = summary[failed]
    missing = [c["cell_id"] for c in (manifest or {}).get("cells", [])
               if c.get("status") not in ("ok", "error")]
    ok = bad.empty and not missing
    msg = "; ".join([f"{_where(r)}: {r['error']}" for _, r in bad.iterrows()] +
                    [f"{m}: not run" for m in missing])
    out.append(GateResult("sweep_cells_ok", "error", "all cells", float(len(bad) + len(missing)),
                          "== 0", "pass" if ok else "fail", msg))
    good = summary[~failed]
    schemes = [x for x in dict.fromkeys(good["scheme"]) if x] if "scheme" in good else []
    ungated = [x for x in schemes if not any(fnmatch.fnmatchcase(x, g.scheme) for g in gates)]
    out.append(GateResult("schemes_gated", "scheme", "all schemes", float(len(ungated)), "== 0",
                          "fail" if ungated else "pass",
                          f"no gate addresses scheme(s) {ungated}" if ungated else ""))
    for g in gates:
        sel = good
        for col in ("scheme", "scenario", "variant", "case_class"):
            pat = getattr(g, col)
            if col in sel.columns and pat != "*":
                sel = sel[[fnmatch.fnmatchcase(str(v), pat) for v in sel[col]]]
        if sel.empty:
            out.append(GateResult(g.name, g.metric, _pattern(g), float("nan"), g.bound,
                                  "skip" if g.allow_missing else "fail", "no matching rows"))
            continue
        vals = pd.to_numeric(sel[g.metric], errors="coerce").to_numpy(dtype=float)
        if g.aggregate == "each":
            for (_, row), v in zip(sel.iterrows(), vals):
                out.append(_judge(g, _where(row), v))
        else:
            finite = vals[np.isfinite(vals)]
            v = float(AGGREGATES[g.aggregate](finite)) if len(finite) else float("nan")
            out.append(_judge(g, f"{g.aggregate} over {len(finite)} rows ({_pattern(g)})", v))
    return out


def _pattern(g: Gate) -> str:
    cls = f" case_class={g.case_class}" if g.case_class != "*" else ""
    return f"scenario={g.scenario} scheme={g.scheme} variant={g.variant}{cls}"


def _judge(g: Gate, where: str, v: float) -> GateResult:
    if not np.isfinite(v):
        return GateResult(g.name, g.metric, where, v, g.bound,
                          "skip" if g.allow_missing else "fail", "value missing (NaN)")
    passed = g.check(v)
    return GateResult(g.name, g.metric, where, v, g.bound, "pass" if passed else "fail",
                      "" if passed else f"{g.metric}={v:.4g} violates {g.bound}")


def results_table(results: list[GateResult]) -> pd.DataFrame:
    return pd.DataFrame([r.__dict__ for r in results])


def junit_xml(results: list[GateResult]) -> str:
    """JUnit XML: one testsuite, one testcase per gate evaluation (failure / skipped)."""
    suite = ET.Element("testsuite", name="radar-harness gates", tests=str(len(results)),
                       failures=str(sum(r.status == "fail" for r in results)),
                       skipped=str(sum(r.status == "skip" for r in results)), errors="0")
    for r in results:
        case = ET.SubElement(suite, "testcase", classname=f"gates.{r.gate}",
                             name=f"{r.gate}[{r.where}]")
        text = f"{r.metric} = {r.value:.6g}, required {r.bound}. {r.message}".strip()
        if r.status == "fail":
            ET.SubElement(case, "failure", message=r.message or "gate failed",
                          type="GateFailure").text = text
        elif r.status == "skip":
            ET.SubElement(case, "skipped", message=r.message or "skipped")
        else:
            ET.SubElement(case, "system-out").text = text
    root = ET.Element("testsuites")
    root.append(suite)
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode")


def markdown(results: list[GateResult]) -> str:
    """Markdown summary: verdict line and a table of every evaluation (failures first)."""
    n_fail = sum(r.status == "fail" for r in results)
    n_pass = sum(r.status == "pass" for r in results)
    n_skip = sum(r.status == "skip" for r in results)
    head = f"## Radar gates: {'FAIL' if n_fail else 'PASS'}\n\n" \
        f"{n_pass} passed, {n_fail} failed, {n_skip} skipped.\n\n" \
        "| status | gate | where | metric | value | bound |\n|---|---|---|---|---|---|\n"
    order = {"fail": 0, "skip": 1, "pass": 2}
    rows = [f"| {r.status.upper()} | {r.gate} | {r.where} | {r.metric} | {r.value:.4g} | "
            f"{r.bound} |" for r in sorted(results, key=lambda r: order[r.status])]
    return head + "\n".join(rows) + "\n"


#: Metrics a passing verdict shows first (the case's own verdicts before accuracy budgets).
_DECIDING = ["r79_margin_m", "r79_pass", "case_pass", "mitigation_floor_recovery_fraction",
             "mitigation_ghost_rate_added", "ghost_rate", "velocity_unambiguity_rate_in_span",
             "velocity_unambiguity_rate"]


def verdict_table(results: list[GateResult]) -> pd.DataFrame:
    """One verdict per case (rows) and scheme (columns) from the per-row gate evaluations.

    A cell reads "pass" when every gate evaluated on that row passed (skips do not count),
    otherwise "FAIL" followed by the failing gates' metrics and values; a passing cell shows
    the values of its two most deciding gates (the case's own verdicts first: `_DECIDING`),
    so the table says both the verdict and the numbers behind it. Aggregated gates (over several
    rows)
    and the built-in ones are not per case and stay in the full table.
    """
    rows: dict[tuple[str, str], list[GateResult]] = {}
    for r in results:
        parts = r.where.split("/")
        if len(parts) != 4:
            continue
        scenario, variant, _seed, scheme = parts
        rows.setdefault((scenario if variant == "baseline" else f"{scenario}/{variant}",
                         scheme), []).append(r)
    cells: dict[str, dict[str, str]] = {}
    for (case, scheme), rs in rows.items():
        fails = [r for r in rs if r.status == "fail"]
        done = [r for r in rs if r.status == "pass"]
        if fails:
            text = "FAIL " + "; ".join(f"{r.metric}={r.value:.3g} ({r.bound})" for r in fails)
        elif done:
            first = sorted(done, key=lambda r: _DECIDING.index(r.metric)
                           if r.metric in _DECIDING else len(_DECIDING))[:2]
            text = "pass " + ", ".join(f"{r.metric}={r.value:.3g}" for r in first)
        else:
            text = "skip"
        cells.setdefault(case, {})[scheme] = text
    table = pd.DataFrame.from_dict(cells, orient="index")
    table.index.name = "case"
    return table.sort_index()
