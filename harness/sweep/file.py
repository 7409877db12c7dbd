"""Reading and validating a sweep TOML file into a `harness.sweep.spec.SweepSpec`.

A variant may replace the R79 preset by a TI profile: ``"radar.profile" = ["my.cfg"]`` in
[vary] or ``profile = "my.cfg"`` in a [[variants]] radar table (a path relative to the sweep
file); its other radar keys then override the profile's fields, and each scheme runs the
profile's waveform (e.g. a DDMA profile's TDMA baseline). Radar-dependent association settings
(unambiguous-velocity window, field of view, maximum range) come from each cell's configs
(`harness.cell.config.cell_association`) unless [association] sets them.

Validation: the file and every variant's configs (both radar presets, the processing config of
every scheme, the tracker config; chip limits, RF budget, CFAR window against the Doppler axis)
are built before any worker starts; a bad value raises ValueError naming the file, the variant,
the key and the value.
"""
from __future__ import annotations

import itertools
import math
from pathlib import Path

from core.checks import check_keys, read_toml
from core.errors import BadInput
from harness.cell.components import default_components
from harness.cell.config import build_configs
from harness.cell.spec import (
    DEFAULT_BASELINE_SCHEME,
    DEFAULT_SCHEMES,
    CellSpec,
    check_scene,
    known_schemes,
)
from harness.plugins import load_plugins
from harness.sil.spec import external_chains_from_toml
from harness.sweep.spec import (
    DEFAULT_SWEEP_PATH,
    MAX_CELLS,
    SECTIONS,
    SweepSpec,
    Variant,
    resolve_scenarios,
)
from metrics.association import AssociationConfig
from metrics.registry import check_criterion
from scenarios.files import is_case_path

__all__ = ["load_sweep", "default_sweep", "validate_cells"]


_TOP_KEYS = {"name", "scenarios", "seeds", "frame_stride", "duration_s", "base", "vary",
             "variants", "description", "schemes", "baseline_scheme", "association",
             "plugins", "external_chains"}


def _check_section(where: str, section: str, overrides: dict) -> None:
    """Reject unknown config fields early (before any worker starts)."""
    if section not in SECTIONS:
        raise BadInput(f"{where}: unknown section {section!r}; use one of {list(SECTIONS)}")
    if not isinstance(overrides, dict):
        raise BadInput(f"{where}: [{section}] must be a table of field = value")
    if section == "radar" and overrides:
        from radarsim.radar_config import radar_paths
        bad = []
        for key, value in overrides.items():
            if key == "profile":
                continue
            try:
                radar_paths({key: value}, warn=False)
            except BadInput:
                bad.append(key)
        if bad:
            raise BadInput(f"{where}: unknown radar field(s) {sorted(bad)}")
        if "profile" in overrides:
            from harness.cell.ti_profile import load_profile
            prof = overrides["profile"]
            if not isinstance(prof, str) or not Path(prof).is_file():
                raise BadInput(f"{where}: radar.profile={prof!r} is not a TI .cfg file")
            try:
                load_profile(Path(prof))
            except BadInput as exc:
                raise BadInput(f"{where}: radar.profile={prof!r}: {exc}") from None
    if section == "processing" and overrides:
        import pipeline
        try:
            pipeline.ProcessingConfig().replace(**overrides)
        except (ValueError, TypeError) as exc:
            raise BadInput(f"{where}: processing {overrides!r}: {exc}") from None
    if section == "scene" and overrides:
        check_scene(overrides)


def _culprit(v: Variant, build) -> str:
    """Which override of a variant breaks its configs: the first that fails on its own, else
    the whole set. ``build(section, overrides)`` raises for bad overrides."""
    for sec in SECTIONS:
        for key, value in getattr(v, sec).items():
            try:
                build(sec, {key: value})
            except (ValueError, TypeError, KeyError) as exc:
                return f"{sec}.{key} = {value!r}: {exc}"
    for sec in SECTIONS:
        try:
            build(sec, dict(getattr(v, sec)))
        except (ValueError, TypeError, KeyError) as exc:
            return f"[{sec}] {getattr(v, sec)!r}: {exc}"
    return ""


def check_case_criteria(name: str, case, where: str = "") -> None:
    """Every criterion of `case` names a metric that can be a criterion (the metrics
    downstream define them).

    Raises
    ------
    core.errors.BadInput
        ``{where}case {name}: criteria[i].metric: ...`` naming the metric and the known ones.
    """
    for i, c in enumerate(getattr(case, "criteria", ()) or ()):
        try:
            check_criterion(c.metric, c.actor_id)
        except BadInput as exc:
            raise BadInput(f"{where}case {name}: criteria[{i}].metric: {exc}") from None


