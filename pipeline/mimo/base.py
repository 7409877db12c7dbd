"""The receive-side half of a MIMO scheme: the chain interface and its registry.

`MIMO_CHAINS` maps each `radarsim.MIMO_SCHEMES` name to a `MimoChain`, the object that turns
one ADC frame of that scheme into a point cloud (transmitter separation, Doppler compensation,
velocity disambiguation, on top of the shared stages of `pipeline.stages`). Registering a
scheme's chain is one `register_chain` call in its own module.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar, NamedTuple

import numpy as np
import pandas as pd

from core.registry import Registry
from radarsim.config import RadarConfig

from ..config import ProcessingConfig
from ..fov import FOV_FIELDS

__all__ = ["MimoChain", "DetectionMap", "DopplerAzimuth", "MIMO_CHAINS", "register_chain",
           "chain_of"]


class DetectionMap(NamedTuple):
    """The square-law map a chain's CFAR runs on.

    Attributes
    ----------
    power : ndarray
        DDMA: (n_range, n_azimuth, n_doppler) coherent maps; TDMA/BPM: (n_range, n_doppler)
        non-coherent sum over the virtual antennas.
    looks : int
        Independent exponential looks per cell under noise.
    cfar_axis : int
        The (cyclic) Doppler axis of `power`.
    """

    power: np.ndarray
    looks: int
    cfar_axis: int


class DopplerAzimuth(NamedTuple):
    """Doppler-azimuth power of one range bin (bins in the chain's natural order).

    Attributes
    ----------
    velocity_mps : (n_dop,) float
        Radial velocity each Doppler row is reported at.
    power : (n_dop, n_az) float
        Azimuth power per Doppler row, azimuth bins in FFT order.
    """

    velocity_mps: np.ndarray
    power: np.ndarray


class MimoChain:
    """Receive side of one MIMO scheme. Subclasses implement the four methods.

    Attributes
    ----------
    name : str
        The `radarsim.MIMO_SCHEMES` name the chain processes.
    variants : dict
        Extra result schemes derived from this one by `ProcessingConfig` overrides on the same
        ADC frame, e.g. ``{"tdma_raw": {"velocity.tdma_disambiguation": False}}``.
    removes_static_clutter : bool
        Whether the chain implements `ProcessingConfig.doppler.clutter_removal` (TI's
        ``clutterRemoval``); `pipeline.process_frame` refuses the setting for the others.
    multi_azimuth_peaks : bool
        Whether the chain can report several azimuth peaks of one (range, Doppler) cell
        (`ProcessingConfig.angle.azimuth_sidelobe_db`, TI's ``multiObjBeamForming``); the others
        report the strongest only (TI's "disabled").
    fov_fields : tuple of str
        The field-of-view limits (`pipeline.fov.FOV_FIELDS`) `pipeline.process_frame`
        applies to the chain's point cloud; a chain that applies one itself, where TI's demo
        does (the velocity limit on the aliased Doppler, before extension), leaves it out.
    mitigation_in_range_stage : bool
        Whether the chain reads the interference settings only through the chirp-level range
        stage (`pipeline.chirp_level.range_stage`, `windowed_range_stage`): then a frame in
        which the mitigation has nothing to repair (`pipeline.chirp_level.idle_mitigation`)
        gives the same cloud with and without it, and `pipeline.process_frames` computes it
        once. Every built-in chain does; a chain that handles interference itself must not
        claim it (the default).
    """

    name: ClassVar[str] = ""
    variants: ClassVar[dict[str, dict[str, Any]]] = {}
    removes_static_clutter: ClassVar[bool] = False
    multi_azimuth_peaks: ClassVar[bool] = False
    mitigation_in_range_stage: ClassVar[bool] = False
    fov_fields: ClassVar[tuple[str, ...]] = tuple(FOV_FIELDS)

    def process(self, cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> pd.DataFrame:
        """(n_chirps, n_rx, n_samples) int16 (real) or complex64 (I/Q) frame -> point cloud
        (`POINT_CLOUD_COLUMNS`): a new frame, the caller's own (`pipeline.process_frame`
        completes it in place, `saturation.apply_policy` with ``owned=True``)."""
        raise NotImplementedError

    def process_variants(self, cfg: RadarConfig, adc: np.ndarray,
                         procs: Sequence[ProcessingConfig]) -> list[pd.DataFrame]:
        """`process` of one frame under each of `procs`, in order. A chain whose settings
        share stages (a scheme and its `variants`) overrides it to compute them once; the
        clouds must equal `process`'s."""
        return [self.process(cfg, adc, proc) for proc in procs]

    def detection_map(self, cfg: RadarConfig, adc: np.ndarray,
                      proc: ProcessingConfig) -> DetectionMap:
        """The map the CFAR runs on."""
        raise NotImplementedError

    def doppler_azimuth(self, cfg: RadarConfig, adc: np.ndarray, range_bin: int,
                        proc: ProcessingConfig) -> DopplerAzimuth:
        """Doppler-azimuth power of one range bin, for plots."""
        raise NotImplementedError

    def range_doppler_power(self, cfg: RadarConfig, adc: np.ndarray,
                            proc: ProcessingConfig) -> np.ndarray:
        """(n_range, n_doppler) power summed over channels, Doppler in natural FFT order."""
        raise NotImplementedError


#: Receive chains by `radarsim.MIMO_SCHEMES` name.
MIMO_CHAINS: Registry[MimoChain] = Registry(
    "chain", field="mimo", kind=MimoChain,
    missing="{field}={name} has no receive chain; registered: {known}")


def register_chain(chain: MimoChain, *, replace: bool = False) -> MimoChain:
    """Add a chain to `MIMO_CHAINS` under `chain.name` and return it.

    Raises
    ------
    ValueError
        If the name is empty or taken (and `replace` is False).

    Examples
    --------
    >>> import pipeline
    >>> from pipeline.mimo.base import MIMO_CHAINS
    >>> from pipeline.mimo.tdma import TdmaChain
    >>> class ReversedTdmaChain(TdmaChain):
    ...     name = "tdma_reversed"
    ...     variants = {}
    >>> pipeline.register_chain(ReversedTdmaChain()).name
    'tdma_reversed'
    >>> _ = MIMO_CHAINS.unregister("tdma_reversed")
    """
    return MIMO_CHAINS.register(chain, replace=replace)


def chain_of(cfg: RadarConfig) -> MimoChain:
    """The registered chain of `cfg.mimo`.

    Raises
    ------
    ValueError
        If no chain is registered for the scheme.

    Examples
    --------
    >>> import radarsim
    >>> from pipeline.mimo.base import chain_of
    >>> type(chain_of(radarsim.presets.r79_tdma())).__name__
    'TdmaChain'
    """
    return MIMO_CHAINS.lookup(cfg.mimo)
