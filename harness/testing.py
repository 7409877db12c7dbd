"""Check kit for plugin authors: runs a registered chain, CFAR mode or metric through the
contract the harness relies on, and names the plugin and the broken item.

Use it in the plugin's own tests::

    from harness.testing import check_chain, check_cfar_mode, check_metric

    def test_my_chain():
        check_chain("my_scheme")            # raises ContractError naming what is broken

Every check raises `ContractError` (an `AssertionError`, so pytest shows it as a failure) with
``<kind> <name> (<origin>): <item>: <what is wrong>``, the origin being the plugin that
registered it (`harness.plugins.origin_of`). The items:

- **columns**: a chain returns a DataFrame with every `pipeline.POINT_CLOUD_COLUMNS` column;
  physical columns float, bins integer (float allowed in an empty cloud), ``saturated`` bool;
- **finite** / **limits**: finite values; range in [0, max range], azimuth and elevation in
  [-90, 90] deg, radial velocity within n_tx x the unambiguous velocity (the widest a
  velocity-extension chain reports), SNR finite;
- **input not mutated**: the ADC frame (a chain) or the tables (a metric) are unchanged;
- **deterministic**: the same input gives the same bits;
- **empty scene**: a noise-only frame (a metric: tables without rows) is processed;
- **saturated frame**: a frame with every sample at the ADC rails is processed.
"""
from __future__ import annotations

import functools

import numpy as np
import pandas as pd

__all__ = ["ContractError", "check_chain", "check_cfar_mode", "check_metric",
           "check_point_cloud", "two_target_scene"]


class ContractError(AssertionError):
    """A registered part breaks the harness's contract (the message names part and item)."""


def _origin(registry, name: str) -> str:
    from harness.plugins import origin_of
    return origin_of(registry.origin(name))


def _fail(who: str, item: str, detail: str) -> ContractError:
    return ContractError(f"{who}: {item}: {detail}")


_FLOAT_COLUMNS = ("range_m", "azimuth_deg", "elevation_deg", "radial_velocity_mps", "snr_db",
                  "x_m", "y_m", "z_m")
_INT_COLUMNS = ("range_bin", "doppler_bin", "azimuth_bin")


def check_point_cloud(cloud, cfg, who: str = "point cloud") -> None:
    """Columns, dtypes, finite values and radar limits of one point cloud.

    Raises
    ------
    ContractError
        Naming `who`, the item (columns, dtypes, finite, limits) and the column.
    """
    from pipeline import POINT_CLOUD_COLUMNS
    if not isinstance(cloud, pd.DataFrame):
        raise _fail(who, "columns", f"returned {type(cloud).__name__}, not a pandas DataFrame")
    missing = [c for c in POINT_CLOUD_COLUMNS if c not in cloud.columns]
    if missing:
        raise _fail(who, "columns", f"missing {missing}")
    for c in _FLOAT_COLUMNS:
        if not pd.api.types.is_float_dtype(cloud[c]):
            raise _fail(who, "dtypes", f"column {c!r} is {cloud[c].dtype}, not float")
    for c in _INT_COLUMNS:  # integer bins (an empty cloud may carry them as float)
        ok = pd.api.types.is_integer_dtype(cloud[c]) or (
            pd.api.types.is_float_dtype(cloud[c]) and len(cloud) == 0)
        if not ok:
            raise _fail(who, "dtypes", f"column {c!r} is {cloud[c].dtype}, not integer")
    if not pd.api.types.is_bool_dtype(cloud["saturated"]):
        raise _fail(who, "dtypes", f"column 'saturated' is {cloud['saturated'].dtype}, not bool")
    for c in _FLOAT_COLUMNS:
        v = cloud[c].to_numpy(dtype=np.float64)
        if not np.isfinite(v).all():
            raise _fail(who, "finite", f"column {c!r} holds {float(v[~np.isfinite(v)][0])!r}")
    v_lim = cfg.n_tx * cfg.max_unambiguous_velocity_mps
    for c, lo, hi, unit in (("range_m", 0.0, cfg.max_range_m, "m"),
                            ("azimuth_deg", -90.0, 90.0, "deg"),
                            ("elevation_deg", -90.0, 90.0, "deg"),
                            ("radial_velocity_mps", -v_lim, v_lim, "m/s")):
        v = cloud[c].to_numpy(dtype=np.float64)
        bad = (v < lo) | (v > hi)
        if bad.any():
            raise _fail(who, "limits", f"column {c!r} value {v[bad][0]:g} {unit} is outside "
                        f"[{lo:g}, {hi:g}] {unit}")


