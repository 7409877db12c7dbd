"""Software-in-the-loop receive chains: a team's chain that runs as its own process.

`harness.sil.spec` defines an ``[[external_chains]]`` entry of a sweep file, `harness.sil.profile`
writes the cell's TI profile for it, `harness.sil.call` runs one call fenced in and checks its
points, `harness.sil.cell` runs a cell's calls and returns its point clouds.
"""
from harness.sil.call import ExternalChainError
from harness.sil.cell import ExternalCellRun
from harness.sil.spec import ExternalChain, external_chains_from_toml

__all__ = ["ExternalChain", "ExternalChainError", "ExternalCellRun", "external_chains_from_toml"]
