"""What one sweep cell runs: `CellSpec`, its result schemes and its scene overrides.

A cell is scenario x radar/processing/tracker overrides x seed. Its result schemes are the
values of the tables' ``scheme`` column: a registered MIMO scheme (``radarsim.MIMO_SCHEMES``)
or a variant its receive chain declares in ``pipeline.MIMO_CHAINS`` (e.g. ``tdma_raw`` = TDMA
without velocity disambiguation on the same TDMA ADC frame).
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from core.errors import BadInput
from harness.sil.spec import ExternalChain

__all__ = ["CellSpec", "ResultScheme", "DEFAULT_SCHEMES", "DEFAULT_BASELINE_SCHEME", "TABLES",
           "SCENE_FIELDS", "check_scene", "result_schemes", "known_schemes", "mimos"]


#: Result schemes of a cell when none are given (the scheme column's values).
DEFAULT_SCHEMES: tuple[str, ...] = ("ddma", "tdma", "tdma_raw")
#: Scheme the SNR gain is taken over.
DEFAULT_BASELINE_SCHEME = "tdma"
#: Tables a cell returns (all pandas DataFrames, written as Parquet).
TABLES = ("summary", "detections", "frames", "actors", "actor_summary", "truth", "tracks")
#: Scene overrides a sweep may give (``[vary] "scene.equipped_share" = [...]``).
SCENE_FIELDS = {"equipped_share": "share of vehicles carrying a radar (interferers), [0, 1]"}


def check_scene(scene) -> None:
    """Validate scene overrides: known keys (`SCENE_FIELDS`), equipped_share in [0, 1]."""
    if not isinstance(scene, dict):
        raise BadInput(f"scene must be a table of field = value, got {scene!r}")
    bad = sorted(set(scene) - set(SCENE_FIELDS))
    if bad:
        raise BadInput(f"unknown scene field(s) {bad}; known: {sorted(SCENE_FIELDS)}")
    share = scene.get("equipped_share", 0.0)
    if isinstance(share, bool) or not isinstance(share, (int, float)) or not 0 <= share <= 1:
        raise BadInput(f"scene.equipped_share={share!r} must be in [0, 1]")


@dataclass(frozen=True)
class ResultScheme:
    """One value of the tables' ``scheme`` column.

    Attributes
    ----------
    name : str
        The column value.
    mimo : str
        The `radarsim.MIMO_SCHEMES` name whose ADC frame it processes.
    processing : dict
        `ProcessingConfig` overrides of a chain variant (empty for the scheme itself).
    external : harness.sil.ExternalChain or None
        The external (software-in-the-loop) chain that processes `mimo`'s ADC frames.
    """

    name: str
    mimo: str
    processing: dict = field(default_factory=dict)
    external: Any = None

    @property
    def is_variant(self) -> bool:
        """A chain variant: the scheme's own chain with other settings on its ADC frame."""
        return self.name != self.mimo and self.external is None


def _scheme_table() -> dict[str, ResultScheme]:
    import pipeline
    import radarsim
    out = {}
    for m in radarsim.MIMO_SCHEMES:
        out[m] = ResultScheme(m, m)
        chain = pipeline.MIMO_CHAINS.get(m)
        for v, overrides in (getattr(chain, "variants", None) or {}).items():
            out[v] = ResultScheme(v, m, dict(overrides))
    return out


def known_schemes() -> list[str]:
    """Names `CellSpec.schemes` accepts: every registered MIMO scheme and its chain's
    variants."""
    return list(_scheme_table())


def _external_table(external) -> dict[str, ResultScheme]:
    """Result schemes of external chains (`harness.sil.ExternalChain`), checked against the
    registries: a name no registered scheme has, a registered transmit scheme."""
    import radarsim
    table = _scheme_table()
    out = {}
    for chain in external or ():
        if chain.name in table:
            raise BadInput(f"external_chains name={chain.name!r} is already a registered "
                           "scheme or chain variant: pick another name")
        if chain.scheme not in radarsim.MIMO_SCHEMES:
            raise BadInput(f"external_chains {chain.name!r}: "
                           f"{radarsim.MIMO_SCHEMES.missing_message(chain.scheme)}")
        out[chain.name] = ResultScheme(chain.name, chain.scheme, {}, chain)
    return out


def result_schemes(names=DEFAULT_SCHEMES, external=()) -> list[ResultScheme]:
    """Resolve result-scheme names against the registries and the external chains.

    Raises
    ------
    ValueError
        Empty list, duplicates or unknown names (naming them and the known ones).
    """
    if isinstance(names, str) or not all(isinstance(n, str) for n in names):
        raise BadInput(f"schemes={names!r} must be a list of scheme names")
    names = list(names)
    if not names:
        raise BadInput("schemes: the list is empty")
    if len(set(names)) != len(names):
        raise BadInput(f"schemes={names!r} holds duplicates")
    table = {**_scheme_table(), **_external_table(external)}
    bad = [n for n in names if n not in table]
    if bad:
        raise BadInput(f"schemes: unknown scheme(s) {bad}; known: {list(table)}")
    return [table[n] for n in names]


