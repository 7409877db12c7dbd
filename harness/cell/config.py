"""The configs of one cell: a `RadarConfig` per MIMO scheme, a `ProcessingConfig` per result
scheme, and the association settings that follow from the radar configs.
"""
from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from core.errors import BadInput
from harness.cell.components import Components
from harness.cell.spec import CellSpec, mimos, result_schemes
from harness.cell.ti_profile import load_profile, profile_processing, simulation_radar
from metrics.association import AssociationConfig

__all__ = ["radar_config", "cell_association", "build_configs"]


def radar_config(overrides: dict, mimo: str):
    """`RadarConfig` of a cell for one MIMO scheme: the R79 preset with `overrides`, or, when
    they name a ``profile`` (TI .cfg path), that profile's radar run with `mimo` and the other
    overrides. A calibration request (``shifter_calibration_deg = {seed = 0, ...}``) is
    resolved here, on the built config (`radarsim.calibration.resolve_calibration`): a config
    is a value and never measures.

    Raises
    ------
    ValueError
        If the profile's chip cannot run `mimo` (e.g. DDMA on a chip without phase shifters),
        naming the profile and the scheme.
    """
    import radarsim
    from radarsim.calibration import resolve_calibration
    from radarsim.radar_config import radar_paths
    ov = dict(overrides)
    path = ov.pop("profile", None)
    ov = radar_paths(ov)  # dotted keys; a flat key of the previous release warns
    cal = "shifter.shifter_calibration_deg"
    request = ov.pop(cal) if isinstance(ov.get(cal), Mapping) else None
    if path is None:
        return resolve_calibration(radarsim.presets.r79(mimo, **ov), request)
    prof = load_profile(Path(path))
    if prof.is_advanced and not prof.is_joined:  # a fast/slow pair is one radar
        raise BadInput(f"radar.profile={str(path)!r}: an advanced-frame profile has one radar "
                       f"per sub-frame ({len(prof.subframes)}), a sweep cell runs one; use "
                       "`radar-harness process` for it, or a profile of one sub-frame")
    base = simulation_radar(prof)  # on the board its compRangeBiasAndRxChanPhase calibrates
    try:
        cfg = base.replace(**{"schedule.mimo": mimo, **ov}) if base.mimo != mimo or ov else base
    except BadInput as exc:
        raise BadInput(f"radar.profile={str(path)!r} ({base.chip}, {base.mimo}) as scheme "
                       f"{mimo!r}: {exc}") from exc
    return resolve_calibration(cfg, request)


def cell_association(radar: dict, overrides: dict | None = None) -> AssociationConfig:
    """Association settings of a cell from its radar configs, then `overrides`.

    The radar-dependent ones follow the configs, not the R79 numbers: the unambiguous-velocity
    window is the widest the cell's schemes report (max of `max_unambiguous_velocity_mps`,
    DDMA's lambda / (4 Tc)), the field of view is the board's (`radarsim.boards.Board.fov_deg`)
    and the maximum range the configs' `max_range_m` (N/2 or N bins x resolution).
    """
    from radarsim.boards import get_board
    cfgs = list(radar.values())
    kw = {"unambiguity_window_mps": max(c.max_unambiguous_velocity_mps for c in cfgs),
          "fov_deg": min(get_board(c.board).fov_deg for c in cfgs),
          "max_range_m": min(c.max_range_m for c in cfgs)}
    kw.update(overrides or {})
    return AssociationConfig(**kw)


def build_configs(spec: CellSpec, comps: Components):
    """(radar config per mimo, processing config per result scheme) of a cell."""
    schemes = result_schemes(spec.schemes, spec.external_chains)
    radar = {m: radar_config(spec.radar, m) for m in mimos(schemes)}
    # A TI profile's processing commands (its CFAR, compression, interference mitigation,
    # velocity extension, fields of view, calibration) are the cell's processing defaults,
    # read by the same function as `radar-harness process`; the sweep's settings override.
    path = spec.radar.get("profile")
    base = {} if path is None else profile_processing(load_profile(Path(path)))
    procs = {s.name: comps.make_processing({**base, **spec.processing, **s.processing})
             for s in schemes}
    return radar, procs
