"""What the example plugin adds, through the harness's public ``register_*`` calls only:

- scheme ``tdma_rev``: TDMA firing the Tx in reverse order (Tx2, Tx4, Tx3, Tx1), with its chain
  (the TDMA receive chain: slot order comes from the config, so it needs no other code);
- CFAR mode ``ca_example``: cell averaging under the plugin's name (``[base.processing]
  cfar_mode = "ca_example"``);
- board ``EXAMPLE_AWR2944_NARROW``: the AWR2944EVM with a +/-60 deg field of view;
- metric ``true_detections_per_frame`` (higher is better), computed for every summary row and
  usable in gates (``gates.toml`` beside this module gates it);
- its case files (``cases/*.toml``, the catalogue's format): ``example_fast_overtake``.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import metrics
import pipeline
import radarsim
from pipeline.cfar import CellAveraging
from pipeline.mimo.tdma import TdmaChain
from radarsim.mimo import TdmaScheme
from scenarios import SCENARIOS
from scenarios.files import load_case_directory


class ReversedTdma(TdmaScheme):
    """TDMA with the Tx slots in reverse order of the R79 demo's."""

    def default_tx_order(self, n_tx):
        return tuple(reversed(super().default_tx_order(n_tx)))


class ReversedTdmaChain(TdmaChain):
    """The TDMA chain for ``tdma_rev`` frames (no chain variants)."""

    name = "tdma_rev"
    variants = {}


def true_detections_per_frame(labelled, actor_frames) -> float:
    """TRUE detections per processed frame (frames: those of the actor-frame table)."""
    n_frames = actor_frames["frame"].nunique() if len(actor_frames) else 0
    n_true = int((labelled["label"] == "TRUE").sum()) if len(labelled) else 0
    return n_true / n_frames if n_frames else float("nan")


radarsim.register_scheme(ReversedTdma("tdma_rev", "TDMA, Tx slots in reverse order"))
pipeline.register_chain(ReversedTdmaChain())
pipeline.CFAR_MODES.register(CellAveraging(name="ca_example",
                                           description="cell averaging (example plugin)"))
radarsim.register_board(dataclasses.replace(radarsim.BOARDS["AWR2944EVM"],
                                            name="EXAMPLE_AWR2944_NARROW", fov_deg=60.0,
                                            source="example plugin: AWR2944EVM, +/-60 deg"))
metrics.register_metric(metrics.Metric(
    name="true_detections_per_frame", unit="", better="higher", table="detections",
    source=true_detections_per_frame, row_value=true_detections_per_frame,
    description="TRUE detections per processed frame (example plugin)"))
SCENARIOS.register_all(load_case_directory(Path(__file__).with_name("cases")).values())