def validate_cells(spec: SweepSpec, source: str | Path | None = None) -> None:
    """Build every variant's configs (both radar presets, the processing configs of every
    scheme, the tracker config) and check every case's criteria against `metrics.METRICS`
    before any worker starts.

    Raises
    ------
    ValueError
        Naming the sweep file, the variant, the key, the value and the config's own message
        (which names the limit); or the case and its criterion's metric (unknown, with the
        known ones, or one that cannot be a criterion).
    """
    import scenarios
    from pipeline.mimo import chain_of
    from pipeline.tracking import TrackerConfig, tracker_paths
    comps = default_components()
    where = f"{source}: " if source is not None else ""
    for name in spec.scenarios:
        case = scenarios.get_case(name) if is_case_path(name) else \
            scenarios.SCENARIOS.get(name)
        check_case_criteria(name, case, where)

    def check(cell: CellSpec) -> None:
        radar, procs = build_configs(cell, comps)
        for proc in procs.values():  # CFAR window and EGE blocks must fit every radar
            for r in radar.values():
                proc.check_radar(r)
                if proc.doppler.clutter_removal and not chain_of(r).removes_static_clutter:
                    raise BadInput(f"clutter_removal=True (a profile's clutterRemoval): the "
                                   f"{r.mimo} chain has no static clutter removal")

    schemes = {"schemes": spec.schemes, "baseline_scheme": spec.baseline_scheme,
               "external_chains": spec.external_chains}

    def build(section: str, overrides: dict) -> None:
        if section == "tracker":
            TrackerConfig().replace(**tracker_paths(overrides, warn=False))
        else:
            check(CellSpec(scenario=spec.scenarios[0], **{section: overrides}, **schemes))

    for v in spec.variants:
        try:
            check(CellSpec(scenario=spec.scenarios[0], seed=spec.seeds[0], variant=v.name,
                           radar=dict(v.radar), processing=dict(v.processing),
                           tracker=dict(v.tracker), scene=dict(v.scene), **schemes))
            TrackerConfig().replace(**v.tracker)  # a flat key warns, naming the new key
        except (ValueError, TypeError, KeyError) as exc:
            why = _culprit(v, build) or f"{type(exc).__name__}: {exc}"
            raise BadInput(f"{where}variant {v.name!r}: {why}") from None


def _fmt(v) -> str:
    return "-".join(map(str, v)) if isinstance(v, (list, tuple)) else str(v)


def _resolve_profiles(p: Path, data: dict) -> None:
    """``radar.profile`` paths relative to the sweep file become absolute (in place)."""
    def fix(v):
        return str((p.parent / v).resolve()) if isinstance(v, str) and \
            not Path(v).is_absolute() else v
    radar = data.get("base", {}).get("radar")
    if isinstance(radar, dict) and "profile" in radar:
        radar["profile"] = fix(radar["profile"])
    vary = data.get("vary", {})
    if isinstance(vary, dict) and isinstance(vary.get("radar.profile"), list):
        vary["radar.profile"] = [fix(v) for v in vary["radar.profile"]]
    for extra in data.get("variants", []) or []:
        if isinstance(extra, dict) and isinstance(extra.get("radar"), dict) and \
                "profile" in extra["radar"]:
            extra["radar"]["profile"] = fix(extra["radar"]["profile"])