def mimos(schemes: list[ResultScheme]) -> list[str]:
    """The MIMO schemes whose ADC frames the result schemes need, in first-use order."""
    return list(dict.fromkeys(s.mimo for s in schemes))


@dataclass(frozen=True, kw_only=True)
class CellSpec:
    """What one sweep cell runs.

    Parameters
    ----------
    scenario : str
        Catalogue name (``scenarios.SCENARIOS``) or the absolute path of a case file (.toml,
        .xosc).
    seed : int
        Scenario and noise seed (>= 0).
    variant : str
        Name of the config variant (the sweep's label for ``radar``/``processing``/...).
    radar : dict
        `RadarConfig` field overrides applied to both presets (e.g. phase_noise_deg_rms).
    processing : dict
        `ProcessingConfig` overrides; keys ``cfar_<field>`` change the CFAR.
    tracker : dict
        Tracker config overrides (if the tracker exists).
    frame_stride : int
        Process every k-th frame (>= 1).
    duration_s : float or None
        Scenario duration override, s (None: the case's own).
    schemes : tuple of str
        Result schemes, in table order: `radarsim.MIMO_SCHEMES` names or variants their
        chains declare (`known_schemes`).
    baseline_scheme : str
        Scheme the SNR gain is taken over (the gain columns of its own row are NaN, as are
        those of every scheme when it is not run).
    scene : dict
        Scene overrides (`SCENE_FIELDS`): ``equipped_share`` replaces the case's share of
        vehicles carrying radars (interference).
    association : dict
        `metrics.association.AssociationConfig` overrides (the sweep's ``[association]``);
        the radar-dependent settings otherwise come from the cell's configs
        (`cell_association`).
    external_chains : tuple of harness.sil.ExternalChain (or their tables)
        Software-in-the-loop chains whose names `schemes` may hold.

    ``radar`` may hold ``profile``: a TI .cfg path whose `RadarConfig` replaces the R79
    preset (the other radar keys then override the profile's fields).
    """

    scenario: str
    seed: int = 0
    variant: str = "baseline"
    radar: dict = field(default_factory=dict)
    processing: dict = field(default_factory=dict)
    tracker: dict = field(default_factory=dict)
    frame_stride: int = 1
    duration_s: float | None = None
    schemes: tuple[str, ...] = DEFAULT_SCHEMES
    baseline_scheme: str = DEFAULT_BASELINE_SCHEME
    scene: dict = field(default_factory=dict)
    association: dict = field(default_factory=dict)
    external_chains: tuple = ()

    def __post_init__(self) -> None:
        if not isinstance(self.scenario, str) or not self.scenario:
            raise BadInput(f"scenario={self.scenario!r} must be a non-empty name")
        check_scene(self.scene)
        object.__setattr__(self, "schemes", tuple(self.schemes))
        # A spec read back from cell.json / the manifest holds its chains as tables.
        object.__setattr__(self, "external_chains", tuple(
            c if isinstance(c, ExternalChain) else ExternalChain(**c)
            for c in self.external_chains))
        result_schemes(self.schemes, self.external_chains)
        known = known_schemes() + [c.name for c in self.external_chains]
        if not isinstance(self.baseline_scheme, str) or self.baseline_scheme not in known:
            raise BadInput(f"baseline_scheme={self.baseline_scheme!r} is not one of {known}")
        if not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise BadInput(f"seed={self.seed!r} must be an integer >= 0")
        if not isinstance(self.frame_stride, (int, np.integer)) or self.frame_stride < 1:
            raise BadInput(f"frame_stride={self.frame_stride!r} must be an integer >= 1")
        if self.duration_s is not None and not self.duration_s > 0:
            raise BadInput(f"duration_s={self.duration_s!r} must be > 0")

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @property
    def cell_id(self) -> str:
        """File-system safe, unique id: scenario, variant, seed and a hash of the overrides.

        The scheme fields enter the hash only when they differ from the defaults, so cells
        written before they existed keep their ids."""
        d = self.to_dict()
        if tuple(d["schemes"]) == DEFAULT_SCHEMES:
            del d["schemes"]
        if d["baseline_scheme"] == DEFAULT_BASELINE_SCHEME:
            del d["baseline_scheme"]
        if not d["scene"]:
            del d["scene"]
        if not d["association"]:
            del d["association"]
        if not d["external_chains"]:
            del d["external_chains"]
        blob = json.dumps(d, sort_keys=True, default=str)
        h = hashlib.sha1(blob.encode()).hexdigest()[:8]
        # a case file is named by its stem here (the hash holds its whole path)
        label = self.scenario.rsplit("/", 1)[-1] if "/" in self.scenario else self.scenario
        safe = re.sub(r"[^A-Za-z0-9_.=-]+", "-", f"{label}__{self.variant}")
        return f"{safe}__s{self.seed}__{h}"
