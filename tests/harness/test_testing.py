"""The plugin authors' check kit catches each contract item on a deliberately broken part and
names the part, its origin and the item."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import metrics
import pipeline
import radarsim
from harness.cell.run import run_cell
from harness.cell.spec import CellSpec
from harness.testing import ContractError, check_cfar_mode, check_chain, check_metric
from pipeline.cfar import CellAveraging
from pipeline.mimo.tdma import TdmaChain
from radarsim.mimo import TdmaScheme
from tests.harness.fakes import FAKE


def _drop_snr(pc, adc):
    return pc.drop(columns="snr_db")


def _int_range(pc, adc):
    return pc.assign(range_m=pc["range_m"].round().astype(np.int64))


def _nan(pc, adc):
    return pc.assign(snr_db=np.nan)


def _far(pc, adc):
    return pc.assign(range_m=pc["range_m"] + 1e4)


def _mutate(pc, adc):
    adc[0, 0, 0] = adc[0, 0, 0] + 1
    return pc


def _noisy(pc, adc):
    return pc.assign(snr_db=pc["snr_db"] + np.random.default_rng().normal(size=len(pc)))


def _empty_fails(pc, adc):
    if len(pc) == 0:  # a chain that assumes at least one peak
        raise IndexError("no peak found")
    return pc


def _saturation_fails(pc, adc):
    if np.abs(adc.astype(np.float32)).max() >= 32767:
        raise FloatingPointError("overflow in the range FFT")
    return pc


BREAKS = {
    "columns": (_drop_snr, r"columns: missing \['snr_db'\]"),
    "dtypes": (_int_range, r"dtypes: column 'range_m' is int64, not float"),
    "finite": (_nan, r"finite: column 'snr_db' holds nan"),
    "limits": (_far, r"limits: column 'range_m' value .* outside \[0, "),
    "input_not_mutated": (_mutate, r"input not mutated: the scene ADC frame was changed"),
    "deterministic": (_noisy, r"deterministic: two runs on the same scene frame differ"),
    "empty_scene": (_empty_fails, r"empty scene: raised IndexError: no peak found"),
    "saturated_frame": (_saturation_fails,
                        r"saturated frame: raised FloatingPointError: overflow"),
}


@pytest.fixture
def broken_scheme(request):
    """Register scheme ``broken_<item>`` whose chain is TDMA's, broken by `request.param`."""
    item = request.param
    breaker = BREAKS[item][0]
    name = f"broken_{item}"

    class Broken(TdmaChain):
        variants = {}

        def process(self, cfg, adc, proc):
            return breaker(super().process(cfg, adc, proc), adc)

    Broken.name = name
    radarsim.register_scheme(TdmaScheme(name, "deliberately broken"))
    pipeline.register_chain(Broken())
    yield name, BREAKS[item][1]
    pipeline.MIMO_CHAINS.unregister(name)
    radarsim.MIMO_SCHEMES.unregister(name)


@pytest.mark.parametrize("broken_scheme", list(BREAKS), indirect=True)
def test_check_chain_names_the_broken_item(broken_scheme):
    name, message = broken_scheme
    with pytest.raises(ContractError, match=rf"chain '{name}' \(module tests\.harness\."
                                            rf"test_testing\).*{message}"):
        check_chain(name)


def test_check_chain_passes_the_built_in_chains():
    check_chain("tdma")


class _BadShapeCa(CellAveraging):
    def noise_estimate(self, train, n_lag, os_rank):
        return train.mean(axis=-1, keepdims=True)


class _MutatingCa(CellAveraging):
    def noise_estimate(self, train, n_lag, os_rank):
        train *= 1.0
        train[..., 0] = 0.0
        return train.mean(axis=-1)


class _NanCa(CellAveraging):
    def noise_estimate(self, train, n_lag, os_rank):
        return train.mean(axis=-1) / train.mean(axis=-1)  # 0 / 0 on empty cells


@pytest.mark.parametrize("cls, message", [
    (_BadShapeCa, r"columns: noise_estimate of \(64, 24\) cells has shape \(64, 1\)"),
    (_MutatingCa, r"input not mutated: noise_estimate changed the noise cells"),
    (_NanCa, r"finite: noise_estimate of the empty scene cells holds nan"),
], ids=["shape", "mutates", "nan"])
def test_check_cfar_mode_names_the_broken_item(cls, message):
    name = f"bad_{cls.__name__.lower()}"
    pipeline.CFAR_MODES.register(cls(name=name, description="broken"))
    try:
        with np.errstate(invalid="ignore"), \
                pytest.raises(ContractError, match=rf"CFAR mode '{name}' .*{message}"):
            check_cfar_mode(name)
    finally:
        pipeline.CFAR_MODES.unregister(name)


def _metric(name, fn):
    return metrics.Metric(name=name, unit="", better="higher", table="detections", source=fn,
                          row_value=fn, description="broken test metric")


def _raises_on_empty(lab, af):
    return float(lab["snr_db"].max() / len(lab))


def _mutates(lab, af):
    lab["snr_db"] = 0.0
    return 1.0


def _random(lab, af):
    return float(np.random.default_rng().random())


def _nan_on_scene(lab, af):
    return float("nan")


def test_a_metric_that_writes_into_its_tables_changes_no_cell_table():
    """A plugin metric's row_value gets copies: a cell's tables are the same with a metric
    registered that overwrites its input, so `check_metric`'s sample cell, whenever it is first
    run, shows the metric the real tables (the mutation check above holds in any test order)."""
    spec = CellSpec(scenario="fast", seed=3, duration_s=0.5)
    want = run_cell(spec, FAKE).tables
    metrics.register_metric(_metric("broken_writer", _mutates))
    try:
        got = run_cell(spec, FAKE).tables
    finally:
        metrics.METRICS.unregister("broken_writer")
    assert (want["detections"]["snr_db"] != 0).all()
    for name in ("detections", "actors"):
        pd.testing.assert_frame_equal(got[name], want[name], check_exact=True)


@pytest.mark.parametrize("fn, message", [
    (_raises_on_empty, r"empty scene: row_value raised ZeroDivisionError"),
    (_mutates, r"input not mutated: row_value changed the scene tables"),
    (_random, r"deterministic: row_value gave"),
    (_nan_on_scene, r"finite: row_value on a real cell's tables is nan"),
], ids=["empty", "mutates", "random", "nan"])
def test_check_metric_names_the_broken_item(fn, message):
    name = f"broken{fn.__name__}"
    metrics.register_metric(_metric(name, fn))
    try:
        with pytest.raises(ContractError, match=rf"metric '{name}' .*{message}"):
            check_metric(name)
    finally:
        metrics.METRICS.unregister(name)
