"""Receive chains of the MIMO schemes, one module per scheme, registered in `MIMO_CHAINS`
under the `radarsim.MIMO_SCHEMES` name they process."""
from . import bpm, ddma, ddma_classic, fast_slow, tdma  # noqa: F401  (each module registers its chain)
from .base import MIMO_CHAINS, DetectionMap, DopplerAzimuth, MimoChain, chain_of, register_chain

__all__ = ["MIMO_CHAINS", "MimoChain", "DetectionMap", "DopplerAzimuth", "register_chain",
           "chain_of"]