def two_target_scene():
    """The kit's scene: a car closing at 30 m and one receding at 80 m (10 m^2 each)."""
    import radarsim
    return radarsim.Scatterers(position_m=[[30.0, 4.0, 0.0], [80.0, -15.0, 0.3]],
                               velocity_mps=[[-12.0, 0.0, 0.0], [6.0, 0.0, 0.0]],
                               rcs_m2=[10.0, 10.0], actor_id=np.array([0, 1]))


def _frames(cfg, seed: int) -> dict[str, np.ndarray]:
    """A two-target frame, a noise-only frame and a frame at the ADC rails."""
    import radarsim
    rng = np.random.default_rng(seed)
    scene = radarsim.simulate_frame(cfg, two_target_scene(), rng)
    empty = radarsim.simulate_frame(cfg, radarsim.Scatterers(
        position_m=np.zeros((0, 3)), velocity_mps=np.zeros((0, 3)), rcs_m2=np.zeros(0),
        actor_id=np.zeros(0, dtype=np.int64)), np.random.default_rng(seed + 1))
    rail = np.iinfo(np.int16).max
    if np.iscomplexobj(scene):
        sign = np.where(np.arange(cfg.n_samples) % 2, 1.0, -1.0).astype(np.float32)
        sat = (rail * sign + 1j * rail * sign[::-1]).astype(np.complex64)
    else:
        sat = np.where(np.arange(cfg.n_samples) % 2, rail, -rail - 1).astype(np.int16)
    return {"scene": scene, "empty scene": empty,
            "saturated frame": np.broadcast_to(sat, scene.shape).copy()}


def check_chain(scheme: str, *, proc=None, cfg=None, seed: int = 0) -> None:
    """Run the chain of `scheme` (`pipeline.process_frame`) through the contract.

    Parameters
    ----------
    scheme : str
        A `radarsim.MIMO_SCHEMES` name with a registered chain.
    proc : pipeline.ProcessingConfig, optional
        Processing settings (default `ProcessingConfig()`).
    cfg : radarsim.RadarConfig, optional
        Radar (default the R79 preset of `scheme`).
    seed : int
        Seed of the test frames.

    Raises
    ------
    ContractError
        ``chain <scheme> (<origin>): <item>: ...`` for the first broken item.
    """
    import pipeline
    import radarsim
    cfg = radarsim.presets.r79(scheme) if cfg is None else cfg
    proc = pipeline.ProcessingConfig() if proc is None else proc
    who = f"chain {scheme!r} ({_origin(pipeline.MIMO_CHAINS, scheme)})"
    for what, adc in _frames(cfg, seed).items():
        before = adc.copy()
        try:
            first = pipeline.process_frame(cfg, adc, proc)
        except Exception as exc:  # noqa: BLE001 - any exception breaks the contract
            raise _fail(who, what, f"raised {type(exc).__name__}: {exc}") from exc
        if not np.array_equal(adc, before):
            raise _fail(who, "input not mutated", f"the {what} ADC frame was changed in place")
        check_point_cloud(first, cfg, f"{who}, {what}")
        again = pipeline.process_frame(cfg, adc.copy(), proc)
        if not first.equals(again):
            raise _fail(who, "deterministic", f"two runs on the same {what} frame differ")


