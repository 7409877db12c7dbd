"""The CFAR's settings (`CfarConfig`): mode, guard and training cells, OS rank, threshold."""
from __future__ import annotations

from dataclasses import dataclass

from core.checks import one_of, require

from .modes import CFAR_MODES, cfar_scale

__all__ = ["CfarConfig", "default_os_rank"]


def default_os_rank(n_training: int) -> int:
    """Rohling's recommended OS rank: k = round(3/4 N) of N training cells (at least 1)."""
    return max(1, round(0.75 * n_training))


@dataclass(frozen=True, kw_only=True, slots=True)
class CfarConfig:
    """CFAR along Doppler (cyclic): mode, guard and training cells, OS rank, threshold.

    Parameters
    ----------
    mode : str
        Key of `pipeline.cfar.CFAR_MODES` ("os", "ca", "cago", "caso").
    guard_cells : int
        Guard cells on each side of the cell under test.
    window_cells : int
        Training cells on each side (N = 2 x window_cells in total).
    training_stride : int
        Take every `training_stride`-th cell as a training cell. The threshold formulas assume
        independent cells; a Hann-windowed spectrum correlates neighbouring bins (power
        correlation 4/9 at lag 1, 1/36 at lag 2), which widens the spread of the noise estimate
        and raises the false-alarm rate above design, so the default samples every other bin.
    os_rank : int or None
        k (1-based) of the OS estimate; default round(3/4 N) (Rohling's recommendation).
    pfa : float or None
        Design false-alarm probability per cell; the threshold scale follows from it
        (Rohling / CA formulas, `cfar.cfar_scale`). Used when `threshold_db` is None.
    threshold_db : float or None
        Explicit threshold scale alpha in dB over the noise estimate (overrides `pfa`).
    """

    mode: str = "os"
    guard_cells: int = 2
    window_cells: int = 12
    training_stride: int = 2
    os_rank: int | None = None
    pfa: float | None = 1e-6
    threshold_db: float | None = None

    def __post_init__(self) -> None:
        one_of("mode", self.mode, CFAR_MODES, what="cfar ")
        require(self, "guard_cells", "integer", ge=0)
        require(self, ("window_cells", "training_stride"), "integer", ge=1)
        n = 2 * self.window_cells
        if self.os_rank is None:
            object.__setattr__(self, "os_rank", default_os_rank(n))
        else:
            require(self, "os_rank", "integer", ge=1, le=n)  # n = 2 x window_cells
        if self.threshold_db is None:
            require(self, "pfa", gt=0, lt=1)  # the threshold comes from pfa
        else:
            require(self, "threshold_db")

    @property
    def n_training(self) -> int:
        """Training cells in total, N."""
        return 2 * self.window_cells

    def scale(self, looks: int = 1) -> float:
        """Threshold scale alpha (linear) over the noise estimate for L-look cells."""
        if self.threshold_db is not None:
            return CFAR_MODES[self.mode].scale_of_db(self.threshold_db)
        return cfar_scale(self.pfa, self.mode, self.n_training, self.os_rank, looks)