def load_sweep(path: str | Path | None = None, *, check_scenarios: bool = True) -> SweepSpec:
    """Read a sweep TOML (None: the shipped default sweep).

    ``check_scenarios`` validates case names against ``scenarios.SCENARIOS``.

    Raises
    ------
    ValueError
        Malformed TOML, unknown keys or config fields, bad values; FileNotFoundError if the
        file does not exist.
    """
    p = Path(path) if path is not None else DEFAULT_SWEEP_PATH
    if p.is_dir():
        raise BadInput(f"sweep file {str(p)!r} is a directory, not a TOML file")
    data = read_toml(p, "sweep file")
    try:
        check_keys(data, _TOP_KEYS)
    except BadInput as exc:
        raise BadInput(f"{p}: {exc}") from None
    plugins = _plugins_key(p, data.get("plugins", []))  # before any name is looked up
    external = external_chains_from_toml(str(p), data.get("external_chains", []), p.parent)
    for key, kind, what in (("base", dict, "a table [base.<section>]"),
                            ("vary", dict, 'a table of "section.field" = [values]'),
                            ("variants", list, "an array of [[variants]] tables"),
                            ("name", str, "a string"), ("description", str, "a string")):
        if key in data and not isinstance(data[key], kind):
            raise BadInput(f"{p}: {key} = {data[key]!r} must be {what}")
    base = data.get("base", {})
    _resolve_profiles(p, data)
    for sec, ov in base.items():
        _check_section(f"{p} [base]", sec, ov)
    variants: list[Variant] = []
    vary = data.get("vary", {})
    if not isinstance(vary, dict):
        raise BadInput(f"{p}: [vary] must be a table of \"section.field\" = [values]")
    keys = list(vary)
    for k in keys:
        if "." not in k or not isinstance(vary[k], list) or not vary[k]:
            raise BadInput(f"{p}: vary key {k!r} must look like \"radar.field\" and map to "
                           "a non-empty list")
    # The product is bounded from the value counts, before any variant is built (a 10^12
    # product would otherwise allocate until MemoryError).
    counts = [len(vary[k]) for k in keys]
    if math.prod(counts) > MAX_CELLS:
        raise BadInput(f"{p}: [vary] gives {math.prod(counts)} variants "
                       f"({' x '.join(f'{n} {k}' for n, k in zip(counts, keys))}), more than "
                       f"the limit {MAX_CELLS} cells of a sweep")
    combos = list(itertools.product(*(vary[k] for k in keys))) if keys else [()]
    for combo in combos:
        ov = {s: dict(base.get(s, {})) for s in SECTIONS}
        parts = []
        for k, v in zip(keys, combo):
            sec, fld = k.split(".", 1)
            _check_section(f"{p} [vary]", sec, {fld: v})
            ov[sec][fld] = v
            parts.append(f"{fld}={_fmt(v)}")
        variants.append(Variant(name=",".join(parts) or "baseline", **ov))
    for i, extra in enumerate(data.get("variants", [])):
        try:
            check_keys(extra, {"name", *SECTIONS}, f"variants[{i}].")
            if "name" not in extra:
                raise BadInput(f"variants[{i}].name: required key missing")
        except BadInput as exc:
            raise BadInput(f"{p}: {exc}") from None
        for s in SECTIONS:
            if not isinstance(extra.get(s, {}), dict):
                raise BadInput(f"{p}: [[variants]] {extra['name']!r}: {s} = {extra[s]!r} must "
                               "be a table of field = value")
        ov = {s: {**base.get(s, {}), **extra.get(s, {})} for s in SECTIONS}
        for s in SECTIONS:
            _check_section(f"{p} [[variants]] {extra['name']}", s, ov[s])
        variants.append(Variant(name=str(extra["name"]), **ov))
    if data.get("variants") and not keys:
        variants = variants[1:]  # explicit variants replace the implicit baseline
    seeds = data.get("seeds", [0])
    try:
        spec = SweepSpec(name=data.get("name", p.stem),
                         scenarios=tuple(resolve_scenarios(data.get("scenarios", "all"),
                                                            check_scenarios, p.parent)),
                         seeds=tuple(seeds) if isinstance(seeds, list) else (seeds,),
                         variants=tuple(variants), frame_stride=data.get("frame_stride", 1),
                         duration_s=data.get("duration_s"),
                         description=data.get("description", ""),
                         schemes=_with_external(
                             _schemes_key(p, data.get("schemes", list(DEFAULT_SCHEMES))),
                             external),
                         baseline_scheme=data.get("baseline_scheme", DEFAULT_BASELINE_SCHEME),
                         association=_association_key(p, data.get("association", {})),
                         plugins=plugins, external_chains=external)
    except BadInput as exc:
        msg = str(exc)
        raise BadInput(msg if msg.startswith(f"{p}:") else f"{p}: {msg}") from None
    if "baseline_scheme" in data and spec.baseline_scheme not in spec.schemes:
        raise BadInput(f"{p}: baseline_scheme={spec.baseline_scheme!r} is not among the "
                       f"schemes run {list(spec.schemes)}: the SNR gain of every scheme "
                       "would be NaN; add it to schemes or pick one of them")
    validate_cells(spec, p)
    return spec


def _plugins_key(p: Path, value) -> tuple[str, ...]:
    """Load the sweep file's ``plugins`` (``.py`` paths relative to the file)."""
    if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
        raise BadInput(f"{p}: plugins={value!r} must be a list of module names or .py paths")
    try:
        load_plugins(value, how="sweep file", base_dir=p.parent)
    except BadInput as exc:
        raise BadInput(f"{p}: {exc}") from None
    return tuple(value)


def _with_external(schemes: tuple[str, ...], external) -> tuple[str, ...]:
    """The schemes run: the file's, then every external chain it does not list."""
    return tuple(schemes) + tuple(c.name for c in external if c.name not in schemes)


def _association_key(p: Path, value) -> dict:
    if not isinstance(value, dict):
        raise BadInput(f"{p}: [association] must be a table of AssociationConfig fields")
    try:
        AssociationConfig(**value)
    except TypeError as exc:
        raise BadInput(f"{p}: [association]: {exc}") from None
    return dict(value)


def _schemes_key(p: Path, value) -> tuple[str, ...]:
    if value == "all":  # every registered scheme and chain variant (harness.cell.spec)
        return tuple(known_schemes())
    if not isinstance(value, list):
        raise BadInput(f"{p}: schemes={value!r} must be a list of scheme names")
    return tuple(value)


def default_sweep() -> SweepSpec:
    """The shipped default: the whole catalogue, both schemes, one seed."""
    return load_sweep(DEFAULT_SWEEP_PATH)
