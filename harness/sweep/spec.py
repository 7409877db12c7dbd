"""A sweep as a value: `SweepSpec` (scenarios x config variants x seeds) and its bounds.

A sweep is usually read from a TOML file (`harness.sweep.file.load_sweep`)::

    name = "phase-noise"
    scenarios = ["r79_motorcycle_rear", "blind_spot_overtake"]   # or "all"
    seeds = [0, 1, 2]
    frame_stride = 2              # process every 2nd frame (default 1)
    duration_s = 6.0              # optional: shorten every case
    schemes = ["ddma", "tdma", "bpm"]  # optional: radarsim.MIMO_SCHEMES names (or chain
                                  # variants such as "tdma_raw"); default ddma, tdma, tdma_raw
    baseline_scheme = "tdma"      # optional: the SNR gain is each scheme minus this one
    [base.radar.impairments]      # RadarConfig overrides for every cell (both schemes), by
    tx_phase_error_deg = [0.0, 3.0, -2.0, 1.0]  # part (waveform, array, schedule, shifter,
                                  # impairments, budget); flat names warn (one release)
    [base.processing]             # ProcessingConfig overrides; cfar_<field> for the CFAR
    cfar_threshold_db = 14.0
    [vary]                        # cartesian product -> one variant per combination
    "radar.impairments.phase_noise_deg_rms" = [0.0, 2.0, 10.0]
    "processing.cfar_mode" = ["os", "ca"]
    [association]                 # optional AssociationConfig overrides (e.g. fov_deg = 60.0)
    plugins = ["my_radar.plugin", "chain.py"]  # optional: plugins to load (harness.plugins)
    [[external_chains]]           # optional: software-in-the-loop chains (harness.sil.spec)

Durations, seeds, strides and the cell count are bounded; the sweep ``name`` is a single folder
name, so ``results/<run-id>`` never leaves the results folder.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from core.errors import BadInput
from harness.cell.spec import DEFAULT_BASELINE_SCHEME, DEFAULT_SCHEMES, CellSpec, result_schemes
from harness.cli.args import MAX_DURATION_S, MAX_SEED
from metrics.association import AssociationConfig
from scenarios.files import is_case_path

__all__ = ["Variant", "SweepSpec", "resolve_scenarios", "SECTIONS", "DEFAULT_SWEEP_PATH",
           "CI_SWEEP_PATH", "SCHEMES_SWEEP_PATH", "MAX_DURATION_S", "MAX_CELLS",
           "MAX_FRAME_STRIDE", "MAX_SEED"]


#: The shipped sweep files (``harness/sweeps/``).
SWEEPS_DIR = Path(__file__).parents[1] / "sweeps"
DEFAULT_SWEEP_PATH = SWEEPS_DIR / "default.toml"
CI_SWEEP_PATH = SWEEPS_DIR / "ci.toml"
SCHEMES_SWEEP_PATH = SWEEPS_DIR / "schemes.toml"
SECTIONS = ("radar", "processing", "tracker", "scene")
#: Most cells in one sweep (scenarios x variants x seeds): beyond it a typo in [vary] is likelier
#: than a plan (10 000 R79 cells are days of CPU).
MAX_CELLS = 10_000
#: Largest frame stride (a stride beyond the frame count keeps only frame 0).
MAX_FRAME_STRIDE = 10_000
#: A sweep name becomes a folder under results/: letters, digits, "_", "-", "." (not first).
_NAME_RE = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,99}")


@dataclass(frozen=True)
class Variant:
    """A named set of config overrides (one column of the sweep)."""

    name: str = "baseline"
    radar: dict = field(default_factory=dict)
    processing: dict = field(default_factory=dict)
    tracker: dict = field(default_factory=dict)
    scene: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SweepSpec:
    """A suite: scenarios x variants x seeds, with frame stride and optional duration.

    Raises
    ------
    ValueError
        Empty scenario or seed list, negative seed, stride < 1, duplicate variant names.
    """

    name: str
    scenarios: tuple[str, ...]
    seeds: tuple[int, ...] = (0,)
    variants: tuple[Variant, ...] = (Variant(),)
    frame_stride: int = 1
    duration_s: float | None = None
    description: str = ""
    schemes: tuple[str, ...] = DEFAULT_SCHEMES
    baseline_scheme: str = DEFAULT_BASELINE_SCHEME
    association: dict = field(default_factory=dict)
    plugins: tuple[str, ...] = ()
    external_chains: tuple = ()

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _NAME_RE.fullmatch(self.name):
            raise BadInput(f"name={self.name!r} must be 1-100 letters, digits, '_', '-' or "
                           "'.' (not first): it names a folder under the results directory")
        object.__setattr__(self, "schemes", tuple(self.schemes))
        object.__setattr__(self, "plugins", tuple(self.plugins))
        object.__setattr__(self, "external_chains", tuple(self.external_chains))
        AssociationConfig(**self.association)  # unknown keys / bad values fail here
        result_schemes(self.schemes, self.external_chains)
        # CellSpec checks the baseline name; check it here too, before any cell is built.
        CellSpec(scenario="-", schemes=self.schemes, baseline_scheme=self.baseline_scheme,
                 external_chains=self.external_chains)
        if not self.scenarios:
            raise BadInput("scenarios: the sweep has no scenario")
        dup = sorted({sc for sc in self.scenarios if list(self.scenarios).count(sc) > 1})
        if dup:
            raise BadInput(f"scenarios: duplicate case(s) {dup}")
        if not self.seeds or any(isinstance(s, bool) or not isinstance(s, int)
                                 or not 0 <= s <= MAX_SEED for s in self.seeds):
            raise BadInput(f"seeds={list(self.seeds)!r} must be a non-empty list of "
                           f"integers in 0..{MAX_SEED}")
        if len(set(self.seeds)) != len(self.seeds):
            raise BadInput(f"seeds={list(self.seeds)!r}: duplicate seed")
        if isinstance(self.frame_stride, bool) or not isinstance(self.frame_stride, int) or \
                not 1 <= self.frame_stride <= MAX_FRAME_STRIDE:
            raise BadInput(f"frame_stride={self.frame_stride!r} must be an integer in "
                           f"1..{MAX_FRAME_STRIDE}")
        if self.duration_s is not None and (
                isinstance(self.duration_s, bool)
                or not isinstance(self.duration_s, (int, float))
                or not 0 < self.duration_s <= MAX_DURATION_S):
            raise BadInput(f"duration_s={self.duration_s!r} must be a number in "
                           f"(0, {MAX_DURATION_S:g}] s")
        names = [v.name for v in self.variants]
        if len(set(names)) != len(names):
            raise BadInput(f"variants: duplicate names {names}")
        n = len(self.scenarios) * len(self.variants) * len(self.seeds)
        if n > MAX_CELLS:
            raise BadInput(f"the sweep has {n} cells ({len(self.scenarios)} scenarios x "
                           f"{len(self.variants)} variants x {len(self.seeds)} seeds), more "
                           f"than the limit {MAX_CELLS}")

    def cells(self) -> list[CellSpec]:
        """Cells in a fixed order: scenario, then variant, then seed."""
        return [CellSpec(scenario=sc, seed=seed, variant=v.name, radar=dict(v.radar),
                         processing=dict(v.processing), tracker=dict(v.tracker),
                         scene=dict(v.scene),
                         frame_stride=self.frame_stride, duration_s=self.duration_s,
                         schemes=self.schemes, baseline_scheme=self.baseline_scheme,
                         association=dict(self.association),
                         external_chains=self.external_chains)
                for sc in self.scenarios for v in self.variants for seed in self.seeds]

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @property
    def run_id(self) -> str:
        """Deterministic id, so rerunning the same command resumes the same directory (the
        scheme keys enter it only when they differ from the defaults)."""
        d = self.to_dict()
        if tuple(d["schemes"]) == DEFAULT_SCHEMES:
            del d["schemes"]
        if d["baseline_scheme"] == DEFAULT_BASELINE_SCHEME:
            del d["baseline_scheme"]
        for v in d["variants"]:  # the scene section enters the id only when used
            if not v.get("scene"):
                v.pop("scene", None)
        if not d["association"]:
            del d["association"]
        for key in ("plugins", "external_chains"):  # enter the id only when used
            if not d[key]:
                del d[key]
        blob = json.dumps(d, sort_keys=True, default=str)
        return f"{self.name}-{hashlib.sha1(blob.encode()).hexdigest()[:8]}"

    def with_overrides(self, *, seeds=None, frame_stride=None, duration_s=None,
                       scenarios=None, schemes=None) -> "SweepSpec":
        """Copy with command-line overrides (None keeps the file's value)."""
        ch: dict[str, Any] = {}
        if schemes is not None:
            ch["schemes"] = tuple(schemes)
        if seeds is not None:
            ch["seeds"] = tuple(seeds)
        if frame_stride is not None:
            ch["frame_stride"] = frame_stride
        if duration_s is not None:
            ch["duration_s"] = duration_s
        if scenarios is not None:
            ch["scenarios"] = tuple(resolve_scenarios(list(scenarios)))
        return dataclasses.replace(self, **ch) if ch else self


def _catalogue() -> list[str]:
    import scenarios
    return list(scenarios.SCENARIOS)


def resolve_scenarios(value, check: bool = True, base_dir: str | Path | None = None
                      ) -> list[str]:
    """Case references of a sweep: ``"all"`` (the catalogue) or a list of catalogue names and
    case files (.toml / .xosc; relative paths are relative to `base_dir`, default the current
    folder, and become absolute). With `check`, every name must be in the catalogue and every
    file must load (`scenarios.get_case`), before any work starts.

    Raises
    ------
    ValueError
        Naming the unknown cases (with the known ones), or the file and its error.
    """
    if value == "all" or value == ["all"]:
        return _catalogue()
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise BadInput(f"scenarios={value!r} must be \"all\" or a list of case names or "
                         "case files")
    import scenarios
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    out = [str((base / v).resolve()) if is_case_path(v) else v for v in value]
    if check:
        known = set(_catalogue())
        bad = [v for v in out if not is_case_path(v) and v not in known]
        if bad:
            raise BadInput(f"scenarios: unknown case(s) {bad}; known: {sorted(known)} "
                             "(or a case file: .toml, .xosc)")
        for v in out:
            if is_case_path(v):
                try:
                    scenarios.get_case(v)
                except (BadInput, OSError) as exc:
                    raise BadInput(f"scenarios: case file {v}: {exc}") from None
    return out