def check_cfar_mode(mode: str, *, seed: int = 0) -> None:
    """Run a CFAR mode through the contract: its noise estimate on exponential training cells
    (shape, finite, positive, input not mutated, deterministic, all-zero and huge cells), then
    the TDMA chain with ``cfar.mode = mode`` (`check_chain`).

    Raises
    ------
    ContractError
        ``CFAR mode <mode> (<origin>): <item>: ...``.
    """
    import pipeline
    who = f"CFAR mode {mode!r} ({_origin(pipeline.CFAR_MODES, mode)})"
    m = pipeline.CFAR_MODES.lookup(mode)
    rng = np.random.default_rng(seed)
    n = 24
    cases = {"noise": rng.exponential(size=(64, n)).astype(np.float32),
             "empty scene": np.zeros((8, n), np.float32),
             "saturated frame": np.full((8, n), 1e30, np.float32)}
    for what, train in cases.items():
        before = train.copy()
        try:
            est = np.asarray(m.noise_estimate(train, n // 2, 18))
        except Exception as exc:  # noqa: BLE001
            raise _fail(who, what, f"noise_estimate raised {type(exc).__name__}: {exc}") from exc
        if not np.array_equal(train, before):
            raise _fail(who, "input not mutated", f"noise_estimate changed the {what} cells")
        if est.shape != train.shape[:-1]:
            raise _fail(who, "columns", f"noise_estimate of {train.shape} cells has shape "
                        f"{est.shape}, not {train.shape[:-1]}")
        if not np.isfinite(est).all() or (est < 0).any():
            raise _fail(who, "finite", f"noise_estimate of the {what} cells holds "
                        f"{float(est[~np.isfinite(est) | (est < 0)][0])!r}")
        if not np.array_equal(est, np.asarray(m.noise_estimate(train.copy(), n // 2, 18))):
            raise _fail(who, "deterministic", f"two noise estimates of the {what} cells differ")
    try:
        proc = pipeline.ProcessingConfig().replace(**{"cfar.mode": mode})
    except Exception as exc:  # noqa: BLE001
        raise _fail(who, "config", f"ProcessingConfig cfar.mode={mode!r} raised "
                    f"{type(exc).__name__}: {exc}") from exc
    check_chain("tdma", proc=proc, seed=seed)


@functools.lru_cache(maxsize=1)
def _sample_tables() -> tuple[pd.DataFrame, pd.DataFrame]:
    """Labelled detections and actor-frames of one short real cell (TDMA, 0.3 s), run once
    per process: `check_metric` hands the metric under test copies."""
    from harness.cell.run import run_cell
    from harness.cell.spec import CellSpec
    res = run_cell(CellSpec(scenario="blind_spot_overtaking", duration_s=0.3,
                            schemes=("tdma",), baseline_scheme="tdma"))
    det = res.tables["detections"]
    return det, res.tables["actors"]


def check_metric(name: str) -> None:
    """Check a metric's definition (unit, direction, description) and, for a metric with
    ``row_value``, its value on a short real cell's tables (a finite float; NaN allowed only
    on empty tables), on empty tables, unchanged inputs and the same value twice.

    Raises
    ------
    ContractError
        ``metric <name> (<origin>): <item>: ...``.
    """
    from metrics.registry import BETTER, METRICS
    who = f"metric {name!r} ({_origin(METRICS, name)})"
    m = METRICS.lookup(name)
    if m.better not in BETTER or not isinstance(m.unit, str) or not m.description.strip():
        raise _fail(who, "definition", f"unit={m.unit!r}, better={m.better!r}, "
                    f"description={m.description!r}")
    if m.row_value is None:
        return
    det, af = _sample_tables()
    for what, (lab0, af0) in {"scene": (det, af),
                              "empty scene": (det.iloc[:0], af.iloc[:0])}.items():
        # the metric gets copies: the sample is kept for the next check (`_sample_tables`)
        lab, frames = lab0.copy(), af0.copy()
        try:
            v = m.row_value(lab, frames)
            v = float(v)
        except Exception as exc:  # noqa: BLE001
            raise _fail(who, what, f"row_value raised {type(exc).__name__}: {exc}") from exc
        if not (lab.equals(lab0) and frames.equals(af0)):
            raise _fail(who, "input not mutated", f"row_value changed the {what} tables")
        if what == "scene" and not np.isfinite(v):
            raise _fail(who, "finite", f"row_value on a real cell's tables is {v!r}")
        if np.isinf(v):
            raise _fail(who, "finite", f"row_value on the {what} tables is {v!r}")
        again = float(m.row_value(lab.copy(), frames.copy()))
        if not (again == v or (np.isnan(again) and np.isnan(v))):
            raise _fail(who, "deterministic", f"row_value gave {v!r}, then {again!r}")
