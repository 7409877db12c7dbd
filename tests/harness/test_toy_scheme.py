"""Proof of the scheme registries: a toy MIMO scheme registered from inside this test file
(no edit anywhere else) runs through `run_cell` next to the built-in ones.

The toy is TDMA with the firing order reversed (Tx2, Tx4, Tx3, Tx1): one `radarsim.MimoScheme`
(transmit side: its default slot order) and one `pipeline.MimoChain` (receive side: the TDMA
chain, which reads the order from the config), each registered under the name "toy_tdma".
"""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import pipeline
import radarsim
from harness.cell import components
from harness.cell.run import run_cell
from harness.cell.spec import CellSpec
from harness.sweep import streams
from pipeline.mimo import MIMO_CHAINS
from pipeline.mimo.tdma import TdmaChain
from radarsim.mimo import MIMO_SCHEMES, TdmaScheme
from tests.harness import fakes


class ToyTdmaScheme(TdmaScheme):
    def default_tx_order(self, n_tx: int) -> tuple[int, ...]:
        return tuple(reversed(super().default_tx_order(n_tx)))


class ToyTdmaChain(TdmaChain):
    name = "toy_tdma"
    variants = {}


@pytest.fixture
def toy_scheme():
    radarsim.register_scheme(ToyTdmaScheme("toy_tdma", "TDMA, reversed slot order"))
    pipeline.register_chain(ToyTdmaChain())
    yield "toy_tdma"
    del MIMO_SCHEMES["toy_tdma"], MIMO_CHAINS["toy_tdma"]


#: Fake scenario and scatterers, the real front end and chain.
REAL_CHAIN = components.Components(run_scenario=fakes.fake_run_scenario,
                                   scene_scatterers=fakes.fake_scene_scatterers,
                                   simulate_frame=components._real_simulate_frame,
                                   process_frame=components._real_process_frame,
                                   make_processing=components._real_make_processing)


def test_toy_scheme_runs_through_run_cell(toy_scheme):
    cfg = radarsim.presets.r79(toy_scheme)
    assert cfg.tx_order == (2, 4, 3, 1) and cfg.max_unambiguous_velocity_mps == \
        pytest.approx(10.22, abs=0.01)
    spec = CellSpec(scenario="slow", seed=0, duration_s=0.25, schemes=("tdma", toy_scheme))
    res = run_cell(spec, REAL_CHAIN)
    s = res.tables["summary"].set_index("scheme")
    assert list(s.index) == ["tdma", toy_scheme]
    assert s.loc[toy_scheme, "n_true"] >= 5  # the car, every frame
    assert s.loc[toy_scheme, "velocity_unambiguity_rate"] == 1.0
    # Same energy per Tx as TDMA: SNR gain over the baseline about 0 dB.
    assert abs(s.loc[toy_scheme, "snr_gain_median_db"]) < 1.5
    # Its own seed stream: TDMA's rows do not change when the toy joins the cell.
    alone = run_cell(CellSpec(scenario="slow", seed=0, duration_s=0.25, schemes=("tdma",)),
                     REAL_CHAIN)
    a = res.tables["detections"]
    pd.testing.assert_frame_equal(a[a.scheme == "tdma"].reset_index(drop=True),
                                  alone.tables["detections"])
    assert streams.stream_id(toy_scheme) not in streams.SEED_STREAMS.values()
    assert np.isnan(s.loc["tdma", "snr_gain_median_db"])
